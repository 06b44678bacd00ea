#pragma once
// Imports of untrusted VDB files in a child process.
//
// OpenVDB 10's reader is not memory-safe on damaged input: the fuzz test found heap corruption in
// bloscFromStream and a crash in StreamMetadata's destructor on mutated copies of real files,
// and corrupt size fields make it allocate gigabytes before it fails. No exception handler can
// contain that, so these variants fork: the child applies a memory and CPU limit, runs the
// in-process import, writes the result to a temporary vx-world VDB (export_vdb) and its summary to
// a pipe; the parent reads the temporary back (our own file) and deletes it. A crash or a limit hit
// in the child becomes an error naming the cap and the option that raises it. The temporary is
// created exclusively with a random name (never a predictable /tmp path). Cost: one fork plus an export/import round trip of the result.
//
// Thread affinity: call from a process that is single-threaded at the time of the call (the vx CLI,
// tests): fork copies only the calling thread, and another thread holding a lock (malloc, TBB)
// would leave the child stuck. POSIX only.

#include <cstdint>
#include <string>
#include <vector>

#include "world/base/result.h"
#include "world/vdb/vdb_volume.h"
#include "world/vdb/vdb_world.h"

namespace vx::vdb {

struct IsolationOptions {
    uint64_t memory_limit = uint64_t(4) << 30; // Child address space (RLIMIT_AS), bytes; 0 = none.
                                               // Not applied in ASan/TSan builds (they reserve
                                               // terabytes of address space).
    uint32_t cpu_seconds = 600;                // Child CPU time (RLIMIT_CPU); 0 = none.
    // What the messages tell the user to raise when a cap is hit (a tool names its own options).
    std::string memory_option = "IsolationOptions::memory_limit";
    std::string cpu_option = "IsolationOptions::cpu_seconds";
};

// import_volume in a child process (see above). Same result; a child crash or limit gives an error.
Result<VolumeImport> import_volume_isolated(const std::string& path, const VolumeImportOptions& options = {},
                                            const IsolationOptions& isolation = {});

// import_world_vdb in a child process (see above).
Result<world::World> import_world_vdb_isolated(const std::string& path, const VdbWorldImportOptions& options = {},
                                               const IsolationOptions& isolation = {});

// list_grids in a child process (see above).
Result<std::vector<GridInfo>> list_grids_isolated(const std::string& path, const IsolationOptions& isolation = {});

} // namespace vx::vdb
