#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "test_util.h"
#include "world/gen/terrain.h"
#include "world/mesh/edit_mesher.h"
#include "world/mesh/reference_meshers.h"
#include "world/world.h"

using namespace vx::world;
using namespace vx::world::test;

namespace {

glm::ivec3 icross(glm::ivec3 a, glm::ivec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct Case {
    double fill;
    int types;
    int transparent;
};

} // namespace

TEST(GreedyMesher, RandomChunksMatchOracleAndClassicGreedy) {
    std::mt19937 rng(42);
    GreedyMesher mesher;
    const Case cases[] = {{0.02, 1, 0}, {0.1, 1, 0}, {0.1, 3, 0}, {0.3, 2, 1}, {0.5, 3, 0},
                          {0.5, 5, 2},  {0.8, 1, 0}, {0.9, 40, 0}, {0.97, 2, 1}, {0.6, 300, 20}};
    for (const Case& c : cases) {
        const BlockRegistry reg = make_registry(c.types - c.transparent, c.transparent);
        for (int rep = 0; rep < 6; ++rep) {
            const Chunk chunk = random_chunk(rng, c.fill, c.types);
            const Apron apron = rep % 3 == 0 ? Apron::air() : random_apron(rng, rep % 3 == 1 ? 0.5 : 1.0, c.types, reg);
            const MesherInput in{chunk, apron, reg};
            ChunkMesh greedy, classic, culled;
            mesher.mesh(in, greedy);
            mesh_classic_greedy(in, classic);
            mesh_culled(in, culled);
            ASSERT_TRUE(covers_exactly(in, greedy)) << "fill " << c.fill << " types " << c.types;
            ASSERT_TRUE(covers_exactly(in, culled));
            ASSERT_TRUE(greedy == classic) << "fill " << c.fill << " types " << c.types << ": "
                                           << greedy.quad_count() << " vs classic " << classic.quad_count();
            int area = 0;
            greedy.for_each_quad([&](const Quad& q) { area += q.area(); });
            EXPECT_EQ(uint32_t(area), culled.quad_count());
        }
    }
}

namespace {

Chunk chunk_from(auto&& fn) {
    std::vector<BlockId> ids(kChunkVolume);
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < kChunkSize; ++y)
            for (int x = 0; x < kChunkSize; ++x)
                ids[local_index(x, y, z)] = fn(x, y, z);
    return Chunk::from_dense(ids);
}

ChunkMesh greedy_of(const Chunk& c, const Apron& a, const BlockRegistry& r) {
    GreedyMesher m;
    ChunkMesh mesh;
    m.mesh({c, a, r}, mesh);
    EXPECT_TRUE(covers_exactly({c, a, r}, mesh));
    return mesh;
}

} // namespace

