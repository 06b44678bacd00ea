// `vx bench render` end to end on lavapipe (CTest label `vulkan`): its report sections and CSV files.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_run.h"

namespace {

using cli_test::read_file;

using cli_test::CliRun;
using cli_test::vx;

std::string dir() { return cli_test::temp_dir("vx_cli_render_test").string(); }


// `vx bench render --lighting thesis --sections report` (tiny): the Table 6.3 rows carry their
// ratios to this run's RT flat and all-off rows (the all-off row is 1.00 of itself) and the
// thesis's ratio beside them.
TEST(CliRender, BenchRenderTableRatios) {
    const std::string out = dir() + "/bench_ratios";
    const CliRun r = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --repeat 1 "
                        "--reference-spp 8 --reflections 1 --lighting thesis --sections report --warmup-ms 20 "
                        "--first-hit-pass on --out " +
                        out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string text = read_file(out + "/render_report.md");
    EXPECT_NE(text.find("after 20 ms of each configuration's frames"), std::string::npos) << text;
    EXPECT_NE(text.find("Hits in passes of their own (split hits): 1."), std::string::npos) << text;
    EXPECT_NE(text.find("Lighting: thesis"), std::string::npos) << text;
    EXPECT_NE(text.find("| x RT flat | x all off | thesis x all off |"), std::string::npos) << text;
    const size_t off = text.find("| RT full: shadows off, reflections (1 bounces) off, denoiser off |");
    ASSERT_NE(off, std::string::npos) << text;
    const std::string row = text.substr(off, text.find('\n', off) - off);
    EXPECT_NE(row.find("| 1.00 | 1.00 |"), std::string::npos) << row;
    EXPECT_NE(text.find("| 34.82 |"), std::string::npos) << text;
}

// `vx bench render --sections equal-error` (tiny): the three thesis rows, each with a cheapest
// configuration (the thesis's own 25 spp raw meets its target, so one always does), and a CSV
// line per measured candidate of both feature sets (shadows: bounce spp 0), timed warm and cold;
// a seed count of 0 and a negative warm-up are exit 2.
TEST(CliRender, BenchRenderEqualError) {
    const std::string out = dir() + "/bench_equal_error";
    const CliRun r = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --repeat 1 --reference-spp 8 "
                        "--reflections 1 --lighting thesis --sections equal-error --error-seeds 2 --warmup-ms 20 "
                        "--out " +
                        out);
    ASSERT_EQ(r.code, 0) << r.out;
    // The bound printed first holds (the second of warm-up frames is counted apart).
    unsigned long long at_most = 0, rendered = 0, warmup = 0;
    const size_t bound_at = r.out.find("at most "), done_at = r.out.find(" frames rendered (and ");
    ASSERT_NE(bound_at, std::string::npos) << r.out;
    ASSERT_NE(done_at, std::string::npos) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + bound_at, "at most %llu frames", &at_most), 1) << r.out;
    ASSERT_EQ(std::sscanf(r.out.c_str() + r.out.rfind('\n', done_at) + 1, " equal error: %llu frames rendered (and %llu",
                          &rendered, &warmup),
              2)
        << r.out;
    EXPECT_GT(rendered, 0u);
    EXPECT_LE(rendered, at_most);
    EXPECT_GT(warmup, 0u);
    const std::string text = read_file(out + "/render_report.md");
    EXPECT_NE(text.find("## Table 6.3 at equal error"), std::string::npos) << text;
    for (const char* row : {"| shadows | ", "| shadows + reflections | ", "| all on (+ thesis's denoiser) | "}) {
        const size_t at = text.find(row);
        ASSERT_NE(at, std::string::npos) << row << "\n" << text;
        EXPECT_EQ(text.substr(at, text.find('\n', at) - at).find("| none |"), std::string::npos) << text;
    }
    // "feature_set,spp,bounce_spp,denoise" and by_weight of each measured line; rmse is the search's
    // metric's (display by default; 8bit on request), both metrics written.
    auto read_csv = [&](const std::string& where, bool display) {
        std::ifstream csv(where + "/equal_error.csv");
        std::string header;
        std::getline(csv, header);
        EXPECT_EQ(header, "feature_set,spp,bounce_spp,denoise,frame_ms,rmse,target_rmse,flat_ms,light_cache,"
                          "rmse_display,rmse_8bit,by_weight,cold_ms,weight_exponent");
        std::set<std::string> keys;
        for (std::string line; std::getline(csv, line);) {
            std::vector<std::string> f;
            for (size_t at = 0, next; at <= line.size(); at = next + 1) {
                next = std::min(line.find(',', at), line.size());
                f.push_back(line.substr(at, next - at));
            }
            EXPECT_EQ(f.size(), 14u) << line;
            if (f.size() != 14u)
                continue;
            EXPECT_TRUE(f[13] == "1" || (f[11] == "1" && f[13] == "0.8")) << line; // weight_exponent
            EXPECT_EQ(f[5], display ? f[9] : f[10]) << line;
            EXPECT_GT(std::stod(f[4]), 0.0) << line; // Lavapipe has timestamps: both timings measured.
            EXPECT_GT(std::stod(f[12]), 0.0) << line;
            EXPECT_GE(std::stod(f[9]), 0.0) << line;
            EXPECT_GE(std::stod(f[10]), 0.0) << line;
            keys.insert(f[0] + "," + f[1] + "," + f[2] + "," + f[3] + (f[11] == "1" ? ",w" : "") +
                        (f[13] == "1" ? "" : "^" + f[13]));
        }
        return keys;
    };
    // The targets and the one-sample rows are always measured (nothing bounds those below), and
    // the fewest samples by weight of each exponent; others may be skipped, depending on the
    // frame times.
    const std::set<std::string> keys = read_csv(out, true);
    for (const char* key : {"shadows,1,0,0", "shadows,25,0,0", "shadows+reflections,1,1,0",
                            "shadows+reflections,25,25,0", "shadows+reflections,16,0,0,w",
                            "shadows+reflections,32,0,0,w^0.8"})
        EXPECT_TRUE(keys.count(key)) << key;
    EXPECT_FALSE(keys.count("shadows,25,0,1")); // 25 raw plus the denoiser: dearer than the target.
    const std::string out8 = dir() + "/bench_equal_error_8bit";
    const CliRun r8 = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --repeat 1 --reference-spp 8 "
                         "--reflections 1 --lighting thesis --sections equal-error --error-seeds 1 "
                         "--error-metric 8bit --warmup-ms 0 --out " +
                         out8);
    ASSERT_EQ(r8.code, 0) << r8.out;
    EXPECT_NE(read_file(out8 + "/render_report.md").find("of the 8-bit output"), std::string::npos);
    read_csv(out8, false);
    const CliRun bad_metric = vx("bench render --sections equal-error --error-metric psnr");
    EXPECT_EQ(bad_metric.code, 2) << bad_metric.out;
    EXPECT_NE(bad_metric.out.find("--error-metric"), std::string::npos) << bad_metric.out;
    EXPECT_EQ(vx("bench render --sections equal-error --error-seeds 0").code, 2);
    const CliRun bad_warmup = vx("bench render --sections equal-error --warmup-ms -5");
    EXPECT_EQ(bad_warmup.code, 2) << bad_warmup.out;
    EXPECT_NE(bad_warmup.out.find("--warmup-ms"), std::string::npos) << bad_warmup.out;
}

