#include "world/io/raw_volume.h"

#include "world/base/file_replace.h"
#include "world/base/stdio_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <unordered_map>
#include <vector>

namespace vx::world {
namespace {

Status check_desc(const RawVolumeDesc& d) {
    if (d.dims.x <= 0 || d.dims.y <= 0 || d.dims.z <= 0)
        return Error{"dims must be positive"};
    if (uint64_t(d.dims.x) > kMaxRawBlocks || uint64_t(d.dims.y) > kMaxRawBlocks ||
        uint64_t(d.dims.z) > kMaxRawBlocks ||
        uint64_t(d.dims.x) * uint64_t(d.dims.y) > kMaxRawBlocks / uint64_t(d.dims.z))
        return Error{"volume too large (more than 2^34 blocks)"};
    if (uint64_t(d.dims.x) * uint64_t(d.dims.y) > kMaxRawPlaneBlocks)
        return Error{"volume too wide: a z-plane (X x Y) of more than 2^28 blocks (16384 x 16384); lay the long axis "
                     "along z"};
    if (!in_world(d.origin) || !in_world(d.origin + d.dims - glm::i64vec3(1)))
        return Error{"volume lies outside the world (block coordinates must stay within [-2^36, 2^36))"};
    return {};
}

} // namespace

Result<RawVolumeStats> load_raw_volume(const std::string& path, const RawVolumeDesc& desc, World& world) {
    if (Status s = check_desc(desc); !s)
        return Error{s.error()};
    std::error_code ec;
    if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
        return Error{"'" + path + "' is not a file"}; // A folder opened, and its size read as 2^63 - 1.
    StdioFile f(std::fopen(path.c_str(), "rb"));
    if (!f)
        return Error{"cannot open '" + path + "': " + std::strerror(errno)};
    const uint64_t bpv = desc.type == RawType::U8 ? 1 : 2;
    const uint64_t expect = uint64_t(desc.dims.x) * uint64_t(desc.dims.y) * uint64_t(desc.dims.z) * bpv;
    if (std::fseek(f.get(), 0, SEEK_END) != 0)
        return Error{"cannot seek in '" + path + "'"};
    const long size = std::ftell(f.get());
    if (size < 0 || uint64_t(size) != expect)
        return Error{"'" + path + "' has " + std::to_string(size) + " bytes but dims " +
                     std::to_string(desc.dims.x) + "," + std::to_string(desc.dims.y) + "," +
                     std::to_string(desc.dims.z) + " of " + (bpv == 1 ? "u8" : "u16") + " need " +
                     std::to_string(expect)};
    std::fseek(f.get(), 0, SEEK_SET);

    RawVolumeStats stats;
    const uint64_t plane_values = uint64_t(desc.dims.x) * uint64_t(desc.dims.y);
    std::vector<uint8_t> plane(plane_values * bpv);
    // Dense buffers of the chunks of the current chunk layer (same chunk z), flushed when z
    // crosses into the next layer.
    std::unordered_map<ChunkCoord, std::vector<BlockId>, ChunkCoordHash> layer;
    auto flush = [&] {
        for (auto& [c, ids] : layer) {
            Chunk chunk = Chunk::from_dense(ids);
            if (chunk.is_empty())
                continue;
            ++stats.chunks;
            world.put_chunk(c, std::move(chunk));
        }
        layer.clear();
    };
    int32_t layer_z = INT32_MIN;
    for (int64_t z = 0; z < desc.dims.z; ++z) {
        if (std::fread(plane.data(), 1, plane.size(), f.get()) != plane.size())
            return Error{"short read from '" + path + "'"};
        const int64_t wz = desc.origin.z + z;
        const int32_t cz = int32_t(wz >> kChunkBits);
        if (cz != layer_z) {
            flush();
            layer_z = cz;
        }
        for (int64_t y = 0; y < desc.dims.y; ++y) {
            const int64_t wy = desc.origin.y + y;
            for (int64_t x = 0; x < desc.dims.x; ++x) {
                const uint64_t i = uint64_t(y * desc.dims.x + x);
                const BlockId id = bpv == 1 ? plane[i] : BlockId(plane[2 * i] | (plane[2 * i + 1] << 8));
                if (id == kAir)
                    continue;
                const BlockPos p(desc.origin.x + x, wy, wz);
                auto [it, fresh] = layer.try_emplace(chunk_of(p));
                if (fresh) {
                    it->second.assign(kChunkVolume, kAir);
                    if (const Chunk* old = world.find_chunk(it->first))
                        old->to_dense(it->second);
                }
                it->second[local_index(local_of(p))] = id;
                ++stats.blocks;
            }
        }
    }
    flush();
    return stats;
}

Status save_raw_volume(const std::string& path, const RawVolumeDesc& desc, const World& world) {
    if (Status s = check_desc(desc); !s)
        return s;
    ReplacingFile f; // A failed save leaves the file that was there, not a cut one.
    if (Status s = f.open(path, "wb"); !s)
        return s;
    const bool u8 = desc.type == RawType::U8;
    std::vector<uint8_t> row(size_t(desc.dims.x) * (u8 ? 1 : 2));
    for (int64_t z = 0; z < desc.dims.z; ++z)
        for (int64_t y = 0; y < desc.dims.y; ++y) {
            for (int64_t x = 0; x < desc.dims.x; ++x) {
                const BlockId id = world.get_block(desc.origin + BlockPos(x, y, z));
                if (u8) {
                    if (id > 255)
                        return Error{"block id " + std::to_string(id) + " does not fit in u8"};
                    row[size_t(x)] = uint8_t(id);
                } else {
                    row[size_t(2 * x)] = uint8_t(id & 0xFF);
                    row[size_t(2 * x + 1)] = uint8_t(id >> 8);
                }
            }
            if (std::fwrite(row.data(), 1, row.size(), f.get()) != row.size())
                return Error{"write to '" + path + "' failed: " + std::strerror(errno)};
        }
    return f.commit();
}

} // namespace vx::world
