#include "world/store/pg_listener.h"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>

#include "world/base/log.h"
#include "world/store/pg_store.h"
#include "world/store/pg_wire.h"

namespace vx::world::pg {

ChangeListener::ChangeListener(std::string conninfo, int connect_timeout_s, size_t max_changes,
                               std::function<void(int)> before_listen)
    : m_conninfo(std::move(conninfo)), m_name(redact_pg_uri(m_conninfo)), m_timeout_s(connect_timeout_s),
      m_before_listen(std::move(before_listen)), m_changes(max_changes), m_lod_changes(max_changes),
      m_thread([this] { run(); }) {}

ChangeListener::~ChangeListener() {
    m_stop.store(true);
    m_thread.join();
}

bool ChangeListener::take(std::vector<ChunkCoord>& out) {
    std::lock_guard lock(m_mutex);
    return m_changes.take(out);
}

void ChangeListener::take_lod(std::vector<LodCoord>& out) {
    m_lod_wanted.store(true);
    std::lock_guard lock(m_mutex);
    (void)m_lod_changes.take(out);
}

void ChangeListener::parse(const char* payload) {
    const size_t prefix = std::strlen(kLodNotifyPrefix);
    if (std::strncmp(payload, kLodNotifyPrefix, prefix) == 0) {
        if (m_lod_wanted.load())
            parse_lod(payload + prefix);
        return;
    }
    std::vector<ChunkCoord> got;
    const char* p = payload;
    while (*p) {
        char* end = nullptr;
        int v[3];
        for (int i = 0; i < 3; ++i) {
            v[i] = int(std::strtol(p, &end, 10));
            if (end == p)
                return; // Not ours (another tool's NOTIFY on this channel): ignore the rest.
            p = end + (*end == ',' || *end == ';' ? 1 : 0);
        }
        got.push_back(ChunkCoord(v[0], v[1], v[2]));
    }
    std::lock_guard lock(m_mutex);
    m_changes.add(got);
}

// "level,x,y,z;..." (after the prefix).
void ChangeListener::parse_lod(const char* p) {
    std::vector<LodCoord> got;
    while (*p) {
        char* end = nullptr;
        long v[4];
        for (long& value : v) {
            value = std::strtol(p, &end, 10);
            if (end == p)
                return; // Malformed: ignore the rest, as parse() does.
            p = end + (*end == ',' || *end == ';' ? 1 : 0);
        }
        if (!valid_lod_level(int(v[0])) || v[0] == 0)
            return;
        got.push_back({int(v[0]), ChunkCoord(int(v[1]), int(v[2]), int(v[3]))});
    }
    std::lock_guard lock(m_mutex);
    m_lod_changes.add(got);
}

std::chrono::steady_clock::time_point ChangeListener::attempt_deadline() const {
    return std::chrono::steady_clock::now() + std::chrono::seconds(attempt_seconds());
}

void ChangeListener::report(const std::string& what) {
    VX_LOG_WARN("PostgreSQL change listener of '%s': %s; reconnecting", m_name.c_str(), what.c_str());
}

// Connects in 50 ms slices that check m_stop, so destruction never waits out a connect timeout
// (a server that is away on TCP). Null when stopped, out of memory, failed or timed out; a
// failure is reported when the last attempt succeeded (the first of a run of failures: a server
// away for an hour gives one line, not one per retry).
PGconn* ChangeListener::connect_polling() {
    using namespace std::chrono;
    PGconn* conn = connect_start(m_conninfo, m_timeout_s);
    const auto deadline = attempt_deadline();
    // libpq: start as if PQconnectPoll had returned PGRES_POLLING_WRITING.
    PostgresPollingStatusType state = PGRES_POLLING_WRITING;
    std::string failure;
    while (conn && PQstatus(conn) != CONNECTION_BAD && state != PGRES_POLLING_OK) {
        if (state == PGRES_POLLING_FAILED || m_stop.load())
            break;
        if (steady_clock::now() >= deadline) {
            failure = "no connection within " + std::to_string(attempt_seconds()) + " s (the connect timeout)";
            break;
        }
        const int ready = poll_socket(conn, state == PGRES_POLLING_READING ? POLLIN : POLLOUT);
        if (ready < 0) {
            failure = std::string("cannot wait on its connection: poll: ") + std::strerror(errno);
            break;
        }
        if (ready > 0)
            state = PQconnectPoll(conn);
    }
    const bool up = conn && state == PGRES_POLLING_OK;
    const bool failed = !up && !m_stop.load();
    if (failed && !m_connect_failing) {
        if (failure.empty())
            failure = conn ? message(conn) : "out of memory";
        report("cannot connect: " + failure);
    }
    m_connect_failing = failed;
    if (conn && !up) {
        PQfinish(conn);
        conn = nullptr;
    }
    return conn;
}

bool ChangeListener::listen(PGconn* conn) {
    using namespace std::chrono;
    if (m_before_listen)
        m_before_listen(PQbackendPID(conn));
    // Bounded (pg_wire.h): a frozen server would otherwise keep the listener, and destruction,
    // waiting for ever. In 50 ms slices that check m_stop, as connect_polling().
    const auto deadline = attempt_deadline();
    if (PQsendQuery(conn, "LISTEN vx_chunks") != 1) {
        report("cannot send LISTEN: " + message(conn));
        return false;
    }
    for (;;) {
        if (m_stop.load())
            return false;
        const auto now = steady_clock::now();
        if (now >= deadline) {
            report("LISTEN got no answer within " + std::to_string(attempt_seconds()) +
                   " s (the connect timeout)");
            return false;
        }
        if (wait_result(conn, std::min(deadline, now + milliseconds(50))))
            break;
    }
    ResultPtr last;
    while (PGresult* r = PQgetResult(conn))
        last.reset(r);
    if (PQresultStatus(last.get()) != PGRES_COMMAND_OK) {
        report("LISTEN failed: " + message(conn, last.get()));
        return false;
    }
    return true;
}

int ChangeListener::poll_socket(PGconn* conn, short events) {
    pollfd fd{PQsocket(conn), events, 0};
    int ready = -1;
    if (const int injected = next_injected_poll_error(); injected != 0)
        errno = injected;
    else
        ready = ::poll(&fd, 1, 50);
    return ready < 0 && errno == EINTR ? 0 : ready; // A signal is no failure: wait again.
}

void ChangeListener::fail_next_poll(int error) {
    std::lock_guard lock(m_poll_errors_mutex);
    m_poll_errors.push_back(error);
}

int ChangeListener::next_injected_poll_error() {
    std::lock_guard lock(m_poll_errors_mutex);
    if (m_poll_errors.empty())
        return 0;
    const int error = m_poll_errors.front();
    m_poll_errors.pop_front();
    return error;
}

void ChangeListener::run() {
    using namespace std::chrono;
    auto backoff = milliseconds(250);
    while (!m_stop.load()) {
        PGconn* conn = connect_polling();
        if (conn && PQstatus(conn) == CONNECTION_OK) {
            PQsetnonblocking(conn, 1); // Nothing queued yet: cannot fail.
            if (listen(conn)) {
                m_listening.store(true);
                m_epoch.fetch_add(1); // After LISTEN: a commit from now on is notified.
                backoff = milliseconds(250);
            }
        }
        // Wait on the socket in short slices so destruction never waits long.
        while (!m_stop.load() && m_listening.load()) {
            const int ready = poll_socket(conn, POLLIN);
            const int error = errno;
            const bool consumed = ready <= 0 || PQconsumeInput(conn);
            // Notifications read before a failure are handed on all the same.
            while (PGnotify* n = PQnotifies(conn)) {
                if (n->be_pid != m_own_pid.load())
                    parse(n->extra);
                PQfreemem(n);
            }
            if (ready < 0 || !consumed || PQstatus(conn) != CONNECTION_OK) {
                m_listening.store(false);
                report(ready < 0 ? std::string("cannot wait on its connection: poll: ") + std::strerror(error)
                                 : "connection lost: " + message(conn));
                break;
            }
        }
        if (conn)
            PQfinish(conn);
        // Lost or never up: retry with back-off (0.25 s doubling to 8 s), waking to check m_stop.
        for (auto waited = milliseconds(0); !m_stop.load() && waited < backoff; waited += milliseconds(50))
            std::this_thread::sleep_for(milliseconds(50));
        backoff = std::min(backoff * 2, milliseconds(8000));
    }
}

} // namespace vx::world::pg
