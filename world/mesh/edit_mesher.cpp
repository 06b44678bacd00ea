#include "world/mesh/edit_mesher.h"

namespace vx::world {
namespace {

const Chunk& chunk_or_air(const World& world, ChunkCoord c) {
    static const Chunk kAirChunk;
    const Chunk* chunk = world.find_chunk(c);
    return chunk ? *chunk : kAirChunk;
}

} // namespace

void EditMesher::mesh_chunk(const World& world, ChunkCoord c, MeshMap& meshes) {
    MeshedChunk& mc = meshes[c];
    mc.apron = m_isolated ? Apron::air() : make_apron(world, c);
    m_mesher.mesh({chunk_or_air(world, c), mc.apron, world.registry()}, mc.mesh);
}

EditResult EditMesher::apply(World& world, BlockPos p, BlockId id, const MeshLookup& lookup) {
    EditResult r;
    const BlockId old = world.set_block(p, id);
    if (old == id)
        return r;
    r.changed = true;
    const ChunkCoord c = chunk_of(p);
    const LocalPos l = local_of(p);
    const BlockRegistry& reg = world.registry();
    if (ChunkMesh* mesh = lookup(c)) {
        // remesh_block reads apron face f only when the block lies on that border.
        for (int f = 0; f < 6; ++f) {
            const Face face = Face(f);
            if (l[face_axis(face)] == (face_positive(face) ? kChunkSize - 1 : 0))
                m_apron.copy_face(face, m_isolated ? nullptr : world.find_neighbour(c, face), reg);
        }
        const uint32_t changed = m_mesher.remesh_block({chunk_or_air(world, c), m_apron, reg}, l, old, *mesh);
        SliceUpdate u{c, false, 0, {}};
        for (int a = 0; a < 3; ++a)
            for (int k = 0; k < 2; ++k)
                if (changed >> (2 * a + k) & 1u)
                    u.slices[size_t(u.count++)] = slice_index(a, l[a] + k);
        if (u.count > 0) // None: the edit changed no visible face (e.g. stone to dirt inside rock).
            r.updates.push_back(u);
        r.slices_remeshed += 6;
    }
    for (int f = 0; f < 6 && !m_isolated; ++f) {
        const Face face = Face(f);
        const int axis = face_axis(face);
        const bool pos = face_positive(face);
        if (l[axis] != (pos ? kChunkSize - 1 : 0) || !has_neighbour(c, face))
            continue;
        const ChunkCoord n = c + face_normal(face);
        ChunkMesh* mesh = lookup(n);
        if (!mesh)
            continue;
        // The neighbour's border plane facing the edited block reads only its apron face back here.
        const Face back = make_face(axis, !pos);
        m_apron.copy_face(back, world.find_chunk(c), reg);
        const int plane = pos ? 0 : kChunkSize;
        m_mesher.remesh_slice({chunk_or_air(world, n), m_apron, reg}, axis, plane, *mesh);
        r.updates.push_back(SliceUpdate{n, false, 1, {slice_index(axis, plane)}});
        r.slices_remeshed += 1;
    }
    return r;
}

EditResult EditMesher::apply(World& world, BlockPos p, BlockId id, MeshMap& meshes) {
    const ChunkCoord c = chunk_of(p);
    const bool meshed = meshes.count(c) > 0;
    EditResult r = apply(world, p, id, [&meshes](ChunkCoord q) -> ChunkMesh* {
        auto it = meshes.find(q);
        return it == meshes.end() ? nullptr : &it->second.mesh;
    });
    if (r.changed && !meshed) {
        mesh_chunk(world, c, meshes);
        r.updates.insert(r.updates.begin(), SliceUpdate{c, true, 0, {}});
        r.slices_remeshed += kSliceCount;
    }
    return r;
}

} // namespace vx::world
