// TlasInstances without a GPU: random adds, updates and removes, each frame slot's buffers
// written only with what changed since that slot's last sync, must always hold what a rebuild
// from scratch of the same chunks would write: every chunk once, instance i with custom index i
// and the chunk table's entry i its chunk's quads, its draw entry its traits, translations
// relative to the origin, a level-k chunk scaled by 2^k; per-level instance counts as the
// reference's.
#include <array>
#include <cstring>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "render/tlas_instances.h"

namespace vx::render {
namespace {

using world::BlockPos;
using world::ChunkCoord;

struct Chunk {
    VkDeviceAddress blas = 0, quads = 0;
    uint32_t slots = 0;
    bool opaque = false;
};
using Key = std::tuple<int, int, int, int>; // Level, x, y, z.
using Reference = std::map<Key, Chunk>;
Key key_of(world::LodCoord c) { return {c.level, c.chunk.x, c.chunk.y, c.chunk.z}; }

// A frame slot's host-visible buffers: replaced (contents lost) when they must grow.
struct SlotBuffers {
    std::vector<VkAccelerationStructureInstanceKHR> instances;
    std::vector<uint64_t> table;
    uint32_t sync(TlasInstances& a, uint32_t slot) {
        bool fresh = false;
        if (instances.size() < a.size()) {
            const size_t capacity = std::max<size_t>(a.size(), 2 * instances.size());
            instances.assign(capacity, {}); // Garbage in a real buffer: every byte differs.
            std::memset(instances.data(), 0xAB, capacity * sizeof(instances[0]));
            table.assign(capacity, 0xABABABABABABABABull);
            fresh = true;
        }
        return a.sync(slot, instances.data(), table.data(), fresh);
    }
};

// What the slot's buffers must hold: the from-scratch rebuild of `ref` in the array's order.
void expect_matches(const TlasInstances& a, const SlotBuffers& b, const Reference& ref, BlockPos origin) {
    ASSERT_EQ(a.size(), ref.size());
    std::array<uint32_t, world::kMaxLodLevel + 1> levels{};
    for (const auto& kv : ref)
        ++levels[size_t(std::get<0>(kv.first))];
    EXPECT_EQ(a.level_counts(), levels);
    std::map<Key, int> seen;
    for (uint32_t i = 0; i < a.size(); ++i) {
        const DrawChunk& d = a.draw_list()[i];
        const Key key = key_of(d.coord);
        ASSERT_EQ(seen[key]++, 0) << "chunk listed twice";
        const auto it = ref.find(key);
        ASSERT_NE(it, ref.end()) << "a removed chunk is still drawn";
        EXPECT_EQ(d.quads, it->second.quads);
        EXPECT_EQ(d.slots, it->second.slots);
        const VkAccelerationStructureInstanceKHR want = TlasInstances::make_instance(d.coord, origin, i, it->second.blas);
        EXPECT_EQ(std::memcmp(&b.instances[i], &want, sizeof want), 0) << "instance " << i;
        EXPECT_EQ(d.opaque, it->second.opaque);
        EXPECT_EQ(b.table[i], it->second.quads) << "table entry " << i;
    }
}

class Harness {
public:
    static constexpr uint32_t kSlots = 2;
    TlasInstances array{kSlots};
    Reference ref;
    std::map<Key, uint32_t> index; // What the owner (SceneAccel) records.
    SlotBuffers slots[kSlots];
    VkDeviceAddress next_address = 0x1000;

