// The streaming VDB reader (vdb_stream.h): our own parser of OpenVDB's file format for the
// vx-world tree. Untrusted input: every count, size and offset is checked against the file before
// it is used, and no allocation depends on a value read (node-sized buffers only).
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include <zlib.h>

#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_meta.h"
#include "world/vdb/vdb_stream.h"
#include "world/vdb/vdb_stream_format.h"

namespace vx::vdb {

using namespace detail;
using world::BlockId;
using world::Chunk;
using world::ChunkCoord;
using world::kChunkVolume;

namespace {

constexpr int kChunksPerNode = 64;
constexpr uint64_t kMaxName = 1 << 16;        // Longest metadata key or type name accepted.
constexpr uint64_t kMaxKeptMeta = 1 << 20;    // Largest vx_* metadata value kept...
constexpr uint64_t kMaxKeptMetaTotal = 1 << 26; // ... and all of them together.

// A bounded read cursor over the file: nothing past `end` is read, a failure sticks.
struct In {
    std::FILE* f = nullptr;
    int64_t pos = 0, end = 0;
    bool failed = false;
    ~In() {
        if (f)
            std::fclose(f);
    }
    int64_t left() const { return end - pos; }
    bool get(void* p, uint64_t n) {
        if (failed || n > uint64_t(left()) || (n && std::fread(p, 1, n, f) != n))
            return !(failed = true);
        pos += int64_t(n);
        return true;
    }
    template <class T> bool pod(T& v) { return get(&v, sizeof v); }
    bool seek(int64_t at) {
        if (failed || at < 0 || at > end || ::fseeko(f, at, SEEK_SET) != 0)
            return !(failed = true);
        pos = at;
        return true;
    }
    bool skip(uint64_t n) { return n <= uint64_t(left()) ? seek(pos + int64_t(n)) : !(failed = true); }
    bool str(std::string& s, uint64_t cap) {
        uint32_t n = 0;
        if (!pod(n) || n > cap || n > uint64_t(left()))
            return !(failed = true);
        s.resize(n);
        return get(s.data(), n);
    }
};

bool lex_less(glm::ivec3 a, glm::ivec3 b) { return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z; }

struct RootTile {
    glm::ivec3 origin;
    int32_t value;
};

} // namespace

struct VdbStreamReader::State {
    std::string path;
    VdbStreamReadOptions options;
    In topo, bufs; // Topology cursor; leaf-values cursor.
    uint32_t compression = 0;
    int32_t background = 0;
    int64_t block_pos = 0, end_pos = 0;
    world::BlockRegistry registry;
    std::string error;

    std::vector<RootTile> tiles; // Active, non-air root tiles, sorted.
    size_t next_tile = 0;
    int tile_node = -1; // Internal4-sized node of tiles[next_tile] being handed out (0..32767).
    uint32_t children_left = 0;
    bool have_child_origin = false;
    glm::ivec3 child_origin{0}, last_origin{0};
    bool any_origin = false;

    // The Internal5 node being walked.
    bool in5 = false;
    glm::ivec3 org5{0};
    int slot5 = 0;
    std::array<uint64_t, kInternal5Slots / 64> child5{}, value5{};
    std::vector<int32_t> values5 = std::vector<int32_t>(kInternal5Slots);

    std::vector<int32_t> values, temp;
    std::vector<uint64_t> selection;
    std::vector<Bytef> zipped;
    std::vector<uint8_t> leaf_masks;
    std::vector<BlockId> dense = std::vector<BlockId>(size_t(kChunksPerNode) * kChunkVolume);
    std::array<bool, kChunksPerNode> touched{};
    bool done = false;

    Status fail(const std::string& what) {
        if (error.empty())
            error = "cannot stream '" + path + "': " + what;
        return Error{error};
    }
    Status damaged() { return fail("the file is damaged or truncated"); }

