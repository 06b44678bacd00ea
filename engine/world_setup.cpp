#include "engine/world_setup.h"

#include <algorithm>

#include "world/gen/terrain.h"
#include "world/store/sqlite_store.h"
#include "world/store/store_open.h"
#if VX_WITH_OPENVDB
#include "world/vdb/vdb_overlay_store.h"
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

// The block names a world file was saved with, one per line for ids 1, 2, ...
std::string block_names(const world::BlockRegistry& registry) {
    std::string out;
    for (size_t id = 1; id < registry.size(); ++id)
        out += registry.info(world::BlockId(id)).name + "\n";
    return out;
}

// The block-name half of check_world_meta (also for a VDB world's edits overlay).
Status check_block_names(world::ChunkStore& store, const std::string& path, const world::BlockRegistry& registry) {
    auto stored = store.get_meta("blocks");
    if (!stored)
        return Error{stored.error()};
    const std::string now = block_names(registry);
    if (*stored && now.compare(0, (*stored)->size(), **stored) != 0) {
        std::string listed = **stored;
        std::replace(listed.begin(), listed.end(), '\n', ' ');
        return Error{path + " was saved with other blocks (ids 1.. were: " + listed +
                     "); keep their order and append new ones"};
    }
    return store.set_meta("blocks", now);
}

// A SQLite world remembers its terrain seed ("seed", as `vx world gen` writes it) and its block
// names ("blocks"): reopening it with another seed would put seams where new chunks meet stored
// ones, and with other blocks would give stored ids new meanings. Appending blocks is fine.
// Runs before the engine's threads start, so the store is used from one thread at a time.
Status check_world_meta(world::ChunkStore& store, const WorldSource& source, const world::BlockRegistry& registry) {
    const std::string path = "'" + source.path + "'";
    if (!source.generator) {
        auto seed = store.get_meta("seed");
        if (!seed)
            return Error{seed.error()};
        if (*seed && **seed != std::to_string(source.seed))
            return Error{path + " holds a world of seed " + **seed + ", not " + std::to_string(source.seed)};
        if (Status s = store.set_meta("seed", std::to_string(source.seed)); !s)
            return s;
    }
    return check_block_names(store, path, registry);
}

Result<std::unique_ptr<world::ChunkStore>> open_store(const WorldSource& source) {
    if (source.path.empty())
        return Error{"the world source needs a path"};
    if (source.kind == WorldSource::Kind::Sqlite) // A file, or a postgresql:// URI (shared).
        return world::open_store({source.path});
#if VX_WITH_OPENVDB
    if (source.read_only) {
        auto store = vdb::VdbStore::open(source.path);
        if (!store)
            return Error{store.error()};
        return std::unique_ptr<world::ChunkStore>(std::move(*store));
    }
    auto store = vdb::VdbOverlayStore::open(
        {.vdb_path = source.path, .overlay = source.overlay, .read_only = false, .read = {}});
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
        if (source.kind == WorldSource::Kind::Vdb) {
            // The overlay stores block ids: reopened with other blocks they would change meaning.
            const std::string overlay = "the edits overlay of '" + source.path + "'";
            if (!source.read_only)
                if (Status s = check_block_names(*out.store, overlay, out.registry); !s)
                    return Error{s.error()};
            out.generator = pick_generator(source, std::make_unique<AirGenerator>());
            return out;
        }
        if (Status s = check_world_meta(*out.store, source, out.registry); !s)
            return Error{s.error()};
        out.generator = pick_generator(source, std::make_unique<world::TerrainGenerator>(source.seed));
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
