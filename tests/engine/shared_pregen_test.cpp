// Pregeneration into a world shared through PostgreSQL: a chunk another client saves between
// pregenerate()'s contains() check and its commit is kept. Uses the throwaway cluster of
// tests/world/pg_cluster.h (skips, with a line, without PostgreSQL's server binaries).
#include <gtest/gtest.h>

#include "engine/job_batch.h"
#include "engine/world_pregen.h"
#include "world/gen/terrain.h"
#include "world/store/pg_store.h"

#include "pg_cluster.h"

using namespace vx::world;
using vx::Result;
using vx::Status;
using vx::engine::JobSystem;
using vx::engine::PregenInfo;
using vx::world::test::PgCluster;

namespace {

// Forwards to `inner`; after the first contains() of `target` that answers "absent", `other`
// saves and commits its own chunk there: the second client wins the race into the gap.
class RacingStore final : public ChunkStore {
public:
    RacingStore(ChunkStore& inner, ChunkStore& other, ChunkCoord target)
        : m_inner(inner), m_other(other), m_target(target) {}
    Result<ChunkLoad> load(ChunkCoord c) override { return m_inner.load(c); }
    Status save(std::span<const ChunkWrite> batch) override { return m_inner.save(batch); }
    Status tick(Clock::time_point now) override { return m_inner.tick(now); }
    Status flush() override { return m_inner.flush(); }
    Result<bool> contains(ChunkCoord c) override {
        Result<bool> r = m_inner.contains(c);
        if (r && !*r && c == m_target && !m_raced) {
            m_raced = true;
            m_race = m_other.save(c, Chunk(BlockId(9)));
            if (m_race)
                m_race = m_other.flush();
        }
        return r;
    }
    Result<uint64_t> count() override { return m_inner.count(); }
    Status for_each_coord(const std::function<bool(ChunkCoord)>& fn) override { return m_inner.for_each_coord(fn); }
    Result<std::optional<std::string>> get_meta(std::string_view key) override { return m_inner.get_meta(key); }
    Status set_meta(std::string_view key, std::string_view value) override { return m_inner.set_meta(key, value); }
    bool read_only() const override { return false; }
    bool raced() const { return m_raced; }
    const Status& race() const { return m_race; }

private:
    ChunkStore& m_inner;
    ChunkStore& m_other;
    ChunkCoord m_target;
    bool m_raced = false;
    Status m_race;
};

std::unique_ptr<PgStore> open_pg(const std::string& uri) {
    PgStoreCreateInfo info;
    info.uri = uri;
    info.listen = false;
    auto s = PgStore::open(info);
    EXPECT_TRUE(s.ok()) << s.error();
    return s.ok() ? std::move(*s) : nullptr;
}

} // namespace

// The second client's chunk survives, and the rest of the box is terrain. Pregeneration used to
// save terrain without a condition, so its commit met the other version and, as a write without
// edits, replaced it.
TEST(SharedPregen, AChunkAnotherClientSavesAfterTheCheckIsKept) {
    std::string why;
    PgCluster* cluster = PgCluster::get(&why);
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster: " << why;
    const std::string uri = cluster->new_database();
    auto mine = open_pg(uri);
    auto other = open_pg(uri);
    ASSERT_TRUE(mine && other);
    const ChunkCoord target(1, 0, 0);
    RacingStore racing(*mine, *other, target);
    const TerrainGenerator gen(5);
    JobSystem jobs(vx::engine::batch_job_system_info(1));
    const PregenInfo info{ChunkCoord(0), ChunkCoord(2, 0, 0), {}};
    auto r = pregenerate(jobs, gen, racing, info);
    ASSERT_TRUE(r) << r.error();
    ASSERT_TRUE(racing.raced());
    ASSERT_TRUE(racing.race().ok()) << racing.race().error();
    auto check = open_pg(uri);
    EXPECT_TRUE(*check->load(target)->chunk == Chunk(BlockId(9))) << "pregeneration wrote over it";
    for (ChunkCoord c : {ChunkCoord(0, 0, 0), ChunkCoord(2, 0, 0)})
        EXPECT_TRUE(*check->load(c)->chunk == gen.generate(c));
}
