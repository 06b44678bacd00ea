#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <grp.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_util.h"
#include "store_test_util.h"
#include "world/store/sqlite_store.h"

using namespace vx::world;
using vx::world::test::TempDir;
using vx::world::test::versioned_chunk;

namespace {

std::unique_ptr<SqliteStore> open_store(const std::string& path, bool read_only = false) {
    SqliteStoreCreateInfo info;
    info.path = path;
    info.read_only = read_only;
    vx::Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
    EXPECT_TRUE(s.ok()) << s.error();
    return s.ok() ? std::move(*s) : nullptr;
}

std::string open_error(const SqliteStoreCreateInfo& info) {
    vx::Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
    EXPECT_FALSE(s.ok());
    return s.ok() ? std::string() : s.error();
}

void expect_chunk(SqliteStore& store, ChunkCoord c, const Chunk& want) {
    vx::Result<ChunkLoad> r = store.load(c);
    ASSERT_TRUE(r.ok()) << r.error();
    ASSERT_EQ(r->state, LoadState::Present) << r->problem;
    EXPECT_TRUE(*r->chunk == want);
}

// Runs one SQL statement with an optional blob parameter straight on the database file.
void raw_sql(const std::string& path, const char* sql, const std::vector<uint8_t>* blob = nullptr) {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, sql, -1, &st, nullptr), SQLITE_OK) << sqlite3_errmsg(db);
    if (blob)
        sqlite3_bind_blob(st, 1, blob->data(), int(blob->size()), SQLITE_TRANSIENT);
    EXPECT_EQ(sqlite3_step(st), SQLITE_DONE) << sqlite3_errmsg(db);
    sqlite3_finalize(st);
    sqlite3_close(db);
}

} // namespace

TEST(SqliteStore, SavesLoadsAndSurvivesReopen) {
    TempDir dir;
    const std::string path = dir.file("world.db");
    std::mt19937 rng(1);
    std::vector<std::pair<ChunkCoord, Chunk>> chunks;
    for (int i = 0; i < 40; ++i)
        chunks.emplace_back(ChunkCoord(i - 20, (i * 7) % 5 - 2, -i * 1000), test::random_chunk(rng, 0.3, 1 + i));
    chunks.emplace_back(ChunkCoord(INT32_MIN, INT32_MAX, 0), Chunk(3));
    {
        auto store = open_store(path);
        ASSERT_TRUE(store);
        std::vector<ChunkWrite> batch;
        for (auto& [c, chunk] : chunks)
            batch.push_back({c, &chunk});
        ASSERT_TRUE(store->save(batch).ok());
        EXPECT_EQ(store->pending_edits(), chunks.size());
        for (auto& [c, chunk] : chunks) // Queued edits read back before any commit.
            expect_chunk(*store, c, chunk);
        ASSERT_TRUE(store->set_meta("seed", "12345").ok());
        ASSERT_TRUE(store->flush().ok());
        EXPECT_EQ(store->pending_edits(), 0u);
        EXPECT_TRUE(*store->contains(chunks[0].first));
        EXPECT_FALSE(*store->contains({99, 99, 99}));
        vx::Result<ChunkLoad> absent = store->load({99, 99, 99});
        ASSERT_TRUE(absent.ok());
        EXPECT_EQ(absent->state, LoadState::Absent);
    }
    auto store = open_store(path);
    ASSERT_TRUE(store);
    for (auto& [c, chunk] : chunks)
        expect_chunk(*store, c, chunk);
    EXPECT_EQ(*store->count(), chunks.size());
    vx::Result<std::vector<ChunkCoord>> coords = store->list_coords();
    ASSERT_TRUE(coords.ok());
    EXPECT_EQ(coords->size(), chunks.size());
    for (auto& [c, chunk] : chunks)
        EXPECT_NE(std::find(coords->begin(), coords->end(), c), coords->end());
    EXPECT_EQ(**store->get_meta("seed"), "12345");
    EXPECT_FALSE(store->get_meta("nothing")->has_value());
}

TEST(SqliteStore, OverwritesEraseAndCloseWithoutFlushCommit) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        ASSERT_TRUE(store);
        ASSERT_TRUE(store->save({1, 1, 1}, versioned_chunk({1, 1, 1}, 1)).ok());
        ASSERT_TRUE(store->save({2, 2, 2}, versioned_chunk({2, 2, 2}, 1)).ok());
        ASSERT_TRUE(store->flush().ok());
        ASSERT_TRUE(store->save({1, 1, 1}, versioned_chunk({1, 1, 1}, 2)).ok());
        ASSERT_TRUE(store->erase({2, 2, 2}).ok());
        EXPECT_FALSE(*store->contains({2, 2, 2}));
        EXPECT_EQ(store->load({2, 2, 2})->state, LoadState::Absent);
    } // The destructor commits the queue.
    auto store = open_store(path);
    ASSERT_TRUE(store);
    expect_chunk(*store, {1, 1, 1}, versioned_chunk({1, 1, 1}, 2));
    EXPECT_EQ(store->load({2, 2, 2})->state, LoadState::Absent);
    EXPECT_EQ(*store->count(), 1u);
}

