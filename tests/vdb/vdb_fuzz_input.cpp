#include "tests/vdb/vdb_fuzz_input.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "world/vdb/vdb_analytic.h"

namespace vx::vdb::fuzz {
namespace {

// Small files (30–245 KB) so an input costs a few tens of ms per read; the level set apart.
constexpr const char* kSmallFiles[] = {"gaffer_arnoldtest_sphere.vdb", "oiio_sphere.vdb",
                                       "arnoldusd_torus01.vdb",        "arnoldusd_grids.vdb",
                                       "gaffer_points.vdb",            "oiio_sphereCd.vdb"};
constexpr const char* kLargeFile = "gaffer_vdbtest_sphere.vdb";
constexpr uint64_t kLargeEvery = 25;

bool one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }

} // namespace

Result<Corpus> load_corpus(const std::string& dir) {
    Corpus c;
    std::vector<std::string> names(std::begin(kSmallFiles), std::end(kSmallFiles));
    names.push_back(kLargeFile);
    for (const std::string& name : names) {
        const std::string path = dir + "/" + name;
        std::ifstream f(path, std::ios::binary);
        if (!f)
            return Error{"cannot open '" + path +
                         "' (the folder of the real VDB files: --data DIR or VX_VDB_DATA_DIR)"};
        std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
        if (bytes.empty() || f.bad())
            return Error{"cannot read '" + path + "': empty or unreadable"};
        c.names.push_back(name);
        c.bytes.push_back(std::move(bytes));
    }
    c.large = int(c.names.size()) - 1;
    return c;
}

Result<Corpus> generated_corpus(const std::string& dir) {
    auto sphere = [](const char* name, bool level_set, double radius) {
        AnalyticVolume v;
        v.name = name;
        v.level_set = level_set;
        v.half_extent = glm::dvec3(radius);
        return v;
    };
    AnalyticVolume box = sphere("density", false, 5.0);
    box.shape = AnalyticShape::Box;
    box.half_extent = glm::dvec3(6.0, 3.0, 4.0);
    box.rotation = axis_rotation(30.0, {1.0, 2.0, 0.5});
    AnalyticVolume ellipsoid = sphere("surface", true, 1.0);
    ellipsoid.half_extent = glm::dvec3(4.0, 2.5, 3.0);
    ellipsoid.index_to_world = glm::dmat3(0.25, 0.0, 0.0, 0.0, 0.2, 0.0, 0.0, 0.0, 0.3);
    std::vector<AnalyticVolume> three = {sphere("density", false, 6.0), sphere("density", false, 9.0),
                                         sphere("density", false, 4.0)};
    three[1].centre = glm::dvec3(0.0, -4.0, 1.0);
    three[2].centre = glm::dvec3(20.0, 0.0, 0.0);
    struct File {
        const char* name;
        std::vector<AnalyticVolume> grids;
    };
    const File files[] = {
        {"fog_sphere.vdb", {sphere("density", false, 8.0)}},
        {"level_set_sphere.vdb", {sphere("ls_sphere", true, 10.0)}},
        {"fog_box.vdb", {box}},
        {"level_set_ellipsoid.vdb", {ellipsoid}},
        {"three_densities.vdb", three},
        {"large_level_set.vdb", {sphere("ls_sphere", true, 48.0)}}, // The large file: last.
    };
    std::vector<std::string> names;
    for (const File& f : files) {
        const std::string path = dir + "/" + f.name;
        if (Status st = write_analytic_vdb(path, std::span<const AnalyticVolume>(f.grids)); !st)
            return Error{st.error()};
        names.push_back(f.name);
    }
    Corpus c;
    for (const std::string& name : names) {
        std::ifstream in(dir + "/" + name, std::ios::binary);
        c.names.push_back(name);
        c.bytes.emplace_back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (c.bytes.back().empty())
            return Error{"cannot read back '" + dir + "/" + name + "'"};
    }
    c.large = int(c.names.size()) - 1;
    return c;
}

Result<Corpus> real_or_generated_corpus(const std::string& data, const std::string& scratch, bool& generated) {
    std::error_code ec;
    generated = !std::filesystem::is_directory(data, ec);
    return generated ? generated_corpus(scratch) : load_corpus(data);
}

const char* mutation_name(Mutation m) {
    switch (m) {
    case Mutation::BitFlips: return "bit flips";
    case Mutation::ByteRun: return "byte run";
    case Mutation::Truncation: return "truncation";
    case Mutation::HeaderFlip: return "header flip";
    }
    return "?";
}

