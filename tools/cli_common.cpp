#include "cli_common.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <unistd.h>
#include <vector>

#include "render/renderer.h"

namespace vx::tools {

std::vector<std::string> split_commas(const std::string& s) {
    std::vector<std::string> parts;
    std::stringstream ss(s);
    std::string item;
    while (std::getline(ss, item, ','))
        parts.push_back(item);
    if (!s.empty() && s.back() == ',')
        parts.push_back("");
    return parts;
}

std::optional<int64_t> parse_i64(const std::string& s) {
    const char* b = s.c_str();
    char* end = nullptr;
    errno = 0;
    const long long x = std::strtoll(b, &end, 10);
    if (errno != 0 || end == b || *end != '\0')
        return std::nullopt;
    return int64_t(x);
}

std::optional<glm::i64vec3> parse_i64vec3(const std::string& s) {
    const auto parts = split_commas(s);
    if (parts.size() != 3)
        return std::nullopt;
    glm::i64vec3 v;
    for (int i = 0; i < 3; ++i) {
        const std::optional<int64_t> x = parse_i64(parts[i]);
        if (!x)
            return std::nullopt;
        v[i] = *x;
    }
    return v;
}

std::optional<glm::dvec3> parse_dvec3(const std::string& s) {
    const auto parts = split_commas(s);
    if (parts.size() != 3)
        return std::nullopt;
    glm::dvec3 v;
    for (int i = 0; i < 3; ++i) {
        const char* b = parts[i].c_str();
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(b, &end);
        if (errno != 0 || end == b || *end != '\0' || !std::isfinite(x))
            return std::nullopt;
        v[i] = x;
    }
    return v;
}

std::optional<glm::uvec2> parse_image_size(const std::string& s) {
    const size_t x = s.find('x');
    if (x == std::string::npos || s.find_first_not_of("0123456789x") != std::string::npos)
        return std::nullopt;
    const std::optional<int64_t> w = parse_i64(s.substr(0, x)), h = parse_i64(s.substr(x + 1));
    if (!w || !h || *w < 1 || *w > 16384 || *h < 1 || *h > 16384)
        return std::nullopt;
    return glm::uvec2(uint32_t(*w), uint32_t(*h));
}

uint32_t split_hits_arg(const std::string& first_hit_pass, uint32_t split_hits) {
    return first_hit_pass == "on" && split_hits < 1 ? 1u : split_hits;
}

std::string weight_exponent_text(float exponent) {
    if (exponent == 1.f)
        return "";
    char text[32];
    std::snprintf(text, sizeof text, "^%g", double(exponent));
    return text;
}

CLI::Validator finite_range(double lo, double hi, const std::string& what) {
    char name[64];
    std::snprintf(name, sizeof name, "FLOAT in [%g, %g]", lo, hi);
    return CLI::Validator(
        [lo, hi, what](std::string& v) {
            char* end = nullptr;
            errno = 0;
            const double x = std::strtod(v.c_str(), &end);
            const bool ok = errno == 0 && end != v.c_str() && *end == '\0' && std::isfinite(x) && x >= lo && x <= hi;
            return ok ? std::string() : what + ", got '" + v + "'";
        },
        name);
}

CLI::Validator decimal_range(uint64_t lo, uint64_t hi, const std::string& what) {
    return CLI::Validator(
        [lo, hi, what](std::string& v) {
            char* end = nullptr;
            errno = 0;
            const unsigned long long x = std::strtoull(v.c_str(), &end, 10);
            const bool ok = !v.empty() && v.find_first_not_of("0123456789") == std::string::npos && errno == 0 &&
                            *end == '\0' && x >= lo && x <= hi;
            return ok ? std::string() : what + ", got '" + v + "'";
        },
        "UINT in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

CLI::Validator seed_range() { return decimal_range(0, UINT64_MAX, "must be 0..18446744073709551615"); }

std::string output_file_problem(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path p(path);
    const fs::file_status st = fs::status(p, ec);
    if (fs::exists(st) && !fs::is_regular_file(st))
        return "'" + path + "' exists and is not a file";
    const fs::path folder = p.has_parent_path() ? p.parent_path() : fs::path(".");
    if (!fs::is_directory(folder, ec))
        return "the folder of '" + path + "' does not exist";
    return {};
}

std::string output_overwrites(const std::string& out, const std::vector<std::string>& inputs) {
    for (const std::string& in : inputs) {
        if (in.empty())
            continue;
        for (const char* suffix : {"", "-wal", "-shm"}) {
            std::error_code ec;
            if (std::filesystem::equivalent(out, in + suffix, ec))
                return in + suffix;
        }
    }
    return {};
}

namespace {
std::vector<std::string>& output_failures() {
    static std::vector<std::string> failures; // The CLI's thread only (see ReportFile).
    return failures;
}
} // namespace

ReportFile::ReportFile(const std::string& path) : std::ofstream(path), m_path(path) {}

ReportFile::~ReportFile() { finish(); }

void ReportFile::finish() {
    if (m_finished)
        return;
    m_finished = true;
    if (is_open())
        close(); // Sets failbit when the last buffered write or the close fails.
    if (fail())
        note_output_failure(m_path, "cannot write it");
}

void note_output_failure(const std::string& path, const std::string& why) {
    output_failures().push_back(path + ": " + why);
}

void note_png(const std::string& path, const render::RenderImage& image) {
    if (Status s = render::write_png(path, image); !s)
        note_output_failure(path, s.error());
}

int report_outputs() {
    for (const std::string& f : output_failures())
        std::fprintf(stderr, "vx: report output not written: %s\n", f.c_str());
    return output_failures().empty() ? kExitOk : kExitFailure;
}

int parse_failure(const CLI::App& app, const CLI::ParseError& e, const std::string& usage) {
    if (e.get_exit_code() == 0) // --help (CLI::CallForHelp, CallForAllHelp): success.
        return app.exit(e);
    const std::string where = usage.empty() ? "'" + app.get_name() + " --help'" : usage;
    std::fprintf(stderr, "vx: %s\nRun %s for usage.\n", e.what(), where.c_str());
    return kExitBadInput;
}

int bad_input(const std::string& message) {
    std::fprintf(stderr, "vx: %s\n", message.c_str());
    return kExitBadInput;
}

int failed(const std::string& message) {
    std::fprintf(stderr, "vx: %s\n", message.c_str());
    return kExitFailure;
}

std::string job_system_problem(const std::string& start_error) {
    return start_error.empty() ? std::string() : "cannot start the worker threads: " + start_error;
}

bool stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

} // namespace vx::tools