TEST(GreedyMesher, HandMadeCases) {
    const BlockRegistry reg = make_registry(3, 1);
    const Apron air = Apron::air();
    // Empty: nothing.
    EXPECT_EQ(greedy_of(Chunk(), air, reg).quad_count(), 0u);
    // Full, isolated: one 32×32 quad per side (12 triangles, as the thesis says).
    EXPECT_EQ(greedy_of(Chunk(1), air, reg).quad_count(), 6u);
    // Full, embedded in opaque neighbours: nothing visible.
    EXPECT_EQ(greedy_of(Chunk(1), Apron::filled(2, reg), reg).quad_count(), 0u);
    // Full, embedded in its own transparent type (water in water): nothing; in another: 6.
    EXPECT_EQ(greedy_of(Chunk(4), Apron::filled(4, reg), reg).quad_count(), 0u);
    // 3D checkerboard: no face can merge; 16384 blocks × 6 faces.
    const Chunk checker = chunk_from([](int x, int y, int z) { return BlockId((x + y + z) & 1); });
    EXPECT_EQ(greedy_of(checker, air, reg).quad_count(), 16384u * 6);
    // Single block in a corner and in the middle.
    EXPECT_EQ(greedy_of(chunk_from([](int x, int y, int z) { return BlockId(x + y + z == 0); }), air, reg).quad_count(), 6u);
    EXPECT_EQ(greedy_of(chunk_from([](int x, int y, int z) { return BlockId(x == 9 && y == 17 && z == 4); }), air, reg).quad_count(), 6u);
    // Blocks on every border and corner (a hollow shell): 6 outer + 6 inner sides.
    const Chunk shell = chunk_from([](int x, int y, int z) {
        auto b = [](int c) { return c == 0 || c == 31; };
        return BlockId(b(x) || b(y) || b(z));
    });
    EXPECT_EQ(greedy_of(shell, air, reg).quad_count(), 12u);
    // Long thin runs: a 32-long rod along each axis through the middle.
    const Chunk rods = chunk_from([](int x, int y, int z) {
        return BlockId((y == 5 && z == 5) || (x == 20 && z == 20) || (x == 9 && y == 27));
    });
    greedy_of(rods, air, reg);
    // Two types side by side never merge: a half-and-half chunk has 6 + 6 sides plus none between.
    const Chunk halves = chunk_from([](int x, int, int) { return BlockId(x < 16 ? 1 : 2); });
    EXPECT_EQ(greedy_of(halves, air, reg).quad_count(), 10u);
    // Stripes of alternating types along x: every x column is its own quad on ±Y and ±Z.
    const Chunk stripes = chunk_from([](int x, int, int) { return BlockId(1 + (x & 1)); });
    EXPECT_EQ(greedy_of(stripes, air, reg).quad_count(), 2u + 4u * 32u);
}

// Rows that repeat the one before (most rows of terrain: air above the ground, stone under it)
// are copied, not unpacked: every palette width of 1 to 8 bits, with one or more transparent
// entries, against air and solid aprons, must still give the classic greedy quads.
TEST(GreedyMesher, RepeatedRowsMatchClassicGreedyAtEveryPaletteWidth) {
    std::mt19937 rng(7);
    GreedyMesher mesher;
    // `types` ids (the last `transparent` of them transparent) plus air: a palette of `bits`.
    struct Width {
        int types, transparent;
        uint32_t bits;
    };
    const Width widths[] = {{1, 0, 1},  {2, 1, 2},  {4, 1, 3},   {7, 2, 3},   {15, 1, 4},
                            {31, 3, 5}, {63, 1, 6}, {127, 2, 7}, {255, 5, 8}};
    for (const Width& w : widths) {
        const BlockRegistry reg = make_registry(w.types - w.transparent, w.transparent);
        for (int rep = 0; rep < 3; ++rep) {
            std::vector<BlockId> ids(kChunkVolume);
            for (int r = 0; r < kChunkSize * kChunkSize; ++r) { // Row r = z * 32 + y, along x.
                BlockId* row = ids.data() + r * kChunkSize;
                if (r > 0 && rng() % 4 != 0) { // Three rows in four repeat the previous one.
                    std::copy_n(row - kChunkSize, kChunkSize, row);
                    continue;
                }
                for (int x = 0; x < kChunkSize; ++x)
                    row[x] = rng() % 3 == 0 ? kAir : BlockId(1 + rng() % w.types);
            }
            for (int t = 0; t <= w.types; ++t) // Every id at least once: the palette's full width.
                ids[size_t(t) * 97] = BlockId(t);
            const Chunk chunk = Chunk::from_dense(ids);
            ASSERT_EQ(chunk.palette()->indices.bits(), w.bits);
            const Apron apron =
                rep == 0 ? Apron::air() : random_apron(rng, rep == 1 ? 0.5 : 1.0, w.types, reg);
            const MesherInput in{chunk, apron, reg};
            ChunkMesh greedy, classic;
            mesher.mesh(in, greedy);
            mesh_classic_greedy(in, classic);
            ASSERT_TRUE(covers_exactly(in, greedy)) << w.bits << " bits, apron " << rep;
            ASSERT_TRUE(greedy == classic) << w.bits << " bits, apron " << rep << ": " << greedy.quad_count()
                                           << " vs classic " << classic.quad_count();
        }
    }
}

