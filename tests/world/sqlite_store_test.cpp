#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <grp.h>
#include <sys/resource.h>
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

// The backend-independent store tests (round trips, write model, corruption, read-only) are in
// store_suite_test.cpp, run over SQLite and PostgreSQL alike; these are SQLite-specific.

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
    const std::string refused = open_error(info);
    EXPECT_NE(refused.find("cannot open"), std::string::npos) << refused;
    EXPECT_NE(refused.find("empty.db"), std::string::npos) << refused;
    EXPECT_FALSE(std::filesystem::exists(info.path)) << "a read-only open created the file";
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

// Rows whose keys name no chunk (written by something else) are counted by --check as damaged and
// listed nowhere: cast to 32 bits, x + 2^32 named chunk x, and text keys read as numbers,
// so the check loaded the real chunks and passed.
TEST(SqliteStoreErrors, RowsWhoseKeysNameNoChunkAreStrayNotAliases) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        ASSERT_TRUE(store->save({7, 0, 0}, versioned_chunk({7, 0, 0}, 1)).ok());
        ASSERT_TRUE(store->save_lod({1, {3, 0, 0}}, versioned_chunk({3, 0, 0}, 2)).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    for (const char* sql : {"INSERT INTO chunks(x, y, z, data) VALUES(7 + 4294967296, 0, 0, x'00')",
                            "INSERT INTO chunks(x, y, z, data) VALUES('seven', 1, 0, x'00')",
                            "INSERT INTO lod_chunks(level, x, y, z, data) VALUES(1 + 4294967296, 3, 0, 0, x'00')",
                            "INSERT INTO lod_chunks(level, x, y, z, data) VALUES(11, 3, 0, 0, x'00')"})
        ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sql << ": " << sqlite3_errmsg(db);
    sqlite3_close(db);
    vx::Result<StoreCheck> check = check_store(path);
    ASSERT_TRUE(check.ok()) << check.error();
    EXPECT_EQ(check->records, 6u);
    EXPECT_EQ(check->corrupt, 4u);
    auto store = open_store(path);
    vx::Result<uint64_t> stray = store->stray_rows();
    ASSERT_TRUE(stray.ok()) << stray.error();
    EXPECT_EQ(*stray, 4u);
    vx::Result<std::vector<ChunkCoord>> coords = store->list_coords();
    ASSERT_TRUE(coords.ok());
    EXPECT_EQ(*coords, std::vector<ChunkCoord>{ChunkCoord(7, 0, 0)});
    vx::Result<std::vector<LodCoord>> lods = store->list_lod_coords();
    ASSERT_TRUE(lods.ok());
    EXPECT_EQ(lods->size(), 1u);
}

// A row far longer than any record is damaged by its length alone, read without its bytes: a
// 300 MB row was read whole (and held) before the length check failed it.
TEST(SqliteStoreErrors, AnOversizedRowIsDamagedWithoutBeingRead) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto store = open_store(path);
        ASSERT_TRUE(store->save({1, 0, 0}, versioned_chunk({1, 0, 0}, 1)).ok());
        ASSERT_TRUE(store->flush().ok());
    }
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "INSERT INTO chunks(x, y, z, data) VALUES(2, 0, 0, zeroblob(64 * 1024 * 1024))", nullptr,
                           nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
    SqliteStoreCreateInfo info;
    info.path = path;
    info.read_only = true; // Nothing moved: only the read is measured.
    info.create = false;
    auto store = SqliteStore::open(info);
    ASSERT_TRUE(store.ok()) << store.error();
    sqlite3_int64 now = 0, peak = 0;
    sqlite3_status64(SQLITE_STATUS_MEMORY_USED, &now, &peak, 1);
    vx::Result<ChunkLoad> r = (*store)->load({2, 0, 0});
    sqlite3_status64(SQLITE_STATUS_MEMORY_USED, &now, &peak, 0);
    ASSERT_TRUE(r.ok()) << r.error();
    EXPECT_EQ(r->state, LoadState::Corrupt);
    EXPECT_NE(r->problem.find("too long (67108864 bytes)"), std::string::npos) << r->problem;
    EXPECT_LT(peak, sqlite3_int64(16) << 20) << "bytes SQLite held while loading";
    vx::Result<ChunkLoad> good = (*store)->load({1, 0, 0});
    ASSERT_TRUE(good.ok());
    EXPECT_EQ(good->state, LoadState::Present);
}

