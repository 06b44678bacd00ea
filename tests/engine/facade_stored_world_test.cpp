// The facade's stored worlds: one writer per SQLite world, and the generator a world was made by.
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <sys/resource.h>

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

// `count` edits of random blocks (ids 1..`kinds`) at random places in the 3 x 1 x 3 chunks around
// the origin (y 0..31), in order.
std::vector<vx::BlockEdit> random_edits(std::mt19937& rng, size_t count, size_t kinds) {
    std::vector<vx::BlockEdit> edits(count);
    for (vx::BlockEdit& e : edits)
        e = {{int64_t(rng() % 96) - 32, int64_t(rng() % 32), int64_t(rng() % 96) - 32}, vx::BlockId(1 + rng() % kinds)};
    return edits;
}

// A full disk on a game's worst day (RLIMIT_FSIZE here: the store's writes past it fail with
// EFBIG, as they would with ENOSPC): the save's ticket turns Failed with the store's reason, the
// edits wait in the store (Stats::store_pending_edits) and the engine goes on; once space returns
// the next save is durable, and the world reopened holds every edit, the first save's and the
// failed one's.
TEST(FacadeChecks, AFullDiskFailsASaveAndTheNextSaveKeepsEveryEdit) {
    const std::string path = checks_world("full_disk");
    vx::Viewer v;
    v.block = {0, vx::terrain_height(42, 0, 0) + 4, 0};
    std::map<std::tuple<int64_t, int64_t, int64_t>, vx::BlockId> expected; // Each block's last edit.
    {
        auto engine = vx::Engine::create(tiny_info(vx::WorldSource::sqlite(path, 42)));
        ASSERT_TRUE(engine) << engine.error();
        vx::Engine& e = **engine;
        ASSERT_TRUE(e.set_viewer(v));
        ASSERT_TRUE(vx::test::settle(e));
        std::mt19937 rng(7);
        const std::vector<vx::BlockEdit> first = random_edits(rng, 2000, e.block_count());
        const std::vector<vx::BlockEdit> second = random_edits(rng, 30000, e.block_count()); // Noise: ~20 KB a chunk.
        ASSERT_TRUE(e.set_blocks(first));
        const vx::Result<vx::SaveTicket> saved = e.save();
        ASSERT_TRUE(saved) << saved.error();
        ASSERT_TRUE(e.wait(*saved));
        rlimit old{};
        ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
        uintmax_t largest = 0;
        for (const char* suffix : {"", "-wal"})
            if (std::filesystem::exists(path + suffix))
                largest = std::max(largest, std::filesystem::file_size(path + suffix));
        const auto old_signal = std::signal(SIGXFSZ, SIG_IGN);
        rlimit full = old;
        full.rlim_cur = rlim_t(largest + 16 * 1024);
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &full), 0);
        const vx::Status edited = e.set_blocks(second);
        const vx::Result<vx::SaveTicket> refused = e.save();
        const vx::Status failed = refused ? e.wait(*refused) : vx::Status(vx::Error{refused.error()});
        e.update();
        const vx::Stats during = e.stats();
        ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0); // Space again (before any ASSERT can return).
        std::signal(SIGXFSZ, old_signal);
        ASSERT_TRUE(edited) << edited.error();
        ASSERT_TRUE(refused) << refused.error();
        ASSERT_FALSE(failed) << "a save past the file size limit was durable";
        EXPECT_NE(failed.error().find("writing the file failed"), std::string::npos) << failed.error();
        EXPECT_EQ(e.save_state(*refused), vx::SaveState::Failed);
        EXPECT_GT(during.store_pending_edits, 0u) << "the edits wait in the store";
        const vx::Result<vx::SaveTicket> again = e.save();
        ASSERT_TRUE(again) << again.error();
        EXPECT_TRUE(e.wait(*again));
        EXPECT_TRUE(e.shutdown());
        for (const std::vector<vx::BlockEdit>* edits : {&first, &second})
            for (const vx::BlockEdit& ed : *edits)
                expected[{ed.pos.x, ed.pos.y, ed.pos.z}] = ed.id;
    }
    auto reopened = vx::Engine::create(tiny_info(vx::WorldSource::sqlite(path, 42)));
    ASSERT_TRUE(reopened) << reopened.error();
    ASSERT_TRUE((*reopened)->set_viewer(v));
    ASSERT_TRUE(vx::test::settle(**reopened));
    size_t lost = 0;
    for (const auto& [p, id] : expected) {
        const vx::BlockPos at{std::get<0>(p), std::get<1>(p), std::get<2>(p)};
        lost += (*reopened)->get_block(at) != std::optional<vx::BlockId>(id);
    }
    EXPECT_EQ(lost, 0u) << "of " << expected.size() << " edited blocks";
}

} // namespace
