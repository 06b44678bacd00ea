#include "engine/world_setup.h"

#include <algorithm>

#include "world/gen/terrain.h"
#include "world/store/sqlite_store.h"
#if VX_WITH_OPENVDB
#include "world/vdb/vdb_store.h"
#endif

namespace vx::engine {

world::Chunk GameGenerator::generate(world::ChunkCoord c) const {
    if (const std::optional<BlockId> id = m_game->uniform(c))
        return world::Chunk(*id);
    // One dense buffer per worker thread: 64 KiB, reused by every chunk that thread generates.
    thread_local std::vector<BlockId> dense(kChunkVolume);
    std::fill(dense.begin(), dense.end(), kAir);
    m_game->generate(c, std::span<BlockId>(dense));
    return world::Chunk::from_dense(dense);
}

Result<world::BlockRegistry> make_registry(const std::vector<BlockType>& blocks) {
    if (blocks.empty())
        return world::BlockRegistry::default_registry();
    if (blocks.size() > 0xFFFEu)
        return Error{"too many block types: " + std::to_string(blocks.size()) + " (at most 65534)"};
    world::BlockRegistry registry;
    for (size_t i = 0; i < blocks.size(); ++i) {
        const BlockType& b = blocks[i];
        Result<world::BlockId> id = registry.add({b.name, b.albedo, b.reflectivity, b.emission, b.opaque});
        if (!id)
            return Error{"block type " + std::to_string(i + 1) + " ('" + b.name + "'): " + id.error()};
    }
    return registry;
}

namespace {

// The generator for chunks no store holds: the game's if given, else `fallback`.
std::unique_ptr<world::ChunkGenerator> pick_generator(const WorldSource& source,
                                                      std::unique_ptr<world::ChunkGenerator> fallback) {
    if (source.generator)
        return std::make_unique<GameGenerator>(source.generator);
    return fallback;
}

Result<std::unique_ptr<world::ChunkStore>> open_store(const WorldSource& source) {
    if (source.path.empty())
        return Error{"the world source needs a path"};
    if (source.kind == WorldSource::Kind::Sqlite) {
        world::SqliteStoreCreateInfo info;
        info.path = source.path;
        auto store = world::SqliteStore::open(info);
        if (!store)
            return Error{store.error()};
        return std::unique_ptr<world::ChunkStore>(std::move(*store));
    }
#if VX_WITH_OPENVDB
    auto store = vdb::VdbStore::open(source.path);
    if (!store)
        return Error{store.error()};
    return std::unique_ptr<world::ChunkStore>(std::move(*store));
#else
    return Error{"VDB worlds are not available: this vx was built without OpenVDB (VX_WITH_OPENVDB=OFF)"};
#endif
}

} // namespace

Result<OpenedWorld> open_world(const WorldSource& source, const std::vector<BlockType>& blocks) {
    Result<world::BlockRegistry> registry = make_registry(blocks);
    if (!registry)
        return Error{registry.error()};
    OpenedWorld out;
    out.registry = std::move(*registry);
    switch (source.kind) {
    case WorldSource::Kind::Terrain:
        out.generator = std::make_unique<world::TerrainGenerator>(source.seed);
        return out;
    case WorldSource::Kind::Generator:
        if (!source.generator)
            return Error{"WorldSource::custom needs a generator (got null)"};
        out.generator = std::make_unique<GameGenerator>(source.generator);
        return out;
    case WorldSource::Kind::Sqlite:
    case WorldSource::Kind::Vdb: {
        auto store = open_store(source);
        if (!store)
            return Error{store.error()};
        out.store = std::move(*store);
        if (source.kind == WorldSource::Kind::Sqlite)
            out.generator = pick_generator(source, std::make_unique<world::TerrainGenerator>(source.seed));
        else
            out.generator = pick_generator(source, std::make_unique<AirGenerator>());
        return out;
    }
    }
    return Error{"unknown world source kind " + std::to_string(int(source.kind))};
}

} // namespace vx::engine

namespace vx {

WorldSource WorldSource::terrain(uint64_t seed) {
    WorldSource s;
    s.kind = Kind::Terrain;
    s.seed = seed;
    return s;
}

WorldSource WorldSource::custom(std::shared_ptr<const Generator> generator) {
    WorldSource s;
    s.kind = Kind::Generator;
    s.generator = std::move(generator);
    return s;
}

WorldSource WorldSource::sqlite(std::string path, uint64_t seed) {
    WorldSource s;
    s.kind = Kind::Sqlite;
    s.path = std::move(path);
    s.seed = seed;
    return s;
}

WorldSource WorldSource::sqlite(std::string path, std::shared_ptr<const Generator> generator) {
    WorldSource s = sqlite(std::move(path), uint64_t(1));
    s.generator = std::move(generator);
    return s;
}

WorldSource WorldSource::vdb(std::string path, std::shared_ptr<const Generator> generator) {
    WorldSource s;
    s.kind = Kind::Vdb;
    s.path = std::move(path);
    s.generator = std::move(generator);
    return s;
}

std::vector<BlockType> default_blocks() {
    const world::BlockRegistry& r = world::BlockRegistry::default_registry();
    std::vector<BlockType> out;
    for (size_t id = 1; id < r.size(); ++id) {
        const world::BlockInfo b = r.info(world::BlockId(id));
        out.push_back({b.name, b.albedo, b.reflectivity, b.emission, b.opaque});
    }
    return out;
}

int64_t terrain_height(uint64_t seed, int64_t x, int64_t z) {
    // Construction is a few lookups; callers spawning a player call this rarely.
    return world::TerrainGenerator(seed).surface_height(x, z);
}

} // namespace vx
