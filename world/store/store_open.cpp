#include "world/store/store_open.h"

#include <atomic>

#include "world/store/pending_writes.h"
#include "world/store/pg_store.h"

namespace vx::world {

namespace {
// Constant-initialised, so vx_vdb's static initialiser may set it before or after this file's.
std::atomic<VdbStoreOpener> g_vdb_store_opener{nullptr};
} // namespace

void set_vdb_store_opener(VdbStoreOpener opener) { g_vdb_store_opener.store(opener); }

VdbStoreOpener vdb_store_opener() { return g_vdb_store_opener.load(); }

Result<std::unique_ptr<ChunkStore>> open_store(const StoreOpenInfo& info) {
    if (is_pg_uri(info.name)) {
        PgStoreCreateInfo pci;
        pci.uri = info.name;
        pci.read_only = info.read_only;
        pci.create = info.create;
        pci.listen = info.listen;
        auto store = PgStore::open(pci);
        if (!store)
            return Error{store.error()};
        return std::unique_ptr<ChunkStore>(std::move(*store));
    }
    SqliteStoreCreateInfo sci;
    sci.path = info.name;
    sci.read_only = info.read_only;
    sci.create = info.create;
    auto store = SqliteStore::open(sci);
    if (!store)
        return Error{store.error()};
    return std::unique_ptr<ChunkStore>(std::move(*store));
}

std::string store_display_name(const std::string& name) { return is_pg_uri(name) ? redact_pg_uri(name) : name; }

Result<StoreCheck> check_world(const std::string& name) {
    if (!is_pg_uri(name))
        return check_store(name);
    PgStoreCreateInfo pci;
    pci.uri = name;
    pci.read_only = true;
    pci.listen = false;
    auto store = PgStore::open(pci);
    if (!store)
        return Error{store.error()};
    auto coords = (*store)->list_coords();
    if (!coords)
        return Error{coords.error()};
    StoreCheck check;
    // Counts one loaded record, naming the first few corrupt ones.
    auto tally = [&](LodCoord c, const ChunkLoad& load) {
        ++check.records;
        if (load.state != LoadState::Corrupt)
            return;
        ++check.corrupt;
        if (check.problems.size() < 8)
            check.problems.push_back(record_name(c) + ": " + load.problem);
    };
    for (ChunkCoord c : *coords) {
        auto load = (*store)->load(c);
        if (!load)
            return Error{load.error()};
        tally(lod_key(c), *load);
    }
    auto lods = (*store)->list_lod_coords();
    if (!lods)
        return Error{lods.error()};
    for (LodCoord c : *lods) {
        auto load = (*store)->load_lod(c);
        if (!load)
            return Error{load.error()};
        tally(c, *load);
    }
    return check;
}

} // namespace vx::world
