// Batch work on the job system (engine/region_mesher.h, scene_loader.h, world_pregen.h):
// every chunk meshed by the pool equals the same chunk meshed alone on this thread, aprons come
// from neighbours (or air), duplicates and absent chunks are handled, and a caller's mesh
// function is the one used; pregeneration saves what the generator makes.

#include <array>
#include <atomic>
#include <climits>
#include <cstring>
#include <filesystem>
#include <string>

#include <unistd.h>

#include <gtest/gtest.h>

#include "engine/job_batch.h"
#include "engine/region_mesher.h"
#include "engine/scene_loader.h"
#include "engine/world_pregen.h"
#include "world/gen/terrain.h"
#include "world/lod/downsample.h"
#include "world/mesh/reference_meshers.h"
#include "world/store/sqlite_store.h"

using namespace vx::engine;
using namespace vx::world;

namespace {

bool same_mesh(const ChunkMesh& a, const ChunkMesh& b) {
    if (a.quad_count() != b.quad_count())
        return false;
    for (int s = 0; s < kSliceCount; ++s) {
        const auto qa = a.slice(s), qb = b.slice(s);
        if (qa.size() != qb.size() || (!qa.empty() && std::memcmp(qa.data(), qb.data(), qa.size_bytes()) != 0))
            return false;
    }
    return true;
}

// Terrain around the origin: 3x3x3 chunks, surface chunks and their neighbours.
World terrain_world() {
    World w;
    const TerrainGenerator gen(7);
    const int h = chunk_of(BlockPos(0, gen.surface_height(0, 0), 0)).y;
    for (int z = -1; z <= 1; ++z)
        for (int y = h - 1; y <= h + 1; ++y)
            for (int x = -1; x <= 1; ++x)
                w.put_chunk(ChunkCoord(x, y, z), gen.generate(ChunkCoord(x, y, z)));
    return w;
}

} // namespace

TEST(RegionMesher, PoolMeshesEqualSerialMeshesWithNeighbourAprons) {
    const World w = terrain_world();
    JobSystem jobs(batch_job_system_info(3));
    RegionMesher mesher(jobs);
    std::vector<ChunkCoord> coords = chunk_coords(w);
    coords.push_back(coords.front());        // A duplicate: meshed once.
    coords.push_back(ChunkCoord(100, 0, 0)); // Not in the world: skipped.
    MeshMap meshes;
    const RegionMeshStats st = mesher.mesh(w, coords, meshes);
    EXPECT_EQ(st.chunks, w.chunk_count());
    ASSERT_EQ(meshes.size(), w.chunk_count());
    EXPECT_EQ(meshes.count(ChunkCoord(100, 0, 0)), 0u);
    GreedyMesher serial;
    uint64_t quads = 0, border_differs = 0;
    for (const auto& [c, mc] : meshes) {
        const Apron apron = make_apron(w, c);
        ChunkMesh expect, isolated;
        serial.mesh({*w.find_chunk(c), apron, w.registry()}, expect);
        EXPECT_TRUE(same_mesh(mc.mesh, expect)) << c.x << "," << c.y << "," << c.z;
        serial.mesh({*w.find_chunk(c), Apron::air(), w.registry()}, isolated);
        border_differs += !same_mesh(isolated, expect);
        quads += expect.quad_count();
    }
    EXPECT_EQ(st.quads, quads);
    EXPECT_GT(quads, 0u);
    EXPECT_GT(border_differs, 0u); // The aprons mattered: some meshes differ from isolated ones.
}

TEST(RegionMesher, AirApronsAndACallersMeshFunction) {
    const World w = terrain_world();
    JobSystem jobs(batch_job_system_info(2));
    std::atomic<int> calls{0};
    RegionMesher mesher(jobs, {ApronMode::Air, [&](GreedyMesher&, const MesherInput& in, ChunkMesh& out) {
                                   ++calls;
                                   mesh_culled(in, out);
                               }});
    MeshMap meshes;
    mesher.mesh(w, chunk_coords(w), meshes);
    EXPECT_EQ(calls.load(), int(w.chunk_count()));
    for (const auto& [c, mc] : meshes) {
        ChunkMesh expect;
        mesh_culled({*w.find_chunk(c), Apron::air(), w.registry()}, expect);
        EXPECT_TRUE(same_mesh(mc.mesh, expect));
    }
    // mesh_one on this thread gives the same as the pool.
    MeshMap one;
    mesher.mesh_one(w, chunk_coords(w).front(), one);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_TRUE(same_mesh(one.begin()->second.mesh, meshes[one.begin()->first].mesh));
}