// copy_face unpacks whole rows and looks palette entries up once; the expected face is read block
// by block with Chunk::get and classified with refresh_face. Widths 1..8 bits take the fast path,
// 9 bits (300 types) the block-by-block one; a third of the blocks are air, and a transparent
// type makes any_transparent true wherever one lands on the face.
TEST(Apron, CopyFaceMatchesBlockByBlockAtEveryPaletteWidth) {
    std::mt19937 rng(11);
    for (const int types : {1, 2, 5, 12, 30, 60, 120, 250, 300}) {
        const BlockRegistry reg = make_registry(types - 1, 1); // The last type is transparent.
        for (int rep = 0; rep < 2; ++rep) {
            std::vector<BlockId> ids(kChunkVolume);
            for (BlockId& b : ids) // rep 1: transparent blocks are rare (often none on a face).
                b = rng() % 3 == 0 ? kAir : BlockId(1 + rng() % (rep == 0 ? types : std::max(1, types - 1)));
            if (rep == 1)
                ids[size_t(local_index(31, 5, 7))] = BlockId(types); // On the -x face's neighbour layer only.
            for (int t = 0; t <= types; ++t)
                ids[size_t(t) * 97 % kChunkVolume] = BlockId(t);
            const Chunk chunk = Chunk::from_dense(ids);
            ASSERT_FALSE(chunk.is_uniform());
            for (int f = 0; f < 6; ++f) {
                Apron got, want;
                got.copy_face(Face(f), &chunk, reg);
                const int axis = face_axis(Face(f)), layer = face_positive(Face(f)) ? 0 : kChunkSize - 1;
                for (int v = 0; v < kChunkSize; ++v)
                    for (int u = 0; u < kChunkSize; ++u)
                        want.ids[f][u + kChunkSize * v] = chunk.get(plane_to_local(axis, layer, u, v));
                want.refresh_face(Face(f), reg);
                ASSERT_EQ(got.ids[f], want.ids[f]) << types << " types, face " << f;
                ASSERT_EQ(got.opaque[f], want.opaque[f]) << types << " types, face " << f;
                ASSERT_EQ(got.any_transparent[f], want.any_transparent[f]) << types << " types, face " << f;
                // Taken here, expanded later (a mesh job): the same face.
                ApronLayer taken;
                taken.take(Face(f), &chunk);
                Apron later;
                later.set_face(Face(f), taken, reg);
                ASSERT_EQ(later.ids[f], want.ids[f]) << types << " types, face " << f;
                ASSERT_EQ(later.opaque[f], want.opaque[f]) << types << " types, face " << f;
                ASSERT_EQ(later.any_transparent[f], want.any_transparent[f]) << types << " types, face " << f;
            }
        }
    }
    // Uniform and absent neighbours through a layer: filled faces (an earlier take leaves nothing).
    const BlockRegistry reg = make_registry(1, 1);
    const Chunk stone(BlockId(1)), glass(BlockId(2));
    ApronLayer layer;
    layer.take(Face(0), &stone);
    Apron a = Apron::filled(2, reg), want = Apron::filled(1, reg);
    a.set_face(Face(0), layer, reg);
    EXPECT_EQ(a.ids[0], want.ids[0]);
    EXPECT_EQ(a.opaque[0], want.opaque[0]);
    EXPECT_EQ(a.any_transparent[0], 0);
    layer.take(Face(0), &glass);
    a.set_face(Face(0), layer, reg);
    EXPECT_EQ(a.any_transparent[0], 1);
    EXPECT_EQ(a.opaque[0][5], 0u);
    layer.take(Face(0), nullptr);
    a.set_face(Face(0), layer, reg);
    EXPECT_EQ(a.ids[0], Apron::air().ids[0]);
    EXPECT_EQ(a.any_transparent[0], 0);
}

