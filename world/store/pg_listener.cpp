#include "world/store/pg_listener.h"

#include <poll.h>

#include <chrono>
#include <cstdlib>

#include "world/base/log.h"
#include "world/store/pg_wire.h"

namespace vx::world::pg {

ChangeListener::ChangeListener(std::string conninfo, int connect_timeout_s)
    : m_conninfo(std::move(conninfo)), m_timeout_s(connect_timeout_s), m_thread([this] { run(); }) {}

ChangeListener::~ChangeListener() {
    m_stop.store(true);
    m_thread.join();
}

void ChangeListener::take(std::vector<ChunkCoord>& out) {
    std::lock_guard lock(m_mutex);
    out.insert(out.end(), m_changes.begin(), m_changes.end());
    m_changes.clear();
}

void ChangeListener::parse(const char* payload) {
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
    m_changes.insert(m_changes.end(), got.begin(), got.end());
}

void ChangeListener::run() {
    using namespace std::chrono;
    auto backoff = milliseconds(250);
    while (!m_stop.load()) {
        PGconn* conn = connect(m_conninfo, m_timeout_s);
        if (PQstatus(conn) == CONNECTION_OK) {
            ResultPtr r(PQexec(conn, "LISTEN vx_chunks"));
            if (PQresultStatus(r.get()) == PGRES_COMMAND_OK) {
                m_listening.store(true);
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
        PQfinish(conn);
        // Lost or never up: retry with back-off (0.25 s doubling to 8 s), waking to check m_stop.
        for (auto waited = milliseconds(0); !m_stop.load() && waited < backoff; waited += milliseconds(50))
            std::this_thread::sleep_for(milliseconds(50));
        backoff = std::min(backoff * 2, milliseconds(8000));
    }
}

} // namespace vx::world::pg