    void set(ChunkCoord c) { set(world::LodCoord{0, c}); }
    void remove(ChunkCoord c) { remove(world::LodCoord{0, c}); }
    void set(world::LodCoord c, bool opaque = false) {
        const Key key = key_of(c);
        Chunk& ch = ref[key];
        ch = {next_address, next_address + 8, uint32_t(next_address % 97), opaque};
        next_address += 0x100;
        put(c, ch);
    }
    // The same BLAS and buffers, the traits toggled (SceneAccel: a registry change, or a refit).
    void toggle_traits(world::LodCoord c) {
        const auto it = ref.find(key_of(c));
        if (it == ref.end())
            return;
        it->second.opaque = !it->second.opaque;
        put(c, it->second);
    }
    void put(world::LodCoord c, const Chunk& ch) {
        const Key key = key_of(c);
        const DrawChunk d{c, ch.quads, ch.slots, ch.opaque};
        if (auto it = index.find(key); it != index.end())
            array.update(it->second, d, ch.blas);
        else
            index[key] = array.add(d, ch.blas);
    }
    void remove(world::LodCoord c) {
        const Key key = key_of(c);
        auto it = index.find(key);
        if (it == index.end())
            return;
        const uint32_t i = it->second;
        index.erase(it);
        ref.erase(key);
        if (const std::optional<world::LodCoord> moved = array.remove(i))
            index.at(key_of(*moved)) = i;
    }
};

TEST(TlasInstances, RandomChangesMatchARebuildInEverySlot) {
    Harness h;
    std::mt19937 rng(1234);
    std::uniform_int_distribution<int> coord(-6, 6), op(0, 9), level(0, 2);
    uint32_t frame = 0;
    for (int step = 0; step < 4000; ++step) {
        // Levels 0..2 over the same chunk coordinates: different entries.
        const world::LodCoord c{level(rng), ChunkCoord(coord(rng), coord(rng) / 3, coord(rng))};
        const int o = op(rng);
        if (o < 4)
            h.set(c, (rng() & 1) != 0); // Add, or a rebuild's new addresses.
        else if (o < 5)
            h.toggle_traits(c);
        else if (o < 9)
            h.remove(c);
        else if (step % 7 == 0) {
            h.array.clear();
            h.ref.clear();
            h.index.clear();
        }
        if (step % 5 == 0) { // A frame: this slot catches up with every change since its last frame.
            const uint32_t slot = frame++ % Harness::kSlots;
            h.array.follow_camera(BlockPos(0, 0, 0));
            h.slots[slot].sync(h.array, slot);
            expect_matches(h.array, h.slots[slot], h.ref, h.array.origin());
            if (testing::Test::HasFailure())
                FAIL() << "at step " << step;
        }
    }
    EXPECT_EQ(h.array.rebases(), 0u); // The camera never moved.
}

TEST(TlasInstances, StillFramesWriteNothingAndAChangeOnlyItself) {
    Harness h;
    for (int x = 0; x < 100; ++x)
        h.set(ChunkCoord(x, 0, 0));
    for (uint32_t s = 0; s < Harness::kSlots; ++s)
        EXPECT_EQ(h.slots[s].sync(h.array, s), 100u);
    for (uint32_t s = 0; s < Harness::kSlots; ++s)
        EXPECT_EQ(h.slots[s].sync(h.array, s), 0u); // Nothing changed.
    h.set(ChunkCoord(7, 0, 0));    // An update: one entry.
    h.remove(ChunkCoord(3, 0, 0)); // The last moves into its place: one entry.
    for (uint32_t s = 0; s < Harness::kSlots; ++s) {
        EXPECT_EQ(h.slots[s].sync(h.array, s), 2u);
        expect_matches(h.array, h.slots[s], h.ref, h.array.origin());
    }
}

TEST(TlasInstances, TheOriginMovesOnlyFarOrWhenEmpty) {
    Harness h;
    const int64_t far = TlasInstances::kRebaseDistance;
    const BlockPos start(int64_t(1) << 30, -5000, 77);
    EXPECT_TRUE(h.array.follow_camera(start)); // Empty: the origin jumps to the camera for free.
    EXPECT_EQ(h.array.origin(), start);
    EXPECT_EQ(h.array.rebases(), 0u);
    const ChunkCoord base = world::chunk_of(start);
    for (int x = 0; x < 10; ++x)
        h.set(base + ChunkCoord(x, 0, 0));
    EXPECT_FALSE(h.array.follow_camera(start)); // Filled: from now on moving costs a rewrite.
    EXPECT_FALSE(h.array.follow_camera(start + BlockPos(far, -far, 0))); // Within reach: stays.
    for (uint32_t s = 0; s < Harness::kSlots; ++s)
        h.slots[s].sync(h.array, s);
    const BlockPos moved = start + BlockPos(far + 1, 0, 3);
    EXPECT_TRUE(h.array.follow_camera(moved)); // Too far: every instance is rewritten once.
    EXPECT_EQ(h.array.origin(), moved);
    EXPECT_EQ(h.array.rebases(), 1u);
    for (uint32_t s = 0; s < Harness::kSlots; ++s) {
        EXPECT_EQ(h.slots[s].sync(h.array, s), 10u);
        expect_matches(h.array, h.slots[s], h.ref, moved);
    }
    // Exact translations: the 64-bit difference, then float.
    const world::BlockPos rel = world::lod_origin(h.array.draw_list()[0].coord) - moved;
    EXPECT_EQ(h.array.instances()[0].transform.matrix[0][3], float(rel.x));
    // Emptied, then filled again: the next frame's origin follows the camera without a re-base.
    for (int x = 0; x < 10; ++x)
        h.remove(base + ChunkCoord(x, 0, 0));
    h.set(base);
    EXPECT_TRUE(h.array.follow_camera(start));
    EXPECT_EQ(h.array.rebases(), 1u);
    for (uint32_t s = 0; s < Harness::kSlots; ++s) {
        h.slots[s].sync(h.array, s);
        expect_matches(h.array, h.slots[s], h.ref, start);
    }
}

// A level-k instance is the chunk-local mesh (cells) scaled by 2^k, translated by lod_origin -
// origin (64-bit first): level 3, chunk (-2, 5, 2^20) from origin (7, -9, 2^25 + 3) has origin
// (-2, 5, 2^20) * 256 = (-512, 1280, 2^28), so the translation is (-519, 1289, 2^28 - 2^25 - 3).
TEST(TlasInstances, ALevelKInstanceIsScaledByTwoToTheK) {
    const world::LodCoord c{3, ChunkCoord(-2, 5, 1 << 20)};
    const BlockPos origin(7, -9, (int64_t(1) << 25) + 3);
    const VkAccelerationStructureInstanceKHR d = TlasInstances::make_instance(c, origin, 5, 0x1234);
    for (int r = 0; r < 3; ++r)
        for (int col = 0; col < 3; ++col)
            EXPECT_EQ(d.transform.matrix[r][col], r == col ? 8.f : 0.f) << r << "," << col;
    EXPECT_EQ(d.transform.matrix[0][3], -519.f);
    EXPECT_EQ(d.transform.matrix[1][3], 1289.f);
    EXPECT_EQ(d.transform.matrix[2][3], float((int64_t(1) << 28) - (int64_t(1) << 25) - 3));
    EXPECT_EQ(d.instanceCustomIndex, 5u);
    EXPECT_EQ(d.accelerationStructureReference, 0x1234u);
    // Level 0 keeps the identity.
    const VkAccelerationStructureInstanceKHR d0 = TlasInstances::make_instance({0, c.chunk}, origin, 0, 1);
    EXPECT_EQ(d0.transform.matrix[0][0], 1.f);
    EXPECT_EQ(d0.transform.matrix[2][3], float((int64_t(1) << 25) - (int64_t(1) << 25) - 3));
}

} // namespace
} // namespace vx::render
