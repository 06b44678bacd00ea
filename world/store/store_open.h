#pragma once
// Opening a world by name: a libpq URI (postgresql://...) names a PostgreSQL world (PgStore),
// anything else a SQLite file (SqliteStore). Every tool and the engine open worlds through here,
// so each accepts both. Thread affinity: any thread; the store returned is used as ChunkStore
// says (one thread at a time).

#include <memory>
#include <string>

#include "world/base/result.h"
#include "world/store/chunk_store.h"
#include "world/store/sqlite_store.h"

namespace vx::world {

struct StoreOpenInfo {
    std::string name;       // A SQLite path or a PostgreSQL URI.
    bool read_only = false; // Open for reading only.
    bool create = true;     // Create the world when absent (read-write only).
    bool listen = true;     // PostgreSQL: collect other processes' changes (poll_changes).
};

// Opens the world; the error names it (passwords redacted) and says what is wrong.
Result<std::unique_ptr<ChunkStore>> open_store(const StoreOpenInfo& info);

// A name fit for messages: the path, or the URI with its password redacted.
std::string store_display_name(const std::string& name);

// Verifies every record of the world `name` (read-only; moves nothing). For SQLite files this
// is check_store (sqlite_store.h); for PostgreSQL worlds every stored record is read and decoded.
Result<StoreCheck> check_world(const std::string& name);

// VDB worlds (a vx VDB file, with or without an edits overlay) live in vx_vdb, which needs OpenVDB; the store
// layer and the engine do not link it, so a program without vx_vdb carries no OpenVDB. When vx_vdb
// is linked into a program it sets this opener during static initialisation (its target forces
// that object in: world/vdb/CMakeLists.txt). Thread-safe; null: vx_vdb is not linked.
struct VdbWorldOpenInfo {
    std::string path;     // The VDB file (never written).
    std::string overlay;  // The edits overlay store (a SQLite path or a PostgreSQL URI); empty:
                          // "<path>.edits.sqlite".
    bool read_only = false; // No overlay: the file alone, read-only.
};
using VdbStoreOpener = Result<std::unique_ptr<ChunkStore>> (*)(const VdbWorldOpenInfo& info);
void set_vdb_store_opener(VdbStoreOpener opener);
VdbStoreOpener vdb_store_opener();

} // namespace vx::world