    Status open_header();    // The file header; finds the "blocks" grid.
    Status read_grid_meta(); // Compression, metadata (the registry), transform.
    Status read_root();      // The root's background and tiles; the values cursor's start.
    Status read_values(In& in, int n, const uint64_t* mask, int32_t* dest);
    Status read_internal4(glm::ivec3 org, std::vector<std::pair<ChunkCoord, Chunk>>& out);
    Status block_id(glm::ivec3 p, int32_t v) {
        if (v >= 0 && v <= 0xFFFF)
            return {};
        return fail("voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                    ") holds " + std::to_string(v) + ", not a block id (0..65535)");
    }
    void uniform_node(glm::ivec3 org, int32_t value, std::vector<std::pair<ChunkCoord, Chunk>>& out) {
        const ChunkCoord base = org >> 5;
        for (int x = 0; x < 4; ++x)
            for (int y = 0; y < 4; ++y)
                for (int z = 0; z < 4; ++z)
                    out.emplace_back(base + ChunkCoord(x, y, z), Chunk(BlockId(value)));
    }
    Result<bool> next(std::vector<std::pair<ChunkCoord, Chunk>>& out);
};

// OpenVDB's readCompressedValues for int32: the metadata byte, inactive values and selection
// mask it names, then the stored values (zipped or raw), spread back over the node's slots.
Status VdbStreamReader::State::read_values(In& in, int n, const uint64_t* mask, int32_t* dest) {
    uint8_t meta = 0;
    if (!in.pod(meta))
        return damaged();
    if (meta > kNoMaskAndAllVals)
        return damaged();
    int32_t inactive0 = meta == kNoMaskOrInactiveVals ? background : int32_t(0u - uint32_t(background));
    int32_t inactive1 = background;
    if (meta == kNoMaskAndOneInactive || meta == kMaskAndOneInactive || meta == kMaskAndTwoInactive)
        if (!in.pod(inactive0) || (meta == kMaskAndTwoInactive && !in.pod(inactive1)))
            return damaged();
    selection.assign(size_t(n / 64), 0);
    if (meta == kMaskAndNoInactive || meta == kMaskAndOneInactive || meta == kMaskAndTwoInactive)
        if (!in.get(selection.data(), size_t(n / 8)))
            return damaged();
    const bool mask_compressed = (compression & kCompressActiveMask) && meta != kNoMaskAndAllVals;
    const int count = mask_compressed ? mask_count(mask, n / 64) : n;
    const uint64_t bytes = uint64_t(count) * sizeof(int32_t);
    temp.resize(size_t(count));
    if (compression & kCompressZip) {
        int64_t size = 0;
        if (!in.pod(size))
            return damaged();
        if (size <= 0) {
            if (uint64_t(0) - uint64_t(size) != bytes || !in.get(temp.data(), bytes))
                return damaged();
        } else {
            if (uint64_t(size) > compressBound(uLong(bytes)) + 64)
                return damaged();
            zipped.resize(size_t(size));
            if (!in.get(zipped.data(), uint64_t(size)))
                return damaged();
            uLongf got = uLongf(bytes);
            if (uncompress(reinterpret_cast<Bytef*>(temp.data()), &got, zipped.data(), uLong(size)) != Z_OK ||
                got != bytes)
                return damaged();
        }
    } else if (!in.get(temp.data(), bytes)) {
        return damaged();
    }
    for (int i = 0, j = 0; i < n; ++i) {
        if (count == n)
            dest[i] = temp[size_t(i)];
        else
            dest[i] = mask_on(mask, i) ? temp[size_t(j++)] : mask_on(selection.data(), i) ? inactive1 : inactive0;
    }
    return {};
}

Status VdbStreamReader::State::open_header() {
    int64_t magic = 0;
    uint32_t version = 0, major = 0, minor = 0;
    uint8_t offsets = 0;
    if (!topo.pod(magic) || magic != kVdbMagic)
        return fail("not an OpenVDB file");
    if (!topo.pod(version) || !topo.pod(major) || !topo.pod(minor) || !topo.pod(offsets))
        return damaged();
    if (version < kMinFileVersion || version > kFileVersion)
        return fail("file format version " + std::to_string(version) + " (the streaming reader reads " +
                    std::to_string(kMinFileVersion) + ".." + std::to_string(kFileVersion) + ")");
    if (offsets != 1)
        return fail("the file has no grid offsets");
    if (!topo.skip(kUuidChars))
        return damaged();
    // File metadata: skipped.
    uint32_t count = 0;
    if (!topo.pod(count))
        return damaged();
    std::string key, type;
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t size = 0;
        if (!topo.str(key, kMaxName) || !topo.str(type, kMaxName) || !topo.pod(size) || !topo.skip(size))
            return damaged();
    }
    int32_t grids = 0;
    if (!topo.pod(grids) || grids < 0)
        return damaged();
    std::string name, parent;
    for (int32_t g = 0;; ++g) {
        if (g == grids)
            return fail("no grid named 'blocks'");
        int64_t pos[3];
        if (!topo.str(name, kMaxName) || !topo.str(type, kMaxName) || !topo.str(parent, kMaxName) ||
            !topo.get(pos, sizeof pos))
            return damaged();
        // What the descriptor says of "blocks" comes first: an instance's offsets are not a
        // tree's (OpenVDB writes no tree for it), and "damaged" would misname a sound file.
        if (name == "blocks" && type != kGridType)
            return fail("grid 'blocks' is a " + type.substr(0, 64) + ", not " + kGridType);
        if (name == "blocks" && !parent.empty())
            return fail("grid 'blocks' is an instance of another grid");
        // An instance (of a grid written before it) has no tree: OpenVDB writes its block offset 0.
        const bool tree_ok = parent.empty() ? pos[0] <= pos[1] && pos[1] <= pos[2] : pos[1] == 0;
        if (!(pos[0] >= topo.pos && pos[0] <= pos[2] && pos[2] <= topo.end && tree_ok))
            return damaged();
        if (name != "blocks") {
            if (!topo.seek(pos[2]))
                return damaged();
            continue;
        }
        block_pos = pos[1];
        end_pos = pos[2];
        if (!topo.seek(pos[0]))
            return damaged();
        break;
    }
    return read_grid_meta();
}

