// The facade's stored worlds: one writer per SQLite world, and the generator a world was made by.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

#include <gtest/gtest.h>

#include <vx/vx.h>

#include "facade_checks_util.h"
#include "world/store/store_open.h"

namespace {

using vx::test::checks_world;
using vx::test::error_of;
using vx::test::tiny_info;

// A generator with a name and version the test picks; every chunk below y = 0 rock.
class NamedGenerator final : public vx::Generator {
public:
    NamedGenerator(std::string name, uint32_t version) : m_name(std::move(name)), m_version(version) {}
    void generate(vx::ChunkCoord, std::span<vx::BlockId>) const override {}
    std::optional<vx::BlockId> uniform(vx::ChunkCoord c) const override {
        return c.y < 0 ? vx::BlockId(1) : vx::kAir;
    }
    std::string_view name() const override { return m_name; }
    uint32_t version() const override { return m_version; }

private:
    std::string m_name;
    uint32_t m_version;
};

// A game's generator that keeps the defaults.
class PlainGenerator final : public vx::Generator {
public:
    void generate(vx::ChunkCoord, std::span<vx::BlockId>) const override {}
};

std::string open_error(const vx::WorldSource& source) { return error_of(vx::Engine::create(tiny_info(source))); }

// Two engines on one SQLite world each saved their own copy of a chunk both edited; the last
// save won, and the other's edit, reported durable, was gone. The second is refused at create.
TEST(FacadeChecks, ASecondEngineOnOneSqliteWorldIsRefused) {
    const std::string path = checks_world("two_writers");
    {
        auto first = vx::Engine::create(tiny_info(vx::WorldSource::sqlite(path, 42)));
        ASSERT_TRUE(first) << first.error();
        const std::string e = open_error(vx::WorldSource::sqlite(path, 42));
        EXPECT_NE(e.find("is open for writing elsewhere"), std::string::npos) << e;
        EXPECT_NE(e.find("PostgreSQL"), std::string::npos) << e;
        (*first)->shutdown();
    }
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(path, 42)), "");
}

TEST(FacadeChecks, StoredWorldRefusesAnotherGenerator) {
    const std::string path = checks_world("generator");
    auto waves = std::make_shared<NamedGenerator>("waves", 1);
    ASSERT_EQ(open_error(vx::WorldSource::sqlite(path, waves)), ""); // Made by waves v1.
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(path, waves)), "");
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(path, std::make_shared<NamedGenerator>("waves", 1))), "");

    // The built-in terrain, of any seed.
    for (uint64_t seed : {uint64_t(1), uint64_t(7)}) {
        const std::string e = open_error(vx::WorldSource::sqlite(path, seed));
        EXPECT_NE(e.find("was made by the generator 'waves' version 1, not the built-in terrain"), std::string::npos)
            << e;
    }
    // Another version, another name, a generator that keeps the defaults.
    std::string e = open_error(vx::WorldSource::sqlite(path, std::make_shared<NamedGenerator>("waves", 2)));
    EXPECT_NE(e.find("made by the generator 'waves' version 1, not the generator 'waves' version 2"), std::string::npos)
        << e;
    e = open_error(vx::WorldSource::sqlite(path, std::make_shared<NamedGenerator>("hills", 1)));
    EXPECT_NE(e.find("not the generator 'hills' version 1"), std::string::npos) << e;
    e = open_error(vx::WorldSource::sqlite(path, std::make_shared<PlainGenerator>()));
    EXPECT_NE(e.find("not the generator 'game' version 1"), std::string::npos) << e;
    // A refused open records nothing: the world still opens with its own generator.
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(path, waves)), "");

    // The reverse: a terrain world refuses a game's generator.
    const std::string terrain = checks_world("terrain");
    ASSERT_EQ(open_error(vx::WorldSource::sqlite(terrain, 7)), "");
    e = open_error(vx::WorldSource::sqlite(terrain, waves));
    EXPECT_NE(e.find("was made by the built-in terrain, not the generator 'waves' version 1"), std::string::npos) << e;
    e = open_error(vx::WorldSource::sqlite(terrain, 8));
    EXPECT_NE(e.find("seed 7, not 8"), std::string::npos) << e;
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(terrain, 7)), "");
}

// Worlds saved before the generator was recorded: one without any meta opens with whatever
// comes and records it; one with a seed was made by the built-in terrain (only it stores one).
TEST(FacadeChecks, OlderWorldsRecordTheirGenerator) {
    auto waves = std::make_shared<NamedGenerator>("waves", 3);
    const std::string bare = checks_world("bare");
    {
        auto store = vx::world::open_store({bare});
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->flush());
    }
    ASSERT_EQ(open_error(vx::WorldSource::sqlite(bare, waves)), "");
    std::string e = open_error(vx::WorldSource::sqlite(bare, 1));
    EXPECT_NE(e.find("made by the generator 'waves' version 3"), std::string::npos) << e;

    const std::string seeded = checks_world("seeded");
    {
        auto store = vx::world::open_store({seeded});
        ASSERT_TRUE(store) << store.error();
        ASSERT_TRUE((*store)->set_meta("seed", "5")); // As `vx world gen --seed 5` wrote it.
        ASSERT_TRUE((*store)->flush());
    }
    e = open_error(vx::WorldSource::sqlite(seeded, waves));
    EXPECT_NE(e.find("made by the built-in terrain"), std::string::npos) << e;
    EXPECT_EQ(open_error(vx::WorldSource::sqlite(seeded, 5)), "");
    {
        auto store = vx::world::open_store({seeded});
        ASSERT_TRUE(store) << store.error();
        auto recorded = (*store)->get_meta("generator");
        ASSERT_TRUE(recorded && *recorded);
        EXPECT_EQ(**recorded, "terrain");
    }
}

} // namespace