TEST(SqliteStore, TickCommitsOnlyEditsOlderThanTheBound) {
    TempDir dir;
    SqliteStoreCreateInfo info;
    info.path = dir.file("w.db");
    info.max_pending_age = std::chrono::seconds(2);
    auto store = std::move(*SqliteStore::open(info));
    ASSERT_TRUE(store->save({0, 0, 0}, Chunk(1)).ok());
    // A time before the save: the edit is younger than 2 s there, so nothing commits.
    ASSERT_TRUE(store->tick(ChunkStore::Clock::time_point{}).ok());
    EXPECT_EQ(store->pending_edits(), 1u);
    // Another connection sees nothing yet.
    EXPECT_EQ(check_store(info.path)->records, 0u);
    ASSERT_TRUE(store->tick(ChunkStore::Clock::now() + std::chrono::seconds(3)).ok());
    EXPECT_EQ(store->pending_edits(), 0u);
    EXPECT_EQ(check_store(info.path)->records, 1u);
}

TEST(SqliteStore, SaveCommitsWhenTheQueueIsTooBig) {
    TempDir dir;
    SqliteStoreCreateInfo info;
    info.path = dir.file("w.db");
    info.max_pending_bytes = 4096; // About two terrain-like records.
    auto store = std::move(*SqliteStore::open(info));
    for (int i = 0; i < 10; ++i)
        ASSERT_TRUE(store->save({i, 0, 0}, versioned_chunk({i, 0, 0}, 5)).ok());
    EXPECT_LT(store->pending_edits(), 10u);
    EXPECT_GT(check_store(info.path)->records, 0u);
}

TEST(SqliteStore, CorruptRecordIsQuarantinedReportedAndNotLost) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    const Chunk a = versioned_chunk({1, 0, 0}, 3), b = versioned_chunk({2, 0, 0}, 3);
    {
        auto store = open_store(path);
        ASSERT_TRUE(store->save({1, 0, 0}, a).ok());
        ASSERT_TRUE(store->save({2, 0, 0}, b).ok());
        ASSERT_TRUE(store->save({3, 0, 0}, Chunk(5)).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    // Flip one payload bit of (1,0,0); file (2,0,0)'s record under (3,0,0) too.
    std::vector<uint8_t> bad = encode_chunk_record({1, 0, 0}, a);
    bad[bad.size() / 2] ^= 0x10;
    raw_sql(path, "UPDATE chunks SET data=?1 WHERE x=1", &bad);
    const std::vector<uint8_t> moved = encode_chunk_record({2, 0, 0}, b);
    raw_sql(path, "UPDATE chunks SET data=?1 WHERE x=3", &moved);

    vx::Result<StoreCheck> before = check_store(path);
    ASSERT_TRUE(before.ok()) << before.error();
    EXPECT_EQ(before->records, 3u);
    EXPECT_EQ(before->corrupt, 2u);
    EXPECT_TRUE(before->database_ok);
    {
        auto store = open_store(path);
        vx::Result<ChunkLoad> r = store->load({1, 0, 0});
        ASSERT_TRUE(r.ok());
        EXPECT_EQ(r->state, LoadState::Corrupt);
        EXPECT_NE(r->problem.find("checksum"), std::string::npos) << r->problem;
        r = store->load({3, 0, 0});
        ASSERT_TRUE(r.ok());
        EXPECT_EQ(r->state, LoadState::Corrupt);
        EXPECT_NE(r->problem.find("filed under"), std::string::npos) << r->problem;
        expect_chunk(*store, {2, 0, 0}, b);
        // Moved aside: the coordinates now read as absent and can be regenerated.
        EXPECT_EQ(store->load({1, 0, 0})->state, LoadState::Absent);
        EXPECT_EQ(*store->quarantine_count(), 2u);
        EXPECT_EQ(*store->count(), 1u);
    }
    vx::Result<StoreCheck> after = check_store(path);
    ASSERT_TRUE(after.ok());
    EXPECT_EQ(after->records, 1u);
    EXPECT_EQ(after->corrupt, 0u);
    EXPECT_EQ(after->quarantined, 2u);
    // The quarantined bytes are kept verbatim.
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* st = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "SELECT data FROM quarantine WHERE x=1", -1, &st, nullptr), SQLITE_OK);
    ASSERT_EQ(sqlite3_step(st), SQLITE_ROW);
    const auto* p = static_cast<const uint8_t*>(sqlite3_column_blob(st, 0));
    EXPECT_EQ(std::vector<uint8_t>(p, p + sqlite3_column_bytes(st, 0)), bad);
    sqlite3_finalize(st);
    sqlite3_close(db);
}

TEST(SqliteStore, ReadOnlyStoreReportsCorruptionWithoutMovingIt) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        ASSERT_TRUE(store->save({1, 0, 0}, Chunk(2)).ok());
    }
    raw_sql(path, "UPDATE chunks SET data=x'00112233'");
    auto store = open_store(path, true);
    ASSERT_TRUE(store);
    EXPECT_EQ(store->load({1, 0, 0})->state, LoadState::Corrupt);
    EXPECT_EQ(store->load({1, 0, 0})->state, LoadState::Corrupt);
    EXPECT_FALSE(store->save({1, 0, 0}, Chunk(1)).ok());
    EXPECT_FALSE(store->set_meta("k", "v").ok());
    EXPECT_EQ(*store->quarantine_count(), 0u);
}

