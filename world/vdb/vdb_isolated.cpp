#include "world/vdb/vdb_isolated.h"

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <type_traits>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "world/vdb/vdb_common.h"

namespace vx::vdb {
namespace {

// ---- a tiny byte encoding for the pipe (both ends are this binary: no versioning needed) ----

struct Writer {
    std::string bytes;
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
    void put(const std::string& s) {
        put(uint64_t(s.size()));
        bytes += s;
    }
};

struct Reader {
    const std::string& bytes;
    size_t pos = 0;
    bool ok = true;
    template <class T> void get(T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (pos + sizeof v > bytes.size()) {
            ok = false;
            return;
        }
        std::memcpy(&v, bytes.data() + pos, sizeof v);
        pos += sizeof v;
    }
    void get(std::string& s) {
        uint64_t n = 0;
        get(n);
        if (!ok || n > bytes.size() - pos) {
            ok = false;
            return;
        }
        s.assign(bytes, pos, n);
        pos += n;
    }
};

void encode(Writer& w, const VolumeImportSummary& s) {
    w.put(s.grid_index);
    w.put(s.grid_name);
    w.put(s.mode);
    w.put(s.voxel_size);
    w.put(s.block_size);
    w.put(s.threshold_absolute);
    w.put(s.max_value);
    w.put(s.solid_blocks);
    w.put(s.supersampled_blocks);
    w.put(s.blocks.min);
    w.put(s.blocks.max);
}

void decode(Reader& r, VolumeImportSummary& s) {
    r.get(s.grid_index);
    r.get(s.grid_name);
    r.get(s.mode);
    r.get(s.voxel_size);
    r.get(s.block_size);
    r.get(s.threshold_absolute);
    r.get(s.max_value);
    r.get(s.solid_blocks);
    r.get(s.supersampled_blocks);
    r.get(s.blocks.min);
    r.get(s.blocks.max);
}

void encode(Writer& w, const GridInfo& g) {
    w.put(g.index);
    w.put(g.name);
    w.put(g.value_type);
    w.put(g.grid_class);
    w.put(g.voxel_size);
    w.put(g.transform);
    w.put(g.active_voxels);
    w.put(g.empty);
    w.put(g.bbox_min);
    w.put(g.bbox_max);
    w.put(g.saved_as_half);
}

void decode(Reader& r, GridInfo& g) {
    r.get(g.index);
    r.get(g.name);
    r.get(g.value_type);
    r.get(g.grid_class);
    r.get(g.voxel_size);
    r.get(g.transform);
    r.get(g.active_voxels);
    r.get(g.empty);
    r.get(g.bbox_min);
    r.get(g.bbox_max);
    r.get(g.saved_as_half);
}

// ---- the child ----

// OpenVDB's node destructors allocate (Tree::clear gathers node pointers), so a bad_alloc at the
// memory limit would turn into std::terminate while a half-read tree unwinds. The first failed
// allocation frees this reserve and throws, leaving the unwinding room.
constexpr size_t kReserveBytes = size_t(256) << 20;
void* g_reserve = nullptr;

void release_reserve() {
    std::free(g_reserve);
    g_reserve = nullptr;
    std::set_new_handler(nullptr);
    throw std::bad_alloc();
}

void limit_child(const IsolationOptions& iso) {
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
    if (iso.memory_limit) {
        const rlimit mem{rlim_t(iso.memory_limit), rlim_t(iso.memory_limit)};
        ::setrlimit(RLIMIT_AS, &mem);
    }
#endif
    if (iso.cpu_seconds) {
        // The hard limit a little later: at the hard limit the kernel sends SIGKILL, which would
        // read as a crash; at the soft one SIGXCPU, which names the cap.
        const rlimit cpu{rlim_t(iso.cpu_seconds), rlim_t(iso.cpu_seconds) + 5};
        ::setrlimit(RLIMIT_CPU, &cpu);
    }
    g_reserve = std::malloc(kReserveBytes);
    std::set_new_handler(release_reserve);
}

bool write_all(int fd, const std::string& data) {
    size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return false;
        done += size_t(n);
    }
    return true;
}

std::string read_all(int fd) {
    std::string data;
    char buf[4096];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return data;
        data.append(buf, size_t(n));
    }
}

