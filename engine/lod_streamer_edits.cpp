// LodStreamer's block edits (main thread): level-0 edits noted and applied up the kept coarse levels
// (remeshed, saved), or their levels marked stale and derived again with this session's edits overlaid.
#include "engine/lod_streamer.h"

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

#include "world/lod/downsample.h"
#include "world/lod/lod_coords.h"
#include "world/store/lod_load.h"

namespace vx::engine {

using namespace vx::world;

void LodStreamer::note_edit(ChunkCoord c) {
    if (top_level() > 0) {
        m_edited.try_emplace(c, 0); // A chunk already waiting keeps its level.
        m_edited_here.insert(c);
        if (m_edited_here.size() >= m_prune_edited_at) { // Those dropped since are saved: kept small.
            std::erase_if(m_edited_here, [&](ChunkCoord e) { return !m_blocks->find_chunk(e); });
            m_prune_edited_at = std::max<size_t>(1024, 2 * m_edited_here.size());
        }
    }
}

void LodStreamer::flush_edits() {
    apply_edits();
    // Edits still waiting for a level to load reach it only on arrival: their levels from that one
    // up are marked stale, so a session that ends first derives them next time. Once per wait
    // (negative: marked): each mark loads the waited level again, and saves may come often.
    if (m_store && m_store->supports_lod() && !m_store->read_only())
        for (auto& [c, waiting] : m_edited)
            if (waiting > 0) {
                if (!m_stale || !m_stale->contains(lod_ancestor({0, c}, waiting))) // Not marked already.
                    mark_stale(c, waiting);
                waiting = -waiting;
            }
    if (!m_batch.empty())
        m_jobs->submit_batch(std::exchange(m_batch, {}));
}

void LodStreamer::apply_edits() {
    const int top = top_level();
    for (auto it = m_edited.begin(); it != m_edited.end();) {
        const Chunk* const edited = m_blocks->find_chunk(it->first); // Null: dropped before this.
        const Chunk* child = edited;
        bool retry = false, unchanged = false;
        int k = 1; // The first level not refreshed from the edited chunk.
        LodCoord x{0, it->first};
        for (; child && k <= top; ++k) {
            const LodCoord p = lod_parent(x);
            auto nit = m_coarse.find(p);
            if (nit == m_coarse.end())
                break; // Not kept: derived from the store if it comes back (stale below).
            Node& n = nit->second;
            if (n.data != Data::Present) {
                retry = n.data == Data::Requested; // Applied once it arrives.
                if (retry && std::abs(it->second) != k)
                    it->second = k;
                break;
            }
            const size_t bytes = n.chunk.memory_bytes();
            if (!refresh_octant(n.chunk, *child, lod_octant(x), m_registry)) {
                // Nothing changed at this level: none above changes either, unless the edit waited
                // for a level to load (those above it were never refreshed, and the one that
                // arrived may hold the edit already: derived over it).
                if (it->second == 0) {
                    unchanged = true;
                    break;
                }
                x = p;
                child = &n.chunk;
                continue;
            }
            m_metrics.block_bytes[size_t(k)] += n.chunk.memory_bytes() - bytes;
            ++m_metrics.edits_applied;
            // The old mesh stays drawn until the new one replaces it.
            if (n.mesh_pending)
                n.mesh_stale = true;
            else
                request_mesh(p, n);
            if (m_store && m_store->supports_lod() && !m_store->read_only())
                m_batch.push_back(std::make_unique<LodSaveJob>(events(), p, n.chunk, *m_store));
            x = p;
            child = &n.chunk;
        }
        if (!retry && m_store && m_store->supports_lod() && !m_store->read_only())
            mark_stale(it->first, unchanged ? top + 1 : k);
        it = retry ? std::next(it) : m_edited.erase(it);
    }
}

// Levels `from` and up over `edited` could not be refreshed from it (it was dropped before its
// edit was applied, or a level between was not kept): stored ones are marked stale and every
// later load of them derives them from the saved blocks; those kept here are derived again now.
void LodStreamer::mark_stale(ChunkCoord edited, int from) {
    if (from > kMaxLodLevel)
        return;
    const std::vector<LodCoord> above = lod_ancestors(edited, from);
    // Copied only when it gains a chunk (jobs hold the old set): every applied edit comes here,
    // and edits in one place name the same ancestors again.
    if (!m_stale || !std::all_of(above.begin(), above.end(), [&](LodCoord c) { return m_stale->contains(c); })) {
        auto stale = std::make_shared<LodDirtySet>(m_stale ? *m_stale : LodDirtySet{});
        stale->insert(above.begin(), above.end());
        m_stale = std::move(stale);
    }
    m_marked_here.insert(above.begin(), above.end());
    m_batch.push_back(std::make_unique<LodMarkDirtyJob>(edited, *m_store, above));
    for (LodCoord c : above) {
        auto nit = m_coarse.find(c);
        if (nit == m_coarse.end())
            continue;
        Node& n = nit->second;
        if (n.data == Data::Requested && n.submitted)
            n.reload_on_arrival = n.merge_children = true; // Its load may predate the edit's save.
        else if (n.data == Data::Present)
            reload(c, n);
    }
}

// Present data replaced by a new load (derived, as `c` is stale); the mesh stays drawn until the
// new one replaces it.
void LodStreamer::reload(LodCoord c, Node& n) {
    if (n.mesh_pending) {
        m_jobs->cancel(lod_job_key(c, JobKind::Mesh));
        --m_metrics.pending_meshes;
        n.mesh_pending = n.mesh_stale = false;
    }
    m_metrics.block_bytes[size_t(c.level)] -= n.chunk.memory_bytes();
    n.chunk = Chunk();
    n.merge_children = true;
    request_data(c, n);
}

// A reloaded chunk is derived from the store, which lacks level-0 edits not saved yet: the
// children held here (level-0 chunks, or present coarse ones) are its freshest cells.
void LodStreamer::merge_children(LodCoord c, Node& n) {
    for (int i = 0; i < kLodChildren; ++i) {
        const LodCoord child = lod_child(c, i);
        const Chunk* cells = nullptr;
        if (child.level == 0) {
            cells = m_blocks->find_chunk(child.chunk);
        } else if (auto it = m_coarse.find(child); it != m_coarse.end() && it->second.data == Data::Present) {
            cells = &it->second.chunk;
        }
        if (cells)
            (void)refresh_octant(n.chunk, *cells, lod_octant(child), m_registry);
    }
}

// Copies of the level-0 chunks under `c` edited in this session and still in memory (null if
// none): a derivation from the store alone would miss their edits until they are saved. Called
// for every coarse request, so the ancestor test (shifts) comes before the chunk lookup.
std::unique_ptr<const LodOverlay> LodStreamer::edited_under(LodCoord c) const {
    std::unique_ptr<LodOverlay> out;
    for (ChunkCoord e : m_edited_here) {
        if (lod_ancestor({0, e}, c.level) != c)
            continue;
        if (const Chunk* chunk = m_blocks->find_chunk(e)) { // Else dropped, so saved: the store has it.
            if (!out)
                out = std::make_unique<LodOverlay>();
            out->emplace(e, *chunk);
        }
    }
    return out;
}

} // namespace vx::engine