Status VdbStreamReader::State::read_grid_meta() {
    if (!topo.pod(compression))
        return damaged();
    if (compression & kCompressBlosc)
        return fail("Blosc compression (the streaming reader reads ZIP and uncompressed files)");
    if (compression & ~(kCompressZip | kCompressActiveMask))
        return fail("unknown compression flags " + std::to_string(compression));
    uint32_t count = 0;
    std::string key, type;
    // Grid metadata: the vx_* items are kept (registry, version), others skipped.
    VdbMetaMap meta;
    uint64_t kept = 0;
    if (!topo.pod(count))
        return damaged();
    for (uint32_t i = 0; i < count; ++i) {
        uint32_t size = 0;
        if (!topo.str(key, kMaxName) || !topo.str(type, kMaxName) || !topo.pod(size))
            return damaged();
        if (key.compare(0, 3, "vx_") == 0 && size <= kMaxKeptMeta && (kept += size) <= kMaxKeptMetaTotal) {
            VdbMetaValue v{type, std::string(size, '\0')};
            if (!topo.get(v.bytes.data(), size))
                return damaged();
            meta[key] = std::move(v);
        } else if (!topo.skip(size)) {
            return damaged();
        }
    }
    if (auto it = meta.find("vx_format_version"); it != meta.end() && it->second.bytes.size() == 4) {
        int32_t v = 0;
        std::memcpy(&v, it->second.bytes.data(), 4);
        if (v > 1)
            return fail("vx-world format version " + std::to_string(v) + ", newer than 1");
    }
    Result<world::BlockRegistry> r = registry_from_meta(meta);
    if (!r)
        return fail(r.error());
    registry = std::move(*r);
    // Transform: ignored (block = index coordinate, as the OpenVDB importer reads it); skipped by
    // the size its map type writes (math/Maps.h: Vec3d fields or one Mat4d). Frustums: refused.
    if (!topo.str(type, kMaxName))
        return damaged();
    static constexpr std::pair<const char*, int> kMaps[] = {
        {"UniformScaleTranslateMap", 6 * 24}, {"ScaleTranslateMap", 6 * 24}, {"UniformScaleMap", 5 * 24},
        {"ScaleMap", 5 * 24}, {"TranslationMap", 24}, {"AffineMap", 128}, {"UnitaryMap", 128}};
    const auto map = std::find_if(std::begin(kMaps), std::end(kMaps), [&](const auto& m) { return type == m.first; });
    if (map == std::end(kMaps))
        return fail("transform " + type.substr(0, 64) + " (the streaming reader knows linear maps)");
    if (!topo.skip(uint64_t(map->second)))
        return damaged();
    return read_root();
}

