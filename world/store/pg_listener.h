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
// Thread affinity: construct and destroy on one thread; take(), take_lod() and set_own_pid()
// thread-safe.

#include <atomic>
#include <cstdint>
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
    // pending coordinates kept (each of the two sets) until a poll takes them.
    ChangeListener(std::string conninfo, int connect_timeout_s, size_t max_changes);
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

private:
    void run();
    pg_conn* connect_polling();
    void parse(const char* payload);
    void parse_lod(const char* items);

    std::string m_conninfo;
    int m_timeout_s;
    std::atomic<bool> m_stop{false}, m_listening{false};
    std::atomic<int> m_own_pid{0};
    std::atomic<uint64_t> m_epoch{0};
    std::atomic<bool> m_lod_wanted{false}; // take_lod() was called: collect coarse changes.
    std::mutex m_mutex;
    ChangeSet<ChunkCoord, ChunkCoordHash> m_changes;  // Guarded by m_mutex.
    ChangeSet<LodCoord, LodCoordHash> m_lod_changes;  // Guarded by m_mutex.
    std::thread m_thread;
};

} // namespace vx::world::pg
