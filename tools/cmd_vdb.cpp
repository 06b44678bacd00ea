// `vx export-vdb` and `vx import-vdb`: worlds to and from OpenVDB files. Imports of files from
// elsewhere run in a child process (vdb_isolated.h): OpenVDB's reader is not safe on damaged input.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_common.h"
#include "commands.h"
#include "world/block_registry_text.h"
#include "world/store/store_open.h"
#include "world/vdb/vdb_isolated.h"
#include "world/vdb/vdb_overlay_store.h"
#include "world_io.h"

namespace vx::tools {
namespace {

using namespace vx::world;
using namespace vx::vdb;
using Clock = std::chrono::steady_clock;

// "X0,Y0,Z0,X1,Y1,Z1" of blocks inside the world (|coordinate| < 2^36), X0 <= X1 and so on. A
// number past 64 bits was clamped by strtoll and exported an empty box as a success.
std::optional<BlockBox> parse_box(const std::string& s) {
    const std::vector<std::string> parts = split_commas(s);
    if (parts.size() != 6)
        return std::nullopt;
    BlockPos lo(0), hi(0);
    for (int i = 0; i < 3; ++i) {
        const std::optional<int64_t> a = parse_i64(parts[size_t(i)]), b = parse_i64(parts[size_t(i + 3)]);
        if (!a || !b)
            return std::nullopt;
        lo[i] = *a;
        hi[i] = *b;
    }
    if (!in_world(lo) || !in_world(hi) || glm::any(glm::greaterThan(lo, hi)))
        return std::nullopt;
    return BlockBox{lo, hi};
}

struct ExportArgs {
    std::string world, out, box, compression = "zip", overlay;
};

bool names_vdb_file(const std::string& world) {
    return world.size() > 4 && world.compare(world.size() - 4, 4, ".vdb") == 0;
}

// The file `out` names when it is one of the files the export reads (the world, the overlay, or
// SQLite's -wal and -shm beside them): the export replaces `out` whole, so the world it read from
// would be gone. Empty when it is none of them.
std::string export_reads(const ExportArgs& a) {
    std::vector<std::string> inputs = {a.world};
    if (names_vdb_file(a.world))
        inputs.push_back(a.overlay.empty() ? default_overlay_name(a.world) : a.overlay);
    return output_overwrites(a.out, inputs);
}

int run_export(const ExportArgs& a) {
    std::optional<BlockBox> box;
    if (!a.box.empty() && !(box = parse_box(a.box)))
        return bad_input("--box must be X0,Y0,Z0,X1,Y1,Z1 with X0 <= X1, Y0 <= Y1, Z0 <= Z1, inside the world "
                         "(|coordinate| < 2^36)");
    if (std::string why = output_file_problem(a.out); !why.empty())
        return bad_input("--out: " + why);
    if (std::string in = export_reads(a); !in.empty())
        return bad_input("--out '" + a.out + "' is '" + in + "', which the export reads: it would replace the world");
    if (!a.overlay.empty() && !names_vdb_file(a.world))
        return bad_input("--overlay goes with a VDB world (a .vdb file), not '" + a.world + "'");
    const auto t0 = Clock::now();
    VdbExportOptions opt;
    opt.box = box;
    opt.compression = a.compression == "none" ? VdbCompression::None : VdbCompression::Zip;
    // A .vdb world is exported with its edits (VDB grid plus overlay, streamed side by side); a
    // store as it is, chunk by chunk. Both write node by node (vdb_stream.h).
    if (names_vdb_file(a.world)) {
        auto done = export_overlay_vdb({.vdb_path = a.world, .overlay = a.overlay, .read_only = true, .read = {}},
                                       a.out, opt);
        if (!done)
            return bad_input(done.error());
        std::printf("vx export-vdb: %" PRIu64 " chunks of %s with its edits -> %s (Int32 grid 'blocks', %s) in %.2f s%s%s\n",
                    done->chunks, a.world.c_str(), a.out.c_str(), a.compression.c_str(),
                    std::chrono::duration<double>(Clock::now() - t0).count(),
                    done->fallback.empty() ? "" : "; read whole, not streamed: ", done->fallback.c_str());
        return kExitOk;
    }
    auto store = open_store({a.world, /*read_only=*/true, /*create=*/false, /*listen=*/false});
    if (!store)
        return bad_input(store.error());
    // The block table the store records (import-vdb and the engine write it), else the default:
    // an imported world's own names and materials were exported as the default palette.
    Result<std::optional<std::string>> table = (*store)->get_meta("registry");
    if (!table)
        return bad_input(table.error());
    Result<BlockRegistry> registry = *table ? registry_from_text(**table) : BlockRegistry::default_registry();
    if (!registry)
        return bad_input(a.world + ": " + registry.error());
    Result<uint64_t> chunks = export_store_vdb(**store, *registry, a.out, opt);
    if (!chunks)
        return bad_input(chunks.error());
    std::printf("vx export-vdb: %" PRIu64 " chunks of %s -> %s (Int32 grid 'blocks', %s) in %.2f s\n",
                *chunks, a.world.c_str(), a.out.c_str(), a.compression.c_str(),
                std::chrono::duration<double>(Clock::now() - t0).count());
    return kExitOk;
}

struct ImportArgs {
    std::string file, out, grid, mode = "auto", sampling = "adaptive", offset = "0,0,0", density;
    int index = -1, voxels_per_block = 0;
    double block_size = 0;         // World units; meaningful when block_size_given.
    bool block_size_given = false;
    float threshold = 0.25f;
    int block = 1;
    bool list = false;
    double max_memory_gib = 4;   // The isolated reader's address-space cap.
    uint32_t max_seconds = 600;  // Its CPU-time cap.
    std::vector<std::string> volume_options; // Volume-only options given (a vx world refuses them).
};

IsolationOptions isolation(const ImportArgs& a) {
    IsolationOptions iso;
    iso.memory_limit = uint64_t(a.max_memory_gib * double(uint64_t(1) << 30));
    iso.cpu_seconds = a.max_seconds;
    iso.memory_option = "--max-memory GiB";
    iso.cpu_option = "--max-seconds S";
    return iso;
}

int list(const std::string& file, const IsolationOptions& iso) {
    auto grids = list_grids_isolated(file, iso);
    if (!grids)
        return bad_input(grids.error());
    for (const GridInfo& g : *grids) {
        std::printf("[%d] '%s' %s, %s, voxel %.4g", g.index, g.name.c_str(), g.value_type.c_str(),
                    g.grid_class.c_str(), g.voxel_size.x);
        if (g.voxel_size.y != g.voxel_size.x || g.voxel_size.z != g.voxel_size.x)
            std::printf(" x %.4g x %.4g", g.voxel_size.y, g.voxel_size.z);
        std::printf(" (%s), %" PRIu64 " active voxels", g.transform.c_str(), g.active_voxels);
        if (!g.empty)
            std::printf(", bbox (%d,%d,%d)..(%d,%d,%d)", g.bbox_min.x, g.bbox_min.y, g.bbox_min.z, g.bbox_max.x,
                        g.bbox_max.y, g.bbox_max.z);
        std::printf("%s\n", g.saved_as_half ? ", half floats" : "");
    }
    return kExitOk;
}

// "0.2:3,0.6:1": mean relative density -> block id.
std::optional<std::vector<DensityBlock>> parse_density(const std::string& s) {
    std::vector<DensityBlock> out;
    for (const std::string& item : split_commas(s)) { // A trailing comma is an empty, bad item.
        float d;
        int id;
        char colon;
        std::istringstream is(item);
        if (!(is >> d >> colon >> id) || colon != ':' || !(d >= 0 && d <= 1) || id < 1 || id > 0xFFFF ||
            is.peek() != std::char_traits<char>::eof()) // "0.5:3x" was 0.5:3.
            return std::nullopt;
        out.push_back({d, BlockId(id)});
    }
    if (out.empty())
        return std::nullopt;
    return out;
}

// The volume options, checked before any file is read: a bad one costs no import.
Result<VolumeImportOptions> volume_options(const ImportArgs& a) {
    VolumeImportOptions o;
    o.grid_name = a.grid;
    o.grid_index = a.index;
    if (a.block_size_given && a.voxels_per_block > 0)
        return Error{"give --block-size (world units) or --voxels-per-block, not both"};
    if (a.block_size_given && !(a.block_size > 0 && std::isfinite(a.block_size)))
        return Error{"--block-size must be a positive, finite length in the file's world units"};
    o.block_size = a.block_size_given ? a.block_size : 0.0;
    o.voxels_per_block = a.voxels_per_block;
    o.mode = a.mode == "levelset" ? VolumeMode::LevelSet : a.mode == "fog" ? VolumeMode::Fog : VolumeMode::Auto;
    o.sampling = a.sampling == "centre"        ? VolumeSampling::CentreOnly
                 : a.sampling == "majority"    ? VolumeSampling::VoxelMajority
                 : a.sampling == "supersample" ? VolumeSampling::Supersample
                                               : VolumeSampling::Adaptive;
    if (!(a.threshold > 0.f && a.threshold <= 1.f)) // NaN too.
        return Error{"--threshold must be a fraction of the grid's maximum in (0, 1]"};
    o.threshold = a.threshold;
    if (a.block < 1 || a.block > 0xFFFF)
        return Error{"--block must be a block id 1..65535"};
    o.block = BlockId(a.block);
    if (!a.density.empty()) {
        auto d = parse_density(a.density);
        if (!d)
            return Error{"--density must look like 0.2:3,0.6:1 (relative density 0..1 : block id)"};
        o.density_blocks = *d;
    }
    auto off = parse_i64vec3(a.offset);
    if (!off)
        return Error{"--offset must be X,Y,Z (integers)"};
    o.offset = *off;
    return o;
}

int run_import(const ImportArgs& a) {
    if (a.list)
        return list(a.file, isolation(a));
    if (a.out.empty())
        return bad_input("need --out WORLD (or --list)");
    if (Status s = check_store_output(a.out); !s)
        return bad_input("--out: " + s.error());
    auto options = volume_options(a);
    if (!options)
        return bad_input(options.error());
    const auto t0 = Clock::now();
    // A vx world (an Int32 grid named 'blocks') comes back as it was; anything else is a volume.
    auto grids = list_grids_isolated(a.file, isolation(a));
    if (!grids)
        return bad_input(grids.error());
    bool is_world = a.grid.empty() && a.index < 0;
    if (is_world) {
        is_world = false;
        for (const GridInfo& g : *grids)
            is_world |= g.name == "blocks" && g.value_type == "int32";
    }
    World world;
    std::string what;
    if (is_world && !a.volume_options.empty())
        return bad_input("'" + a.file + "' holds a vx world (Int32 grid 'blocks'), imported block for block: " +
                         a.volume_options.front() + " is for volumes (name a grid with --grid or --index to " +
                         "import it as one)");
    if (is_world) {
        auto w = import_world_vdb_isolated(a.file, {}, isolation(a));
        if (!w)
            return bad_input(w.error());
        world = std::move(*w);
        what = "vx world grid 'blocks'";
    } else {
        const VolumeImportOptions& o = *options;
        std::fprintf(stderr, "importing %s ...\n", a.file.c_str());
        auto r = import_volume_isolated(a.file, o, isolation(a));
        if (!r)
            return bad_input(r.error());
        const VolumeImportSummary& s = r->summary;
        char line[512];
        const double finest = std::min({s.voxel_size.x, s.voxel_size.y, s.voxel_size.z});
        std::snprintf(line, sizeof line, "grid [%d] '%s', %s, voxel size %.4g, block size %.4g (%.3g voxels), %" PRIu64
                      " solid blocks (%" PRIu64 " supersampled)", s.grid_index, s.grid_name.c_str(),
                      to_string(s.mode), s.voxel_size.x, s.block_size, s.block_size / finest, s.solid_blocks,
                      s.supersampled_blocks);
        what = line;
        world = std::move(r->world);
    }
    if (Status s = save_store_world(world, a.out, a.file); !s)
        return bad_input(s.error());
    std::printf("vx import-vdb: %s -> %s: %s, %zu chunks, %.2f s\n", a.file.c_str(), a.out.c_str(), what.c_str(),
                world.chunk_count(), std::chrono::duration<double>(Clock::now() - t0).count());
    return kExitOk;
}

} // namespace

void add_vdb_commands(CLI::App& app, std::function<int()>& action) {
    auto e = std::make_shared<ExportArgs>();
    CLI::App* ex = app.add_subcommand("export-vdb", "Write a stored world (or a box of it) as an OpenVDB file");
    ex->add_option("world", e->world, "World store, or a VDB world (.vdb: written with its edits overlay)")->required();
    ex->add_option("--overlay", e->overlay, "The VDB world's edits (default: <world>.edits.sqlite)");
    ex->add_option("--out", e->out, "Output .vdb")->required();
    ex->add_option("--box", e->box, "Only blocks X0,Y0,Z0,X1,Y1,Z1 (inclusive, world block coordinates)");
    ex->add_option("--compression", e->compression, "zip (small; any OpenVDB reads it) or none (fast)")
        ->check(CLI::IsMember({"zip", "none"}));
    ex->callback([e, &action] { action = [e] { return run_export(*e); }; });

    auto i = std::make_shared<ImportArgs>();
    CLI::App* im = app.add_subcommand("import-vdb", "Import a VDB file (a vx world, or any level set / fog volume) into a world store");
    im->add_option("file", i->file, "Input .vdb")->required();
    im->add_option("--out", i->out, "World store to write (replaced only when the import succeeds)");
    im->add_flag("--list", i->list, "List the file's grids and exit");
    im->add_option("--grid", i->grid, "Grid by name");
    im->add_option("--index", i->index, "Grid by index (see --list)")->check(CLI::NonNegativeNumber);
    CLI::Option* block_size = im->add_option(
        "--block-size", i->block_size,
        "Block edge in the file's world units (decimal; default: the voxel size, one block per voxel)");
    im->add_option("--voxels-per-block", i->voxels_per_block, "Block edge as N voxels (1..64; cubic voxels only)")
        ->check(CLI::Range(1, 64));
    im->add_option("--mode", i->mode, "auto, levelset or fog")->check(CLI::IsMember({"auto", "levelset", "fog"}));
    im->add_option("--threshold", i->threshold, "Fog: solid at this fraction of the grid's max (0..1]");
    im->add_option("--block", i->block, "Block id of solid blocks (default 1, stone)");
    im->add_option("--density", i->density, "Fog: relative density -> block id, e.g. 0.2:3,0.6:1");
    im->add_option("--offset", i->offset, "X,Y,Z added to every block (world block coordinates)");
    im->add_option("--max-memory", i->max_memory_gib, "Memory cap of the isolated reader in GiB (default 4; 0: none)")
        ->check(finite_range(0.0, 65536.0, "a size in GiB from 0 to 65536"));
    im->add_option("--max-seconds", i->max_seconds, "CPU-time cap of the isolated reader in seconds (default 600; 0: none)");
    im->add_option("--sampling", i->sampling, "adaptive (default), centre, majority or supersample")
        ->check(CLI::IsMember({"adaptive", "centre", "majority", "supersample"}));
    im->callback([i, block_size, im, &action] {
        i->block_size_given = block_size->count() > 0;
        i->volume_options.clear();
        for (const char* name : {"--block-size", "--voxels-per-block", "--mode", "--threshold", "--block",
                                 "--density", "--offset", "--sampling"})
            if (im->get_option(name)->count() > 0)
                i->volume_options.push_back(name);
        action = [i] { return run_import(*i); };
    });
}

} // namespace vx::tools
