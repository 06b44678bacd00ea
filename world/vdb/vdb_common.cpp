#include "world/vdb/vdb_common.h"

#include <atomic>
#include <filesystem>
#include <system_error>

#include <unistd.h>

#include <tbb/task_arena.h>

namespace vx::vdb::detail {

Error make_error(std::string_view context, std::string_view what) {
    std::string msg(context);
    if (!what.empty())
        msg += ": ";
    for (size_t i = 0; i < what.size(); ++i) {
        const char c = what[i];
        if (c == '\x1b') { // Skip ANSI colour sequences ("\x1b[31m").
            while (i < what.size() && what[i] != 'm')
                ++i;
            continue;
        }
        msg += (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
    }
    while (!msg.empty() && msg.back() == ' ')
        msg.pop_back();
    return Error{msg};
}

std::string temp_path_beside(const std::string& path) {
    static std::atomic<uint64_t> counter{0};
    return path + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
}

Status replace_file(const std::string& from, const std::string& to) {
    std::error_code ec;
    std::filesystem::rename(from, to, ec);
    if (ec) {
        std::filesystem::remove(from, ec);
        return make_error("cannot rename '" + from + "' to '" + to + "'", ec.message());
    }
    return {};
}

void run_in_calling_thread(const std::function<void()>& f) {
    // One slot, reserved for this thread: the arena never asks TBB for workers.
    tbb::task_arena arena(1, 1);
    arena.execute(f);
}

} // namespace vx::vdb::detail
