#include "parallel_mesh.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

namespace vx::tools {

double mesh_parallel(std::vector<MeshJob>& jobs, const world::BlockRegistry& registry, MeshMode mode,
                     unsigned threads) {
    if (threads == 0)
        threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<size_t> next{0};
    auto worker = [&] {
        world::GreedyMesher mesher;
        // Chunks are claimed in small batches: one atomic add per 8 chunks keeps contention off.
        constexpr size_t kBatch = 8;
        for (;;) {
            const size_t begin = next.fetch_add(kBatch, std::memory_order_relaxed);
            if (begin >= jobs.size())
                return;
            for (size_t i = begin; i < std::min(jobs.size(), begin + kBatch); ++i) {
                MeshJob& j = jobs[i];
                const world::MesherInput in{*j.chunk, j.out->apron, registry};
                switch (mode) {
                case MeshMode::Greedy: mesher.mesh(in, j.out->mesh); break;
                case MeshMode::Culled: world::mesh_culled(in, j.out->mesh); break;
                case MeshMode::Naive: world::mesh_naive(in, j.out->mesh); break;
                }
            }
        }
    };
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool)
        t.join();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace vx::tools