Status VdbStreamReader::State::read_root() {
    // Tree: one buffer, the background, root tiles, then root children.
    int32_t buffers = 0;
    uint32_t n_tiles = 0;
    if (!topo.pod(buffers) || buffers != 1 || !topo.pod(background) || !topo.pod(n_tiles) || !topo.pod(children_left))
        return damaged();
    if (uint64_t(n_tiles) * 17 > uint64_t(topo.left()) || uint64_t(children_left) * 8205 > uint64_t(topo.left()))
        return damaged();
    uint64_t tile_chunks = 0;
    for (uint32_t i = 0; i < n_tiles; ++i) {
        RootTile t;
        uint8_t active = 0;
        if (!topo.pod(t.origin) || !topo.pod(t.value) || !topo.pod(active))
            return damaged();
        if ((t.origin & (kInternal5Dim - 1)) != glm::ivec3(0))
            return damaged();
        if (!active || t.value == 0)
            continue;
        if (Status s = block_id(t.origin, t.value); !s)
            return s;
        tile_chunks += uint64_t(1) << 21; // 128³ chunks.
        if (tile_chunks > options.max_tile_chunks)
            return fail("tiles expand to more than " + std::to_string(options.max_tile_chunks) + " chunks");
        tiles.push_back(t);
    }
    std::sort(tiles.begin(), tiles.end(), [](const RootTile& a, const RootTile& b) { return lex_less(a.origin, b.origin); });
    for (size_t i = 1; i < tiles.size(); ++i)
        if (tiles[i].origin == tiles[i - 1].origin)
            return damaged();
    if (!bufs.seek(block_pos))
        return damaged();
    return {};
}

// Reads one Internal4 node's topology at the topology cursor and its leaves at the values
// cursor, and hands out its non-empty chunks.
Status VdbStreamReader::State::read_internal4(glm::ivec3 org, std::vector<std::pair<ChunkCoord, Chunk>>& out) {
    std::array<uint64_t, kInternal4Slots / 64> child{}, value{};
    if (!topo.get(child.data(), sizeof child) || !topo.get(value.data(), sizeof value))
        return damaged();
    values.resize(kInternal4Slots);
    if (Status s = read_values(topo, kInternal4Slots, value.data(), values.data()); !s)
        return s;
    const int leaves = mask_count(child.data(), int(child.size()));
    leaf_masks.resize(size_t(leaves) * 64);
    if (!topo.get(leaf_masks.data(), leaf_masks.size()))
        return damaged();
    touched.fill(false);
    const auto chunk_ids = [&](glm::ivec3 slot) {
        const int k = node_offset(slot.x >> 2, slot.y >> 2, slot.z >> 2, 2);
        if (!touched[size_t(k)]) {
            touched[size_t(k)] = true;
            std::fill_n(dense.begin() + ptrdiff_t(k) * kChunkVolume, kChunkVolume, world::kAir);
        }
        return dense.data() + size_t(k) * kChunkVolume;
    };
    std::array<int32_t, kLeafVoxels> leaf;
    std::array<uint64_t, 8> mask;
    for (int s = 0, l = 0; s < kInternal4Slots; ++s) {
        const glm::ivec3 slot(s >> 8, (s >> 4) & 15, s & 15);
        const glm::ivec3 lo = org + slot * 8, local = (slot & 3) * 8;
        if (mask_on(child.data(), s)) {
            // The leaf's values repeat its topology mask: a mismatch means damage.
            if (!bufs.get(mask.data(), sizeof mask) || std::memcmp(mask.data(), &leaf_masks[size_t(l++) * 64], 64) != 0)
                return damaged();
            if (Status st = read_values(bufs, kLeafVoxels, mask.data(), leaf.data()); !st)
                return st;
            if (mask_count(mask.data(), 8) == 0)
                continue;
            BlockId* ids = chunk_ids(slot);
            for (int i = 0; i < kLeafVoxels; ++i) {
                if (!mask_on(mask.data(), i))
                    continue;
                const glm::ivec3 v(i >> 6, (i >> 3) & 7, i & 7);
                if (Status st = block_id(lo + v, leaf[size_t(i)]); !st)
                    return st;
                ids[world::local_index(local.x + v.x, local.y + v.y, local.z + v.z)] = BlockId(leaf[size_t(i)]);
            }
        } else if (mask_on(value.data(), s) && values[size_t(s)] != 0) {
            if (Status st = block_id(lo, values[size_t(s)]); !st)
                return st;
            BlockId* ids = chunk_ids(slot);
            for (int z = 0; z < 8; ++z)
                for (int y = 0; y < 8; ++y)
                    for (int x = 0; x < 8; ++x)
                        ids[world::local_index(local.x + x, local.y + y, local.z + z)] = BlockId(values[size_t(s)]);
        }
    }
    const ChunkCoord base = org >> 5;
    for (int k = 0; k < kChunksPerNode; ++k) {
        if (!touched[size_t(k)])
            continue;
        Chunk c = Chunk::from_dense(std::span<const BlockId>(dense.data() + size_t(k) * kChunkVolume, kChunkVolume));
        if (!c.is_empty())
            out.emplace_back(base + ChunkCoord(k >> 4, (k >> 2) & 3, k & 3), std::move(c));
    }
    return {};
}

