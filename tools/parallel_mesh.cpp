#include "parallel_mesh.h"

#include "world/mesh/reference_meshers.h"

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

namespace vx::tools {

void parallel_for(size_t count, unsigned threads, const std::function<void(size_t)>& fn, size_t batch) {
    if (threads == 0)
        threads = std::max(1u, std::thread::hardware_concurrency());
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (;;) {
            const size_t begin = next.fetch_add(batch, std::memory_order_relaxed);
            if (begin >= count)
                return;
            for (size_t i = begin; i < std::min(count, begin + batch); ++i)
                fn(i);
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t)
        pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool)
        t.join();
}

double mesh_parallel(std::vector<MeshJob>& jobs, const world::BlockRegistry& registry, MeshMode mode,
                     unsigned threads) {
    const auto t0 = std::chrono::steady_clock::now();
    // One mesher (scratch memory) per thread; chunks claimed 8 at a time keep the counter cold.
    parallel_for(jobs.size(), threads, [&](size_t i) {
        thread_local world::GreedyMesher mesher;
        MeshJob& j = jobs[i];
        const world::MesherInput in{*j.chunk, j.out->apron, registry};
        switch (mode) {
        case MeshMode::Greedy: mesher.mesh(in, j.out->mesh); break;
        case MeshMode::Culled: world::mesh_culled(in, j.out->mesh); break;
        case MeshMode::Naive: world::mesh_naive(in, j.out->mesh); break;
        }
    }, 8);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace vx::tools