std::string describe_death(int status, const IsolationOptions& iso) {
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        if (sig == SIGXCPU)
            return std::string("the reader process hit its CPU time limit of ") + std::to_string(iso.cpu_seconds) +
                   " s (raise " + iso.cpu_option + ")";
        return std::string("OpenVDB's reader crashed (") + ::strsignal(sig) + "); the file is probably damaged";
    }
    return "the reader process failed (exit " + std::to_string(WEXITSTATUS(status)) + ")";
}

// The child's error, with the memory cap named when the child ran into it (its reserve is gone).
std::string child_error(const std::string& error, const IsolationOptions& iso) {
    if (g_reserve || !iso.memory_limit)
        return error;
    char cap[32];
    std::snprintf(cap, sizeof cap, "%.3g GiB", double(iso.memory_limit) / double(uint64_t(1) << 30));
    return error + " (the reader hit its memory cap of " + cap + "; raise " + iso.memory_option + ")";
}

// Runs `body` (-> Result<std::string> payload) in a forked child and returns its payload.
template <class F> Result<std::string> run_child(const std::string& path, const IsolationOptions& iso, F&& body) {
    int fds[2];
    if (::pipe(fds) != 0)
        return detail::make_error("cannot read '" + path + "': pipe", std::strerror(errno));
    std::fflush(nullptr); // Nothing buffered gets written twice.
    const pid_t pid = ::fork();
    if (pid < 0) {
        const int err = errno;
        ::close(fds[0]);
        ::close(fds[1]);
        return detail::make_error("cannot read '" + path + "': fork", std::strerror(err));
    }
    if (pid == 0) {
        ::close(fds[0]);
        // Only the result pipe: an inherited descriptor would keep what the parent holds open
        // past its close for the child's life (a store's writer lock, file_lock.h).
        const unsigned out = unsigned(fds[1]);
        if (out > 3)
            ::close_range(3, out - 1, 0);
        ::close_range(out + 1, ~0U, 0);
        limit_child(iso);
        Result<std::string> r = body();
        const std::string msg = std::string(1, r.ok() ? '\0' : '\1') + (r.ok() ? r.value() : child_error(r.error(), iso));
        ::_exit(write_all(fds[1], msg) ? 0 : 2);
    }
    ::close(fds[1]);
    const std::string data = read_all(fds[0]);
    ::close(fds[0]);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || data.empty())
        return Error{"cannot read '" + path + "': " + describe_death(status, iso)};
    if (data[0] != '\0')
        return Error{data.substr(1)};
    return data.substr(1);
}

// A temporary for the child's result, created exclusively; removed with the object.
struct TempFile {
    std::string path;
    ~TempFile() {
        std::error_code ec;
        if (!path.empty())
            std::filesystem::remove(path, ec);
    }
};

Status make_temp(TempFile& tmp, const std::string& path) {
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::temp_directory_path(ec);
    Result<std::string> name = detail::create_temp_beside(((ec ? "." : dir) / "vx_vdb_isolated.vdb").string());
    if (!name)
        return Error{"cannot read '" + path + "': " + name.error()};
    tmp.path = std::move(*name);
    return {};
}

// Reads back the world the child wrote (our own format, so in-process reading is safe).
Result<world::World> read_back(const std::string& path, const TempFile& tmp, uint64_t max_chunks) {
    VdbWorldImportOptions o;
    o.max_chunks = max_chunks;
    Result<world::World> w = import_world_vdb(tmp.path, o);
    if (!w)
        return Error{"cannot import '" + path + "': reading the child's result failed: " + w.error()};
    return w;
}