// Terrain inside a generated world (the mesher benchmark's "terrain inside a world"): 2- and
// 3-bit palettes, water, aprons from the neighbours.
TEST(GreedyMesher, TerrainInsideAWorldMatchesClassicGreedy) {
    World world;
    const TerrainGenerator gen(12345);
    for (int x = -1; x < 3; ++x)
        for (int z = 1; z < 5; ++z)
            for (int y = -1; y < 2; ++y)
                world.put_chunk({x, y, z}, gen.generate({x, y, z}));
    GreedyMesher mesher;
    int with_water = 0;
    const BlockId water = world.registry().find("water").value_or(kAir);
    for (int x = 0; x < 2; ++x)
        for (int z = 2; z < 4; ++z) {
            const ChunkCoord c(x, 0, z);
            const Chunk& chunk = *world.find_chunk(c);
            ASSERT_FALSE(chunk.is_uniform());
            const auto& pal = chunk.palette()->ids;
            with_water += std::find(pal.begin(), pal.end(), water) != pal.end();
            const Apron apron = make_apron(world, c);
            const MesherInput in{chunk, apron, world.registry()};
            ChunkMesh greedy, classic;
            mesher.mesh(in, greedy);
            mesh_classic_greedy(in, classic);
            ASSERT_TRUE(covers_exactly(in, greedy));
            ASSERT_TRUE(greedy == classic) << greedy.quad_count() << " vs classic " << classic.quad_count();
        }
    EXPECT_GT(with_water, 0); // The sea level crosses these chunks (seed 12345).
}

namespace {

// The same quads in the same order in every slice (what a renderer's mesh hash sees).
bool same_order(const ChunkMesh& a, const ChunkMesh& b) {
    for (int s = 0; s < kSliceCount; ++s) {
        auto sa = a.slice(s), sb = b.slice(s);
        if (!std::equal(sa.begin(), sa.end(), sb.begin(), sb.end()))
            return false;
    }
    return true;
}

} // namespace

// remesh_block with the old id merges only the plane sides whose face at the edited block
// changed, and swaps lone 1 x 1 quads in place; after every edit the mesh must equal a full mesh
// of the new state, quad for quad in the same order (so an edit and its undo restore it exactly),
// on one-id chunks (1-bit palettes), noise, transparent blocks, wide palettes and solid aprons.
TEST(GreedyMesher, RemeshBlockWithOldIdEqualsFullMesh) {
    std::mt19937 rng(11);
    const Case cases[] = {{0.5, 1, 0}, {0.5, 3, 0}, {0.5, 5, 2}, {0.9, 2, 1}, {0.6, 300, 20}};
    GreedyMesher mesher, full;
    for (const Case& c : cases) {
        const BlockRegistry reg = make_registry(c.types - c.transparent, c.transparent);
        for (int rep = 0; rep < 3; ++rep) {
            Chunk chunk = rep == 0 && c.types == 1
                              ? chunk_from([](int x, int y, int z) { return BlockId((x + y + z) & 1); })
                              : random_chunk(rng, c.fill, c.types);
            const Apron apron = rep == 0 ? Apron::air() : random_apron(rng, rep == 1 ? 0.5 : 1.0, c.types, reg);
            ChunkMesh mesh, expect;
            mesher.mesh({chunk, apron, reg}, mesh);
            for (int i = 0; i < 300; ++i) {
                // Borders often, so apron faces are read too.
                auto coord = [&] { return rng() % 4 == 0 ? (rng() % 2 ? 31 : 0) : int(rng() % 32); };
                const LocalPos p(coord(), coord(), coord());
                const BlockId id = rng() % 3 == 0 ? kAir : BlockId(1 + rng() % c.types);
                const BlockId old = chunk.set(p, id);
                mesher.remesh_block({chunk, apron, reg}, p, old, mesh);
                full.mesh({chunk, apron, reg}, expect);
                ASSERT_TRUE(same_order(mesh, expect)) << "types " << c.types << " edit " << i;
                if (i % 50 == 0) {
                    mesh_classic_greedy({chunk, apron, reg}, expect);
                    ASSERT_TRUE(mesh == expect);
                }
            }
        }
    }
}

