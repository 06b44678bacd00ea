// The streaming VDB writer (vdb_stream.h): our own serializer of OpenVDB's file format for the
// vx-world tree. For an identical tree its topology and leaf values are byte for byte what
// OpenVDB 10 writes (tests/vdb/vdb_stream_test.cpp compares them).
#include <algorithm>
#include <array>
#include <cerrno>
#include <cinttypes>
#include <climits>
#include <cstring>
#include <filesystem>
#include <random>

#include <zlib.h>

#include "world/vdb/vdb_common.h"
#include "world/vdb/vdb_meta.h"
#include "world/vdb/vdb_stream.h"
#include "world/vdb/vdb_stream_format.h"

namespace vx::vdb {

using namespace detail;
using world::BlockId;
using world::BlockPos;
using world::Chunk;
using world::ChunkCoord;
using world::kChunkSize;
using world::kChunkVolume;

bool file_order_less(ChunkCoord a, ChunkCoord b) {
    const auto lex = [](glm::ivec3 p, glm::ivec3 q) {
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
    };
    if (a >> 7 != b >> 7)
        return lex(a >> 7, b >> 7);
    if (a >> 2 != b >> 2)
        return lex(a >> 2, b >> 2);
    return lex(a, b);
}

namespace {

constexpr int kChunksPerNode = 64;  // 4 x 4 x 4 chunks per Internal4 node.
constexpr int kSlotsPerChunk = kChunkSize / 8;

// A FILE* that remembers its first failure.
struct Out {
    std::FILE* f = nullptr;
    bool failed = false;
    void put(const void* p, size_t n) {
        if (n && !failed && std::fwrite(p, 1, n, f) != n)
            failed = true;
    }
    template <class T> void pod(const T& v) { put(&v, sizeof v); }
    void str(const std::string& s) {
        pod(uint32_t(s.size()));
        put(s.data(), s.size());
    }
    int64_t tell() const { return int64_t(::ftello(f)); }
    void patch(int64_t at, const void* p, size_t n) {
        const int64_t back = tell();
        if (::fseeko(f, at, SEEK_SET) != 0)
            failed = true;
        put(p, n);
        if (::fseeko(f, back, SEEK_SET) != 0)
            failed = true;
    }
};

// Opens a scratch file beside `path` and unlinks it: it vanishes with the process.
Result<std::FILE*> open_scratch(const std::string& path) {
    Result<std::string> name = create_temp_beside(path);
    if (!name)
        return Error{name.error()};
    std::FILE* f = std::fopen(name->c_str(), "w+b");
    std::error_code ec;
    std::filesystem::remove(*name, ec);
    if (!f)
        return make_error("cannot open a temporary beside '" + path + "'", std::strerror(errno));
    return f;
}

std::string random_uuid() {
    std::random_device rd;
    std::mt19937_64 rng((uint64_t(rd()) << 32) ^ rd());
    char s[kUuidChars + 1];
    const uint64_t a = rng(), b = rng();
    // Version 4, variant 1, as boost::uuids::random_generator makes for OpenVDB.
    std::snprintf(s, sizeof s, "%08" PRIx32 "-%04" PRIx32 "-4%03" PRIx32 "-%04" PRIx32 "-%012" PRIx64, uint32_t(a >> 32),
                  uint32_t(a >> 16) & 0xFFFF, uint32_t(a) & 0xFFF, 0x8000 | (uint32_t(b >> 48) & 0x3FFF),
                  uint64_t(b & 0xFFFFFFFFFFFFull));
    return s;
}

BlockBox intersect(const BlockBox& a, const BlockBox& b) { return {glm::max(a.min, b.min), glm::min(a.max, b.max)}; }

bool in_vdb_range(BlockPos p) {
    return std::abs(p.x) <= kVdbCoordLimit && std::abs(p.y) <= kVdbCoordLimit && std::abs(p.z) <= kVdbCoordLimit;
}

} // namespace

struct VdbStreamWriter::State {
    std::string path, target, tmp; // As given; what tmp replaces (a link's end); the temporary.
    // The file; the current Internal5 node's children's topology; the root's children's topology
    // (root tiles precede them in the file); leaf values.
    Out out, kids, roots, bufs;
    uint32_t compression = 0;
    BlockBox box{BlockPos(INT64_MIN), BlockPos(INT64_MAX)};
    bool finished = false, broken = false;