Mutation mutate(std::string& bytes, std::mt19937& rng) {
    const auto kind = Mutation(rng() % 4);
    switch (kind) {
    case Mutation::BitFlips:
        for (int i = 0, n = 1 + int(rng() % 8); i < n; ++i)
            bytes[rng() % bytes.size()] ^= char(1u << (rng() % 8));
        break;
    case Mutation::ByteRun: // Random bytes over a short run (lengths, counts, type names).
        for (size_t i = rng() % bytes.size(), n = 1 + rng() % 8; n > 0 && i < bytes.size(); --n, ++i)
            bytes[i] = char(rng());
        break;
    case Mutation::Truncation:
        bytes.resize(rng() % bytes.size());
        break;
    case Mutation::HeaderFlip: // The first 512 bytes hold the most structure.
        bytes[rng() % std::min<size_t>(512, bytes.size())] ^= char(1u << (rng() % 8));
        break;
    }
    return kind;
}

Input make_input(const Corpus& corpus, uint32_t seed, uint64_t index) {
    Input in;
    const int small = corpus.large; // The small files come first.
    in.file = index % kLargeEvery == kLargeEvery - 1 ? corpus.large : int(index % uint64_t(small));
    std::seed_seq seq{seed, uint32_t(index), uint32_t(index >> 32)};
    std::mt19937 rng(seq);
    in.bytes = corpus.bytes[size_t(in.file)];
    in.mutation = mutate(in.bytes, rng);
    return in;
}

const char* outcome_name(Outcome o) {
    switch (o) {
    case Outcome::Imported: return "imported";
    case Outcome::Error: return "error";
    case Outcome::ChildCrashed: return "child crashed";
    case Outcome::MemoryCap: return "memory cap";
    case Outcome::CpuCap: return "cpu cap";
    }
    return "?";
}

Outcome classify(const std::string& error) {
    // The wording of vdb_isolated.cpp's describe_death and of the child's bad_alloc.
    if (error.find("crashed") != std::string::npos)
        return Outcome::ChildCrashed;
    if (error.find("bad_alloc") != std::string::npos)
        return Outcome::MemoryCap;
    if (error.find("CPU time limit") != std::string::npos)
        return Outcome::CpuCap;
    return Outcome::Error;
}

IsolationOptions fuzz_isolation() {
    IsolationOptions iso;
    iso.memory_limit = uint64_t(1) << 30;
    iso.cpu_seconds = 20;
    return iso;
}

namespace {

void check_error(ReadReport& rep, const std::string& what, const std::string& error) {
    const Outcome o = classify(error);
    ++rep.outcomes[int(o)];
    rep.lines.push_back(what + ": " + outcome_name(o) + ": " + error);
    if (!one_line(error))
        rep.malformed.push_back(std::string(what) + ": error is not one line: '" + error + "'");
}

void volume_read(ReadReport& rep, const std::string& path, int voxels_per_block,
                 const IsolationOptions& iso) {
    VolumeImportOptions o;
    o.voxels_per_block = voxels_per_block;
    o.max_blocks = uint64_t(1) << 24; // Bounds the work a corrupt bbox can ask for.
    Result<VolumeImport> r = import_volume_isolated(path, o, iso);
    ++rep.reads;
    if (!r.ok()) {
        check_error(rep, "import_volume " + std::to_string(voxels_per_block), r.error());
        return;
    }
    ++rep.outcomes[int(Outcome::Imported)];
    rep.lines.push_back("import_volume " + std::to_string(voxels_per_block) + ": imported: " +
                        std::to_string(r->summary.solid_blocks) + " solid blocks");
    if (r->summary.solid_blocks > o.max_blocks)
        rep.malformed.push_back("import_volume: " + std::to_string(r->summary.solid_blocks) +
                                " solid blocks over max_blocks " + std::to_string(o.max_blocks));
}

} // namespace

ReadReport run_reads(const std::string& path, Reads reads, const IsolationOptions& iso) {
    ReadReport rep;
    if (reads == Reads::Import) {
        volume_read(rep, path, 4, iso);
        return rep;
    }
    Result<std::vector<GridInfo>> grids = list_grids_isolated(path, iso);
    ++rep.reads;
    if (grids.ok()) {
        ++rep.outcomes[int(Outcome::Imported)];
        rep.lines.push_back("list_grids: imported: " + std::to_string(grids->size()) + " grids");
    } else {
        check_error(rep, "list_grids", grids.error());
    }
    for (int voxels_per_block : {1, 4})
        volume_read(rep, path, voxels_per_block, iso);
    VdbWorldImportOptions w;
    w.max_chunks = 1 << 12;
    Result<world::World> world = import_world_vdb_isolated(path, w, iso);
    ++rep.reads;
    if (world.ok()) {
        ++rep.outcomes[int(Outcome::Imported)];
        rep.lines.push_back("import_world_vdb: imported");
        rep.malformed.push_back("import_world_vdb: a mutated foreign file read as a vx world (no 'blocks' grid)");
    } else {
        check_error(rep, "import_world_vdb", world.error());
    }
    return rep;
}

} // namespace vx::vdb::fuzz