TEST(SceneLoader, TerrainSceneMeshesTheRadiusWithGeneratedNeighbours) {
    JobSystem jobs(batch_job_system_info(2));
    SceneLoadInfo info;
    info.kind = SceneKind::Terrain;
    info.seed = 7;
    info.radius = 1;
    info.vradius = 1;
    info.eye = world_pos_at({0.5, 40.5, 0.5});
    auto scene = load_scene(jobs, info);
    ASSERT_TRUE(scene) << scene.error();
    // 3x3x3 meshed, a ring more generated (5x5x5) so every meshed apron is real.
    EXPECT_EQ(scene->meshes.size(), 27u);
    EXPECT_EQ(scene->world->chunk_count(), 125u);
    const TerrainGenerator gen(7);
    GreedyMesher serial;
    for (const auto& [c, mc] : scene->meshes) {
        EXPECT_EQ(scene->world->find_chunk(c)->get(LocalPos(3, 4, 5)), gen.generate(c).get(LocalPos(3, 4, 5)));
        ChunkMesh expect;
        serial.mesh({*scene->world->find_chunk(c), make_apron(*scene->world, c), scene->world->registry()}, expect);
        EXPECT_TRUE(same_mesh(mc.mesh, expect));
    }
    EXPECT_EQ(scene->triangles, 2 * scene->quads);
}

TEST(SceneLoader, BadInputIsAOneLineError) {
    JobSystem jobs(batch_job_system_info(1));
    SceneLoadInfo info;
    info.kind = SceneKind::SeedScene;
    info.seed_block = "unobtainium";
    auto r = load_scene(jobs, info);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("unobtainium"), std::string::npos);
    info.kind = SceneKind::StoredWorld;
    info.world_path = "/nonexistent/dir/w.db";
    r = load_scene(jobs, info);
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().find("/nonexistent/dir/w.db"), std::string::npos);
    info.kind = SceneKind::Terrain;
    info.radius = 65;
    EXPECT_FALSE(load_scene(jobs, info));
    // An eye within 2^17 blocks of the world's edge: its box of chunks would leave
    // the 32-bit chunk coordinates (they once overflowed there). Just inside loads as anywhere.
    const int64_t last = kWorldMaxBlock - kEdgeMarginBlocks; // The last block inside the margin.
    info.radius = 0;
    info.vradius = 0;
    for (int64_t x : {last + 1, kWorldMaxBlock, kWorldMinBlock}) {
        info.eye = WorldPos{BlockPos(x, 40, 0), glm::dvec3(0.5)};
        r = load_scene(jobs, info);
        ASSERT_FALSE(r) << x;
        EXPECT_NE(r.error().find("--eye must stay 2^17 blocks inside"), std::string::npos) << r.error();
    }
    info.eye = WorldPos{BlockPos(last, 40, 0), glm::dvec3(0.5)};
    r = load_scene(jobs, info);
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ(r->world->chunk_count(), 27u); // The eye's chunk and its ring of neighbours.
}

