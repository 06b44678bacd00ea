#pragma once
// Where the facade's streamer reports: meshes go on to the renderer (when there is one; with
// levels of detail through the LodStreamer, which passes on the drawn ones), and loads, meshes
// and unloads become ChunkEvents for the game (when it asked for them). Main thread
// only, like the streamer that calls it.

#include <utility>
#include <vector>

#include <vx/vx.h>

#include "engine/chunk_streamer.h"
#include "engine/lod_streamer.h"
#include "engine/mesh_sink.h"
#include "render/renderer.h"

namespace vx::engine {

class EngineSink final : public LodMeshSink, public StreamObserver {
public:
    // `renderer` may be null (no GPU); it must outlive the sink's use.
    EngineSink(render::Renderer* renderer, bool record_events) : m_renderer(renderer), m_record(record_events) {}

    void on_mesh(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) override {
        ++m_world_changes;
        // The edit's slices go on: only they are uploaded and the chunk's BLAS refitted (without
        // them every edit re-sent the whole mesh and rebuilt the BLAS). An empty mesh removes it.
        if (m_renderer)
            m_renderer->set_chunk(c, mesh, changed_slices);
        record(ChunkEvent::Kind::Meshed, c);
    }
    void on_unload(world::ChunkCoord c) override {
        ++m_world_changes;
        if (m_renderer)
            m_renderer->remove_chunk(c);
    }
    void on_block_edited(world::BlockPos p) override {
        if (m_renderer)
            m_renderer->note_edit(p, p);
    }
    // Coarse levels (LodStreamer): drawn scaled by their cell size; no ChunkEvents (the game's
    // events are about block data).
    void on_lod_mesh(world::LodCoord c, const world::ChunkMesh& mesh) override {
        if (m_renderer)
            m_renderer->set_chunk(c, mesh);
    }
    void on_lod_unload(world::LodCoord c) override {
        if (m_renderer)
            m_renderer->remove_chunk(c);
    }
    void on_chunk_loaded(world::ChunkCoord c) override {
        ++m_world_changes;
        record(ChunkEvent::Kind::Loaded, c);
    }
    void on_chunk_unloaded(world::ChunkCoord c) override { record(ChunkEvent::Kind::Unloaded, c); }

    // Takes the events recorded so far.
    std::vector<ChunkEvent> take_events() { return std::exchange(m_events, {}); }
    // Moves on every chunk load, mesh (edits included) and unload: the world may have changed.
    uint64_t world_changes() const { return m_world_changes; }
    // The renderer is gone (shutdown, recreation): stop forwarding.
    void detach_renderer() { m_renderer = nullptr; }
    // A new renderer (recreated after a lost device): meshes go to it from now on.
    void attach_renderer(render::Renderer* renderer) { m_renderer = renderer; }

private:
    void record(ChunkEvent::Kind kind, world::ChunkCoord c) {
        if (m_record)
            m_events.push_back({kind, c});
    }

    render::Renderer* m_renderer;
    bool m_record;
    uint64_t m_world_changes = 0;
    std::vector<ChunkEvent> m_events;
};

} // namespace vx::engine
