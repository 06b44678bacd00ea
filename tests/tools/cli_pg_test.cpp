// The vx CLI on PostgreSQL worlds: a libpq URI is accepted wherever a world path is (world gen,
// world info [--check], export-vdb, import-vdb --out), and bad ones fail with one line, exit 2.
// Uses the throwaway cluster of tests/world/pg_cluster.h; skips with a line without PostgreSQL.
#include <string>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "cli_run.h"
#include "pg_cluster.h"

using cli_test::CliRun;
using vx::world::test::PgCluster;

namespace {

// Quoted for the shell (URIs hold '?' and '&').
std::string q(const std::string& s) { return "'" + s + "'"; }

PgCluster* cluster_or_skip() {
    std::string why;
    PgCluster* c = PgCluster::get(&why);
    if (!c)
        std::printf("PostgreSQL CLI tests skipped: %s\n", why.c_str());
    return c;
}

} // namespace

TEST(CliPg, WorldGenInfoCheckAndCorruption) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    CliRun r = cli_test::vx("world gen " + q(uri) + " --seed 9 --radius 1 --bottom -1 --top 1");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("27 chunks"), std::string::npos) << r.out;
    r = cli_test::vx("world info " + q(uri));
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("chunks stored: 27"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("seed: 9"), std::string::npos) << r.out;
    r = cli_test::vx("world info " + q(uri) + " --check");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("records: 27, corrupt: 0"), std::string::npos) << r.out;
    EXPECT_EQ(cli_test::vx("world gen " + q(uri) + " --seed 10 --radius 1").code, 2); // Another seed.

    // Flip the last byte of one record behind the store's back: --check finds it.
    PGconn* c = PQconnectdb(uri.c_str());
    PGresult* res = PQexec(c, "UPDATE vx_chunks SET data = overlay(data placing "
                              "decode(lpad(to_hex((get_byte(data, length(data) - 1) + 1) % 256), 2, '0'), 'hex') "
                              "from length(data) for 1) WHERE x = 0 AND y = 0 AND z = 0");
    EXPECT_EQ(PQresultStatus(res), PGRES_COMMAND_OK) << PQerrorMessage(c);
    PQclear(res);
    PQfinish(c);
    r = cli_test::vx("world info " + q(uri) + " --check");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("records: 27, corrupt: 1"), std::string::npos) << r.out;

    // A database that holds something else, and one that does not exist: one line, exit 2.
    const std::string foreign = cluster->new_database();
    c = PQconnectdb(foreign.c_str());
    PQclear(PQexec(c, "CREATE TABLE songs(title text)"));
    PQfinish(c);
    r = cli_test::vx("world gen " + q(foreign) + " --seed 1 --radius 0");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("refusing"), std::string::npos) << r.out;
    r = cli_test::vx("world info " + q(cluster->uri("nowhere")));
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("cannot connect"), std::string::npos) << r.out;
}

// --lod-levels on a PostgreSQL world: coarse chunks go to vx_lod_chunks (created then), world
// info counts them per level and --check verifies them with the rest.
TEST(CliPg, WorldGenStoresCoarseLevels) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const std::string uri = cluster->new_database();
    CliRun r = cli_test::vx("world gen " + q(uri) + " --seed 9 --radius 1 --bottom -1 --top 1 --lod-levels 2");
    ASSERT_EQ(r.code, 0) << r.out;
    // Chunks -1..1 on each axis: -1..0 at levels 1 and 2 (floored shifts), 8 chunks each.
    EXPECT_NE(r.out.find("level 2: 8 coarse chunks"), std::string::npos) << r.out;
    r = cli_test::vx("world info " + q(uri));
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("level 1 coarse chunks stored: 8"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 2 coarse chunks stored: 8"), std::string::npos) << r.out;
    r = cli_test::vx("world info " + q(uri) + " --check");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("records: 43, corrupt: 0"), std::string::npos) << r.out;

    // A level-1 record filed under level 2: --check finds it.
    PGconn* c = PQconnectdb(uri.c_str());
    PGresult* res = PQexec(c, "UPDATE vx_lod_chunks SET data = (SELECT data FROM vx_lod_chunks WHERE level = 1 "
                              "AND x = 0 AND y = 0 AND z = 0) WHERE level = 2 AND x = 0 AND y = 0 AND z = 0");
    EXPECT_EQ(PQresultStatus(res), PGRES_COMMAND_OK) << PQerrorMessage(c);
    PQclear(res);
    PQfinish(c);
    r = cli_test::vx("world info " + q(uri) + " --check");
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("records: 43, corrupt: 1"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("level 2 chunk 0,0,0"), std::string::npos) << r.out;
}

#if VX_WITH_OPENVDB
TEST(CliPg, VdbRoundTripBetweenSqliteAndPostgres) {
    PgCluster* cluster = cluster_or_skip();
    if (!cluster)
        GTEST_SKIP() << "no PostgreSQL cluster (see the line above)";
    const auto dir = cli_test::temp_dir("vx_cli_pg_test");
    const std::string a = cluster->new_database(), b = cluster->new_database();
    const std::string vdb = (dir / "w.vdb").string(), back = (dir / "back.vdb").string();
    ASSERT_EQ(cli_test::vx("world gen " + q(a) + " --seed 4 --radius 1 --bottom -1 --top 0").code, 0);
    CliRun r = cli_test::vx("export-vdb " + q(a) + " --out " + vdb);
    ASSERT_EQ(r.code, 0) << r.out;
    r = cli_test::vx("import-vdb " + vdb + " --out " + q(b));
    ASSERT_EQ(r.code, 0) << r.out;
    r = cli_test::vx("export-vdb " + q(b) + " --out " + back);
    ASSERT_EQ(r.code, 0) << r.out;
    r = cli_test::vx("world info " + q(b) + " --check");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("records: 18, corrupt: 0"), std::string::npos) << r.out; // 3 × 2 × 3.
}
#endif