Result<bool> VdbStreamReader::State::next(std::vector<std::pair<ChunkCoord, Chunk>>& out) {
    out.clear();
    if (!error.empty())
        return Error{error};
    while (!done) {
        if (in5) { // The rest of the Internal5 node being walked.
            while (slot5 < kInternal5Slots) {
                const int s = slot5++;
                const glm::ivec3 org = org5 + glm::ivec3(s >> 10, (s >> 5) & 31, s & 31) * kInternal4Dim;
                if (mask_on(child5.data(), s)) {
                    if (Status st = read_internal4(org, out); !st)
                        return Error{st.error()};
                } else if (mask_on(value5.data(), s) && values5[size_t(s)] != 0) {
                    if (Status st = block_id(org, values5[size_t(s)]); !st)
                        return Error{st.error()};
                    uniform_node(org, values5[size_t(s)], out);
                }
                if (!out.empty())
                    return true;
            }
            in5 = false;
        }
        if (!have_child_origin && children_left > 0) {
            if (!topo.pod(child_origin) || (child_origin & (kInternal5Dim - 1)) != glm::ivec3(0) ||
                (any_origin && !lex_less(last_origin, child_origin)))
                return Error{damaged().error()};
            have_child_origin = any_origin = true;
            last_origin = child_origin;
            --children_left;
        }
        const bool tile_first =
            next_tile < tiles.size() && (!have_child_origin || lex_less(tiles[next_tile].origin, child_origin));
        if (tile_first) { // The next 128³ part of a root tile.
            const RootTile t = tiles[next_tile];
            const int j = ++tile_node;
            if (j == kInternal5Slots - 1) {
                tile_node = -1;
                ++next_tile;
            }
            uniform_node(t.origin + glm::ivec3(j >> 10, (j >> 5) & 31, j & 31) * kInternal4Dim, t.value, out);
            return true;
        }
        if (have_child_origin) {
            if (next_tile < tiles.size() && tiles[next_tile].origin == child_origin)
                return Error{damaged().error()};
            have_child_origin = false;
            org5 = child_origin;
            if (!topo.get(child5.data(), sizeof child5) || !topo.get(value5.data(), sizeof value5))
                return Error{damaged().error()};
            if (Status st = read_values(topo, kInternal5Slots, value5.data(), values5.data()); !st)
                return Error{st.error()};
            in5 = true;
            slot5 = 0;
            continue;
        }
        // The end: both cursors must stop where the file says the tree's parts end.
        if (topo.pos != block_pos || bufs.pos != end_pos)
            return Error{damaged().error()};
        done = true;
    }
    return false;
}

VdbStreamReader::VdbStreamReader(std::unique_ptr<State> s) : m_state(std::move(s)) {}
VdbStreamReader::~VdbStreamReader() = default;

Result<std::unique_ptr<VdbStreamReader>> VdbStreamReader::open(const std::string& path,
                                                               const VdbStreamReadOptions& options) {
    auto s = std::make_unique<State>();
    s->path = path;
    s->options = options;
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec)
        return make_error("cannot read '" + path + "'", ec.message());
    for (In* in : {&s->topo, &s->bufs}) {
        in->f = std::fopen(path.c_str(), "rb");
        if (!in->f)
            return make_error("cannot read '" + path + "'", std::strerror(errno));
        in->end = int64_t(size);
    }
    if (Status st = s->open_header(); !st)
        return Error{st.error()};
    return std::unique_ptr<VdbStreamReader>(new VdbStreamReader(std::move(s)));
}

const world::BlockRegistry& VdbStreamReader::registry() const { return m_state->registry; }

Result<bool> VdbStreamReader::next(std::vector<std::pair<ChunkCoord, Chunk>>& out) {
    Result<bool> r = m_state->next(out);
    if (!r)
        out.clear();
    return r;
}

} // namespace vx::vdb
