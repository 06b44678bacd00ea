#pragma once
// Helpers shared by the LodStreamer tests (lod_streamer_test.cpp, lod_streamer_edit_test.cpp): what a
// renderer would draw, a small view, and a LodStreamer fed by a ChunkStreamer, settled on a synthetic clock.

#include <chrono>
#include <span>
#include <thread>
#include <unordered_set>

#include <glm/glm.hpp>

#include "engine/chunk_streamer.h"
#include "engine/lod_streamer.h"

namespace vx::engine::test {

using world::BlockRegistry;
using world::ChunkCoord;
using world::ChunkGenerator;
using world::ChunkMesh;
using world::ChunkStore;
using world::LodCoord;
using world::LodCoordHash;
using world::LodViewSettings;
using Clock = std::chrono::steady_clock;
using LodSet = std::unordered_set<LodCoord, LodCoordHash>;

// What a renderer would draw: every chunk handed over and not taken back (an empty mesh counts:
// it covers air).
class DrawnRecorder final : public LodMeshSink {
public:
    void on_mesh(ChunkCoord c, const ChunkMesh&, std::span<const int>) override { drawn.insert({0, c}); }
    void on_unload(ChunkCoord c) override { drawn.erase({0, c}); }
    void on_lod_mesh(LodCoord c, const ChunkMesh&) override { drawn.insert(c); }
    void on_lod_unload(LodCoord c) override { drawn.erase(c); }
    LodSet drawn;
};

inline LodViewSettings small_view() {
    LodViewSettings s;
    s.radius0 = 2;
    s.vradius0 = 1;
    s.ring = 2;
    s.vertical_reach = 64;
    s.view_distance = 420;
    return s;
}

inline StreamingSettings streaming_for(const LodViewSettings& v) {
    StreamingSettings s;
    s.view_radius = v.radius0;
    s.view_radius_vertical = v.vradius0;
    s.worker_count = 2;
    s.lookahead_s = 0.5;
    return s;
}

// A LodStreamer fed by a ChunkStreamer as its mesh sink, the way the engine wires them; tests
// take its parts by structured binding: auto& [rec, lod, streamer] = rig.
struct Rig {
    Rig(const ChunkGenerator& gen, ChunkStore* store, const LodViewSettings& s) : Rig(gen, store, s, streaming_for(s)) {}
    Rig(const ChunkGenerator& gen, ChunkStore* store, const LodViewSettings& s, const StreamingSettings& ss)
        : lod(gen, store, rec, s, BlockRegistry::default_registry()), streamer(gen, store, lod, ss) {
        lod.attach(streamer.jobs(), streamer.world());
    }
    DrawnRecorder rec; // Declared first: lod draws into it.
    LodStreamer lod;
    ChunkStreamer streamer;
};

inline bool settle(ChunkStreamer& streamer, LodStreamer& lod, const glm::dvec3& eye, Clock::time_point& now) {
    const auto limit = Clock::now() + std::chrono::minutes(3);
    while (Clock::now() < limit) {
        now += std::chrono::milliseconds(16);
        streamer.update(eye, glm::dvec3(1, 0, 0), now);
        lod.update(eye, now, Clock::now() + std::chrono::milliseconds(2));
        if (streamer.settled() && lod.settled())
            return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
}

} // namespace vx::engine::test
