#pragma once
// Shared by the CLI tests: runs the vx binary through the shell and captures its output.
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

namespace cli_test {

struct CliRun {
    int code;
    std::string out; // stdout and stderr together.
};

inline CliRun vx(const std::string& args, const std::string& env = "") {
    const std::string cmd = env + " " + std::string(VX_BINARY) + " " + args + " 2>&1";
    std::FILE* p = popen(cmd.c_str(), "r");
    CliRun r{-1, {}};
    if (!p)
        return r;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0)
        r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A scratch directory per test program (`name`), so test programs may run in parallel.
inline std::filesystem::path temp_dir(const std::string& name = "vx_cli_test") {
    auto d = std::filesystem::temp_directory_path() / name;
    std::filesystem::create_directories(d);
    return d;
}

// A whole file's bytes, a command's output file ("" when it cannot be read).
inline std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

} // namespace cli_test
