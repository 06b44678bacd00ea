// Culled, naive and classic greedy meshers: one quad per face, written for clarity, used as comparison points
// and as oracles for the greedy mesher.
#include "world/mesh/reference_meshers.h"

namespace vx::world {
namespace {

// The block just across face `f` of local block p: in the chunk, or in the apron.
BlockId neighbour_of(const MesherInput& in, LocalPos p, Face f) {
    const int axis = face_axis(f);
    LocalPos q = p + face_normal(f);
    if (q[axis] < 0 || q[axis] >= kChunkSize) {
        const int u = p[plane_u_axis(axis)], v = p[plane_v_axis(axis)];
        return in.apron.ids[int(f)][u + kChunkSize * v];
    }
    return in.chunk.get(q);
}

template <class Keep> void mesh_unit_faces(const MesherInput& in, ChunkMesh& out, Keep&& keep) {
    out.begin(0);
    for (int axis = 0; axis < 3; ++axis) {
        for (int plane = 0; plane < kPlanesPerAxis; ++plane) {
            out.begin_slice(slice_index(axis, plane));
            // Same order as the greedy mesher: negative faces of layer `plane`, then positive
            // faces of layer `plane - 1`, each row by row.
            for (int pass = 0; pass < 2; ++pass) {
                const bool positive = pass == 1;
                const int layer = positive ? plane - 1 : plane;
                if (layer < 0 || layer >= kChunkSize)
                    continue;
                const Face f = make_face(axis, positive);
                for (int v = 0; v < kChunkSize; ++v)
                    for (int u = 0; u < kChunkSize; ++u) {
                        const LocalPos p = plane_to_local(axis, layer, u, v);
                        const BlockId id = in.chunk.get(p);
                        if (id != kAir && keep(id, p, f))
                            out.push(Quad::make(axis, plane, positive, u, v, 1, 1, id));
                    }
            }
        }
    }
    out.end();
}

} // namespace

void mesh_culled(const MesherInput& in, ChunkMesh& out) {
    mesh_unit_faces(in, out, [&](BlockId id, LocalPos p, Face f) {
        return face_visible(id, neighbour_of(in, p, f), in.registry);
    });
}

void mesh_naive(const MesherInput& in, ChunkMesh& out) {
    mesh_unit_faces(in, out, [](BlockId, LocalPos, Face) { return true; });
}

void mesh_classic_greedy(const MesherInput& in, ChunkMesh& out) {
    ChunkMesh culled;
    mesh_culled(in, culled);
    out.begin(0);
    for (int s = 0; s < kSliceCount; ++s) {
        out.begin_slice(s);
        for (int pass = 0; pass < 2; ++pass) {
            BlockId grid[kChunkSize][kChunkSize] = {}; // [v][u]; 0 = no face.
            int axis = s / kPlanesPerAxis, plane = s % kPlanesPerAxis;
            for (const Quad& q : culled.slice(s))
                if (q.positive() == (pass == 1))
                    grid[q.v0()][q.u0()] = q.block;
            for (int v = 0; v < kChunkSize; ++v)
                for (int u = 0; u < kChunkSize; ++u) {
                    const BlockId id = grid[v][u];
                    if (!id)
                        continue;
                    int w = 1;
                    while (u + w < kChunkSize && grid[v][u + w] == id)
                        ++w;
                    int h = 1;
                    for (; v + h < kChunkSize; ++h) {
                        bool row = true;
                        for (int k = 0; k < w && row; ++k)
                            row = grid[v + h][u + k] == id;
                        if (!row)
                            break;
                    }
                    for (int dv = 0; dv < h; ++dv)
                        for (int k = 0; k < w; ++k)
                            grid[v + dv][u + k] = 0;
                    out.push(Quad::make(axis, plane, pass == 1, u, v, w, h, id));
                }
        }
    }
    out.end();
}

const char* mesher_name(MesherKind kind) {
    switch (kind) {
    case MesherKind::Greedy: return "greedy";
    case MesherKind::Culled: return "culled";
    case MesherKind::Naive: return "naive";
    }
    return "?";
}

} // namespace vx::world