    int64_t at_stream_pos = 0, at_bbox_min = 0, at_bbox_max = 0, at_mem = 0, at_count = 0;
    glm::ivec3 bb_min{INT32_MAX}, bb_max{INT32_MIN};
    uint64_t voxels = 0, leaves = 0, internal4 = 0, internal5 = 0;

    // The Internal4 node being gathered.
    bool have_node = false;
    ChunkCoord node{0};
    std::vector<std::pair<ChunkCoord, Chunk>> chunks;
    std::vector<BlockId> dense = std::vector<BlockId>(size_t(kChunksPerNode) * kChunkVolume);
    std::vector<uint8_t> leaf_masks;

    // The Internal5 node being written.
    bool have5 = false;
    ChunkCoord node5{0};
    std::array<uint64_t, kInternal5Slots / 64> child5{}, value5{};
    std::vector<int32_t> values5 = std::vector<int32_t>(kInternal5Slots);
    uint64_t root_children = 0;
    std::vector<std::pair<glm::ivec3, int32_t>> root_tiles; // Internal5 nodes of one id (4096³).

    std::vector<int32_t> active;
    std::vector<Bytef> zipped;

    ~State() {
        for (std::FILE* f : {out.f, kids.f, roots.f, bufs.f})
            if (f)
                std::fclose(f);
        if (!finished && !tmp.empty()) {
            std::error_code ec;
            std::filesystem::remove(tmp, ec);
        }
    }

    bool io_failed() const { return out.failed || kids.failed || roots.failed || bufs.failed; }

    // Appends the first `n` bytes of scratch file `from` to `to`, and rewinds `from`.
    static void append(Out& to, Out& from, int64_t n) {
        std::vector<char> buf(size_t(1) << 20);
        if (std::fflush(from.f) != 0 || ::fseeko(from.f, 0, SEEK_SET) != 0)
            from.failed = true;
        for (int64_t left = n; left > 0 && !from.failed && !to.failed;) {
            const size_t want = size_t(std::min<int64_t>(left, int64_t(buf.size())));
            if (std::fread(buf.data(), 1, want, from.f) != want)
                from.failed = true;
            to.put(buf.data(), want);
            left -= int64_t(want);
        }
        if (::fseeko(from.f, 0, SEEK_SET) != 0)
            from.failed = true;
    }

    // A value array as writeCompressedValues stores it when every inactive value is the
    // background 0: metadata byte 0, then the active values, zipped when that is smaller.
    void write_values(Out& o, const std::vector<int32_t>& v) {
        o.pod(uint8_t(kNoMaskOrInactiveVals));
        const size_t bytes = v.size() * sizeof(int32_t);
        if (!(compression & kCompressZip)) {
            o.put(v.data(), bytes);
            return;
        }
        uLongf n = compressBound(uLong(bytes));
        zipped.resize(n);
        const int rc = compress2(zipped.data(), &n, reinterpret_cast<const Bytef*>(v.data()), uLong(bytes),
                                 Z_DEFAULT_COMPRESSION);
        if (rc == Z_OK && n < bytes) {
            o.pod(int64_t(n));
            o.put(zipped.data(), n);
        } else { // Stored raw, its size negated.
            o.pod(-int64_t(bytes));
            o.put(v.data(), bytes);
        }
    }

    void grow_bbox(glm::ivec3 lo, glm::ivec3 hi) {
        bb_min = glm::min(bb_min, lo);
        bb_max = glm::max(bb_max, hi);
    }

