#pragma once
// The change listener of a PgStore: its own connection, LISTEN vx_chunks, and a thread that
// waits on the socket and collects the chunk coordinates other processes committed. Payloads
// are "x,y,z;x,y,z;..." sent by the writers' commits (pg_store.cpp), or for coarse chunks
// "lod;level,x,y,z;..." (not caught up after a gap: coarse chunks are re-derived from the
// level-0 changes, which are); notifications from the
// writer connection of this same store are skipped (its backend pid). Notifications sent while
// the listener is not connected are lost: each time it starts listening it bumps listen_epoch(),
// and the store then compares what it knows against the table (PgStore::catch_up).
// Thread affinity: construct and destroy on one thread; take(), take_lod() and set_own_pid()
// thread-safe.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "world/coords.h"
#include "world/lod/lod_coords.h"

struct pg_conn;

namespace vx::world::pg {

class ChangeListener {
public:
    // Starts the thread; it connects (and reconnects with back-off) by itself.
    ChangeListener(std::string conninfo, int connect_timeout_s);
    ~ChangeListener();
    ChangeListener(const ChangeListener&) = delete;
    ChangeListener& operator=(const ChangeListener&) = delete;

    // Moves the coordinates collected since the last call into `out` (appended).
    void take(std::vector<ChunkCoord>& out);
    // The same for coarse chunks (payloads starting with kLodNotifyPrefix).
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
    std::mutex m_mutex;
    std::vector<ChunkCoord> m_changes; // Guarded by m_mutex.
    std::vector<LodCoord> m_lod_changes; // Guarded by m_mutex.
    std::thread m_thread;
};

} // namespace vx::world::pg