// `vx bench render --sections paths` (tiny): a row per path and configuration with RMSE median
// and p95, and a CSV line per frame; the edit path's row has a recovery figure.
TEST(CliRender, BenchRenderCameraPaths) {
    const std::string out = dir() + "/bench_paths";
    const CliRun r = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --reflections 1 "
                        "--sections paths --path-frames 6 --path-reference-spp 8 --out " +
                        out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string text = read_file(out + "/render_report.md");
    EXPECT_NE(text.find("## Camera paths"), std::string::npos) << text;
    for (const char* path : {"| orbit | ", "| fly-over | ", "| edit | "}) {
        size_t rows = 0;
        for (size_t at = text.find(path); at != std::string::npos; at = text.find(path, at + 1))
            ++rows;
        EXPECT_EQ(rows, 4u) << path << "\n" << text;
    }
    std::ifstream csv(out + "/paths.csv");
    int frames = 0;
    for (std::string line; std::getline(csv, line);)
        frames += line.rfind("orbit,", 0) == 0 ? 1 : 0;
    EXPECT_EQ(frames, 4 * 6); // Four configurations (the sandbox's among them), six frames.
    EXPECT_NE(text.find("| orbit | sandbox: "), std::string::npos) << text; // Marked, not added.
    EXPECT_EQ(vx("bench render --sections paths --path-frames 2").code, 2);
    // Report files that cannot be written (here folders in their place) exit 1 naming them: the
    // bench once exited 0 with its figures lost.
    const std::string blocked = dir() + "/bench_paths_blocked";
    std::filesystem::remove_all(blocked);
    std::filesystem::create_directories(blocked + "/paths.csv");
    std::filesystem::create_directories(blocked + "/render_report.md");
    const CliRun lost = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --reflections 1 "
                           "--sections paths --path-frames 4 --path-reference-spp 8 --out " +
                           blocked);
    EXPECT_EQ(lost.code, 1) << lost.out;
    EXPECT_NE(lost.out.find("not written: " + blocked + "/paths.csv"), std::string::npos) << lost.out;
    EXPECT_NE(lost.out.find("not written: " + blocked + "/render_report.md"), std::string::npos) << lost.out;
}

