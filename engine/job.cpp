#include "engine/job.h"

namespace vx::engine {

const char* job_kind_name(JobKind kind) {
    switch (kind) {
    case JobKind::Load: return "load";
    case JobKind::Save: return "save";
    case JobKind::Generate: return "generate";
    case JobKind::Mesh: return "mesh";
    case JobKind::Light: return "light";
    case JobKind::Task: return "task";
    case JobKind::IoTask: return "io-task";
    }
    return "?";
}

bool JobContext::is_cancelled() const {
    return m_job.m_token.is_cancelled() || m_job.m_abandoned.load(std::memory_order_acquire) ||
           m_stopping.load(std::memory_order_acquire);
}

glm::dvec3 Job::priority_position() const {
    const world::BlockPos origin = world::chunk_origin(m_key.chunk);
    const double half = world::kChunkSize * 0.5;
    return glm::dvec3(double(origin.x) + half, double(origin.y) + half, double(origin.z) + half);
}

} // namespace vx::engine
