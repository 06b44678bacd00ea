#include "world/store/pg_listener.h"

#include <poll.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>

#include "world/base/log.h"
#include "world/store/pg_wire.h"

namespace vx::world::pg {

ChangeListener::ChangeListener(std::string conninfo, int connect_timeout_s, size_t max_changes)
    : m_conninfo(std::move(conninfo)), m_timeout_s(connect_timeout_s), m_changes(max_changes),
      m_lod_changes(max_changes), m_thread([this] { run(); }) {}

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

// Connects in 50 ms slices that check m_stop, so destruction never waits out a connect timeout
// (a server that is away on TCP). Null when stopped, out of memory, failed or timed out.
PGconn* ChangeListener::connect_polling() {
    using namespace std::chrono;
    PGconn* conn = connect_start(m_conninfo, m_timeout_s);
    const auto deadline = steady_clock::now() + seconds(std::max(m_timeout_s, 1));
    // libpq: start as if PQconnectPoll had returned PGRES_POLLING_WRITING.
    PostgresPollingStatusType state = PGRES_POLLING_WRITING;
    while (conn && PQstatus(conn) != CONNECTION_BAD && state != PGRES_POLLING_OK) {
        if (state == PGRES_POLLING_FAILED || m_stop.load() || steady_clock::now() >= deadline)
            break;
        pollfd fd{PQsocket(conn), short(state == PGRES_POLLING_READING ? POLLIN : POLLOUT), 0};
        const int ready = ::poll(&fd, 1, 50);
        if (ready < 0)
            break;
        if (ready > 0)
            state = PQconnectPoll(conn);
    }
    if (conn && state != PGRES_POLLING_OK) {
        PQfinish(conn);
        conn = nullptr;
    }
    return conn;
}

void ChangeListener::run() {
    using namespace std::chrono;
    auto backoff = milliseconds(250);
    while (!m_stop.load()) {
        PGconn* conn = connect_polling();
        if (conn && PQstatus(conn) == CONNECTION_OK) {
            PQsetnonblocking(conn, 1); // Nothing queued yet: cannot fail.
            // Bounded (pg_wire.h): a frozen server would otherwise keep destruction waiting.
            bool timed_out = false;
            const auto deadline = steady_clock::now() + seconds(std::max(m_timeout_s, 1));
            ResultPtr r = pg::run(conn, "LISTEN vx_chunks", deadline, timed_out);
            if (PQresultStatus(r.get()) == PGRES_COMMAND_OK) {
                m_listening.store(true);
                m_epoch.fetch_add(1); // After LISTEN: a commit from now on is notified.
                backoff = milliseconds(250);
            }
        }
        // Wait on the socket in short slices so destruction never waits long.
        while (!m_stop.load() && m_listening.load()) {
            pollfd fd{PQsocket(conn), POLLIN, 0};
            const int ready = ::poll(&fd, 1, 50);
            if (ready < 0 || (ready > 0 && !PQconsumeInput(conn)) || PQstatus(conn) != CONNECTION_OK) {
                m_listening.store(false);
                break;
            }
            while (PGnotify* n = PQnotifies(conn)) {
                if (n->be_pid != m_own_pid.load())
                    parse(n->extra);
                PQfreemem(n);
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
