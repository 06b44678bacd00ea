#include "world/base/file_replace.h"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>
#include <system_error>
#include <utility>

#include <fcntl.h>
#include <unistd.h>

namespace vx::world {

Result<std::string> create_temp_beside(const std::string& path) {
    static std::atomic<uint64_t> counter{0};
    thread_local std::mt19937_64 rng(std::random_device{}() ^ (uint64_t(::getpid()) << 32) ^
                                     counter.fetch_add(1));
    int err = 0;
    for (int attempt = 0; attempt < 64; ++attempt) {
        char suffix[24];
        std::snprintf(suffix, sizeof suffix, ".tmp-%012llx", (unsigned long long)(rng() & 0xFFFFFFFFFFFFull));
        std::string name = path + suffix;
        const int fd = ::open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            return name;
        }
        err = errno;
        if (err != EEXIST)
            break;
    }
    return Error{"cannot create a temporary file beside '" + path + "': " + std::strerror(err)};
}

Status replace_file(const std::string& from, const std::string& to) {
    std::error_code ec;
    std::filesystem::rename(from, to, ec);
    if (ec) {
        const std::string why = ec.message(); // Before remove() reuses ec.
        std::filesystem::remove(from, ec);
        return Error{"cannot rename '" + from + "' to '" + to + "': " + why};
    }
    return {};
}

WriteTarget write_target(const std::string& path) {
    namespace fs = std::filesystem;
    fs::path p = path;
    std::error_code ec;
    for (int hop = 0; hop < 40; ++hop) { // Linux's own limit on links in a path (ELOOP).
        const fs::file_status st = fs::symlink_status(p, ec);
        if (ec || !fs::exists(st))
            return {p.string(), false}; // Absent (or a dangling link's end): created by the rename.
        if (!fs::is_symlink(st))
            return {p.string(), !fs::is_regular_file(st)};
        const fs::path next = fs::read_symlink(p, ec);
        if (ec)
            break;
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    return {path, true}; // A loop: fopen reports it (ELOOP).
}

void keep_permissions(const std::string& temp, const std::string& target) {
    std::error_code ec;
    const std::filesystem::file_status old = std::filesystem::status(target, ec);
    if (!ec && std::filesystem::is_regular_file(old))
        std::filesystem::permissions(temp, old.permissions(), ec);
}

ReplacingFile::ReplacingFile(ReplacingFile&& other) noexcept
    : m_file(std::move(other.m_file)), m_path(std::move(other.m_path)), m_target(std::move(other.m_target)),
      m_temp(std::exchange(other.m_temp, {})), m_finished(std::exchange(other.m_finished, false)) {}

ReplacingFile& ReplacingFile::operator=(ReplacingFile&& other) noexcept {
    if (this != &other) {
        discard();
        m_file = std::move(other.m_file);
        m_path = std::move(other.m_path);
        m_target = std::move(other.m_target);
        m_temp = std::exchange(other.m_temp, {});
        m_finished = std::exchange(other.m_finished, false);
    }
    return *this;
}

ReplacingFile::~ReplacingFile() { discard(); }

void ReplacingFile::discard() {
    m_file.reset();
    m_finished = false;
    if (!m_temp.empty()) {
        std::error_code ec;
        std::filesystem::remove(m_temp, ec);
        m_temp.clear();
    }
}

Status ReplacingFile::open(const std::string& path, const char* mode) {
    discard();
    m_path = path;
    const WriteTarget target = write_target(path);
    m_target = target.path;
    if (!target.in_place) {
        Result<std::string> temp = create_temp_beside(m_target);
        if (!temp)
            return Error{temp.error()}; // It names the path and the cause.
        m_temp = std::move(*temp);
        keep_permissions(m_temp, m_target);
    }
    m_file.reset(std::fopen(target.in_place ? path.c_str() : m_temp.c_str(), mode));
    if (!m_file) {
        const int err = errno;
        discard();
        return Error{"cannot create '" + path + "': " + std::strerror(err)};
    }
    return {};
}

Status ReplacingFile::finish() {
    VX_ASSERT(m_file || m_finished);
    if (m_finished)
        return {};
    if (Status s = close_written(std::move(m_file), m_path); !s) {
        discard();
        return s;
    }
    m_finished = true;
    return {};
}

Status ReplacingFile::commit() {
    if (Status s = finish(); !s)
        return s;
    m_finished = false;
    const std::string temp = std::exchange(m_temp, {});
    return temp.empty() ? Status{} : replace_file(temp, m_target);
}

} // namespace vx::world
