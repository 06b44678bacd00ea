// vx_vdb_fuzz: the long run of the VDB importer fuzz test (docs/vdb.md, "Untrusted files").
//
//   vx_vdb_fuzz [--iterations N] [--seed S] [--first I] [--jobs J] [--data DIR]
//               [--reads all|import] [--out FILE.csv] [--stall-seconds T] [--child-stderr]
//   vx_vdb_fuzz --only I [--seed S] [--reads ...] [--keep FILE.vdb]
//
// The readers' own output (OpenVDB warnings, glibc's abort messages) goes to /dev/null unless
// --child-stderr or --only. --inject-escape I makes the worker kill itself (SIGSEGV) on input I,
// as an uncontained crash would, and --inject-hang I makes it wait forever there, as a deadlocked
// reader would: the driver's tests check that both are counted and named.
//
// Inputs first..first+N-1 of vdb_fuzz_input.h (input i depends only on seed and i), each written
// to a temporary file and read through the isolated API. J worker processes take every J-th input;
// each is single-threaded, as vdb_isolated.h requires of a caller that forks (threads sharing one
// process could fork while another holds OpenVDB's registry lock). The coordinator process never
// touches OpenVDB: it forks the workers, gathers one record per input through a pipe, prints
// progress to stderr every 10 s and one summary line to stdout.
//
// An escape is anything the isolated reader failed to contain: a worker killed by a signal or
// exiting early (its in-flight input took the caller down), a worker with no finished input for
// --stall-seconds (a hang; its process group is killed), or a malformed result (vdb_fuzz_input.h).
// The coordinator respawns the worker after the escaping input, names it (rerun it with --only),
// and exits 1 if there was any escape, 2 on bad arguments, else 0.

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/vdb/vdb_fuzz_input.h"

#if defined(__SANITIZE_ADDRESS__)
// As vdb_fuzz_test.cpp: no RLIMIT_AS under ASan, so allocations over 1 GiB fail instead.
extern "C" const char* __asan_default_options() { return "max_allocation_size_mb=1024:allocator_may_return_null=1"; }
#endif

namespace fuzz = vx::vdb::fuzz;

namespace {

struct Options {
    uint64_t iterations = 1000;
    uint64_t first = 0;
    uint32_t seed = 1;
    int jobs = 1;
    std::string data = VX_VDB_DATA_DIR;
    fuzz::Reads reads = fuzz::Reads::All;
    std::string out;
    std::string keep;
    bool only = false;
    bool child_stderr = false;
    uint64_t inject_escape = UINT64_MAX;
    uint64_t inject_hang = UINT64_MAX;
    int stall_seconds = 300; // Children have 20 s of CPU; wall time on a loaded machine is longer.
};

// One finished input, sent whole through the pipe (under PIPE_BUF, so writes never interleave).
struct Record {
    uint64_t index = 0;
    uint32_t worker = 0;
    uint8_t file = 0;
    uint8_t mutation = 0;
    uint16_t reads = 0;
    uint32_t outcomes[fuzz::kOutcomeCount] = {};
    uint32_t malformed = 0;
    float ms = 0;
};
static_assert(sizeof(Record) < PIPE_BUF);

bool parse_u64(const char* s, uint64_t& out) {
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(s, &end, 10);
    if (errno || !*s || *end || *s == '-')
        return false;
    out = v;
    return true;
}

bool parse_args(int argc, char** argv, Options& o) {
    if (const char* env = std::getenv("VX_VDB_DATA_DIR"); env && *env)
        o.data = env;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : nullptr;
        uint64_t n = 0;
        auto number = [&](uint64_t lo, uint64_t hi) { return v && parse_u64(v, n) && n >= lo && n <= hi && ++i; };
        if (a == "--iterations" && number(1, UINT64_MAX / 2))
            o.iterations = n;
        else if (a == "--first" && number(0, UINT64_MAX / 2))
            o.first = n;
        else if (a == "--only" && number(0, UINT64_MAX / 2))
            o.first = n, o.iterations = 1, o.only = true;
        else if (a == "--seed" && number(0, UINT32_MAX))
            o.seed = uint32_t(n);
        else if (a == "--jobs" && number(1, 1024))
            o.jobs = int(n);
        else if (a == "--inject-escape" && number(0, UINT64_MAX / 2))
            o.inject_escape = n;
        else if (a == "--inject-hang" && number(0, UINT64_MAX / 2))
            o.inject_hang = n;
        else if (a == "--child-stderr")
            o.child_stderr = true;
        else if (a == "--stall-seconds" && number(1, 86400))
            o.stall_seconds = int(n);
        else if (a == "--data" && v)
            o.data = v, ++i;
        else if (a == "--out" && v)
            o.out = v, ++i;
        else if (a == "--keep" && v)
            o.keep = v, ++i;
        else if (a == "--reads" && v && (std::strcmp(v, "all") == 0 || std::strcmp(v, "import") == 0))
            o.reads = std::strcmp(v, "all") == 0 ? fuzz::Reads::All : fuzz::Reads::Import, ++i;
        else {
            std::fprintf(stderr, "vx_vdb_fuzz: bad or incomplete argument '%s' (see the top of vdb_fuzz_main.cpp)\n",
                         a.c_str());
            return false;
        }
    }
    if (o.only)
        o.jobs = 1, o.child_stderr = true;
    return true;
}

