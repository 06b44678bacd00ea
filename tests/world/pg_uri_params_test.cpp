// vx's own parameters in a PostgreSQL URI (pg_uri_params.h): taken out wherever they stand, the
// rest handed to libpq unchanged, bad values refused naming the parameter. No server needed.
#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "world/store/pg_uri_params.h"

using namespace vx::world;
using std::chrono::milliseconds;

TEST(PgUriParams, TheQueryTimeoutIsTakenOutWhereverItStands) {
    struct Case {
        const char* uri;
        const char* libpq;
    };
    const Case cases[] = {
        {"postgresql:///w?vx_query_timeout_ms=2000", "postgresql:///w"},                             // Alone.
        {"postgresql:///w?vx_query_timeout_ms=2000&host=/tmp&user=a", "postgresql:///w?host=/tmp&user=a"}, // First.
        {"postgresql:///w?host=/tmp&vx_query_timeout_ms=2000&user=a", "postgresql:///w?host=/tmp&user=a"}, // Middle.
        {"postgres://ann:pw@h:5/w?host=/tmp&vx_query_timeout_ms=2000", "postgres://ann:pw@h:5/w?host=/tmp"}, // Last.
    };
    for (const Case& c : cases) {
        auto p = split_pg_uri_params(c.uri);
        ASSERT_TRUE(p.ok()) << c.uri << ": " << p.error();
        EXPECT_EQ(p->uri, c.libpq) << c.uri;
        ASSERT_TRUE(p->query_timeout.has_value()) << c.uri;
        EXPECT_EQ(*p->query_timeout, milliseconds(2000)) << c.uri;
    }
    // The last one given wins, as libpq's rule for its own parameters; the bounds are accepted.
    auto twice = split_pg_uri_params("postgresql:///w?vx_query_timeout_ms=1&vx_query_timeout_ms=3600000");
    ASSERT_TRUE(twice.ok()) << twice.error();
    EXPECT_EQ(twice->uri, "postgresql:///w");
    EXPECT_EQ(*twice->query_timeout, kMaxUriQueryTimeout);
}

TEST(PgUriParams, OtherNamesAreLeftAsTheyAre) {
    for (const char* uri : {"postgresql://h/w", "postgresql:///w?host=/tmp&user=a", "postgresql:///w?",
                            "postgresql:///w?a=1&&b=2", "postgresql:///w?vx_query_timeout_msx=5",
                            "host=/tmp vx_query_timeout_ms=5", "worlds/w.db"}) {
        auto p = split_pg_uri_params(uri);
        ASSERT_TRUE(p.ok()) << uri << ": " << p.error();
        EXPECT_EQ(p->uri, uri);
        EXPECT_FALSE(p->query_timeout.has_value()) << uri;
    }
}

TEST(PgUriParams, BadQueryTimeoutsAreRefusedNamingTheParameter) {
    for (const char* value : {"abc", "0", "-5", "+5", "", "1.5", " 5", "2s", "3600001", "99999999999999999999999"}) {
        const std::string uri = std::string("postgresql:///w?host=/tmp&vx_query_timeout_ms=") + value + "&user=a";
        auto p = split_pg_uri_params(uri);
        ASSERT_FALSE(p.ok()) << uri;
        EXPECT_NE(p.error().find("vx_query_timeout_ms must be a whole number of milliseconds from 1 to 3600000"),
                  std::string::npos)
            << p.error();
        EXPECT_NE(p.error().find(std::string("'") + value + "'"), std::string::npos) << p.error();
    }
    auto bare = split_pg_uri_params("postgresql:///w?vx_query_timeout_ms");
    ASSERT_FALSE(bare.ok());
    EXPECT_NE(bare.error().find("vx_query_timeout_ms"), std::string::npos) << bare.error();
}