// replace_slice_range keeps the quads before `first` and after `last` in order, whether the
// range shrinks, grows within the slice's spare room or past it (the storage is laid out again),
// and leaves the other slices alone.
TEST(ChunkMesh, ReplaceSliceRangeKeepsTheRestInOrder) {
    auto q = [](int u, BlockId id) { return Quad::make(2, 5, false, u, 0, 1, 1, id); };
    auto ids_of = [](std::span<const Quad> s) {
        std::vector<int> out;
        for (const Quad& x : s)
            out.push_back(x.u0() * 100 + x.block);
        return out;
    };
    ChunkMesh mesh;
    mesh.begin(0);
    for (int s = 0; s < kSliceCount; ++s) {
        mesh.begin_slice(s);
        for (int i = 0; i < (s % 3) + 2; ++i)
            mesh.push(q(i, BlockId(s % 7 + 1)));
    }
    mesh.end();
    const ChunkMesh before = mesh;
    const int s = slice_index(2, 5); // 71: 4 quads, ids 2.
    const Quad two[] = {q(10, 9), q(11, 9)};
    mesh.replace_slice_range(s, 1, 3, {two, 1}); // Shrinks: 0, 10, 3.
    EXPECT_EQ(ids_of(mesh.slice(s)), (std::vector<int>{2, 1009, 302}));
    mesh.replace_slice_range(s, 0, 1, two); // Grows past the exact-size capacity: 10, 11, 10, 3.
    EXPECT_EQ(ids_of(mesh.slice(s)), (std::vector<int>{1009, 1109, 1009, 302}));
    mesh.replace_slice_range(s, 3, 4, two); // Grows at the end, within the new headroom.
    EXPECT_EQ(ids_of(mesh.slice(s)), (std::vector<int>{1009, 1109, 1009, 1009, 1109}));
    mesh.replace_slice_range(s, 1, 2, {}); // Removes one in the middle.
    EXPECT_EQ(ids_of(mesh.slice(s)), (std::vector<int>{1009, 1009, 1009, 1109}));
    EXPECT_EQ(mesh.quad_count(), before.quad_count());
    for (int t = 0; t < kSliceCount; ++t) {
        if (t != s) {
            EXPECT_EQ(ids_of(mesh.slice(t)), ids_of(before.slice(t))) << "slice " << t;
        }
    }
}

// block_ids: each block of the quads once, in the order first met, over the slices' quads only
// (a slice shrunk in place leaves stale quads in its spare room, which are not counted).
TEST(ChunkMesh, BlockIdsListEachBlockOfTheQuadsOnce) {
    auto q = [](int plane, int u, BlockId id) { return Quad::make(0, plane, false, u, 0, 1, 1, id); };
    ChunkMesh mesh;
    mesh.begin(0);
    for (int s = 0; s < kSliceCount; ++s) {
        mesh.begin_slice(s);
        if (s == 3)
            for (const Quad& x : {q(3, 0, 7), q(3, 1, 7), q(3, 2, 2), q(3, 3, 9)})
                mesh.push(x);
        if (s == 5)
            for (const Quad& x : {q(5, 0, 2), q(5, 1, 7), q(5, 2, 4)})
                mesh.push(x);
    }
    mesh.end();
    EXPECT_TRUE(ChunkMesh().block_ids().empty());
    EXPECT_EQ(mesh.block_ids(), (std::vector<BlockId>{7, 2, 9, 4}));
    mesh.replace_slice(3, std::vector<Quad>{q(3, 0, 2)}); // 9 is gone, but for the spare room.
    EXPECT_EQ(mesh.block_ids(), (std::vector<BlockId>{2, 7, 4}));
}

TEST(SimpleMeshers, NaiveEmitsEveryFaceCulledOnlyVisible) {
    const BlockRegistry reg = make_registry(1, 0);
    const Apron air = Apron::air();
    ChunkMesh naive, culled;
    mesh_naive({Chunk(1), air, reg}, naive);
    mesh_culled({Chunk(1), air, reg}, culled);
    EXPECT_EQ(naive.triangle_count(), 393216u); // 32768 blocks × 12 (thesis 3.1).
    EXPECT_EQ(culled.triangle_count(), 12288u); // 6 × 32 × 32 × 2 (thesis 3.2).
    glm::ivec3 c[4];
    for (const Quad& q : culled.slice(1, 32)) { // +Y faces at the top plane.
        quad_corners(q, c);
        const glm::ivec3 n = icross(c[1] - c[0], c[3] - c[0]);
        EXPECT_EQ(n, glm::ivec3(0, 1, 0));
    }
}