// Why the reader process cannot hand `w` back (the result travels as a VDB file, whose index is
// 32 bits: |block| <= kVdbCoordLimit), naming the furthest chunk; "" when it can. The export's
// own error named the temporary file and said nothing of the offset.
std::string beyond_transport(const world::World& w) {
    std::string why;
    w.for_each_chunk([&](world::ChunkCoord c, const world::Chunk&) {
        const world::BlockPos lo = world::chunk_origin(c), hi = lo + world::BlockPos(world::kChunkSize - 1);
        const bool inside = glm::all(glm::greaterThanEqual(lo, world::BlockPos(-kVdbCoordLimit))) &&
                            glm::all(glm::lessThanEqual(hi, world::BlockPos(kVdbCoordLimit)));
        if (!inside && why.empty())
            why = "the imported blocks reach (" + std::to_string(lo.x) + ", " + std::to_string(lo.y) + ", " +
                  std::to_string(lo.z) + "), beyond the +-" + std::to_string(kVdbCoordLimit) +
                  " blocks an isolated import carries (OpenVDB's 32-bit index); place the volume nearer the "
                  "origin (--offset)";
    });
    return why;
}

} // namespace

Result<VolumeImport> import_volume_isolated(const std::string& path, const VolumeImportOptions& options,
                                            const IsolationOptions& isolation) {
    TempFile tmp;
    if (Status s = make_temp(tmp, path); !s)
        return Error{s.error()};
    Result<std::string> payload = run_child(path, isolation, [&]() -> Result<std::string> {
        Result<VolumeImport> r = import_volume(path, options);
        if (!r)
            return Error{r.error()};
        if (const std::string why = beyond_transport(r->world); !why.empty())
            return Error{why};
        if (Status s = export_vdb(r->world, tmp.path); !s)
            return Error{s.error()};
        Writer w;
        encode(w, r->summary);
        return w.bytes;
    });
    if (!payload)
        return Error{payload.error()};
    VolumeImport out;
    Reader r{*payload};
    decode(r, out.summary);
    if (!r.ok)
        return Error{"cannot import '" + path + "': the reader process sent a short summary"};
    Result<world::World> w = read_back(path, tmp, UINT64_MAX);
    if (!w)
        return Error{w.error()};
    out.world = std::move(*w);
    return out;
}

Result<world::World> import_world_vdb_isolated(const std::string& path, const VdbWorldImportOptions& options,
                                               const IsolationOptions& isolation) {
    TempFile tmp;
    if (Status s = make_temp(tmp, path); !s)
        return Error{s.error()};
    Result<std::string> payload = run_child(path, isolation, [&]() -> Result<std::string> {
        Result<world::World> w = import_world_vdb(path, options);
        if (!w)
            return Error{w.error()};
        if (Status s = export_vdb(*w, tmp.path); !s)
            return Error{s.error()};
        return std::string();
    });
    if (!payload)
        return Error{payload.error()};
    return read_back(path, tmp, options.max_chunks);
}

Result<std::vector<GridInfo>> list_grids_isolated(const std::string& path, const IsolationOptions& isolation) {
    Result<std::string> payload = run_child(path, isolation, [&]() -> Result<std::string> {
        Result<std::vector<GridInfo>> g = list_grids(path);
        if (!g)
            return Error{g.error()};
        Writer w;
        w.put(uint64_t(g->size()));
        for (const GridInfo& info : *g)
            encode(w, info);
        return w.bytes;
    });
    if (!payload)
        return Error{payload.error()};
    Reader r{*payload};
    uint64_t n = 0;
    r.get(n);
    std::vector<GridInfo> out;
    for (uint64_t i = 0; r.ok && i < n; ++i)
        decode(r, out.emplace_back());
    if (!r.ok)
        return Error{"cannot read '" + path + "': the reader process sent a short grid list"};
    return out;
}

} // namespace vx::vdb
