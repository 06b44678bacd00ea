#pragma once
// One writer per file: an exclusive advisory lock (flock(2)) on a lock file beside it, held for
// the owner's lifetime and dropped by the kernel when the process dies (kill -9 leaves nothing
// stale). A second writer, in this process or another, is refused at once instead of each
// saving its own copy of the same chunks (the last save wins; the other's edits, reported saved,
// are gone).
//
// The lock is on "<path>-lock", not on the file itself: closing any descriptor of a file drops
// the process's POSIX (fcntl) locks on it, and SQLite keeps its own locks that way. The lock file
// stays after the owner closes it: removing it would let a waiting writer lock a removed file
// while a third one locks a new file of the same name.
//
// Move-only; any thread (one owner).

#include <string>

#include "world/base/result.h"

namespace vx::world {

class FileLock {
public:
    // Locks "<path>-lock" (created if missing, mode 0666 less the umask). Errors, one line naming
    // `path`: another writer holds it, or the lock file cannot be made (folder missing or
    // read-only).
    static Result<FileLock> acquire(const std::string& path);

    FileLock() = default;
    FileLock(FileLock&& o) noexcept;
    FileLock& operator=(FileLock&& o) noexcept;
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;
    ~FileLock(); // Unlocks.

    bool held() const { return m_fd >= 0; }

private:
    explicit FileLock(int fd) : m_fd(fd) {}
    int m_fd = -1;
};

// The lock file of `path`: the file's own path (symbolic links resolved) + "-lock". Hard links
// are not resolved: two names of one file have two locks.
std::string lock_file_of(const std::string& path);

} // namespace vx::world