bool write_record(int fd, const Record& r) {
    for (;;) {
        const ssize_t n = ::write(fd, &r, sizeof r);
        if (n < 0 && errno == EINTR)
            continue;
        return n == ssize_t(sizeof r);
    }
}

// A worker's folder for its input file; the coordinator removes it when the worker is killed.
std::filesystem::path worker_dir(pid_t pid) {
    return std::filesystem::temp_directory_path() / ("vx_vdb_fuzz_" + std::to_string(pid));
}

// Points fds 1 and 2 at /dev/null for the readers this worker forks (OpenVDB logs warnings to
// stdout, glibc its abort messages to stderr) and returns a stream on a copy of stderr for the
// worker's own messages.
std::FILE* silence_readers() {
    const int null_fd = ::open("/dev/null", O_WRONLY);
    const int keep = ::dup(2);
    std::FILE* err = null_fd >= 0 && keep >= 0 ? ::fdopen(keep, "w") : nullptr;
    if (err) {
        ::dup2(null_fd, 1);
        ::dup2(null_fd, 2);
    }
    if (null_fd >= 0)
        ::close(null_fd);
    return err ? err : stderr;
}

Record make_record(uint32_t worker, uint64_t index, const fuzz::Input& in, const fuzz::ReadReport& rep,
                   float ms) {
    Record r;
    r.index = index;
    r.worker = worker;
    r.file = uint8_t(in.file);
    r.mutation = uint8_t(in.mutation);
    r.reads = uint16_t(rep.reads);
    std::copy(std::begin(rep.outcomes), std::end(rep.outcomes), r.outcomes);
    r.malformed = uint32_t(rep.malformed.size());
    r.ms = ms;
    return r;
}

// --only: the input and every read's outcome with its message.
void print_details(std::FILE* err, const Options& o, const fuzz::Corpus& corpus, uint64_t index,
                   const fuzz::Input& in, const fuzz::ReadReport& rep) {
    std::fprintf(err, "input %llu (seed %u): %s, %s, %zu bytes%s%s\n", (unsigned long long)index, o.seed,
                 corpus.names[size_t(in.file)].c_str(), fuzz::mutation_name(in.mutation), in.bytes.size(),
                 o.keep.empty() ? "" : ", kept as ", o.keep.c_str());
    for (const std::string& line : rep.lines)
        std::fprintf(err, "  %s\n", line.c_str());
}

std::string rerun(uint32_t seed, uint64_t index) {
    return "vx_vdb_fuzz --seed " + std::to_string(seed) + " --only " + std::to_string(index);
}

