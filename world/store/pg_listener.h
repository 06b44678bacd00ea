#pragma once
// The change listener of a PgStore: its own connection, LISTEN vx_chunks, and a thread that
// waits on the socket and collects the chunk coordinates other processes committed. Payloads
// are "x,y,z;x,y,z;..." sent by the writers' commits (pg_store.cpp), or for coarse chunks
// "lod;level,x,y,z;..." (not caught up after a gap: coarse chunks are re-derived from the
// level-0 changes, which are); notifications from the
// writer connection of this same store are skipped (its backend pid). Notifications sent while
// the listener is not connected are lost: each time it starts listening it bumps listen_epoch(),
// and the store then compares what it knows against the table (PgStore::catch_up).
// Pending changes are a bounded set (ChangeSet): a process that polls rarely or never (a
// generation tool) holds at most that many coordinates, and past it is told to re-check
// everything instead. Coarse changes are collected only once someone asked for them (take_lod).
// Failures (LISTEN refused or unanswered within the connect timeout, poll() failing, the link
// lost) are logged as one warning line each, a connection that cannot be made once per run of
// failed attempts; the thread then drops the connection and reconnects
// with back-off, and the next LISTEN bumps listen_epoch() so the store catches up on what it missed.
// Thread affinity: construct and destroy on one thread; take(), take_lod(), set_own_pid() and
// fail_next_poll() thread-safe.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <unordered_set>
#include <vector>

#include "world/coords.h"
#include "world/lod/lod_coords.h"

struct pg_conn;

namespace vx::world::pg {

// Coordinates waiting for a poll, each once. Past `max` it forgets them all and remembers that it
// overflowed: the poller must then re-check everything it holds (what poll_changes returns).
// Not thread-safe (the owner locks).
template <class Coord, class Hash>
class ChangeSet {
public:
    explicit ChangeSet(size_t max) : m_max(max) {}
    void add(std::span<const Coord> coords) {
        for (size_t i = 0; i < coords.size() && !m_overflowed; ++i) {
            m_set.insert(coords[i]);
            if (m_set.size() > m_max)
                overflow();
        }
    }
    // Everything changed (catch-up could not tell what): the same as an overflow.
    void overflow() {
        m_set = {}; // Frees the buckets too.
        m_overflowed = true;
    }
    // Appends the coordinates to `out` and empties the set; true when it overflowed since the last
    // take (then `out` may miss changes: re-check everything).
    bool take(std::vector<Coord>& out) {
        out.insert(out.end(), m_set.begin(), m_set.end());
        m_set.clear();
        const bool overflowed = m_overflowed;
        m_overflowed = false;
        return overflowed;
    }
    size_t size() const { return m_set.size(); }

private:
    size_t m_max;
    std::unordered_set<Coord, Hash> m_set;
    bool m_overflowed = false;
};

class ChangeListener {
public:
    // Starts the thread; it connects (and reconnects with back-off) by itself. `max_changes`:
    // pending coordinates kept (each of the two sets) until a poll takes them. `before_listen`
    // (a test hook, vx's own fault-injection tests): called on the listener thread with the
    // backend pid of each new connection before its LISTEN is sent (a test freezes it there).
    ChangeListener(std::string conninfo, int connect_timeout_s, size_t max_changes,
                   std::function<void(int backend_pid)> before_listen = {});
    ~ChangeListener();
    ChangeListener(const ChangeListener&) = delete;
    ChangeListener& operator=(const ChangeListener&) = delete;

    // Moves the coordinates collected since the last call into `out` (appended). True when more
    // than `max_changes` piled up meanwhile and were forgotten: re-check everything.
    bool take(std::vector<ChunkCoord>& out);
    // The same for coarse chunks (payloads starting with kLodNotifyPrefix), collected from the
    // first call on (nobody asking: nothing kept). Coarse changes are hints, so an overflow only
    // drops them.
    void take_lod(std::vector<LodCoord>& out);
    // The backend pid of the store's writer connection: its own notifications are skipped.
    void set_own_pid(int pid) { m_own_pid.store(pid); }
    // True once the listener's connection is up and listening.
    bool listening() const { return m_listening.load(); }
    // How many times the listener has started listening (0: not yet). A change means
    // notifications may have been missed since the last value seen.
    uint64_t listen_epoch() const { return m_epoch.load(); }

    // Test hook (vx's own fault-injection tests; thread-safe): the listener's next poll() (while
    // connecting or listening; calls queue up, one per poll) returns -1 with errno `error`
    // instead of waiting, as poll(2) does when it fails.
    void fail_next_poll(int error);

private:
    void run();
    // The deadline of one connect or LISTEN started now: connect_timeout, at least 1 s (libpq's
    // least is 2 s; 0, "for ever", would keep destruction waiting on a frozen server).
    std::chrono::steady_clock::time_point attempt_deadline() const;
    int attempt_seconds() const { return std::max(m_timeout_s, 1); } // attempt_deadline()'s length.
    pg_conn* connect_polling();
    // LISTEN on `conn`, waiting in short slices that check m_stop. False (reported) when it
    // failed, passed attempt_deadline() or the listener is stopping.
    bool listen(pg_conn* conn);
    // poll() on the connection's socket for `events` for up to 50 ms (EINTR: 0, nothing ready),
    // or the injected failure (fail_next_poll).
    int poll_socket(pg_conn* conn, short events);
    int next_injected_poll_error(); // 0: none queued.
    void report(const std::string& what); // Logs one warning line; the listener reconnects.
    void parse(const char* payload);
    void parse_lod(const char* items);

    std::string m_conninfo;
    std::string m_name; // Redacted, for messages.
    int m_timeout_s;
    std::atomic<bool> m_stop{false}, m_listening{false};
    std::atomic<int> m_own_pid{0};
    std::atomic<uint64_t> m_epoch{0};
    std::atomic<bool> m_lod_wanted{false}; // take_lod() was called: collect coarse changes.
    bool m_connect_failing = false;           // The last attempt could not connect (listener thread).
    std::mutex m_poll_errors_mutex;
    std::deque<int> m_poll_errors;            // fail_next_poll's queue; guarded by m_poll_errors_mutex.
    std::function<void(int)> m_before_listen; // Set before the thread starts; read by it only.
    std::mutex m_mutex;
    ChangeSet<ChunkCoord, ChunkCoordHash> m_changes;  // Guarded by m_mutex.
    ChangeSet<LodCoord, LodCoordHash> m_lod_changes;  // Guarded by m_mutex.
    std::thread m_thread;
};

} // namespace vx::world::pg
