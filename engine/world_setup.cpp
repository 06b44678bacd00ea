#include "engine/world_setup.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <exception>

#include "world/block_registry_text.h"
#include "world/gen/terrain.h"
#include "world/store/sqlite_store.h"
#include "world/store/store_open.h"

namespace vx::engine {

Result<world::Chunk> GameGenerator::try_generate(world::ChunkCoord c) const {
    // One dense buffer per worker thread: 64 KiB, reused by every chunk that thread generates.
    thread_local std::vector<BlockId> dense(kChunkVolume);
    try {
        if (const std::optional<BlockId> id = m_game->uniform(c))
            return world::Chunk(*id);
        std::fill(dense.begin(), dense.end(), kAir);
        m_game->generate(c, std::span<BlockId>(dense));
    } catch (const std::exception& e) { // The game's code: the boundary where its failures stop.
        return Error{std::string("the game's generator threw: ") + e.what()};
    } catch (...) {
        return Error{"the game's generator threw an exception that is not a std::exception"};
    }
    return world::Chunk::from_dense(dense);
}

world::Chunk GameGenerator::generate(world::ChunkCoord c) const {
    Result<world::Chunk> chunk = try_generate(c);
    VX_ASSERT_MSG(chunk, "a game's generator failed where no failure can be reported");
    return std::move(*chunk);
}

bool GameGenerator::generate_coarse(world::LodCoord c, world::Chunk& out) const {
    thread_local std::vector<BlockId> dense(kChunkVolume);
    std::string why;
    try {
        std::fill(dense.begin(), dense.end(), kAir);
        if (!m_game->generate_coarse(c.level, c.chunk, std::span<BlockId>(dense)))
            return false;
        out = world::Chunk::from_dense(dense);
        return true;
    } catch (const std::exception& e) {
        why = std::string(" (") + e.what() + ")";
    } catch (...) {
    }
    static std::atomic<bool> logged{false}; // Once, whatever was thrown.
    if (!logged.exchange(true))
        VX_LOG_ERROR("the game's generate_coarse threw%s; coarse chunks are built from blocks instead", why.c_str());
    return false;
}

int GameGenerator::coarse_levels() const {
    try {
        return std::clamp(m_game->coarse_levels(), 0, world::kMaxLodLevel);
    } catch (...) {
        return 0;
    }
}

Result<world::BlockRegistry> make_registry(const std::vector<BlockType>& blocks) {
    if (blocks.empty())
        return world::BlockRegistry::default_registry();
    if (blocks.size() > 0xFFFEu)
        return Error{"too many block types: " + std::to_string(blocks.size()) + " (at most 65534)"};
    world::BlockRegistry registry;
    for (size_t i = 0; i < blocks.size(); ++i) {
        const BlockType& b = blocks[i];
        // add() checks the ranges <vx/types.h> documents, so a bad material is refused at create
        // rather than rendering wrongly frames later.
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


// Refuses block names `now` that do not start with the `stored` ones (ids would change meaning).
Status check_blocks(const std::optional<std::string>& stored, const std::string& now, const std::string& path) {
    if (stored && now.compare(0, stored->size(), *stored) != 0) {
        std::string listed = *stored;
        std::replace(listed.begin(), listed.end(), '\n', ' ');
        return Error{path + " was saved with other blocks (ids 1.. were: " + listed +
                     "); keep their order and append new ones"};
    }
    return {};
}

// The block-name half of check_world_meta, for a VDB world's edits overlay.
Status check_block_names(world::ChunkStore& store, const std::string& path, const world::BlockRegistry& registry) {
    auto stored = store.get_meta("blocks");
    if (!stored)
        return Error{stored.error()};
    const std::string now = world::registry_names_text(registry);
    if (Status s = check_blocks(*stored, now, path); !s)
        return s;
    return store.set_meta("blocks", now);
}

// What made a world's unedited chunks, as its meta "generator" records it: "terrain" for the
// built-in terrain (its seed is "seed"), "game:NAME/VERSION" for a game's Generator.
// The game's name() and version() may throw: an error, as its generate() gives.
Result<std::string> generator_identity(const WorldSource& source) {
    if (!source.generator)
        return std::string("terrain");
    try {
        return "game:" + std::string(source.generator->name()) + "/" + std::to_string(source.generator->version());
    } catch (const std::exception& e) {
        return Error{std::string("the game's generator name() or version() threw: ") + e.what()};
    } catch (...) {
        return Error{"the game's generator name() or version() threw an exception that is not a std::exception"};
    }
}

// The identity for messages: "the built-in terrain" or "the generator 'NAME' version V".
std::string describe_generator(const std::string& identity) {
    if (identity.rfind("game:", 0) != 0)
        return "the built-in terrain";
    const size_t slash = identity.rfind('/');
    return "the generator '" + identity.substr(5, slash - 5) + "' version " + identity.substr(slash + 1);
}

// A SQLite world remembers what generated it ("generator"), its terrain seed ("seed", as `vx
// world gen` writes it) and its block names ("blocks"): reopening it with another generator or
// seed would put seams where new chunks meet stored ones, and with other blocks would give stored
// ids new meanings. Appending blocks is fine. A world from before "generator" was recorded gets
// it now; if it has a "seed" it was made by the built-in terrain (only that stores a seed).
// Nothing is written unless every check passes. Runs before the engine's threads start, so the
// store is used from one thread at a time.
Status check_world_meta(world::ChunkStore& store, const WorldSource& source, const world::BlockRegistry& registry) {
    const std::string path = "'" + source.path + "'";
    auto made_by = store.get_meta("generator");
    auto seed = store.get_meta("seed");
    auto stored = store.get_meta("blocks");
    for (const auto* r : {&made_by, &seed, &stored})
        if (!*r)
            return Error{r->error()};
    const Result<std::string> made_now = generator_identity(source);
    if (!made_now)
        return Error{made_now.error()};
    const std::string& identity = *made_now;
    const std::string recorded = *made_by ? **made_by : (*seed ? std::string("terrain") : identity);
    if (recorded != identity)
        return Error{path + " was made by " + describe_generator(recorded) + ", not " + describe_generator(identity) +
                     ": its unedited chunks would not match; open it with that generator"};
    if (!source.generator && *seed && **seed != std::to_string(source.seed))
        return Error{path + " holds a world of seed " + **seed + ", not " + std::to_string(source.seed)};
    const std::string now = world::registry_names_text(registry);
    if (Status s = check_blocks(*stored, now, path); !s)
        return s;
    if (Status s = store.set_meta("generator", identity); !s)
        return s;
    if (!source.generator)
        if (Status s = store.set_meta("seed", std::to_string(source.seed)); !s)
            return s;
    if (Status s = store.set_meta("registry", world::registry_to_text(registry)); !s)
        return s; // The materials too, for `vx export-vdb` (block_registry_text.h).
    return store.set_meta("blocks", now);
}

Result<std::unique_ptr<world::ChunkStore>> open_store(const WorldSource& source) {
    if (source.path.empty())
        return Error{"the world source needs a path"};
    if (source.kind == WorldSource::Kind::Sqlite) // A file, or a postgresql:// URI (shared).
        return world::open_store({source.path});
    if (const world::VdbStoreOpener open_vdb = world::vdb_store_opener())
        return open_vdb({source.path, source.overlay, source.read_only});
    return Error{"VDB worlds need vx's vdb component linked into the program: find_package(vx COMPONENTS vdb) "
                 "and link vx::vdb (vx built with VX_WITH_OPENVDB=ON)"};
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
        // Before the store is opened: a world created with the terrain in the generator's place
        // would be tagged with it for good (reopened with the generator, it is refused).
        if (source.generator_required && !source.generator)
            return Error{"WorldSource::sqlite(path, generator) got a null generator (for the built-in terrain, pass "
                         "a seed)"};
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
    s.generator_required = true;
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
    // Construction is a few lookups; callers spawning a player call this rarely. Columns past the
    // world's edge are the edge's (the noise lattice near 2^63 would overflow).
    x = std::clamp(x, world::kWorldMinBlock, world::kWorldMaxBlock);
    z = std::clamp(z, world::kWorldMinBlock, world::kWorldMaxBlock);
    return world::TerrainGenerator(seed).surface_height(x, z);
}

} // namespace vx
