#include "world/edit_mesher.h"

namespace vx::world {

void EditMesher::mesh_chunk(const World& world, ChunkCoord c, MeshMap& meshes) {
    MeshedChunk& mc = meshes[c];
    mc.apron = make_apron(world, c);
    static const Chunk kEmpty;
    const Chunk* chunk = world.find_chunk(c);
    m_mesher.mesh({chunk ? *chunk : kEmpty, mc.apron, world.registry()}, mc.mesh);
}

EditResult EditMesher::apply(World& world, BlockPos p, BlockId id, MeshMap& meshes) {
    EditResult r;
    const ChunkCoord c = chunk_of(p);
    const LocalPos l = local_of(p);
    if (world.set_block(p, id) == id)
        return r;
    r.changed = true;
    if (auto it = meshes.find(c); it != meshes.end()) {
        const Chunk& chunk = world.chunk(c);
        m_mesher.remesh_block({chunk, it->second.apron, world.registry()}, l, it->second.mesh);
        r.slices_remeshed += 6;
    } else {
        mesh_chunk(world, c, meshes);
        r.slices_remeshed += kSliceCount;
    }
    r.touched.push_back(c);
    for (int f = 0; f < 6; ++f) {
        const Face face = Face(f);
        const int axis = face_axis(face);
        const bool pos = face_positive(face);
        if (l[axis] != (pos ? kChunkSize - 1 : 0))
            continue;
        const ChunkCoord n = c + face_normal(face);
        auto it = meshes.find(n);
        if (it == meshes.end())
            continue;
        // In the neighbour, this block lies across its opposite face.
        const Face back = make_face(axis, !pos);
        it->second.apron.set(back, l[plane_u_axis(axis)], l[plane_v_axis(axis)], id, world.registry());
        static const Chunk kEmpty;
        const Chunk* nc = world.find_chunk(n);
        m_mesher.remesh_slice({nc ? *nc : kEmpty, it->second.apron, world.registry()}, axis,
                              pos ? 0 : kChunkSize, it->second.mesh);
        r.slices_remeshed += 1;
        r.touched.push_back(n);
    }
    return r;
}

} // namespace vx::world
