#pragma once
// Helpers shared by the world tests: random chunks and aprons, and the brute-force mesh oracle.

#include <random>
#include <set>
#include <string>
#include <tuple>

#include <gtest/gtest.h>

#include "world/mesh/mesher.h"

namespace vx::world::test {

// A registry with `opaque` opaque types (ids 1..opaque) and `transparent` transparent ones after.
inline BlockRegistry make_registry(int opaque, int transparent) {
    BlockRegistry r;
    for (int i = 0; i < opaque + transparent; ++i) {
        BlockInfo b;
        b.name = "b";
        b.name += std::to_string(i + 1); // (operator+ trips a GCC 12 -Wrestrict false positive)
        b.opaque = i < opaque;
        EXPECT_TRUE(r.add(b).ok());
    }
    return r;
}

// Each block is non-air with probability `fill`, of a type uniform in 1..types.
inline Chunk random_chunk(std::mt19937& rng, double fill, int types) {
    std::vector<BlockId> ids(kChunkVolume);
    std::bernoulli_distribution solid(fill);
    std::uniform_int_distribution<int> type(1, types);
    for (BlockId& b : ids)
        b = solid(rng) ? BlockId(type(rng)) : kAir;
    return Chunk::from_dense(ids);
}

inline Apron random_apron(std::mt19937& rng, double fill, int types, const BlockRegistry& reg) {
    Apron a;
    std::bernoulli_distribution solid(fill);
    std::uniform_int_distribution<int> type(1, types);
    for (int f = 0; f < 6; ++f) {
        for (auto& b : a.ids[f])
            b = solid(rng) ? BlockId(type(rng)) : kAir;
        a.refresh_face(Face(f), reg);
    }
    return a;
}

// Checks that `mesh` covers every visible face of the input exactly once, with the right block
// and orientation, puts each quad in its own slice, and emits nothing else.
inline ::testing::AssertionResult covers_exactly(const MesherInput& in, const ChunkMesh& mesh) {
    auto neighbour = [&](LocalPos p, Face f) -> BlockId {
        const int axis = face_axis(f);
        LocalPos q = p + face_normal(f);
        if (q[axis] < 0 || q[axis] >= kChunkSize)
            return in.apron.ids[int(f)][p[plane_u_axis(axis)] + kChunkSize * p[plane_v_axis(axis)]];
        return in.chunk.get(q);
    };
    std::set<std::tuple<int, int, int, int>> covered; // (face, x, y, z)
    size_t counted = 0;
    for (int s = 0; s < kSliceCount; ++s) {
        for (const Quad& q : mesh.slice(s)) {
            ++counted;
            if (slice_index(q.axis(), q.plane()) != s)
                return ::testing::AssertionFailure() << "quad in slice " << s << " has plane " << q.plane();
            const int a = q.axis();
            const int layer = q.positive() ? q.plane() - 1 : q.plane();
            if (layer < 0 || layer >= kChunkSize || q.u0() + q.width() > kChunkSize ||
                q.v0() + q.height() > kChunkSize)
                return ::testing::AssertionFailure() << "quad out of the chunk";
            for (int v = q.v0(); v < q.v0() + q.height(); ++v)
                for (int u = q.u0(); u < q.u0() + q.width(); ++u) {
                    const LocalPos p = plane_to_local(a, layer, u, v);
                    const BlockId id = in.chunk.get(p);
                    if (id != q.block)
                        return ::testing::AssertionFailure() << "quad block " << q.block << " over block " << id;
                    if (!face_visible(id, neighbour(p, q.face()), in.registry))
                        return ::testing::AssertionFailure() << "hidden face emitted at " << p.x << "," << p.y
                                                             << "," << p.z << " face " << int(q.face());
                    if (!covered.insert({int(q.face()), p.x, p.y, p.z}).second)
                        return ::testing::AssertionFailure() << "face covered twice";
                }
        }
    }
    if (counted != mesh.quad_count())
        return ::testing::AssertionFailure() << "quad_count " << mesh.quad_count() << " != " << counted;
    for (int z = 0; z < kChunkSize; ++z)
        for (int y = 0; y < kChunkSize; ++y)
            for (int x = 0; x < kChunkSize; ++x)
                for (int f = 0; f < 6; ++f) {
                    const LocalPos p(x, y, z);
                    if (face_visible(in.chunk.get(p), neighbour(p, Face(f)), in.registry) &&
                        !covered.count({f, x, y, z}))
                        return ::testing::AssertionFailure() << "visible face missing at " << x << "," << y << ","
                                                             << z << " face " << f;
                }
    return ::testing::AssertionSuccess();
}

} // namespace vx::world::test
