// A VDB world as the streaming engine's source: the read-only store serves the exported chunks,
// refuses writes, and the streamer meshes from it exactly what it would from the world itself.
#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "engine/chunk_streamer.h"
#include "world/gen/terrain.h"
#include "world/vdb/vdb_store.h"

using namespace vx;
using namespace vx::world;

namespace {

struct CountingSink : engine::MeshSink {
    size_t meshes = 0;
    void on_mesh(ChunkCoord, const ChunkMesh&, std::span<const int>) override { ++meshes; }
    void on_unload(ChunkCoord) override {}
};

} // namespace

TEST(VdbStore, ServesAnExportedWorldToTheStreamer) {
    const TerrainGenerator gen(6);
    World src;
    for (int y = -1; y <= 1; ++y)
        for (int z = -3; z <= 3; ++z)
            for (int x = -3; x <= 3; ++x)
                src.put_chunk(ChunkCoord(x, y, z), gen.generate(ChunkCoord(x, y, z)));
    const auto path = (std::filesystem::temp_directory_path() / "vx_vdb_store.vdb").string();
    ASSERT_TRUE(vdb::export_vdb(src, path).ok());

    auto store = vdb::VdbStore::open(path);
    ASSERT_TRUE(store.ok()) << store.error();
    EXPECT_TRUE((*store)->read_only());
    EXPECT_FALSE((*store)->save(ChunkCoord(0), Chunk(1)).ok());
    auto one = (*store)->load(ChunkCoord(1, 0, -2));
    ASSERT_TRUE(one.ok());
    ASSERT_EQ(one->state, LoadState::Present);
    EXPECT_TRUE(*one->chunk == *src.find_chunk(ChunkCoord(1, 0, -2)));
    EXPECT_EQ((*store)->load(ChunkCoord(50, 0, 0))->state, LoadState::Absent);

    // The streamer loads the view from the VDB (chunks beyond it are generated).
    CountingSink sink;
    engine::StreamingSettings st;
    st.view_radius = 1;
    st.view_radius_vertical = 0;
    st.worker_count = 1;
    engine::ChunkStreamer streamer(gen, store->get(), sink, st);
    auto now = std::chrono::steady_clock::now();
    const auto limit = now + std::chrono::minutes(2);
    while (!streamer.settled() && std::chrono::steady_clock::now() < limit) {
        streamer.update(glm::dvec3(16, 16, 16), glm::dvec3(0, 0, -1), now += std::chrono::milliseconds(16));
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    ASSERT_TRUE(streamer.settled());
    EXPECT_EQ(sink.meshes, 9u);
    for (int z = -1; z <= 1; ++z)
        for (int x = -1; x <= 1; ++x)
            EXPECT_TRUE(*streamer.world().find_chunk(ChunkCoord(x, 0, z)) == *src.find_chunk(ChunkCoord(x, 0, z)));
    std::filesystem::remove(path);
}