    void write_header(const world::BlockRegistry& registry, const VdbExportOptions& options);
    void flush_node();
    void flush_internal5();
};

void VdbStreamWriter::State::write_header(const world::BlockRegistry& registry, const VdbExportOptions& options) {
    out.pod(kVdbMagic);
    out.pod(kFileVersion);
    out.pod(kLibraryMajor);
    out.pod(kLibraryMinor);
    out.pod(uint8_t(1)); // The file has grid offsets.
    const std::string uuid = random_uuid();
    out.put(uuid.data(), uuid.size());
    // File metadata, grid count, the grid descriptor (name, type, no instance parent).
    out.pod(uint32_t(1));
    out.str("creator");
    out.str("string");
    out.str("vx");
    out.pod(int32_t(1));
    out.str("blocks");
    out.str(kGridType);
    out.str("");
    at_stream_pos = out.tell(); // Grid, tree-buffer and end offsets: patched by finish().
    const int64_t zero3[3] = {0, 0, 0};
    out.put(zero3, sizeof zero3);
    out.pod(compression);

    VdbMetaMap meta;
    meta["class"] = meta_string("unknown");
    meta["name"] = meta_string("blocks");
    meta["file_compression"] = meta_string((compression & kCompressZip) ? "zip + active values" : "active values");
    const int32_t no_box[3] = {0, 0, 0};
    meta["file_bbox_min"] = {"vec3i", std::string(reinterpret_cast<const char*>(no_box), 12)};
    meta["file_bbox_max"] = meta["file_bbox_min"];
    meta["file_mem_bytes"] = meta_int64(0);
    meta["file_voxel_count"] = meta_int64(0);
    meta["vx_format"] = meta_string("vx-world");
    meta["vx_format_version"] = meta_int32(1);
    meta["vx_chunk_size"] = meta_int32(kChunkSize);
    if (options.box && !options.box->empty() && in_vdb_range(options.box->min) && in_vdb_range(options.box->max)) {
        const int32_t lo[3] = {int32_t(options.box->min.x), int32_t(options.box->min.y), int32_t(options.box->min.z)};
        const int32_t hi[3] = {int32_t(options.box->max.x), int32_t(options.box->max.y), int32_t(options.box->max.z)};
        meta["vx_box_min"] = {"vec3i", std::string(reinterpret_cast<const char*>(lo), 12)};
        meta["vx_box_max"] = {"vec3i", std::string(reinterpret_cast<const char*>(hi), 12)};
    }
    add_registry_meta(meta, registry);
    out.pod(uint32_t(meta.size()));
    for (const auto& [key, value] : meta) {
        out.str(key);
        out.str(value.type);
        const int64_t at = out.tell() + 4; // The value, after its size.
        if (key == "file_bbox_min")
            at_bbox_min = at;
        else if (key == "file_bbox_max")
            at_bbox_max = at;
        else if (key == "file_mem_bytes")
            at_mem = at;
        else if (key == "file_voxel_count")
            at_count = at;
        out.str(value.bytes);
    }
    // Voxel (i, j, k) covers world [i, i + 1): scale 1, translation 0.5 (vdb_world.h). The map
    // stores translation, scale, voxel size, 1/scale, 1/scale², 1/(2 scale).
    out.str(kTransformType);
    for (double v : {0.5, 1.0, 1.0, 1.0, 1.0, 0.5})
        for (int axis = 0; axis < 3; ++axis)
            out.pod(v);
    // Tree: one buffer, background 0; the root's tiles and children follow in finish().
    out.pod(int32_t(1));
    out.pod(int32_t(0));
}

// Writes the gathered Internal4 node: its leaves' values to `bufs`, its topology to `kids`, or a
// tile of its Internal5 parent when all 4096 slots are active tiles of one value (OpenVDB's
// prune() does the same), or nothing when it holds no block.
void VdbStreamWriter::State::flush_node() {
    if (!have_node)
        return;
    have_node = false;
    const ChunkCoord n5 = node >> 5;
    if (have5 && n5 != node5)
        flush_internal5();
    if (!have5) {
        have5 = true;
        node5 = n5;
    }
    std::array<int, kChunksPerNode> index;
    index.fill(-1);
    std::array<bool, kChunksPerNode> whole_uniform{};
    std::array<BlockBox, kChunksPerNode> clip;
    for (size_t i = 0; i < chunks.size(); ++i) {
        const ChunkCoord c = chunks[i].first;
        const int k = node_offset(c.x & 3, c.y & 3, c.z & 3, 2);
        index[size_t(k)] = int(i);
        const BlockBox cb{world::chunk_origin(c), world::chunk_origin(c) + BlockPos(kChunkSize - 1)};
        clip[size_t(k)] = intersect(cb, box);
        whole_uniform[size_t(k)] = chunks[i].second.is_uniform() && clip[size_t(k)].min == cb.min && clip[size_t(k)].max == cb.max;
        if (!whole_uniform[size_t(k)])
            chunks[i].second.to_dense(std::span(dense).subspan(size_t(k) * kChunkVolume, kChunkVolume));
    }
    std::array<uint64_t, kInternal4Slots / 64> child4{}, value4{};
    std::vector<int32_t> tiles;
    leaf_masks.clear();
    const glm::ivec3 org4 = node * kInternal4Dim;
    std::array<uint64_t, 8> leaf_mask;
    for (int s = 0; s < kInternal4Slots; ++s) {
        const glm::ivec3 slot(s >> 8, (s >> 4) & 15, s & 15);
        const int k = node_offset(slot.x >> 2, slot.y >> 2, slot.z >> 2, 2);
        if (index[size_t(k)] < 0)
            continue;
        const Chunk& chunk = chunks[size_t(index[size_t(k)])].second;
        const glm::ivec3 lo = org4 + slot * 8;
        if (whole_uniform[size_t(k)]) {
            if (chunk.uniform_id() != world::kAir) {
                mask_set(value4.data(), s);
                tiles.push_back(int32_t(chunk.uniform_id()));
                grow_bbox(lo, lo + 7);
                voxels += kLeafVoxels;
            }
            continue;
        }
        const BlockId* ids = dense.data() + size_t(k) * kChunkVolume;
        const glm::ivec3 local = (slot & (kSlotsPerChunk - 1)) * 8;
        const BlockBox& cl = clip[size_t(k)];
        leaf_mask.fill(0);
        active.clear();
        glm::ivec3 vmin(INT32_MAX), vmax(INT32_MIN);
        bool uniform = true;
        for (int x = 0; x < 8; ++x)
            for (int y = 0; y < 8; ++y)
                for (int z = 0; z < 8; ++z) {
                    const BlockId id = ids[world::local_index(local.x + x, local.y + y, local.z + z)];
                    const glm::ivec3 p = lo + glm::ivec3(x, y, z);
                    if (id == world::kAir || !cl.contains(BlockPos(p)))
                        continue;
                    uniform = uniform && (active.empty() || int32_t(id) == active[0]);
                    mask_set(leaf_mask.data(), node_offset(x, y, z, 3));
                    active.push_back(int32_t(id));
                    vmin = glm::min(vmin, p);
                    vmax = glm::max(vmax, p);
                }
        if (active.empty())
            continue;
        voxels += active.size();
        grow_bbox(vmin, vmax);
        if (uniform && active.size() == size_t(kLeafVoxels)) { // A full slot of one id: a tile.
            mask_set(value4.data(), s);
            tiles.push_back(active[0]);
            continue;
        }
        mask_set(child4.data(), s);
        const auto* mb = reinterpret_cast<const uint8_t*>(leaf_mask.data());
        leaf_masks.insert(leaf_masks.end(), mb, mb + sizeof leaf_mask);
        bufs.put(leaf_mask.data(), sizeof leaf_mask); // A leaf's values repeat its mask.
        write_values(bufs, active);
        ++leaves;
    }
    chunks.clear();
    const int offset5 = node_offset(node.x & 31, node.y & 31, node.z & 31, kInternal5Log2);
    if (leaf_masks.empty() && tiles.size() == size_t(kInternal4Slots) &&
        std::all_of(tiles.begin(), tiles.end(), [&](int32_t v) { return v == tiles[0]; })) {
        mask_set(value5.data(), offset5);
        values5[size_t(offset5)] = tiles[0];
        return;
    }
    if (leaf_masks.empty() && tiles.empty())
        return;
    mask_set(child5.data(), offset5);
    kids.put(child4.data(), sizeof child4);
    kids.put(value4.data(), sizeof value4);
    write_values(kids, tiles);
    kids.put(leaf_masks.data(), leaf_masks.size());
    ++internal4;
}

// Writes the Internal5 node in progress (origin, masks, tile values, then its children's
// topology from `kids`) to `roots` as the next root child; or, when its 32768 slots are active
// tiles of one id, keeps it as a root tile (OpenVDB's prune() again); or nothing when it is empty.
void VdbStreamWriter::State::flush_internal5() {
    if (!have5)
        return;
    have5 = false;
    const auto any = [](const auto& m) { return std::any_of(m.begin(), m.end(), [](uint64_t w) { return w != 0; }); };
    const bool no_children = !any(child5);
    const bool all_tiles = std::all_of(value5.begin(), value5.end(), [](uint64_t w) { return w == ~uint64_t(0); });
    const glm::ivec3 org = node5 * kInternal5Dim;
    if (no_children && all_tiles &&
        std::all_of(values5.begin(), values5.end(), [&](int32_t v) { return v == values5[0]; })) {
        root_tiles.emplace_back(org, values5[0]);
    } else if (!no_children || any(value5)) {
        roots.pod(org);
        roots.put(child5.data(), sizeof child5);
        roots.put(value5.data(), sizeof value5);
        active.clear();
        for (int i = 0; i < kInternal5Slots; ++i)
            if (mask_on(value5.data(), i))
                active.push_back(values5[size_t(i)]);
        write_values(roots, active);
        append(roots, kids, kids.tell());
        ++root_children;
        ++internal5;
    }
    if (::fseeko(kids.f, 0, SEEK_SET) != 0)
        kids.failed = true;
    child5.fill(0);
    value5.fill(0);
}

VdbStreamWriter::VdbStreamWriter(std::unique_ptr<State> s) : m_state(std::move(s)) {}
VdbStreamWriter::~VdbStreamWriter() = default;

Result<std::unique_ptr<VdbStreamWriter>> VdbStreamWriter::create(const std::string& path,
                                                                 const world::BlockRegistry& registry,
                                                                 const VdbExportOptions& options) {
    auto s = std::make_unique<State>();
    s->path = path;
    // The file is patched as it is written (seeks), then renamed over its target: a device or a
    // FIFO there can take neither, and a rename over a device would replace it.
    const world::WriteTarget target = world::write_target(path);
    if (target.in_place) {
        std::error_code ec;
        const bool folder = std::filesystem::is_directory(target.path, ec);
        const std::string why = folder ? std::strerror(EISDIR) : "not a regular file (a VDB export needs one)";
        return Error{"cannot export to '" + path + "': " + why};
    }
    s->target = target.path;
    Result<std::string> tmp = create_temp_beside(s->target);
    if (!tmp)
        return Error{"cannot export to '" + path + "': " + tmp.error()};
    s->tmp = *tmp;
    world::keep_permissions(s->tmp, s->target);
    s->out.f = std::fopen(s->tmp.c_str(), "wb");
    if (!s->out.f)
        return make_error("cannot export to '" + path + "'", std::strerror(errno));
    for (Out* o : {&s->kids, &s->roots, &s->bufs}) {
        Result<std::FILE*> f = open_scratch(path);
        if (!f)
            return Error{"cannot export to '" + path + "': " + f.error()};
        o->f = *f;
    }
    s->compression = kCompressActiveMask | (options.compression == VdbCompression::Zip ? kCompressZip : 0);
    if (options.box)
        s->box = *options.box;
    s->write_header(registry, options);
    if (s->io_failed())
        return make_error("cannot write '" + path + "'", std::strerror(errno));
    return std::unique_ptr<VdbStreamWriter>(new VdbStreamWriter(std::move(s)));
}

Status VdbStreamWriter::add(ChunkCoord c, const Chunk& chunk) {
    State& s = *m_state;
    if (s.broken || s.finished)
        return Error{"cannot write '" + s.path + "': the export already failed or finished"};
    const BlockBox clip = intersect({world::chunk_origin(c), world::chunk_origin(c) + BlockPos(kChunkSize - 1)}, s.box);
    if (clip.empty() || chunk.is_empty())
        return {};
    if (!in_vdb_range(clip.min) || !in_vdb_range(clip.max)) {
        s.broken = true;
        char msg[160];
        std::snprintf(msg, sizeof msg, "chunk (%d, %d, %d) lies beyond OpenVDB's 32-bit index range (|block| <= %lld)",
                      c.x, c.y, c.z, (long long)kVdbCoordLimit);
        return Error{"cannot export to '" + s.path + "': " + msg};
    }
    const ChunkCoord node = node_of(c);
    if (s.have_node && node != s.node) {
        if (!file_order_less(s.node * 4, c)) {
            s.broken = true;
            return Error{"cannot export to '" + s.path + "': chunks out of file order (a bug)"};
        }
        s.flush_node();
    }
    for (const auto& held : s.chunks)
        if (held.first == c) {
            s.broken = true;
            return Error{"cannot export to '" + s.path + "': a chunk given twice (a bug)"};
        }
    s.have_node = true;
    s.node = node;
    s.chunks.emplace_back(c, chunk);
    ++m_chunks;
    if (s.io_failed()) {
        s.broken = true;
        return make_error("cannot write '" + s.path + "'", std::strerror(errno));
    }
    return {};
}

Status VdbStreamWriter::finish() {
    State& s = *m_state;
    if (s.broken || s.finished)
        return Error{"cannot write '" + s.path + "': the export already failed or finished"};
    s.flush_node();
    s.flush_internal5();
    // The root: tile and child counts, the tiles (origin, value, active), the children; then the
    // leaf values.
    s.out.pod(uint32_t(s.root_tiles.size()));
    s.out.pod(uint32_t(s.root_children));
    for (const auto& [org, value] : s.root_tiles) {
        s.out.pod(org);
        s.out.pod(value);
        s.out.pod(uint8_t(1));
    }
    State::append(s.out, s.roots, s.roots.tell());
    const int64_t block_pos = s.out.tell();
    State::append(s.out, s.bufs, s.bufs.tell());
    const int64_t end_pos = s.out.tell();
    // The offsets and statistics that precede the tree.
    const int64_t pos[3] = {s.at_stream_pos + 24, block_pos, end_pos};
    s.out.patch(s.at_stream_pos, pos, sizeof pos);
    s.out.patch(s.at_bbox_min, &s.bb_min, 12);
    s.out.patch(s.at_bbox_max, &s.bb_max, 12);
    const int64_t mem = int64_t(kMemTree + kMemInternal5 * s.internal5 + kMemInternal4 * s.internal4 + kMemLeaf * s.leaves);
    s.out.patch(s.at_mem, &mem, 8);
    const int64_t count = int64_t(s.voxels);
    s.out.patch(s.at_count, &count, 8);
    const bool flushed = std::fflush(s.out.f) == 0;
    const bool closed = std::fclose(s.out.f) == 0;
    s.out.f = nullptr;
    if (s.io_failed() || !flushed || !closed) {
        s.broken = true;
        return make_error("cannot write '" + s.path + "'", std::strerror(errno));
    }
    s.finished = true;
    if (Status r = replace_file(s.tmp, s.target); !r)
        return r;
    return {};
}

} // namespace vx::vdb
