#pragma once
// Helpers shared by the PgStore tests (pg_store_test.cpp, pg_store_changes_test.cpp,
// pg_store_conflict_test.cpp): a store opened on a URI, and one SQL statement run on its own connection.

#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "world/store/pg_store.h"

namespace vx::world::test {

inline std::unique_ptr<PgStore> open_pg(const std::string& uri) {
    PgStoreCreateInfo info;
    info.uri = uri;
    auto s = PgStore::open(info);
    EXPECT_TRUE(s.ok()) << s.error();
    return s.ok() ? std::move(*s) : nullptr;
}

inline void sql(const std::string& uri, const char* statement) {
    PGconn* c = PQconnectdb(uri.c_str());
    PGresult* r = PQexec(c, statement);
    EXPECT_TRUE(PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK) << PQerrorMessage(c);
    PQclear(r);
    PQfinish(c);
}

} // namespace vx::world::test