TEST(QuadCorners, CounterClockwiseFromTheAirSide) {
    for (int axis = 0; axis < 3; ++axis)
        for (int pos = 0; pos < 2; ++pos) {
            glm::ivec3 c[4];
            quad_corners(Quad::make(axis, 3, pos == 1, 1, 2, 4, 5, 1), c);
            const glm::ivec3 n = icross(c[1] - c[0], c[3] - c[0]);
            EXPECT_EQ(n, face_normal(make_face(axis, pos == 1)) * 20) << axis << pos;
            for (auto& p : c)
                EXPECT_EQ(p[axis], 3);
        }
}

// Thousands of random edits, inside chunks and on borders, in a 3×3×3 world: after every edit
// the incrementally updated meshes equal full remeshes of every affected chunk.
// 4000 random edits (two in three on a chunk border) through the six-slice path: every mesh an
// edit reports equals a fresh full mesh, slices not reported are unchanged, and at the end every
// chunk equals a fresh mesh. `isolated`: chunks meshed alone, air beyond (the seed scene).
void incremental_equals_full(bool isolated) {
    std::mt19937 rng(7);
    World world(make_registry(4, 2));
    for (int i = 0; i < 20000; ++i) {
        const BlockPos p(rng() % 96, rng() % 96, rng() % 96);
        world.set_block(p - BlockPos(32), BlockId(1 + rng() % 6));
    }
    EditMesher em(isolated);
    MeshMap meshes;
    for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
            for (int x = -1; x <= 1; ++x)
                em.mesh_chunk(world, ChunkCoord(x, y, z), meshes);
    GreedyMesher full;
    auto pick = [&](bool border) -> int64_t {
        const int64_t base = int64_t(rng() % 3) * 32 - 32;
        if (!border)
            return base + int64_t(rng() % 32);
        return base + (rng() % 2 ? 31 : 0);
    };
    for (int i = 0; i < 4000; ++i) {
        const bool border = (i % 3) != 0;
        const BlockPos p(pick(border && rng() % 2), pick(border && rng() % 2), pick(border));
        const BlockId id = (rng() % 3 == 0) ? kAir : BlockId(1 + rng() % 6);
        const ChunkCoord edited = chunk_of(p);
        const auto before_it = meshes.find(edited);
        const bool had_mesh = before_it != meshes.end();
        ChunkMesh before;
        if (had_mesh)
            before = before_it->second.mesh;
        const EditResult r = em.apply(world, p, id, meshes);
        if (had_mesh) { // Slices the edit does not report are exactly as they were.
            std::array<bool, kSliceCount> listed{};
            for (const SliceUpdate& u : r.updates)
                for (int k = 0; u.chunk == edited && k < u.count; ++k)
                    listed[size_t(u.slices[size_t(k)])] = true;
            for (int s = 0; s < kSliceCount; ++s)
                if (!listed[size_t(s)]) {
                    const std::span<const Quad> a = before.slice(s), b = meshes.at(edited).mesh.slice(s);
                    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "edit " << i << " slice " << s;
                }
        }
        for (const SliceUpdate& u : r.updates) {
            const ChunkCoord c = u.chunk;
            const Apron fresh = isolated ? Apron::air() : make_apron(world, c);
            ChunkMesh expect;
            const Chunk* chunk = world.find_chunk(c);
            const Chunk empty;
            full.mesh({chunk ? *chunk : empty, fresh, world.registry()}, expect);
            ASSERT_TRUE(meshes.at(c).mesh == expect) << "edit " << i << " chunk " << c.x << "," << c.y << "," << c.z;
        }
    }
    // Finally every chunk, not just the touched ones.
    for (auto& [c, mc] : meshes) {
        ChunkMesh expect;
        const Chunk* chunk = world.find_chunk(c);
        const Chunk empty;
        full.mesh({chunk ? *chunk : empty, isolated ? Apron::air() : make_apron(world, c), world.registry()}, expect);
        ASSERT_TRUE(mc.mesh == expect) << c.x << "," << c.y << "," << c.z;
    }
}

TEST(EditMesher, IncrementalEqualsFullRemesh) { incremental_equals_full(false); }

