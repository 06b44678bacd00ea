// A block table as text (world/block_registry_text.h): every registered id comes back with its
// name and material bit for bit, gaps stay gaps, and damaged text is one error naming its line.
#include <gtest/gtest.h>

#include "world/block_registry_text.h"

namespace vx::world {
namespace {

void expect_same(const BlockRegistry& a, const BlockRegistry& b) {
    ASSERT_EQ(a.size(), b.size());
    for (size_t id = 1; id < a.size(); ++id) {
        ASSERT_EQ(a.contains(BlockId(id)), b.contains(BlockId(id))) << id;
        if (!a.contains(BlockId(id)))
            continue;
        const BlockInfo x = a.info(BlockId(id)), y = b.info(BlockId(id));
        EXPECT_EQ(x.name, y.name);
        EXPECT_EQ(x.albedo, y.albedo) << x.name;
        EXPECT_EQ(x.reflectivity, y.reflectivity) << x.name;
        EXPECT_EQ(x.emission, y.emission) << x.name;
        EXPECT_EQ(x.opaque, y.opaque) << x.name;
    }
}

TEST(BlockRegistryText, RoundTripsExactlyWithGaps) {
    expect_same(BlockRegistry::default_registry(),
                *registry_from_text(registry_to_text(BlockRegistry::default_registry())));
    BlockRegistry r;
    for (int i = 1; i <= 300; ++i) {
        BlockInfo b;
        b.name = "custom block " + std::to_string(i);
        b.albedo = glm::vec3(float(i) / 301.f, 1.f / float(i), 0.1f + 1e-7f * float(i));
        b.reflectivity = float(i % 7) / 7.f;
        b.emission = i % 5 == 0 ? glm::vec3(3.3f, 1e-3f, float(i)) : glm::vec3(0.f);
        b.opaque = i % 3 != 0;
        ASSERT_TRUE(r.set(BlockId(i == 300 ? 1000 : i), b).ok()); // Ids 301..999 unregistered.
    }
    Result<BlockRegistry> back = registry_from_text(registry_to_text(r));
    ASSERT_TRUE(back.ok()) << back.error();
    expect_same(r, *back);
    EXPECT_FALSE(back->contains(BlockId(500)));
}

// The largest table a store can hold: 65535 ids (names are looked up by an index, so loading it
// is linear; a linear find made it 2 billion name comparisons).
TEST(BlockRegistryText, RoundTripsTheLargestTable) {
    BlockRegistry r;
    for (int i = 1; i <= 0xFFFF; ++i) {
        BlockInfo b;
        b.name = "b";
        b.name += std::to_string(i);
        b.albedo = glm::vec3(float(i & 255) / 255.f);
        ASSERT_TRUE(r.add(b).ok()) << i;
    }
    EXPECT_FALSE(r.add(BlockInfo{"one too many"}).ok());
    Result<BlockRegistry> back = registry_from_text(registry_to_text(r));
    ASSERT_TRUE(back.ok()) << back.error();
    expect_same(r, *back);
    EXPECT_EQ(back->find("b65535"), std::optional<BlockId>(0xFFFF));
}

TEST(BlockRegistryText, DamagedTextNamesItsLine) {
    const std::pair<const char*, const char*> cases[] = {
        {"stone\t0.5 0.5 0.5\t0\t0 0 0\t1\nsand\t0.5 0.5\t0\t0 0 0\t1\n", "line 2"},
        {"stone\t0.5 0.5 0.5\t0\t0 0 0\t2\n", "line 1"},
        {"stone\t0.5 0.5 x\t0\t0 0 0\t1\n", "line 1"},
        {"stone\t0.5 0.5 0.5\tnan\t0 0 0\t1\n", "line 1"},
        {"stone\t0.5 0.5 0.5\t0\t0 0 0\n", "line 1"},
        {"\t0.5 0.5 0.5\t0\t0 0 0\t1\n", "empty"},
        {"a\t1 1 1\t0\t0 0 0\t1\na\t1 1 1\t0\t0 0 0\t1\n", "line 2"},
        // Numbers, but outside the materials' ranges: refused, not rendered.
        {"a\t1 1 1\t0\t0 0 0\t1\nb\t1.5 1 1\t0\t0 0 0\t1\n", "line 2: albedo must be 0..1"},
        {"a\t1 1 1\t2\t0 0 0\t1\n", "line 1: reflectivity must be 0..1"},
        {"a\t1 1 1\t0\t0 -1 0\t1\n", "line 1: emission must be finite and >= 0"},
    };
    for (const auto& [text, says] : cases) {
        Result<BlockRegistry> r = registry_from_text(text);
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_NE(r.error().find(says), std::string::npos) << r.error();
        EXPECT_EQ(r.error().find('\n'), std::string::npos) << r.error();
    }
}

} // namespace
} // namespace vx::world