// The world file deleted, or replaced by another file, while the store has it open: SQLite keeps
// writing to the old inode, so every later commit succeeded into a file no one can open again
// and a save reported durable was lost. Now the flush fails, and the queue is kept.
TEST(SqliteStoreErrors, AFileDeletedOrReplacedWhileOpenFailsItsFlushes) {
    for (const bool replace : {false, true}) {
        TempDir dir;
        const std::string path = dir.file("w.db");
        auto store = open_store(path);
        ASSERT_NE(store, nullptr);
        ASSERT_TRUE(store->save({1, 0, 0}, versioned_chunk({1, 0, 0}, 1)).ok());
        ASSERT_TRUE(store->flush().ok());
        for (const char* suffix : {"", "-wal", "-shm"})
            std::filesystem::remove(path + suffix);
        if (replace)
            std::ofstream(path) << "another file";
        ASSERT_TRUE(store->save({2, 0, 0}, versioned_chunk({2, 0, 0}, 2)).ok());
        const vx::Status s = store->flush();
        ASSERT_FALSE(s.ok()) << replace;
        EXPECT_NE(s.error().find("deleted or replaced while open"), std::string::npos) << s.error();
        EXPECT_GT(store->pending_edits(), 0u) << "the queue is kept";
        EXPECT_EQ(store->health().pending_edits, store->pending_edits()) << "what a game's stats show";
    }
}

// A chunk of random blocks: its record does not compress, so a few of them fill a disk.
Chunk noise_chunk(uint32_t seed) {
    std::mt19937 rng{seed};
    Chunk c;
    for (int i = 0; i < kChunkVolume; ++i)
        c.set(i, BlockId(1 + rng() % 250));
    return c;
}

// The disk fills up during a commit (RLIMIT_FSIZE here: writes past it fail with EFBIG, as they
// fail with ENOSPC on a full disk): the flush fails and says why, the edits
// stay queued and in the store's health, earlier commits stay readable; once space returns the
// next flush saves every edit, and the file reopens with all of them.
TEST(SqliteStoreErrors, ADiskFullCommitKeepsItsEditsAndTheNextFlushSavesThem) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    auto store = open_store(path);
    ASSERT_NE(store, nullptr);
    ASSERT_TRUE(store->save({0, 0, 0}, noise_chunk(0)).ok());
    ASSERT_TRUE(store->flush().ok());
    rlimit old{};
    ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
    const auto old_signal = std::signal(SIGXFSZ, SIG_IGN);
    uintmax_t largest = 0;
    for (const char* suffix : {"", "-wal"})
        if (std::filesystem::exists(path + suffix))
            largest = std::max(largest, std::filesystem::file_size(path + suffix));
    rlimit full = old;
    full.rlim_cur = rlim_t(largest + 16 * 1024);
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &full), 0);
    constexpr int kChunks = 12; // About 32 KB each: far past the 16 KB left.
    for (int i = 1; i <= kChunks; ++i)
        ASSERT_TRUE(store->save({i, 0, 0}, noise_chunk(uint32_t(i))).ok());
    const vx::Status failed = store->flush();
    const uint64_t pending = store->pending_edits();
    const StoreHealth health = store->health();
    const vx::Result<ChunkLoad> earlier = store->load({0, 0, 0});
    ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0); // Space again (before any ASSERT can return).
    std::signal(SIGXFSZ, old_signal);
    ASSERT_FALSE(failed.ok()) << "a commit past the file size limit succeeded";
    // What failed (SQLite alone says "disk I/O error"; ENOSPC it calls "database or disk is
    // full"), and that nothing was lost.
    EXPECT_NE(failed.error().find("writing the file failed"), std::string::npos) << failed.error();
    EXPECT_NE(failed.error().find("12 edits kept in memory"), std::string::npos) << failed.error();
    EXPECT_EQ(pending, uint64_t(kChunks)) << "the queue is kept";
    EXPECT_EQ(health.pending_edits, pending);
    ASSERT_TRUE(earlier.ok()) << earlier.error();
    EXPECT_EQ(earlier->state, LoadState::Present);
    const vx::Status saved = store->flush();
    ASSERT_TRUE(saved.ok()) << saved.error();
    EXPECT_EQ(store->pending_edits(), 0u);
    store.reset();
    auto reopened = open_store(path);
    ASSERT_NE(reopened, nullptr);
    for (int i = 0; i <= kChunks; ++i) {
        const vx::Result<ChunkLoad> r = reopened->load({i, 0, 0});
        ASSERT_TRUE(r.ok()) << r.error();
        ASSERT_EQ(r->state, LoadState::Present) << i;
        EXPECT_TRUE(*r->chunk == noise_chunk(uint32_t(i))) << i;
    }
}

