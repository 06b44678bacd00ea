#include "world/base/file_lock.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <utility>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace vx::world {

std::string lock_file_of(const std::string& path) {
    // Beside the file itself: a symbolic link to a world (or a path through one) names the same
    // lock as the world's own path, so a writer through the link is refused too.
    std::error_code ec;
    const std::filesystem::path real = std::filesystem::weakly_canonical(path, ec);
    return (ec ? path : real.string()) + "-lock";
}

Result<FileLock> FileLock::acquire(const std::string& path) {
    const std::string lock = lock_file_of(path);
    int fd = -1;
    do
        fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    while (fd < 0 && errno == EINTR);
    if (fd < 0)
        return Error{"'" + path + "': cannot open its lock file '" + lock + "': " + std::strerror(errno)};
    int r = 0;
    do
        r = ::flock(fd, LOCK_EX | LOCK_NB);
    while (r != 0 && errno == EINTR);
    if (r != 0) {
        const int err = errno;
        ::close(fd);
        if (err == EWOULDBLOCK)
            return Error{"'" + path + "' is open for writing elsewhere (another process, or another store in this "
                         "one); one writer at a time (a world shared by several needs PostgreSQL)"};
        return Error{"'" + path + "': cannot lock '" + lock + "': " + std::strerror(err)};
    }
    return FileLock(fd);
}

FileLock::FileLock(FileLock&& o) noexcept : m_fd(std::exchange(o.m_fd, -1)) {}

FileLock& FileLock::operator=(FileLock&& o) noexcept {
    if (this != &o) {
        if (m_fd >= 0)
            ::close(m_fd);
        m_fd = std::exchange(o.m_fd, -1);
    }
    return *this;
}

FileLock::~FileLock() {
    if (m_fd >= 0)
        ::close(m_fd); // Closing the only descriptor of this open file drops the flock.
}

} // namespace vx::world