TEST(SqliteStoreErrors, BadPathsAndFilesGiveClearErrors) {
    TempDir dir;
    SqliteStoreCreateInfo info;
    info.path = dir.file("missing_dir/w.db");
    EXPECT_NE(open_error(info).find("missing_dir/w.db"), std::string::npos);
    info.path = dir.file("absent.db");
    info.create = false;
    EXPECT_NE(open_error(info).find("cannot open"), std::string::npos);
    info.read_only = true;
    EXPECT_NE(open_error(info).find("cannot open"), std::string::npos);

    info = {};
    info.path = dir.file("garbage.db");
    {
        std::ofstream f(info.path, std::ios::binary);
        std::mt19937 rng(4);
        for (int i = 0; i < 8192; ++i)
            f.put(char(rng()));
    }
    EXPECT_NE(open_error(info).find("not a database"), std::string::npos);
    EXPECT_FALSE(check_store(info.path).ok());

    info.path = dir.file("other.db");
    raw_sql(info.path, "CREATE TABLE songs(title TEXT)");
    EXPECT_NE(open_error(info).find("not a vx world store"), std::string::npos);

    info.path = dir.file("empty.db"); // A new store opened read-only is refused, not created.
    info.read_only = true;
    open_error(info);
}

// Opens the store in a forked child and returns "opened" or the error. Root ignores file
// permissions, so as root (README and CI run so) the child first drops to the unprivileged
// uid/gid 65534 ("nobody"); any other user opens as itself.
std::string open_in_unprivileged_child(const SqliteStoreCreateInfo& info) {
    int fds[2];
    if (pipe(fds) != 0)
        return "pipe failed";
    const pid_t pid = fork();
    if (pid == 0) {
        close(fds[0]);
        constexpr uid_t kNobody = 65534;
        std::string message;
        if (geteuid() == 0 && (setgroups(0, nullptr) != 0 || setgid(kNobody) != 0 || setuid(kNobody) != 0))
            message = "could not drop privileges";
        else if (access(info.path.c_str(), W_OK) == 0)
            message = "the test's file is writable by uid " + std::to_string(geteuid());
        else {
            vx::Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
            message = s.ok() ? "opened" : s.error();
        }
        const ssize_t written = write(fds[1], message.data(), message.size());
        _exit(written == ssize_t(message.size()) ? 0 : 1);
    }
    close(fds[1]);
    std::string message;
    char buf[512];
    for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) > 0;)
        message.append(buf, size_t(n));
    close(fds[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
    return message;
}

TEST(SqliteStoreErrors, ReadOnlyFileIsRefusedForWriting) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        ASSERT_TRUE(store->save({0, 0, 0}, Chunk(1)).ok());
    }
    ASSERT_EQ(chmod(path.c_str(), 0444), 0);
    // The folder is open to the child (mkdtemp made it 0700), as for a user whose one file is
    // read-only in a folder of their own.
    ASSERT_EQ(chmod(dir.path().c_str(), 0777), 0);
    SqliteStoreCreateInfo info;
    info.path = path;
    const std::string refused = open_in_unprivileged_child(info);
    EXPECT_NE(refused.find("the file is read-only"), std::string::npos) << refused;
    info.read_only = true; // Control: the same child may read it.
    EXPECT_EQ(open_in_unprivileged_child(info), "opened");
}

TEST(SqliteStoreErrors, DamagedDatabaseFileNeverCrashes) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        std::vector<Chunk> chunks;
        for (int i = 0; i < 200; ++i)
            chunks.push_back(versioned_chunk({i, 0, 0}, 1));
        for (int i = 0; i < 200; ++i)
            ASSERT_TRUE(store->save({i, 0, 0}, chunks[size_t(i)]).ok());
    }
    // Overwrite everything after the first page (header and schema) with garbage.
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(0, std::ios::end);
        const std::streamoff size = f.tellg();
        ASSERT_GT(size, 8192);
        std::mt19937 rng(2);
        f.seekp(4096);
        for (std::streamoff i = 4096; i < size; ++i)
            f.put(char(rng()));
    }
    vx::Result<StoreCheck> check = check_store(path);
    EXPECT_TRUE(!check.ok() || !check->database_ok || check->corrupt > 0);
    SqliteStoreCreateInfo info;
    info.path = path;
    vx::Result<std::unique_ptr<SqliteStore>> s = SqliteStore::open(info);
    if (s.ok()) { // Opening may succeed; then reads fail cleanly or report corrupt records.
        int bad = 0;
        for (int i = 0; i < 200; ++i) {
            vx::Result<ChunkLoad> r = (*s)->load({i, 0, 0});
            bad += !r.ok() || r->state != LoadState::Present;
        }
        EXPECT_GT(bad, 0);
    }
}
