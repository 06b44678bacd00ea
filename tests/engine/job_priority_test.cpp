// Unit tests of the viewer-relative score and the lazily re-heaped priority queue (no threads).

#include <random>
#include <set>

#include <gtest/gtest.h>

#include "engine/job_priority.h"

using namespace vx::engine;

namespace {

Viewer viewer_at(glm::dvec3 pos, glm::dvec3 fwd) { return Viewer{pos, fwd}; }

JobKey key_x(int x) { return JobKey{vx::world::ChunkCoord(x, 0, 0), JobKind::Mesh}; }

// Pops everything (all entries live) and returns the chunk x of each, in pop order.
std::vector<int> pop_all(PriorityJobQueue& q) {
    std::vector<int> xs;
    QueueEntry e;
    while (q.pop([](const QueueEntry&) { return true; }, e))
        xs.push_back(e.key.chunk.x);
    return xs;
}

} // namespace

TEST(PriorityScore, DistanceStretchedByAngleFromViewDirection) {
    const Viewer v = viewer_at({0, 0, 0}, {1, 0, 0});
    // Weight 1: ahead scores d, to the side 1.5 d, behind 2 d.
    EXPECT_DOUBLE_EQ(priority_score(v, 1.0, {10, 0, 0}), 10.0);
    EXPECT_DOUBLE_EQ(priority_score(v, 1.0, {0, 10, 0}), 15.0);
    EXPECT_DOUBLE_EQ(priority_score(v, 1.0, {-10, 0, 0}), 20.0);
    // Weight 0: pure distance. Forward need not be normalized.
    EXPECT_DOUBLE_EQ(priority_score(v, 0.0, {-10, 0, 0}), 10.0);
    EXPECT_DOUBLE_EQ(priority_score(viewer_at({0, 0, 0}, {5, 0, 0}), 1.0, {0, 0, 10}), 15.0);
    // No direction, or the viewer's own position: plain distance.
    EXPECT_DOUBLE_EQ(priority_score(viewer_at({0, 0, 0}, {0, 0, 0}), 1.0, {-3, 4, 0}), 5.0);
    EXPECT_DOUBLE_EQ(priority_score(v, 1.0, {0, 0, 0}), 0.0);
}

TEST(PriorityJobQueue, PopsLowestScoreThenSubmissionOrder) {
    PriorityJobQueue q;
    q.set_viewer(viewer_at({0, 0, 0}, {1, 0, 0}), 1);
    // Scores: x=3 -> 3, x=-2 -> 4 (behind), x=1 -> 1, x=4 -> 4 (ahead, same score as x=-2).
    const int xs[] = {3, -2, 1, 4};
    uint64_t seq = 0;
    for (int x : xs)
        q.push(key_x(x), seq + 1, seq, glm::dvec3(x, 0, 0)), ++seq;
    // x=-2 and x=4 tie at 4: x=-2 was submitted first.
    EXPECT_EQ(pop_all(q), (std::vector<int>{1, 3, -2, 4}));
}

TEST(PriorityJobQueue, ViewerChangeReordersAtNextPopOnly) {
    PriorityJobQueue q;
    q.set_viewer(viewer_at({0, 0, 0}, {1, 0, 0}), 1);
    for (int x = -3; x <= 3; ++x)
        q.push(key_x(x), uint64_t(x + 10), uint64_t(x + 10), glm::dvec3(x * 10.0, 0, 0));
    const uint64_t rebuilds = q.rebuild_count();
    // Viewer jumps to x=100 looking back towards -x: the far end is now nearest and in front.
    q.set_viewer(viewer_at({100, 0, 0}, {-1, 0, 0}), 2);
    EXPECT_EQ(q.rebuild_count(), rebuilds); // Lazy: nothing re-scored yet.
    EXPECT_EQ(pop_all(q), (std::vector<int>{3, 2, 1, 0, -1, -2, -3}));
    EXPECT_EQ(q.rebuild_count(), rebuilds + 1); // Exactly one re-heap for the move.
}

TEST(PriorityJobQueue, SkipsDeadEntriesAndPurgesThem) {
    PriorityJobQueue q;
    std::set<uint64_t> live;
    for (uint64_t g = 1; g <= 1000; ++g) {
        q.push(key_x(int(g)), g, g, glm::dvec3(double(g), 0, 0));
        live.insert(g);
    }
    auto is_live = [&](const QueueEntry& e) { return live.count(e.generation) != 0; };
    // Kill 900 entries, as replaced/cancelled jobs do; the queue purges once dead ones dominate.
    for (uint64_t g = 1; g <= 1000; ++g)
        if (g % 10 != 0) {
            live.erase(g);
            q.note_dead(is_live);
        }
    EXPECT_LT(q.size(), 1000u / 2);
    std::vector<int> order;
    QueueEntry e;
    while (q.pop(is_live, e))
        order.push_back(e.key.chunk.x);
    ASSERT_EQ(order.size(), 100u);
    for (size_t i = 0; i < order.size(); ++i)
        EXPECT_EQ(order[i], int(10 * (i + 1)));
    EXPECT_TRUE(q.empty());
}

TEST(PriorityJobQueue, MatchesSortedOrderOnRandomInput) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-500.0, 500.0);
    PriorityJobQueue q;
    const Viewer v = viewer_at({coord(rng), coord(rng), coord(rng)}, {0.3, -0.2, 0.9});
    q.set_viewer(v, 1);
    std::vector<std::pair<double, int>> expected;
    for (int i = 0; i < 500; ++i) {
        const glm::dvec3 p(coord(rng), coord(rng), coord(rng));
        q.push(key_x(i), uint64_t(i + 1), uint64_t(i), p);
        expected.emplace_back(priority_score(v, 1.0, p), i);
    }
    std::sort(expected.begin(), expected.end());
    const std::vector<int> got = pop_all(q);
    ASSERT_EQ(got.size(), expected.size());
    for (size_t i = 0; i < got.size(); ++i)
        EXPECT_EQ(got[i], expected[i].second) << "at " << i;
}
