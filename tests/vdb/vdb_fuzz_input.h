#pragma once
// The VDB fuzz inputs and checks shared by the CTest fuzz test (vdb_fuzz_test.cpp, 120 inputs)
// and the long-run driver (vdb_fuzz_main.cpp, vx_vdb_fuzz): mutated copies of the real VDB files
// read through the isolated API (vdb_isolated.h), which must import or refuse each with a one-line
// error and never crash or hang the caller.
//
// Input i depends only on (seed, i): its file is picked by i and its mutation drawn from an
// mt19937 seeded with (seed, i), so one failing input of a long run can be rebuilt alone.
//
// Thread affinity: everything here is thread-safe except run_reads, which forks (see
// vdb_isolated.h: call it from a single-threaded process).

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "world/base/result.h"
#include "world/vdb/vdb_isolated.h"

namespace vx::vdb::fuzz {

// The original files, read once and kept in memory (the driver mutates ~10^5 copies).
struct Corpus {
    std::vector<std::string> names;       // File names in the data folder, in pick order.
    std::vector<std::string> bytes;       // Their contents, parallel to names.
    int large = -1;                       // Index of the 0.8 MB level set (every 25th input).
};

// Reads the fuzzed files from `dir`: six small ones (30–245 KB) and gaffer_vdbtest_sphere.vdb.
// Fails with a one-line error naming the missing file.
Result<Corpus> load_corpus(const std::string& dir);

// Without the real files (a clone alone): equivalent inputs OpenVDB writes into `dir` (which must
// exist) and reads back: small fog and level-set spheres, a rotated fog box, a non-uniformly
// scaled level-set ellipsoid, a three-grid fog file, and a level set of about 1 MB as the large
// file. Other writers' quirks (half floats, old versions, point data) are then not covered.
Result<Corpus> generated_corpus(const std::string& dir);

// load_corpus(data) when that folder exists, else generated_corpus(scratch); `generated` says which.
Result<Corpus> real_or_generated_corpus(const std::string& data, const std::string& scratch, bool& generated);

enum class Mutation { BitFlips, ByteRun, Truncation, HeaderFlip };
const char* mutation_name(Mutation m);

// Mutates `bytes` (not empty) in place with draws from `rng`; returns the kind applied.
Mutation mutate(std::string& bytes, std::mt19937& rng);

struct Input {
    int file = 0;          // Index into Corpus::names.
    Mutation mutation{};
    std::string bytes;     // The mutated file.
};

// Input `index` of the run with `seed`: small files in turn, the level set every 25th input
// (it costs ~10x a small file per read).
Input make_input(const Corpus& corpus, uint32_t seed, uint64_t index);

// Which isolated reads each input gets.
enum class Reads {
    All,    // list_grids, import_volume at 1 and 4 voxels per block, import_world_vdb (CTest).
    // One import_volume at 4 voxels per block: OpenVDB parses the whole file and the importer
    // converts every leaf, in one fork. At 1 voxel per block the level set's adaptive
    // supersampling took ~70% of a run's CPU time; the parser is what is fuzzed.
    Import,
};

// The outcome class of one isolated read.
enum class Outcome { Imported, Error, ChildCrashed, MemoryCap, CpuCap };
constexpr int kOutcomeCount = 5;
const char* outcome_name(Outcome o);

// Classifies an error message of an isolated read.
Outcome classify(const std::string& error);

struct ReadReport {
    int reads = 0;
    int outcomes[kOutcomeCount] = {}; // Indexed by Outcome.
    // Escapes the caller survived: results that break the API contract (an error that is not one
    // non-empty line, solid_blocks over max_blocks, a foreign file read as a vx world).
    std::vector<std::string> malformed;
    std::vector<std::string> lines; // "read: outcome: message", one per read (for --only).
};

// Limits for the fuzz children: 1 GiB (OpenVDB asks for GBs on a bad size field), 20 s CPU (a hang).
IsolationOptions fuzz_isolation();

// Writes nothing; runs the isolated reads of `reads` on the file at `path`.
ReadReport run_reads(const std::string& path, Reads reads, const IsolationOptions& iso);

} // namespace vx::vdb::fuzz
