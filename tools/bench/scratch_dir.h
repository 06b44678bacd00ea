#pragma once
// A folder a benchmark makes for its files and removes whole when done. It is always new
// (mkdtemp(3): base/prefix-XXXXXX, made by this call and by no one else), so removing it can
// never take a file the run did not make: not the user's folder named as the place for scratch
// files, and not /tmp when $TMPDIR is unusable (`vx bench store` once fell back to /tmp itself and
// removed it at exit). Main thread; one owner.

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

#include "world/base/result.h"

namespace vx::tools {

class ScratchDir {
public:
    // Makes a new folder `prefix` + "-XXXXXX" in `base` (empty: $TMPDIR, else /tmp). The error
    // names the base and the cause (a missing folder, a file, no permission).
    static Result<ScratchDir> make(const std::string& prefix, std::string base = "") {
        if (base.empty()) {
            const char* env = std::getenv("TMPDIR");
            base = env && *env ? env : "/tmp";
        }
        std::string name = base + "/" + prefix + "-XXXXXX";
        if (!::mkdtemp(name.data()))
            return Error{"cannot make a scratch folder in '" + base + "': " + std::strerror(errno)};
        ScratchDir d;
        d.m_path = std::move(name);
        return d;
    }

    ScratchDir() = default;
    ScratchDir(ScratchDir&& other) noexcept : m_path(std::exchange(other.m_path, {})) {}
    ScratchDir& operator=(ScratchDir&& other) noexcept {
        if (this != &other) {
            remove();
            m_path = std::exchange(other.m_path, {});
        }
        return *this;
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir() { remove(); }

    // The folder; empty for a moved-from or default one.
    const std::string& path() const { return m_path; }

private:
    void remove() {
        if (m_path.empty())
            return;
        std::error_code ec; // Best effort: a file still open elsewhere may keep it.
        std::filesystem::remove_all(m_path, ec);
        m_path.clear();
    }

    std::string m_path;
};

} // namespace vx::tools
