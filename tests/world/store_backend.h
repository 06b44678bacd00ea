#pragma once
// The store test suite runs over every ChunkStore backend: these adapters give each test a fresh
// world (a SQLite file, or a new database on the throwaway PostgreSQL cluster) and the raw access
// a test needs to damage a record behind the store's back.

#include <sqlite3.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <libpq-fe.h>

#include "pg_cluster.h"
#include "store_test_util.h"
#include "world/store/pg_store.h"
#include "world/store/sqlite_store.h"

namespace vx::world::test {

struct StoreOptions {
    std::chrono::milliseconds max_pending_age{1000};
    size_t max_pending_bytes = size_t(32) << 20;
    bool read_only = false;
};

class StoreBackend {
public:
    virtual ~StoreBackend() = default;
    // Empty when the backend can run here, else why not (one line, for GTEST_SKIP).
    virtual std::string unavailable() const { return {}; }
    virtual std::string new_world() = 0;
    virtual std::unique_ptr<ChunkStore> open(const std::string& world, const StoreOptions& o = {}) = 0;
    // Replaces the stored bytes of chunk `c` (which must be stored) with `bytes`.
    virtual void write_raw(const std::string& world, ChunkCoord c, const std::vector<uint8_t>& bytes) = 0;
    // Replaces the stored bytes of coarse chunk `c` (which must be stored) with `bytes`.
    virtual void write_raw_lod(const std::string& world, LodCoord c, const std::vector<uint8_t>& bytes) = 0;
    // The quarantined bytes of chunk `c` (the newest), empty if none.
    virtual std::vector<uint8_t> quarantined(const std::string& world, ChunkCoord c) = 0;
    virtual uint64_t quarantine_count(const std::string& world) = 0;
};

class SqliteBackend final : public StoreBackend {
public:
    std::string new_world() override { return m_dir.file("w" + std::to_string(++m_worlds) + ".db"); }
    std::unique_ptr<ChunkStore> open(const std::string& world, const StoreOptions& o) override {
        SqliteStoreCreateInfo info;
        info.path = world;
        info.read_only = o.read_only;
        info.max_pending_age = o.max_pending_age;
        info.max_pending_bytes = o.max_pending_bytes;
        auto s = SqliteStore::open(info);
        EXPECT_TRUE(s.ok()) << s.error();
        return s.ok() ? std::move(*s) : nullptr;
    }
    void write_raw(const std::string& world, ChunkCoord c, const std::vector<uint8_t>& bytes) override {
        exec(world, "UPDATE chunks SET data=?4 WHERE x=?1 AND y=?2 AND z=?3", c, &bytes);
    }
    void write_raw_lod(const std::string& world, LodCoord c, const std::vector<uint8_t>& bytes) override {
        const std::string sql = "UPDATE lod_chunks SET data=?4 WHERE x=?1 AND y=?2 AND z=?3 AND level=" +
                                std::to_string(c.level);
        exec(world, sql.c_str(), c.chunk, &bytes);
    }
    std::vector<uint8_t> quarantined(const std::string& world, ChunkCoord c) override {
        std::vector<uint8_t> out;
        exec(world, "SELECT data FROM quarantine WHERE x=?1 AND y=?2 AND z=?3 ORDER BY id DESC LIMIT 1", c, nullptr,
             &out);
        return out;
    }
    uint64_t quarantine_count(const std::string& world) override {
        auto check = check_store(world);
        return check.ok() ? check->quarantined : ~0ull;
    }

private:
    static void exec(const std::string& path, const char* sql, ChunkCoord c, const std::vector<uint8_t>* blob,
                     std::vector<uint8_t>* out = nullptr) {
        sqlite3* db = nullptr;
        ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
        sqlite3_stmt* st = nullptr;
        ASSERT_EQ(sqlite3_prepare_v2(db, sql, -1, &st, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
        sqlite3_bind_int64(st, 1, c.x);
        sqlite3_bind_int64(st, 2, c.y);
        sqlite3_bind_int64(st, 3, c.z);
        if (blob)
            sqlite3_bind_blob(st, 4, blob->data(), int(blob->size()), SQLITE_TRANSIENT);
        const int rc = sqlite3_step(st);
        if (out && rc == SQLITE_ROW) {
            const auto* p = static_cast<const uint8_t*>(sqlite3_column_blob(st, 0));
            out->assign(p, p + sqlite3_column_bytes(st, 0));
        } else {
            EXPECT_EQ(rc, out ? SQLITE_ROW : SQLITE_DONE) << sqlite3_errmsg(db);
        }
        if (!out && blob) {
            EXPECT_EQ(sqlite3_changes(db), 1) << sql;
        }
        sqlite3_finalize(st);
        sqlite3_close(db);
    }
    TempDir m_dir;
    int m_worlds = 0;
};

class PgBackend final : public StoreBackend {
public:
    std::string unavailable() const override {
        std::string why;
        return PgCluster::get(&why) ? std::string() : why;
    }
    std::string new_world() override { return PgCluster::get()->new_database(); }
    std::unique_ptr<ChunkStore> open(const std::string& world, const StoreOptions& o) override {
        PgStoreCreateInfo info;
        info.uri = world;
        info.read_only = o.read_only;
        info.max_pending_age = o.max_pending_age;
        info.max_pending_bytes = o.max_pending_bytes;
        auto s = PgStore::open(info);
        EXPECT_TRUE(s.ok()) << s.error();
        return s.ok() ? std::move(*s) : nullptr;
    }
    void write_raw(const std::string& world, ChunkCoord c, const std::vector<uint8_t>& bytes) override {
        const std::string sql = "UPDATE vx_chunks SET data=$1 WHERE x=" + std::to_string(c.x) +
                                " AND y=" + std::to_string(c.y) + " AND z=" + std::to_string(c.z);
        const char* values[] = {reinterpret_cast<const char*>(bytes.data())};
        const int lengths[] = {int(bytes.size())}, formats[] = {1};
        PGconn* conn = PQconnectdb(world.c_str());
        PGresult* r = PQexecParams(conn, sql.c_str(), 1, nullptr, values, lengths, formats, 1);
        EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(conn);
        EXPECT_STREQ(PQcmdTuples(r), "1");
        PQclear(r);
        PQfinish(conn);
    }
    void write_raw_lod(const std::string& world, LodCoord c, const std::vector<uint8_t>& bytes) override {
        const std::string sql = "UPDATE vx_lod_chunks SET data=$1 WHERE level=" + std::to_string(c.level) +
                                " AND x=" + std::to_string(c.chunk.x) + " AND y=" + std::to_string(c.chunk.y) +
                                " AND z=" + std::to_string(c.chunk.z);
        const char* values[] = {reinterpret_cast<const char*>(bytes.data())};
        const int lengths[] = {int(bytes.size())}, formats[] = {1};
        PGconn* conn = PQconnectdb(world.c_str());
        PGresult* r = PQexecParams(conn, sql.c_str(), 1, nullptr, values, lengths, formats, 1);
        EXPECT_EQ(PQresultStatus(r), PGRES_COMMAND_OK) << PQerrorMessage(conn);
        EXPECT_STREQ(PQcmdTuples(r), "1");
        PQclear(r);
        PQfinish(conn);
    }
    std::vector<uint8_t> quarantined(const std::string& world, ChunkCoord c) override {
        const std::string sql = "SELECT data FROM vx_quarantine WHERE x=" + std::to_string(c.x) +
                                " AND y=" + std::to_string(c.y) + " AND z=" + std::to_string(c.z) +
                                " ORDER BY id DESC LIMIT 1";
        std::vector<uint8_t> out;
        PGconn* conn = PQconnectdb(world.c_str());
        PGresult* r = PQexecParams(conn, sql.c_str(), 0, nullptr, nullptr, nullptr, nullptr, 1);
        if (PQresultStatus(r) == PGRES_TUPLES_OK && PQntuples(r) == 1) {
            const auto* p = reinterpret_cast<const uint8_t*>(PQgetvalue(r, 0, 0));
            out.assign(p, p + PQgetlength(r, 0, 0));
        }
        PQclear(r);
        PQfinish(conn);
        return out;
    }
    // Level 0 and coarse quarantines (the latter's table exists once a coarse chunk was saved).
    uint64_t quarantine_count(const std::string& world) override {
        PGconn* conn = PQconnectdb(world.c_str());
        auto count = [&](const char* sql) {
            PGresult* r = PQexec(conn, sql);
            const uint64_t n = PQresultStatus(r) == PGRES_TUPLES_OK ? std::strtoull(PQgetvalue(r, 0, 0), nullptr, 10)
                                                                     : ~0ull;
            PQclear(r);
            return n;
        };
        uint64_t n = count("SELECT count(*) FROM vx_quarantine");
        if (n != ~0ull && count("SELECT count(*) FROM pg_tables WHERE tablename = 'vx_lod_quarantine'") == 1) {
            const uint64_t lod = count("SELECT count(*) FROM vx_lod_quarantine");
            n = lod == ~0ull ? lod : n + lod;
        }
        PQfinish(conn);
        return n;
    }
};

inline std::unique_ptr<StoreBackend> make_backend(const std::string& name) {
    if (name == "sqlite")
        return std::make_unique<SqliteBackend>();
    return std::make_unique<PgBackend>();
}

// Fixture of the suite: GetParam() names the backend.
class StoreSuite : public ::testing::TestWithParam<std::string> {
protected:
    void SetUp() override {
        m_backend = make_backend(GetParam());
        if (std::string why = m_backend->unavailable(); !why.empty())
            GTEST_SKIP() << GetParam() << " store tests skipped: " << why;
    }
    StoreBackend& backend() { return *m_backend; }

private:
    std::unique_ptr<StoreBackend> m_backend;
};

} // namespace vx::world::test
