#include "engine/job_priority.h"

#include <algorithm>
#include <cmath>

namespace vx::engine {
namespace {

// std heap functions build a max-heap; "greater" puts the lowest (score, sequence) on top.
bool runs_later(const QueueEntry& a, const QueueEntry& b) {
    if (a.score != b.score)
        return a.score > b.score;
    return a.sequence > b.sequence;
}

} // namespace

double priority_score(const Viewer& viewer, double view_weight, const glm::dvec3& point) {
    const glm::dvec3 to_point = point - viewer.position;
    const double d = glm::length(to_point);
    const double f = glm::length(viewer.forward);
    if (d <= 1e-9 || f <= 1e-12)
        return d;
    const double cos_a = std::clamp(glm::dot(to_point, viewer.forward) / (d * f), -1.0, 1.0);
    return d * (1.0 + view_weight * (1.0 - cos_a) * 0.5);
}

void PriorityJobQueue::push(const JobKey& key, uint64_t generation, uint64_t sequence,
                            const glm::dvec3& position) {
    QueueEntry e;
    e.score = priority_score(m_viewer, m_view_weight, position);
    e.sequence = sequence;
    e.generation = generation;
    e.position = position;
    e.key = key;
    m_heap.push_back(e);
    // A stale heap is rebuilt wholesale at the next pop; keeping heap order now would be wasted.
    if (m_heap_epoch == m_viewer_epoch)
        std::push_heap(m_heap.begin(), m_heap.end(), runs_later);
}

void PriorityJobQueue::set_viewer(const Viewer& viewer, uint64_t epoch) {
    m_viewer = viewer;
    m_viewer_epoch = epoch;
}

void PriorityJobQueue::rescore_and_heapify() {
    for (QueueEntry& e : m_heap)
        e.score = priority_score(m_viewer, m_view_weight, e.position);
    std::make_heap(m_heap.begin(), m_heap.end(), runs_later);
    m_heap_epoch = m_viewer_epoch;
    m_dead_hint = 0;
    ++m_rebuilds;
}

QueueEntry PriorityJobQueue::pop_top() {
    std::pop_heap(m_heap.begin(), m_heap.end(), runs_later);
    QueueEntry e = m_heap.back();
    m_heap.pop_back();
    return e;
}

} // namespace vx::engine
