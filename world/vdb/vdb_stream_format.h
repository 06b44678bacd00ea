#pragma once
// Internal to vdb_stream_writer.cpp and vdb_stream_reader.cpp: the constants of OpenVDB's file
// format (version 224, as OpenVDB 10 writes it) for the vx-world tree, learnt from OpenVDB's
// headers (io/Compression.h, tree/RootNode.h, InternalNode.h, LeafNode.h, util/NodeMasks.h) and
// files it wrote. No OpenVDB types.

#include <bit>
#include <cstdint>
#include <cstring>

namespace vx::vdb::detail {

inline constexpr int64_t kVdbMagic = 0x56444220;  // " BDV" as OpenVDB's int64 header word.
inline constexpr uint32_t kFileVersion = 224;     // OPENVDB_FILE_VERSION of OpenVDB 10.
inline constexpr uint32_t kMinFileVersion = 222;  // Node-mask compression: per-node metadata byte.
inline constexpr uint32_t kLibraryMajor = 10, kLibraryMinor = 0; // Written as OpenVDB 10.0 does.
inline constexpr const char* kGridType = "Tree_int32_5_4_3";
inline constexpr const char* kTransformType = "UniformScaleTranslateMap";
inline constexpr int kUuidChars = 36;

// Compression flags (io::COMPRESS_*).
inline constexpr uint32_t kCompressZip = 0x1, kCompressActiveMask = 0x2, kCompressBlosc = 0x4;

// Per-node value metadata byte (io::NO_MASK_OR_INACTIVE_VALS .. NO_MASK_AND_ALL_VALS).
enum ValueMeta : uint8_t {
    kNoMaskOrInactiveVals = 0, // Inactive values are all +background: only active values stored.
    kNoMaskAndMinusBg = 1,     // Inactive values are all -background.
    kNoMaskAndOneInactive = 2, // One inactive value, stored.
    kMaskAndNoInactive = 3,    // A selection mask picks -background or +background.
    kMaskAndOneInactive = 4,   // One stored value and the background, selected by a mask.
    kMaskAndTwoInactive = 5,   // Two stored values, selected by a mask.
    kNoMaskAndAllVals = 6,     // Every value stored.
};

// Node sizes: log2 of children per axis, and voxels per axis.
inline constexpr int kLeafLog2 = 3, kInternal4Log2 = 4, kInternal5Log2 = 5;
inline constexpr int kLeafVoxels = 1 << (3 * kLeafLog2);          // 512
inline constexpr int kInternal4Slots = 1 << (3 * kInternal4Log2); // 4096
inline constexpr int kInternal5Slots = 1 << (3 * kInternal5Log2); // 32768
inline constexpr int kInternal4Dim = 128, kInternal5Dim = 4096;   // Voxels per axis.

// OpenVDB's estimate of a tree's memory ("file_mem_bytes"), from its memUsage() rules: a fixed
// part (tree and empty root), 8 bytes per slot plus two masks and an origin per internal node,
// 2144 bytes per int32 leaf (fitted to files OpenVDB 10 wrote: exact for them).
inline constexpr uint64_t kMemTree = 1304, kMemInternal5 = 270348, kMemInternal4 = 33804, kMemLeaf = 2144;

// Bit masks as OpenVDB saves them: 64-bit words, bit i of the node in word i / 64, little-endian.
inline bool mask_on(const uint64_t* m, int i) { return (m[i >> 6] >> (i & 63)) & 1; }
inline void mask_set(uint64_t* m, int i) { m[i >> 6] |= uint64_t(1) << (i & 63); }
inline int mask_count(const uint64_t* m, int words) {
    int n = 0;
    for (int w = 0; w < words; ++w)
        n += std::popcount(m[w]);
    return n;
}

// Offset of the child holding voxel-local coordinates (x, y, z) in a node of 2^log2 children per
// axis: x major, z minor.
inline constexpr int node_offset(int x, int y, int z, int log2) { return (x << (2 * log2)) | (y << log2) | z; }

} // namespace vx::vdb::detail