// `vx bench render --sections defaults` (tiny): a table row and a CSV line per candidate (7
// sample settings x denoiser off / on; the sandbox's settings, vx::RenderSettings::recommended(),
// are one of them and marked), one pick that qualifies, the ms and error columns filled, and the
// frames rendered: 14 candidates x 2 paths x (8 warm-up + 4 frames) = 336, references for
// 2 x 4 poses of max(1, 8 / 8) + parity frames = 12, and the cost pass's 3 rounds x 14 candidates
// x 2 paths x (1 uncounted + 4 frames) = 420.
TEST(CliRender, BenchRenderDefaultsSection) {
    const std::string out = dir() + "/bench_defaults";
    const CliRun r = vx("bench render --seed 1 --radius 0 --vradius 1 --size 16x12 --sections defaults "
                        "--path-frames 4 --path-reference-spp 8 --out " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string text = read_file(out + "/render_report.md");
    EXPECT_NE(text.find("## Sandbox defaults from the curves"), std::string::npos) << text;
    EXPECT_NE(text.find("Frames rendered: 768 (references 12, candidates 336 with warm-up, timing 420)"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("(the sandbox's) |"), std::string::npos) << text;
    std::ifstream csv(out + "/defaults.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header.rfind("shadow_spp,bounce_spp,denoise,history,sandbox_now,ms,", 0), 0u) << header;
    int rows = 0, picks = 0;
    for (std::string line; std::getline(csv, line);) {
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');)
            f.push_back(x);
        ASSERT_EQ(f.size(), 14u) << line;
        ++rows;
        EXPECT_GT(std::stod(f[5]), 0.0) << line;  // ms
        EXPECT_GT(std::stod(f[10]), 0.0) << line; // error
        EXPECT_LE(std::stod(f[11]), std::stod(f[10])) << line; // best at 2x includes itself
        if (f[13] == "1") {
            ++picks;
            EXPECT_EQ(f[12], "1") << line; // The pick qualifies.
        }
    }
    EXPECT_EQ(rows, 14);
    EXPECT_EQ(picks, 1);
    EXPECT_EQ(vx("bench render --sections defaults --path-frames 3").code, 2);
}

// `vx bench render --sections geometry`: three mesher rows (naive > culled > greedy triangles),
// the refit run refits and the rebuild run only builds, trace rows after k = 0, 1, 10, 100.
TEST(CliRender, BenchRenderGeometrySection) {
    const std::string out = dir() + "/bench_geometry";
    const CliRun r = vx("bench render --seed 1 --radius 0 --vradius 1 --size 32x24 --repeat 1 --sections geometry "
                        "--out " + out);
    ASSERT_EQ(r.code, 0) << r.out;
    std::ifstream csv(out + "/geometry.csv");
    std::map<std::string, std::vector<std::string>> rows; // "mesher,greedy" -> its fields.
    std::vector<std::string> ks;
    for (std::string line; std::getline(csv, line);) {
        if (line.empty() || line[0] == '#')
            continue;
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');)
            f.push_back(x);
        ASSERT_GE(f.size(), 4u) << line;
        if (f[0] == "trace")
            ks.push_back(f[1]);
        rows[f[0] + "," + f[1]] = f;
    }
    ASSERT_TRUE(rows.count("mesher,greedy") && rows.count("mesher,culled") && rows.count("mesher,naive")) << r.out;
    const double greedy = std::stod(rows["mesher,greedy"][2]), culled = std::stod(rows["mesher,culled"][2]),
                 naive = std::stod(rows["mesher,naive"][2]);
    EXPECT_GT(greedy, 0.0);
    EXPECT_LT(greedy, culled);
    EXPECT_LT(culled, naive);
    ASSERT_TRUE(rows.count("burst,refit") && rows.count("burst,rebuild")) << r.out;
    // Fields: burst, run, median ms, refits, builds.
    EXPECT_GT(std::stoi(rows["burst,refit"][3]), std::stoi(rows["burst,refit"][4]));
    EXPECT_EQ(std::stoi(rows["burst,rebuild"][3]), 0);
    EXPECT_GT(std::stoi(rows["burst,rebuild"][4]), 0);
    EXPECT_EQ(ks, (std::vector<std::string>{"0", "1", "10", "100"}));
    const std::string text = read_file(out + "/render_report.md");
    EXPECT_NE(text.find("## Geometry"), std::string::npos);
    EXPECT_EQ(vx("bench render --sections everything").code, 2);
}

} // namespace