// health() (thread-safe, what Stats::store_pending_edits shows) follows the queue: it read 0 for
// every SQLite world, so a game could not see edits waiting for their commit.
TEST(SqliteStoreErrors, HealthShowsTheEditsWaitingForACommit) {
    TempDir dir;
    auto store = open_store(dir.file("w.db"));
    ASSERT_NE(store, nullptr);
    EXPECT_EQ(store->health().pending_edits, 0u);
    ASSERT_TRUE(store->save({1, 0, 0}, versioned_chunk({1, 0, 0}, 1)).ok());
    ASSERT_TRUE(store->set_meta("k", "v").ok());
    EXPECT_EQ(store->health().pending_edits, 2u);
    ASSERT_TRUE(store->flush().ok());
    EXPECT_EQ(store->health().pending_edits, 0u);
}

// One writer per file. Two writers each saved their own copy of the same chunk, and the last
// save won: the other's edit, reported saved, was gone. A second writer (in this process or
// another) is refused at once; readers are not; a writer killed with SIGKILL leaves no lock.
TEST(SqliteStoreErrors, ASecondWriterIsRefusedReadersAreNot) {
    TempDir dir;
    const std::string path = dir.file("w.db");
    {
        auto first = open_store(path);
        ASSERT_TRUE(first);
        ASSERT_TRUE(first->save({0, 0, 0}, versioned_chunk({0, 0, 0}, 1)).ok());
        ASSERT_TRUE(first->flush().ok());
        const std::string refused = open_error({.path = path});
        EXPECT_NE(refused.find("is open for writing elsewhere"), std::string::npos) << refused;
        EXPECT_NE(refused.find(path), std::string::npos) << refused;
        const std::string link = dir.file("link.db"); // The same file by another name: refused too.
        std::filesystem::create_symlink(path, link);
        const std::string by_link = open_error({.path = link});
        EXPECT_NE(by_link.find("is open for writing elsewhere"), std::string::npos) << by_link;
        auto reader = open_store(path, /*read_only=*/true);
        ASSERT_TRUE(reader);
        EXPECT_EQ(reader->load({0, 0, 0})->state, LoadState::Present);
        std::fflush(nullptr);
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            auto s = SqliteStore::open({.path = path});
            ::_exit(!s && s.error().find("is open for writing elsewhere") != std::string::npos ? 0 : 1);
        }
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "another process opened it for writing";
    }
    // Closed: the next writer opens. Then a writer in a child that is killed: its lock goes with it.
    ASSERT_TRUE(open_store(path));
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        auto s = SqliteStore::open({.path = path});
        const char c = s ? 'y' : 'n';
        (void)!::write(ready[1], &c, 1);
        ::pause();
        ::_exit(0);
    }
    char c = 0;
    ASSERT_EQ(::read(ready[0], &c, 1), 1);
    EXPECT_EQ(c, 'y');
    EXPECT_NE(open_error({.path = path}).find("is open for writing elsewhere"), std::string::npos);
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    ::close(ready[0]);
    ::close(ready[1]);
    auto after = open_store(path);
    ASSERT_TRUE(after);
    EXPECT_EQ(after->load({0, 0, 0})->state, LoadState::Present);
}
