#pragma once
// Save tickets: each save request gets a sequence number, and the I/O lane reports when the
// store flush covering it finished. Because the I/O lane runs in submission order and a flush
// commits everything queued before it, a successful flush of sequence s makes every ticket <= s
// durable, and a later success supersedes an earlier failure.
//
// Threads: next() on the main thread; finished() on the I/O lane thread (or whichever thread
// destroys an unrun flush job); state() and wait() on any thread. Thread-safe.

#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>

#include "world/base/result.h"

namespace vx::engine {

enum class SaveState : uint8_t {
    Pending, // Handed to the I/O lane; its flush has not finished yet.
    Durable, // A flush covering it succeeded: it survives a crash of the process.
    Failed,  // The latest flush covering it failed (error()); a later save may still cover it.
    Unknown, // Never handed out by next().
};

class SaveTracker {
public:
    // Main thread. A new sequence number (1, 2, ...); the caller queues a flush reporting it.
    uint64_t next();
    // Any thread. The flush of `sequence` finished with `status`.
    void finished(uint64_t sequence, const Status& status);

    // Thread-safe.
    SaveState state(uint64_t sequence) const;
    // Thread-safe. The message of the latest failed flush ("" if none failed).
    std::string last_error() const;
    // Thread-safe, never from the I/O lane itself. Blocks until `sequence` is durable (success)
    // or a flush covering it failed (the error of the first such flush: its own, not a later
    // one's). Sequences never handed out by next() fail at once.
    Status wait(uint64_t sequence) const;
    // Thread-safe. The highest sequence known durable (0: none yet).
    uint64_t durable() const;

private:
    SaveState state_nolock(uint64_t sequence) const;

    mutable std::mutex m_mutex;
    mutable std::condition_variable m_changed;
    uint64_t m_issued = 0;  // Last sequence handed out.
    uint64_t m_durable = 0; // Highest sequence whose flush succeeded.
    uint64_t m_failed = 0;  // Highest sequence whose flush failed.
    std::string m_error;    // Message of that failure.
    // Failed flushes not superseded by a success since (so few: a flush fails on a bad day).
    std::map<uint64_t, std::string> m_failures;
};

} // namespace vx::engine
