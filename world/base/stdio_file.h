#pragma once
// An owned C stdio file and its checked close, for every whole-file writer (raw volumes, OBJ
// exports, PNG images). Any thread; one file per owner.

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

#include "world/base/result.h"

namespace vx::world {

struct StdioFileCloser {
    // Files only read, and written files left on an error path: a close's error adds nothing there.
    // A written file that succeeded is closed by close_written, which checks it.
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using StdioFile = std::unique_ptr<std::FILE, StdioFileCloser>;

// Flushes and closes `f`, a file written to `path`. A write the disk refused (ENOSPC shows at the
// flush, or as the stream's error flag) and a failing close (NFS and quotas report a lost write
// there; POSIX close(2), EIO) are both errors naming the file and the cause.
inline Status close_written(StdioFile f, const std::string& path) {
    const bool write_failed = std::fflush(f.get()) != 0 || std::ferror(f.get()) != 0;
    const int write_errno = errno;
    const bool close_failed = std::fclose(f.release()) != 0;
    if (write_failed)
        return Error{"write to '" + path + "' failed: " + std::strerror(write_errno)};
    if (close_failed)
        return Error{"closing '" + path + "' failed: " + std::strerror(errno)};
    return {};
}

} // namespace vx::world
