#pragma once
// Viewer-relative job priority and the priority queue of the pool lane.
//
// Score (lower runs first): the distance from the viewer, stretched for points away from the view
// direction:  score = d * (1 + w * (1 - cos a) / 2),  a = angle between the view direction and the
// direction to the point. With the default w = 1 a point straight ahead scores d, one to the side
// 1.5 d and one behind 2 d: nearest first, and at equal distance in front before behind (godot_voxel
// weighs its task priorities by distance and by the angle to the camera the same way).
//
// Scores depend on the viewer, which moves. Recomputing them on every pop would cost O(n) per job;
// instead the queue remembers the viewer epoch its heap was built for and, on the first pop after
// the epoch changed, recomputes every score and re-heaps (O(n) once per viewer move, Floyd's
// heap construction). Entries are invalidated lazily (replaced or cancelled jobs leave a dead
// entry that the pop skips); dead entries are purged on re-heap or when they outnumber live ones.

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "engine/job.h"

namespace vx::engine {

// Where the viewer is and looks. Plain value (not thread-safe). Position in world block coordinates; forward need not
// be normalized (a zero forward means "no direction": pure distance).
struct Viewer {
    glm::dvec3 position{0.0};
    glm::dvec3 forward{0.0, 0.0, -1.0};
};

// Thread-safe (pure). See the file comment; view_weight >= 0 (0 = pure distance).
double priority_score(const Viewer& viewer, double view_weight, const glm::dvec3& point);

// One queued pool job as the heap sees it. Plain value (not thread-safe). The owner decides liveness: an entry is live while the
// owner's slot for `key` still holds the job of `generation`.
struct QueueEntry {
    double score = 0.0;
    uint64_t sequence = 0; // Submission order; breaks score ties (FIFO among equals).
    uint64_t generation = 0;
    glm::dvec3 position{0.0}; // priority_position() captured at submission.
    JobKey key;
};

// Min-heap of QueueEntry by (score, sequence) with lazy re-prioritization. Not thread-safe: the
// JobSystem guards it with its lock.
class PriorityJobQueue {
public:
    // Adds an entry scored for the viewer of the queue's current epoch.
    void push(const JobKey& key, uint64_t generation, uint64_t sequence, const glm::dvec3& position);
    bool empty() const { return m_heap.empty(); }
    size_t size() const { return m_heap.size(); } // Live and dead entries.

    // Records a new viewer; scores are recomputed at the next pop, not now.
    void set_viewer(const Viewer& viewer, uint64_t epoch);
    void set_view_weight(double w) { m_view_weight = w; }

    // Pops the best entry for which is_live(entry) holds; dead entries met on the way are
    // discarded. Returns false when no live entry remains. Re-heaps first if the epoch changed.
    template <class IsLive> bool pop(IsLive&& is_live, QueueEntry& out) {
        if (m_heap_epoch != m_viewer_epoch)
            rebuild(is_live);
        while (!m_heap.empty()) {
            QueueEntry e = pop_top();
            if (is_live(e)) {
                out = e;
                return true;
            }
            if (m_dead_hint > 0)
                --m_dead_hint;
        }
        return false;
    }

    // Notes that an entry became dead (its job was replaced or cancelled); purges dead entries when
    // they outnumber live ones so the heap cannot grow without bound under churn.
    template <class IsLive> void note_dead(IsLive&& is_live) {
        ++m_dead_hint;
        if (m_dead_hint > 64 && m_dead_hint * 2 > m_heap.size())
            rebuild(is_live);
    }

    // Drops every entry.
    void clear() {
        m_heap.clear();
        m_dead_hint = 0;
    }

    // How many times the heap was rebuilt (for tests and metrics).
    uint64_t rebuild_count() const { return m_rebuilds; }

private:
    template <class IsLive> void rebuild(IsLive&& is_live) {
        std::vector<QueueEntry> live;
        live.reserve(m_heap.size());
        for (const QueueEntry& e : m_heap)
            if (is_live(e))
                live.push_back(e);
        m_heap.swap(live);
        rescore_and_heapify();
    }
    void rescore_and_heapify();
    QueueEntry pop_top();

    std::vector<QueueEntry> m_heap;
    Viewer m_viewer;
    double m_view_weight = 1.0;
    uint64_t m_viewer_epoch = 0;
    uint64_t m_heap_epoch = 0;
    size_t m_dead_hint = 0;
    uint64_t m_rebuilds = 0;
};

} // namespace vx::engine
