#pragma once
// The facade's world description made real: the block registry from the game's BlockTypes, the
// chunk generator (built-in terrain, the game's vx::Generator adapted, or air) and the store
// (SQLite, read-only VDB, or none). Main thread (creation only); the generators they make are
// thread-safe through const, as world::ChunkGenerator requires.

#include <memory>
#include <vector>

#include <vx/vx.h>

#include "world/block_registry.h"
#include "world/gen/chunk_generator.h"
#include "world/store/chunk_store.h"

namespace vx::engine {

// A game's vx::Generator as a world::ChunkGenerator: fills a dense 32³ array (one per worker
// thread, reused) and packs it into a palette chunk. Thread-safe if the game's generator is.
// The game's code may throw: try_generate catches anything its generate() or uniform() throws
// and returns the exception's what() (the half-filled array is dropped).
class GameGenerator final : public world::ChunkGenerator {
public:
    explicit GameGenerator(std::shared_ptr<const Generator> game) : m_game(std::move(game)) {}
    Result<world::Chunk> try_generate(world::ChunkCoord c) const override;
    // Only for callers that cannot report a failure: aborts if the game's generator throws. The
    // engine calls try_generate.
    world::Chunk generate(world::ChunkCoord c) const override;
    // The game's generate_coarse(); false when it offers none, or throws (logged once: the engine
    // then builds the chunk from generated blocks, which reports any error of its own).
    bool generate_coarse(world::LodCoord c, world::Chunk& out) const override;
    int coarse_levels() const override;

private:
    std::shared_ptr<const Generator> m_game;
};

// Every chunk air: what lies outside a VDB world. Thread-safe.
class AirGenerator final : public world::ChunkGenerator {
public:
    world::Chunk generate(world::ChunkCoord) const override { return world::Chunk(); }
};

struct OpenedWorld {
    world::BlockRegistry registry;
    std::unique_ptr<world::ChunkGenerator> generator;
    std::unique_ptr<world::ChunkStore> store; // Null: nothing persists.
};

// Air plus blocks[i] at id i + 1; the default registry when `blocks` is empty. Errors name the
// block (empty or duplicate name, too many blocks).
Result<world::BlockRegistry> make_registry(const std::vector<BlockType>& blocks);
// Opens the source's store and makes its generator. Errors name the path or the missing part.
Result<OpenedWorld> open_world(const WorldSource& source, const std::vector<BlockType>& blocks);

} // namespace vx::engine