// Pregeneration saves every chunk of the box, exactly as generated, and counts what it made.
TEST(WorldPregen, SavesEveryChunkOfTheBoxAsGenerated) {
    const auto path = std::filesystem::temp_directory_path() / ("vx_pregen_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path);
    const TerrainGenerator gen(11);
    PregenStats made;
    {
        auto store = SqliteStore::open({path.string()});
        ASSERT_TRUE(store) << store.error();
        JobSystem jobs(batch_job_system_info(2));
        size_t last_done = 0, calls = 0;
        auto r = pregenerate(jobs, gen, **store,
                             {ChunkCoord(-1, -1, -1), ChunkCoord(1, 1, 0), [&](size_t done, size_t total) {
                                  EXPECT_EQ(total, 18u);
                                  EXPECT_GE(done, last_done);
                                  last_done = done;
                                  ++calls;
                              }});
        ASSERT_TRUE(r) << r.error();
        made = *r;
        EXPECT_GE(calls, 1u);
        EXPECT_EQ(last_done, 18u);
    }
    EXPECT_EQ(made.chunks, 18u); // 3 x 3 x 2.
    auto store = SqliteStore::open({path.string(), /*read_only=*/true, /*create=*/false});
    ASSERT_TRUE(store) << store.error();
    GreedyMesher mesher;
    uint64_t quads = 0, non_uniform = 0;
    for (int y = -1; y <= 1; ++y)
        for (int z = -1; z <= 0; ++z)
            for (int x = -1; x <= 1; ++x) {
                const ChunkCoord c(x, y, z);
                auto load = (*store)->load(c);
                ASSERT_TRUE(load && load->state == LoadState::Present) << x << "," << y << "," << z;
                const Chunk expect = gen.generate(c);
                for (int i = 0; i < kChunkSize; ++i) {
                    const LocalPos p(i, (i * 7) % kChunkSize, (i * 13) % kChunkSize);
                    EXPECT_EQ(load->chunk->get(p), expect.get(p));
                }
                ChunkMesh m;
                mesher.mesh({expect, Apron::air(), BlockRegistry::default_registry()}, m);
                quads += m.quad_count();
                non_uniform += !expect.is_uniform();
            }
    EXPECT_EQ(made.quads, quads);
    EXPECT_EQ(made.non_uniform, non_uniform);
    store->reset();
    std::filesystem::remove(path);
}

// With lod_levels, pregeneration also stores every coarse chunk over the box, each exactly what
// generate_lod makes (the terrain's direct coarse chunks), and counts them per level.
TEST(WorldPregen, StoresCoarseLevelsOverTheBox) {
    const auto path = std::filesystem::temp_directory_path() / ("vx_pregen_lod_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path);
    const TerrainGenerator gen(11);
    // Box x -2..1, y -1..0, z 0..2 (floored shifts): level 1 is x -1..0, y -1..0, z 0..1 (8
    // chunks); level 2 is x -1..0, y -1..0, z 0..0 (4).
    const ChunkCoord lo(-2, -1, 0), hi(1, 0, 2);
    PregenStats made;
    {
        auto store = SqliteStore::open({path.string()});
        ASSERT_TRUE(store) << store.error();
        JobSystem jobs(batch_job_system_info(2));
        size_t last_done = 0, last_total = 0;
        PregenInfo info{lo, hi, [&](size_t done, size_t total) {
                            last_done = done;
                            last_total = total;
                        }};
        info.lod_levels = 2;
        auto r = pregenerate(jobs, gen, **store, info);
        ASSERT_TRUE(r) << r.error();
        made = *r;
        EXPECT_EQ(last_total, 24u + 8u + 4u);
        EXPECT_EQ(last_done, last_total);
    }
    EXPECT_EQ(made.chunks, 24u); // 4 x 2 x 3.
    ASSERT_EQ(made.lod_chunks.size(), 2u);
    EXPECT_EQ(made.lod_chunks[0], 8u);
    EXPECT_EQ(made.lod_chunks[1], 4u);
    auto store = SqliteStore::open({path.string(), /*read_only=*/true, /*create=*/false});
    ASSERT_TRUE(store) << store.error();
    size_t found = 0;
    for (int k = 1; k <= 2; ++k) {
        const ChunkCoord l = lo >> k, h = hi >> k;
        for (int y = l.y; y <= h.y; ++y)
            for (int z = l.z; z <= h.z; ++z)
                for (int x = l.x; x <= h.x; ++x) {
                    const LodCoord c{k, ChunkCoord(x, y, z)};
                    auto load = (*store)->load_lod(c);
                    ASSERT_TRUE(load && load->state == LoadState::Present) << k << ": " << x << "," << y << "," << z;
                    auto expect = generate_lod(gen, c);
                    ASSERT_TRUE(expect);
                    EXPECT_TRUE(*load->chunk == *expect);
                    ++found;
                }
    }
    EXPECT_EQ(found, 12u);
    auto listed = (*store)->list_lod_coords();
    ASSERT_TRUE(listed);
    EXPECT_EQ(listed->size(), 12u); // Nothing outside the box's coarse chunks.
    EXPECT_TRUE((*store)->list_lod_dirty()->empty());
    store->reset();
    std::filesystem::remove(path);
}

// Over a world that has chunks (a player's edits, an earlier run), pregeneration keeps them, and
// keeps the coarse chunks the store has or marks stale (derived from those edits on load): it
// saved terrain over them all. A damaged coarse record is derived from the blocks below and saved
// (its check moved it aside, and it was then counted as kept: missing, it read as terrain).
TEST(WorldPregen, KeepsWhatTheStoreHas) {
    const auto path = std::filesystem::temp_directory_path() / ("vx_pregen_keep_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path);
    const TerrainGenerator gen(11);
    const ChunkCoord lo(-2, -1, 0), hi(1, 0, 2); // Levels 1 and 2 as in StoresCoarseLevelsOverTheBox.
    const ChunkCoord edited(0, 0, 1);
    const LodCoord stored{1, ChunkCoord(0, 0, 0)}, stale{2, ChunkCoord(-1, -1, 0)}, damaged{1, ChunkCoord(-1, 0, 1)};
    PregenStats made;
    {
        auto store = SqliteStore::open({path.string()});
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->save(edited, Chunk(5)));
        ASSERT_TRUE((*store)->save_lod(stored, Chunk(6)));
        const uint8_t junk[4] = {0xDE, 0xAD, 0xBE, 0xEF};
        const Chunk unused; // The record is written as given.
        const LodWrite bad{damaged, &unused, junk};
        ASSERT_TRUE((*store)->save_lod(std::span<const LodWrite>(&bad, 1)));
        ASSERT_TRUE((*store)->mark_lod_dirty(std::span<const LodCoord>(&stale, 1)));
        ASSERT_TRUE((*store)->flush());
        JobSystem jobs(batch_job_system_info(2));
        PregenInfo info{lo, hi, {}};
        info.lod_levels = 2;
        auto r = pregenerate(jobs, gen, **store, info);
        ASSERT_TRUE(r) << r.error();
        made = *r;
    }
    EXPECT_EQ(made.chunks, 23u);
    EXPECT_EQ(made.kept, 1u);
    ASSERT_EQ(made.lod_chunks.size(), 2u);
    EXPECT_EQ(made.lod_chunks[0], 6u);
    EXPECT_EQ(made.lod_chunks[1], 3u);
    EXPECT_EQ(made.lod_kept, 3u);
    auto store = SqliteStore::open({path.string(), /*read_only=*/true, /*create=*/false});
    ASSERT_TRUE(store) << store.error();
    auto chunk = (*store)->load(edited);
    ASSERT_TRUE(chunk && chunk->state == LoadState::Present);
    EXPECT_TRUE(*chunk->chunk == Chunk(5));
    auto coarse = (*store)->load_lod(stored);
    ASSERT_TRUE(coarse && coarse->state == LoadState::Present);
    EXPECT_TRUE(*coarse->chunk == Chunk(6));
    auto derived = (*store)->load_lod(damaged);
    ASSERT_TRUE(derived);
    ASSERT_EQ(derived->state, LoadState::Present);
    std::array<Chunk, kLodChildren> kids;
    std::array<const Chunk*, kLodChildren> ptrs;
    for (int i = 0; i < kLodChildren; ++i) { // Stored (the box's), else the terrain's (outside it).
        const ChunkCoord kc = lod_child(damaged, i).chunk;
        auto kid = (*store)->load(kc);
        ASSERT_TRUE(kid);
        kids[size_t(i)] = kid->state == LoadState::Present ? std::move(*kid->chunk) : gen.generate(kc);
        ptrs[size_t(i)] = &kids[size_t(i)];
    }
    EXPECT_TRUE(*derived->chunk == downsample(ptrs)) << "derived from the blocks below";
    auto marked = (*store)->load_lod(stale);
    ASSERT_TRUE(marked);
    EXPECT_EQ(marked->state, LoadState::Absent);
    auto dirty = (*store)->list_lod_dirty();
    ASSERT_TRUE(dirty);
    EXPECT_EQ(*dirty, std::vector<LodCoord>{stale});
    store->reset();
    std::filesystem::remove(path);
}

namespace {

// A SQLite store seen through the ChunkStore defaults for coarse levels (a game's store that
// keeps none), or one whose coarse saves fail (injected).
using vx::Error;
using vx::Result;
using vx::Status;

class LevelZeroStore final : public ChunkStore {
public:
    LevelZeroStore(std::unique_ptr<ChunkStore> inner, bool failing_lod)
        : m_inner(std::move(inner)), m_failing_lod(failing_lod) {}
    Result<ChunkLoad> load(ChunkCoord c) override { return m_inner->load(c); }
    Status save(std::span<const ChunkWrite> batch) override { return m_inner->save(batch); }
    Status tick(Clock::time_point now) override { return m_inner->tick(now); }
    Status flush() override { return m_inner->flush(); }
    Result<bool> contains(ChunkCoord c) override { return m_inner->contains(c); }
    Result<uint64_t> count() override { return m_inner->count(); }
    Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override { return m_inner->for_each_coord(fn); }
    Result<std::optional<std::string>> get_meta(std::string_view key) override { return m_inner->get_meta(key); }
    Status set_meta(std::string_view key, std::string_view value) override { return m_inner->set_meta(key, value); }
    bool read_only() const override { return false; }
    using ChunkStore::save_lod;
    bool supports_lod() const override { return m_failing_lod; }
    Status save_lod(std::span<const LodWrite> batch) override {
        return m_failing_lod ? Status(Error{"the disk is full (injected)"}) : ChunkStore::save_lod(batch);
    }

private:
    std::unique_ptr<ChunkStore> m_inner;
    bool m_failing_lod;
};

} // namespace

// A store without coarse levels is refused before anything is generated; a coarse save that fails
// fails the pregeneration with the store's message (level 0 was saved by then).
TEST(WorldPregen, CoarseLevelsNeedAStoreThatKeepsThem) {
    const auto path =
        std::filesystem::temp_directory_path() / ("vx_pregen_nolod_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path);
    const TerrainGenerator gen(3);
    JobSystem jobs(batch_job_system_info(2));
    PregenInfo info{ChunkCoord(0), ChunkCoord(1, 0, 0), {}};
    info.lod_levels = 1;
    for (bool failing : {false, true}) {
        auto sqlite = SqliteStore::open({path.string()});
        ASSERT_TRUE(sqlite) << sqlite.error();
        LevelZeroStore store(std::move(*sqlite), failing);
        EXPECT_EQ(store.load_lod({1, {0, 0, 0}})->state, LoadState::Absent);
        auto r = pregenerate(jobs, gen, store, info);
        ASSERT_FALSE(r);
        const char* want = failing ? "the disk is full (injected)" : "keeps no coarse levels";
        EXPECT_NE(r.error().find(want), std::string::npos) << r.error();
        EXPECT_EQ(*store.count(), failing ? 2u : 0u);
    }
    std::filesystem::remove(path);
}

// A box pregenerate() cannot make is an error before any chunk: lo above hi, the world's
// outermost layer (an int loop to INT32_MAX never ended), more than kMaxPregenChunks (a box of
// 2^32 layers once queued until memory ran out). Nothing reaches the store.
TEST(WorldPregen, BoxesItCannotMakeAreErrors) {
    const auto path = std::filesystem::temp_directory_path() / ("vx_pregen_box_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path);
    auto store = SqliteStore::open({path.string()});
    ASSERT_TRUE(store) << store.error();
    const TerrainGenerator gen(3);
    JobSystem jobs(batch_job_system_info(2));
    const int max = INT32_MAX, min = INT32_MIN;
    struct Case {
        ChunkCoord lo, hi;
        const char* want;
    };
    const Case cases[] = {
        {{0, 1, 0}, {0, 0, 0}, "lo is above hi"},
        {{0, max, 0}, {0, max, 0}, "outermost chunk layer"},
        {{min, 0, 0}, {min, 0, 0}, "outermost chunk layer"},
        {{0, min + 1, 0}, {0, max - 1, 0}, "more than 67108864 chunks"},
        {{-5000, 0, -5000}, {5000, 0, 5000}, "more than 67108864 chunks"},
    };
    for (const Case& c : cases) {
        auto r = pregenerate(jobs, gen, **store, {c.lo, c.hi, {}});
        ASSERT_FALSE(r) << c.want;
        EXPECT_NE(r.error().find(c.want), std::string::npos) << r.error();
    }
    EXPECT_EQ(*(*store)->count(), 0u);
    // One layer in from the edge is a box like any other.
    auto edge = pregenerate(jobs, gen, **store, {{0, max - 1, 0}, {0, max - 1, 0}, {}});
    ASSERT_TRUE(edge) << edge.error();
    EXPECT_EQ(edge->chunks, 1u);
    std::filesystem::remove(path);
}
