#pragma once
// Grid metadata of a vx-world VDB file (vdb_world.h) as raw items, without OpenVDB types: the
// streaming writer and reader (vdb_stream.h) serialize them themselves, and the OpenVDB importer
// converts its metadata to this form, so the registry is written and read by one piece of code.

#include <map>
#include <string>

#include "world/base/result.h"
#include "world/block_registry.h"

namespace vx::vdb::detail {

// One metadata item as a VDB file stores it: OpenVDB's type name ("int32", "string", "vec3s",
// "float", "bool", "vec3i", "int64") and the value bytes (little-endian). A plain value.
struct VdbMetaValue {
    std::string type;
    std::string bytes;
};
// Keys in byte order, as OpenVDB writes them (its MetaMap is a std::map<std::string, ...>).
using VdbMetaMap = std::map<std::string, VdbMetaValue>;

VdbMetaValue meta_int32(int32_t v);
VdbMetaValue meta_int64(int64_t v);
VdbMetaValue meta_string(std::string v);

// Adds "vx_block_table_size" and the "vx_block_<id>_*" items of every registered id. Thread-safe.
void add_registry_meta(VdbMetaMap& meta, const world::BlockRegistry& registry);

// The registry those items describe; the default registry when the file has none; a one-line
// error for a table size outside 1..65536, items of the wrong type or size, or a bad entry.
// Thread-safe.
Result<world::BlockRegistry> registry_from_meta(const VdbMetaMap& meta);

} // namespace vx::vdb::detail
