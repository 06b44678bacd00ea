#pragma once
// The renderer as the streamer's MeshSink: every mesh the engine makes or edits goes to the
// renderer's BLAS table with the slices an edit changed (only those are uploaded, then a refit,
// when they still fit their slots), every unloaded chunk leaves it. Main thread only, like both
// sides.

#include "engine/mesh_sink.h"
#include "render/renderer.h"

namespace vx::engine {

class RendererSink final : public MeshSink {
public:
    explicit RendererSink(render::Renderer& renderer) : m_renderer(renderer) {}

    void on_mesh(world::ChunkCoord c, const world::ChunkMesh& mesh, std::span<const int> changed_slices) override {
        m_renderer.set_chunk(c, mesh, changed_slices); // An empty mesh removes the chunk's BLAS (none for air).
    }
    void on_unload(world::ChunkCoord c) override { m_renderer.remove_chunk(c); }

private:
    render::Renderer& m_renderer;
};

} // namespace vx::engine
