#pragma once
// Failure injection for thread starts: while a RefuseThreads lives, the OS refuses new threads of
// this process as it does when it is out of them (pthread_create fails with EAGAIN, std::thread
// throws std::system_error). Real refusals, no hook in the engine:
// - every thread: the default stack size becomes 2^48 bytes, more than the address space, so no
//   stack can be mapped (pthread_setattr_default_np; restored afterwards);
// - all but about `allowed` more: the address space is capped (RLIMIT_AS) a few 64 MiB stacks
//   above what the process maps now. Sanitizers reserve terabytes of address space, so a test
//   using this mode skips under them.
// Main thread of a test; not thread-safe.

#include <pthread.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstddef>
#include <cstdio>
#include <fstream>
#include <string>

namespace vx::engine::test {

class RefuseThreads {
public:
    // allowed < 0: every thread started while this lives is refused. Else threads get 64 MiB
    // stacks and the address space room for about `allowed` more of them.
    explicit RefuseThreads(int allowed = -1) {
        if (pthread_getattr_default_np(&m_saved) != 0)
            return;
        m_have_saved = true;
        const size_t stack = allowed < 0 ? size_t(1) << 48 : size_t(64) << 20;
        pthread_attr_t a;
        pthread_attr_init(&a);
        const bool set = pthread_attr_setstacksize(&a, stack) == 0 && pthread_setattr_default_np(&a) == 0;
        pthread_attr_destroy(&a);
        if (!set)
            return;
        m_active = true;
        if (allowed >= 0 && getrlimit(RLIMIT_AS, &m_rlimit) == 0) {
            rlimit capped = m_rlimit;
            // A thread maps its stack and, the first time it allocates, may reserve a malloc
            // arena (64 MiB): two stacks' room a thread.
            capped.rlim_cur = mapped_bytes() + size_t(allowed) * 2 * stack + stack / 2;
            m_limited = setrlimit(RLIMIT_AS, &capped) == 0;
            m_active = m_limited;
        }
    }
    RefuseThreads(const RefuseThreads&) = delete;
    RefuseThreads& operator=(const RefuseThreads&) = delete;
    ~RefuseThreads() {
        if (m_limited)
            setrlimit(RLIMIT_AS, &m_rlimit);
        if (!m_have_saved)
            return;
        pthread_setattr_default_np(&m_saved);
        pthread_attr_destroy(&m_saved);
    }
    bool ok() const { return m_active; } // The injection is in place.

private:
    // The process's mapped address space now (/proc/self/statm: pages).
    static size_t mapped_bytes() {
        std::ifstream statm("/proc/self/statm");
        size_t pages = 0;
        statm >> pages;
        return pages * size_t(sysconf(_SC_PAGESIZE));
    }

    pthread_attr_t m_saved{};
    rlimit m_rlimit{};
    bool m_have_saved = false, m_active = false, m_limited = false;
};

} // namespace vx::engine::test