// ---- a worker: inputs begin, begin + stride, ... below end ----

[[noreturn]] void worker_main(const Options& o, const fuzz::Corpus& corpus, uint32_t id, uint64_t begin,
                              uint64_t stride, uint64_t end, int fd) {
    ::setpgid(0, 0); // Its isolated readers join its group, so a stalled worker is killed whole.
    const std::filesystem::path dir = worker_dir(::getpid());
    std::filesystem::create_directories(dir);
    const std::string path = o.keep.empty() ? (dir / "input.vdb").string() : o.keep;
    const vx::vdb::IsolationOptions iso = fuzz::fuzz_isolation();
    std::FILE* err = o.child_stderr ? stderr : silence_readers();
    for (uint64_t i = begin; i < end; i += stride) {
        if (i == o.inject_escape)
            ::raise(SIGSEGV);
        while (i == o.inject_hang)
            ::pause();
        const auto t0 = std::chrono::steady_clock::now();
        const fuzz::Input in = fuzz::make_input(corpus, o.seed, i);
        std::ofstream(path, std::ios::binary | std::ios::trunc) << in.bytes;
        const fuzz::ReadReport rep = fuzz::run_reads(path, o.reads, iso);
        const float ms = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
        for (const std::string& m : rep.malformed)
            std::fprintf(err, "vx_vdb_fuzz: ESCAPE at input %llu: malformed result: %s; rerun: %s\n",
                         (unsigned long long)i, m.c_str(), rerun(o.seed, i).c_str());
        if (o.only)
            print_details(err, o, corpus, i, in, rep);
        std::fflush(err);
        if (!write_record(fd, make_record(id, i, in, rep, ms)))
            ::_exit(3);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
    std::fflush(err);
    ::_exit(0);
}

// ---- the coordinator ----

struct Worker {
    pid_t pid = -1;
    uint64_t next = 0;                              // The input it is working on.
    std::chrono::steady_clock::time_point last;     // Its last finished input (or start).
};

struct Totals {
    uint64_t inputs = 0, reads = 0, malformed = 0, deaths = 0, hangs = 0;
    uint64_t outcomes[fuzz::kOutcomeCount] = {};
    uint64_t escapes() const { return malformed + deaths + hangs; }
};

class Coordinator {
public:
    Coordinator(const Options& o, const fuzz::Corpus& c) : m_o(o), m_corpus(c), m_end(o.first + o.iterations) {}

    int run() {
        if (::pipe(m_fds) != 0) {
            std::fprintf(stderr, "vx_vdb_fuzz: pipe: %s\n", std::strerror(errno));
            return 2;
        }
        if (!m_o.out.empty()) {
            m_csv = std::fopen(m_o.out.c_str(), "w");
            if (!m_csv) {
                std::fprintf(stderr, "vx_vdb_fuzz: cannot write '%s': %s\n", m_o.out.c_str(), std::strerror(errno));
                return 2;
            }
            std::fprintf(m_csv, "index,file,mutation,reads,imported,error,child_crashed,memory_cap,cpu_cap,"
                                "malformed,ms\n");
        }
        m_start = m_last_progress = std::chrono::steady_clock::now();
        m_workers.resize(size_t(std::min<uint64_t>(uint64_t(m_o.jobs), m_o.iterations)));
        for (size_t w = 0; w < m_workers.size(); ++w)
            spawn(uint32_t(w), m_o.first + w);
        loop(); // The write end stays open here too, for respawned workers.
        ::close(m_fds[0]);
        ::close(m_fds[1]);
        if (m_csv)
            std::fclose(m_csv);
        summary();
        return m_t.escapes() == 0 ? 0 : 1;
    }

private:
    void spawn(uint32_t id, uint64_t begin) {
        Worker& w = m_workers[id];
        w.next = begin;
        w.last = std::chrono::steady_clock::now();
        if (begin >= m_end) {
            w.pid = -1;
            return;
        }
        std::fflush(nullptr);
        const pid_t pid = ::fork();
        if (pid == 0) {
            ::close(m_fds[0]);
            worker_main(m_o, m_corpus, id, begin, m_workers.size(), m_end, m_fds[1]);
        }
        if (pid < 0) {
            std::fprintf(stderr, "vx_vdb_fuzz: fork: %s; worker %u's inputs are skipped\n", std::strerror(errno), id);
            ++m_t.deaths;
        }
        if (pid > 0)
            ::setpgid(pid, pid); // As the worker does itself: whichever runs first.
        w.pid = pid;
    }

    void loop() {
        for (;;) {
            pollfd p{m_fds[0], POLLIN, 0};
            if (::poll(&p, 1, 1000) > 0)
                drain();
            reap();
            check_stalls();
            progress(false);
            if (live() == 0 && !pending())
                return;
        }
    }

    bool pending() const {
        pollfd p{m_fds[0], POLLIN, 0};
        return ::poll(&p, 1, 0) > 0 && (p.revents & POLLIN);
    }

    size_t live() const {
        return size_t(std::count_if(m_workers.begin(), m_workers.end(), [](const Worker& w) { return w.pid > 0; }));
    }

    void take(const Record& r) {
        Worker& w = m_workers[r.worker];
        w.next = r.index + m_workers.size();
        w.last = std::chrono::steady_clock::now();
        ++m_t.inputs;
        m_t.reads += r.reads;
        m_t.malformed += r.malformed;
        for (int k = 0; k < fuzz::kOutcomeCount; ++k)
            m_t.outcomes[k] += r.outcomes[k];
        if (m_csv)
            std::fprintf(m_csv, "%llu,%s,%s,%u,%u,%u,%u,%u,%u,%u,%.1f\n", (unsigned long long)r.index,
                         m_corpus.names[r.file].c_str(), fuzz::mutation_name(fuzz::Mutation(r.mutation)), r.reads,
                         r.outcomes[0], r.outcomes[1], r.outcomes[2], r.outcomes[3], r.outcomes[4], r.malformed,
                         double(r.ms));
    }

    // A worker that ended before its last input escaped on its in-flight one.
    void reap() {
        int status = 0;
        pid_t pid;
        while ((pid = ::waitpid(-1, &status, WNOHANG)) > 0) {
            auto it = std::find_if(m_workers.begin(), m_workers.end(), [&](const Worker& w) { return w.pid == pid; });
            if (it == m_workers.end())
                continue;
            it->pid = -1;
            drain(); // Records it sent before dying move `next` on.
            if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
                continue;
            if (it->next >= m_end)
                continue;
            ++m_t.deaths;
            const std::string how = WIFSIGNALED(status) ? std::string("killed by ") + ::strsignal(WTERMSIG(status))
                                                        : "exit " + std::to_string(WEXITSTATUS(status));
            escape(*it, pid, "worker " + how);
        }
    }

    // Records are written whole (under PIPE_BUF), so a read of one never gets a part.
    void drain() {
        Record r;
        while (pending()) {
            const ssize_t n = ::read(m_fds[0], &r, sizeof r);
            if (n < 0 && errno == EINTR)
                continue;
            if (n != ssize_t(sizeof r))
                return;
            take(r);
        }
    }

    void check_stalls() {
        const auto now = std::chrono::steady_clock::now();
        for (Worker& w : m_workers) {
            if (w.pid <= 0 || now - w.last < std::chrono::seconds(m_o.stall_seconds))
                continue;
            const pid_t pid = w.pid;
            ::kill(-pid, SIGKILL); // Its process group: the worker and its reader, both ours.
            int status = 0;
            ::waitpid(pid, &status, 0);
            w.pid = -1;
            drain();
            ++m_t.hangs;
            escape(w, pid, "no input finished in " + std::to_string(m_o.stall_seconds) + " s (hang)");
        }
    }

    void escape(Worker& w, pid_t pid, const std::string& what) {
        std::error_code ec;
        std::filesystem::remove_all(worker_dir(pid), ec);
        const uint64_t input = w.next;
        const std::string& file = m_corpus.names[size_t(fuzz::make_input(m_corpus, m_o.seed, input).file)];
        std::fprintf(stderr, "vx_vdb_fuzz: ESCAPE at input %llu (%s): %s; rerun: %s\n", (unsigned long long)input,
                     file.c_str(), what.c_str(), rerun(m_o.seed, input).c_str());
        spawn(uint32_t(&w - m_workers.data()), input + m_workers.size());
    }

    void progress(bool force) {
        const auto now = std::chrono::steady_clock::now();
        if (!force && now - m_last_progress < std::chrono::seconds(10))
            return;
        m_last_progress = now;
        const double s = std::chrono::duration<double>(now - m_start).count();
        const double rate = m_t.inputs / std::max(s, 1e-9);
        const double eta = rate > 0 ? double(m_o.iterations - m_t.inputs) / rate : 0;
        std::fprintf(stderr,
                     "vx_vdb_fuzz: %llu/%llu inputs, %llu reads, %.0f s, %.1f inputs/s, eta %.0f s, escapes %llu\n",
                     (unsigned long long)m_t.inputs, (unsigned long long)m_o.iterations,
                     (unsigned long long)m_t.reads, s, rate, eta, (unsigned long long)m_t.escapes());
    }

    void summary() const {
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
        std::string outcomes;
        for (int k = 0; k < fuzz::kOutcomeCount; ++k)
            outcomes += std::string(k ? ", " : "") + fuzz::outcome_name(fuzz::Outcome(k)) + " " +
                        std::to_string(m_t.outcomes[k]);
        std::printf("vx_vdb_fuzz: %llu inputs (seed %u, from %llu, reads %s) = %llu isolated reads in %.0f s "
                    "(%.2f inputs/s, %d jobs): %s; escapes %llu (worker deaths %llu, hangs %llu, malformed %llu)\n",
                    (unsigned long long)m_t.inputs, m_o.seed, (unsigned long long)m_o.first,
                    m_o.reads == fuzz::Reads::All ? "all" : "import", (unsigned long long)m_t.reads, s,
                    m_t.inputs / std::max(s, 1e-9), int(m_workers.size()), outcomes.c_str(),
                    (unsigned long long)m_t.escapes(), (unsigned long long)m_t.deaths, (unsigned long long)m_t.hangs,
                    (unsigned long long)m_t.malformed);
    }

    const Options& m_o;
    const fuzz::Corpus& m_corpus;
    const uint64_t m_end;
    int m_fds[2] = {-1, -1};
    std::FILE* m_csv = nullptr;
    std::vector<Worker> m_workers;
    Totals m_t;
    std::chrono::steady_clock::time_point m_start, m_last_progress;
};

} // namespace

int main(int argc, char** argv) {
    Options o;
    if (!parse_args(argc, argv, o))
        return 2;
    // Without the real files, OpenVDB writes equivalent inputs into a scratch folder (removed at exit).
    const std::filesystem::path scratch = worker_dir(::getpid()).string() + "_corpus";
    std::filesystem::create_directories(scratch);
    bool generated = false;
    vx::Result<fuzz::Corpus> corpus = fuzz::real_or_generated_corpus(o.data, scratch.string(), generated);
    std::error_code ec;
    std::filesystem::remove_all(scratch, ec);
    if (!corpus) {
        std::fprintf(stderr, "vx_vdb_fuzz: %s\n", corpus.error().c_str());
        return 2;
    }
    if (generated)
        std::fprintf(stderr, "vx_vdb_fuzz: no real VDB files at %s: fuzzing inputs written by OpenVDB here\n",
                     o.data.c_str());
    return Coordinator(o, *corpus).run();
}
