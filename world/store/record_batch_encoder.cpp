// RecordBatchEncoder: a batch of chunk records encoded on the caller and parked helper threads.
#include "world/store/record_batch_encoder.h"

#include <algorithm>

namespace vx::world {

RecordBatchEncoder::RecordBatchEncoder(int zstd_level, unsigned threads) : m_level(zstd_level) {
    if (threads == 0)
        threads = std::max(1u, std::thread::hardware_concurrency());
    m_threads = std::min(threads, kMaxThreads);
}

RecordBatchEncoder::~RecordBatchEncoder() {
    {
        std::lock_guard lock(m_mutex);
        m_stop = true;
    }
    m_wake.notify_all();
    for (std::thread& t : m_helpers)
        t.join();
}

void RecordBatchEncoder::start_helpers() {
    // Every codec exists before the first helper runs: helpers only read the vector.
    for (unsigned i = 0; i + 1 < m_threads; ++i)
        m_helper_codecs.push_back(std::make_unique<RecordCodec>(m_level));
    m_helpers.reserve(m_threads - 1);
    for (unsigned i = 0; i + 1 < m_threads; ++i)
        m_helpers.emplace_back([this, i] { helper_main(i); });
}

void RecordBatchEncoder::run_jobs(RecordCodec& codec, std::span<const Job> jobs) {
    for (size_t i = m_next.fetch_add(1, std::memory_order_relaxed); i < jobs.size();
         i = m_next.fetch_add(1, std::memory_order_relaxed)) {
        const Job& j = jobs[i];
        codec.encode_lod(LodCoord{j.level, j.coord}, *j.chunk, *j.out);
    }
}

void RecordBatchEncoder::helper_main(unsigned index) {
    RecordCodec& codec = *m_helper_codecs[index];
    uint64_t seen = 0;
    std::unique_lock lock(m_mutex);
    for (;;) {
        m_wake.wait(lock, [&] { return m_stop || m_generation != seen; });
        if (m_stop)
            return;
        seen = m_generation;
        const std::span<const Job> jobs = m_jobs;
        lock.unlock();
        run_jobs(codec, jobs);
        lock.lock();
        if (++m_finished == m_threads - 1)
            m_done.notify_one();
    }
}

void RecordBatchEncoder::encode(std::span<const Job> jobs, RecordCodec& codec) {
    if (jobs.size() < kMinShared || m_threads <= 1) {
        for (const Job& j : jobs)
            codec.encode_lod(LodCoord{j.level, j.coord}, *j.chunk, *j.out);
        return;
    }
    if (m_helpers.empty())
        start_helpers();
    {
        std::lock_guard lock(m_mutex);
        m_jobs = jobs;
        m_next.store(0, std::memory_order_relaxed);
        m_finished = 0;
        ++m_generation;
    }
    m_wake.notify_all();
    run_jobs(codec, jobs);
    // Every helper takes part in every batch (one that wakes after all jobs were taken leaves at
    // once), and the next batch starts only after all have left this one: no helper can take an
    // index of one batch while holding another's jobs.
    std::unique_lock lock(m_mutex);
    m_done.wait(lock, [&] { return m_finished == m_threads - 1; });
    m_jobs = {};
}

void RecordBatchEncoder::Batch::supersede(LodCoord c) {
    if (auto it = m_index.find(c); it != m_index.end())
        m_jobs[it->second].chunk = nullptr;
}

void RecordBatchEncoder::Batch::add(LodCoord c, const Chunk& chunk, std::vector<uint8_t>& out) {
    auto [it, added] = m_index.try_emplace(c, m_jobs.size());
    const Job job{c.chunk, &chunk, &out, c.level};
    if (added)
        m_jobs.push_back(job);
    else
        m_jobs[it->second] = job;
}

std::span<const RecordBatchEncoder::Job> RecordBatchEncoder::Batch::jobs() {
    std::erase_if(m_jobs, [](const Job& j) { return j.chunk == nullptr; });
    m_index.clear();
    return m_jobs;
}

} // namespace vx::world