// Edits of chunks meshed alone read air beyond the chunk, as the meshes were made: a border edit
// read the real neighbour, found the old face hidden and kept the quad of the block it removed
// (`vx mesh --scene seed --edits`).
TEST(EditMesher, IsolatedChunksStayIsolated) { incremental_equals_full(true); }

// Chunks on the world's edge (chunk coordinates INT32_MIN and INT32_MAX) have no neighbour
// beyond it: their aprons read air there, and an edit on the edge remeshes nothing outside (the
// neighbour's coordinate would overflow). The meshes equal those of the same blocks near the
// origin with nothing loaded beyond, through full meshing and 2000 border edits.
TEST(EditMesher, TheWorldsEdgeMeshesAsAirBeyond) {
    for (const int corner : {INT32_MIN, INT32_MAX}) {
        const int inward = corner == INT32_MIN ? 1 : -1;
        // Block offset of the corner chunk from its twin at (0,0,0) (the twin's neighbours beyond
        // the edge side are simply never loaded).
        const BlockPos shift = chunk_origin(ChunkCoord(corner));
        std::mt19937 rng(23);
        World edge(make_registry(4, 2)), twin(make_registry(4, 2));
        auto both_set = [&](BlockPos p, BlockId id) { // p relative to the twin's chunk (0,0,0).
            edge.set_block(p + shift, id);
            twin.set_block(p, id);
        };
        auto pick = [&](bool border) -> int64_t { // Two chunks per axis, from the edge inwards.
            const int64_t base = inward > 0 ? int64_t(rng() % 2) * 32 : -int64_t(rng() % 2) * 32;
            return base + (border ? (rng() % 2 ? 31 : 0) : int64_t(rng() % 32));
        };
        for (int i = 0; i < 6000; ++i)
            both_set(BlockPos(pick(false), pick(false), pick(false)), BlockId(1 + rng() % 6));
        std::vector<ChunkCoord> twin_chunks; // The 2 x 2 x 2 chunks, the twin's coordinates.
        for (int i = 0; i < 8; ++i)
            twin_chunks.push_back(ChunkCoord(i & 1, i >> 1 & 1, i >> 2) * inward);
        // Solid chunks where a neighbour coordinate that wrapped round would land: read as an
        // apron, they would hide the edge's faces.
        for (const ChunkCoord d : twin_chunks)
            for (int f = 0; f < 6; ++f) {
                const ChunkCoord c = ChunkCoord(corner) + d;
                if (has_neighbour(c, Face(f)))
                    continue;
                ChunkCoord wrapped = c;
                wrapped[face_axis(Face(f))] = face_positive(Face(f)) ? INT32_MIN : INT32_MAX;
                edge.put_chunk(wrapped, Chunk(BlockId(1)));
            }
        EditMesher em_edge, em_twin;
        MeshMap m_edge, m_twin;
        for (const ChunkCoord d : twin_chunks) {
            em_edge.mesh_chunk(edge, ChunkCoord(corner) + d, m_edge);
            em_twin.mesh_chunk(twin, d, m_twin);
        }
        auto expect_same = [&](int edit) {
            ASSERT_EQ(m_edge.size(), m_twin.size()) << "corner " << corner << " edit " << edit;
            for (const auto& [c, mc] : m_twin) {
                const auto it = m_edge.find(ChunkCoord(corner) + c);
                ASSERT_NE(it, m_edge.end());
                ASSERT_TRUE(it->second.mesh == mc.mesh) << "corner " << corner << " edit " << edit;
            }
        };
        expect_same(-1);
        for (int i = 0; i < 2000; ++i) {
            const BlockPos p(pick(rng() % 2), pick(rng() % 2), pick(true)); // On a border plane.
            const BlockId id = rng() % 3 == 0 ? kAir : BlockId(1 + rng() % 6);
            const EditResult a = em_edge.apply(edge, p + shift, id, m_edge);
            const EditResult b = em_twin.apply(twin, p, id, m_twin);
            ASSERT_EQ(a.updates.size(), b.updates.size());
            if (i % 100 == 0)
                expect_same(i);
        }
        expect_same(2000);
    }
}
