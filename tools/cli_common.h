#pragma once
// Shared helpers of the vx CLI: argument parsing of vectors, and the exit codes.

#include <cstdint>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace CLI {
class App;
class ParseError;
class Validator;
}
namespace vx::render {
struct RenderImage;
}

namespace vx::tools {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;  // The command ran and found a problem (e.g. corrupt records).
inline constexpr int kExitBadInput = 2; // Bad arguments or unreadable/corrupt input.

// "a,b,,c" -> {"a", "b", "", "c"}; a trailing comma gives a trailing empty part.
std::vector<std::string> split_commas(const std::string& s);

// Parses one decimal 64-bit integer; nullopt on anything else (overflow included).
std::optional<int64_t> parse_i64(const std::string& s);
// Parses "X,Y,Z" of 64-bit integers; nullopt on anything else (overflow included).
std::optional<glm::i64vec3> parse_i64vec3(const std::string& s);
// Parses "X,Y,Z" of finite doubles.
std::optional<glm::dvec3> parse_dvec3(const std::string& s);
// Parses an image size "WxH", each 1..16384, nothing else ("64x48x1" and sizes that wrapped a
// 32-bit integer, 4294967360x48 read as 64x48, are refused).
std::optional<glm::uvec2> parse_image_size(const std::string& s);

// render::RenderSettings::split_hits of `vx render` and `vx bench render`: --split-hits, where
// --first-hit-pass on (stop 28's option, kept so its commands still run) asks for at least 1.
uint32_t split_hits_arg(const std::string& first_hit_pass, uint32_t split_hits);

// How reports name render::RenderSettings::weight_exponent after "by weight": "" for 1, else
// "^0.8" (shortest form).
std::string weight_exponent_text(float exponent);

// A CLI11 check that the option is a finite decimal within [lo, hi]: CLI::Range lets NaN through
// (every comparison with it is false), and "nan" would reach the renderer or a size cast.
// `what` names the accepted values in the message, e.g. "an exponent from 0.05 to 1".
CLI::Validator finite_range(double lo, double hi, const std::string& what);
// A CLI11 check that the option is a plain decimal within [lo, hi] (at most 2^64 - 1): CLI11
// reads "-1" into an unsigned as 2^64 - 1, and an out-of-range value into its largest; an int
// option of -5 took the "not given" meaning of -1.
CLI::Validator decimal_range(uint64_t lo, uint64_t hi, const std::string& what);
// decimal_range over every seed, 0..2^64 - 1 (--seed of each command).
CLI::Validator seed_range();

// "" when a command may write its output file at `path` (nothing there yet, or a file it
// replaces, in a folder that exists), else why not: checked before the work, not after it.
std::string output_file_problem(const std::string& path);

// The one of `inputs` (or SQLite's -wal and -shm beside it) that `out` names, directly or by a
// link, else "": a command that wrote `out` would replace the file it reads. Empty inputs are
// skipped.
std::string output_overwrites(const std::string& out, const std::vector<std::string>& inputs);

// A file of a bench's report (CSV, Markdown): an std::ofstream that, on closing, records a failed
// open or write (report_outputs): a long bench's figures must not vanish silently on a full disk.
// CLI thread only.
class ReportFile : public std::ofstream {
public:
    explicit ReportFile(const std::string& path);
    ~ReportFile() override; // finish(), unless called.
    // Closes the file and records a failure; call it before report_outputs() while in scope.
    void finish();
    ReportFile(const ReportFile&) = delete;
    ReportFile& operator=(const ReportFile&) = delete;

private:
    std::string m_path;
    bool m_finished = false;
};
// Records that the report output at `path` was not written (`why`: e.g. write_png's error).
void note_output_failure(const std::string& path, const std::string& why);
// Writes a bench's picture as PNG; a failure is noted (note_output_failure), not fatal.
void note_png(const std::string& path, const render::RenderImage& image);
// A bench's exit: kExitOk when every report output was written, else prints each one that was not
// and returns kExitFailure (the figures above were measured; the files are incomplete).
int report_outputs();

// Prints "vx: <message>" to stderr and returns kExitBadInput.
int bad_input(const std::string& message);
// A command's CLI11 parse failure at the tool's boundary: --help prints the help and is kExitOk;
// anything else is one "vx: <what>" line, where to find the usage, and kExitBadInput (CLI11's
// own exit codes, e.g. 105 for a failed check, are not the tool's). `usage` says where the usage
// is; empty: "'<app name> --help'".
int parse_failure(const CLI::App& app, const CLI::ParseError& e, const std::string& usage = "");
// Prints "vx: <message>" to stderr and returns kExitFailure: the machine, not the input, stopped
// the command (the OS refused its threads).
int failed(const std::string& message);
// "" when `jobs` can run jobs, else the line to print (engine::JobSystem::start_error()).
std::string job_system_problem(const std::string& start_error);

// Whether stderr is a terminal: progress bars redraw in place ('\r') only there; piped into a
// log, commands print one summary line instead. Thread-safe.
bool stderr_is_terminal();

} // namespace vx::tools
