// `vx bench render --sections defaults` (tools/bench_render_defaults.h).
#include "bench_render_defaults.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <vector>

#include <vx/vx.h>

#include "bench_render_frames.h"
#include "cli_common.h"
#include "bench_render_paths.h"
#include "defaults_rule.h"
#include "render/image_metrics.h"
#include "world/base/median.h"

namespace vx::tools {
namespace {

constexpr uint32_t kHistory = 8;       // Frames of the denoised candidates' history.
constexpr uint32_t kWarmup = kHistory; // Still frames before a path: enough to fill the history.
constexpr uint32_t kTimingRounds = 3;  // The cost pass's rounds, each over every candidate in turn.
// Added to the references' seed: a reference of one frame (or the renderer's frame 0) traces
// with the settings' seed, and would repeat the samples of a raw candidate of as many samples.
constexpr uint32_t kReferenceSeed = 0x9e3779b9u;

struct Candidate {
    GameSettings g;
    bool sandbox_now = false; // The sandbox's settings (vx::RenderSettings::recommended()).
};

// What the candidate measured, per path (orbit, fly-over) and over both.
struct Measured {
    double ms = -1;               // Median GPU ms a frame (trace + denoiser): time_candidates().
    double median[2] = {}, p95[2] = {};
    double error = 0;             // max(p95[0], p95[1]).
};

std::string name_of(const Candidate& c) {
    const GameSettings& g = c.g;
    std::string name = std::to_string(g.spp) + " / " + std::to_string(g.bounce_spp) + " spp, denoiser ";
    if (!g.denoise)
        name += "off";
    else
        name += g.history > 1 ? "on, history " + std::to_string(g.history) : "on, no history";
    return c.sandbox_now ? name + " (the sandbox's)" : name;
}

// The sweep, then the sandbox's settings: marked where the sweep has them, else appended.
std::vector<Candidate> candidates() {
    std::vector<Candidate> v;
    for (uint32_t spp : {1u, 2u, 4u, 8u})
        for (uint32_t bounce : spp == 1 ? std::vector<uint32_t>{1} : std::vector<uint32_t>{1, spp})
            for (bool denoise : {false, true})
                v.push_back({{spp, bounce, denoise, denoise ? kHistory : 1}});
    const GameSettings now = sandbox_settings();
    auto same = [&](const Candidate& c) { return c.g == now; };
    if (auto it = std::find_if(v.begin(), v.end(), same); it != v.end())
        it->sandbox_now = true;
    else
        v.push_back({now, true});
    return v;
}

// A frame's cost: the GPU's trace and denoiser passes (what the settings change), or the
// submit-to-fence wall time where the queue has no timestamps.
double frame_cost(const render::RenderStats& st) {
    if (st.gpu_trace_ms < 0)
        return st.gpu_ms;
    return st.gpu_trace_ms + std::max(st.gpu_denoise_ms, 0.0);
}

// Runs `c` along both paths (kWarmup still frames first) against their references: the error.
Measured measure(render::Renderer& r, const render::RenderSettings& s, const std::vector<CameraPath>& paths,
                 const std::vector<std::vector<render::ImageF>>& refs, uint64_t* frames) {
    Measured m;
    for (size_t p = 0; p < paths.size(); ++p) {
        for (uint32_t i = 0; i < kWarmup; ++i)
            bench_frame(r, s, paths[p].poses[0]);
        std::vector<double> error;
        for (size_t i = 0; i < paths[p].poses.size(); ++i)
            error.push_back(render::rmse(render::to_float(bench_frame(r, s, paths[p].poses[i])), refs[p][i]));
        m.median[p] = median(error);
        m.p95[p] = percentile(error, 0.95);
        m.error = std::max(m.error, m.p95[p]);
        *frames += kWarmup + paths[p].poses.size();
    }
    return m;
}

// The cost: every candidate renders both paths back to back, with no error arithmetic between
// frames (the error pass leaves the GPU idle for tens of milliseconds a frame, and a cheap
// frame's GPU time then varied 2x between sweeps on the H200, docs/render_report.md), in
// kTimingRounds rounds that take the candidates in turn, so a drift of the GPU's clocks reaches
// them all alike. Sets each Measured::ms to the median over its frames.
void time_candidates(render::Renderer& r, const std::vector<render::RenderSettings>& settings,
                     const std::vector<CameraPath>& paths, std::vector<Measured>& measured, uint64_t* frames) {
    std::vector<std::vector<double>> cost(settings.size());
    for (uint32_t round = 0; round < kTimingRounds; ++round)
        for (size_t c = 0; c < settings.size(); ++c)
            for (const CameraPath& path : paths) {
                bench_frame(r, settings[c], path.poses[0]); // Not counted: the settings' first frame.
                for (const render::Camera& pose : path.poses) {
                    bench_frame(r, settings[c], pose);
                    cost[c].push_back(frame_cost(r.last_stats()));
                }
                *frames += 1 + path.poses.size();
            }
    for (size_t c = 0; c < settings.size(); ++c)
        measured[c].ms = median(cost[c]);
}

std::string intro(const DefaultsBenchInfo& info, uint32_t bounces, uint32_t n) {
    return "## Sandbox defaults from the curves\n\nCandidates: shadow spp {1, 2, 4, 8}, bounce spp {1, spp}, "
           "denoiser off (no history) or on with an 8-frame history, " +
           std::to_string(bounces) +
           " reflection bounces (the facade's default, which the sandbox keeps); and the sandbox's settings "
           "(vx::RenderSettings::recommended()). Each runs the orbit and fly-over paths (" +
           std::to_string(n) + " frames each, after " + std::to_string(kWarmup) +
           " still frames at the path's first pose, not counted) against one converged reference per pose (" +
           std::to_string(std::max(1u, info.reference_spp / 8) * 8) +
           " samples per pixel, rendered once, shared by every candidate). ms: median GPU time of trace + "
           "denoiser over both paths' frames, from a separate pass that renders them back to back, " +
           std::to_string(kTimingRounds) +
           " rounds taking the candidates in turn. Error: the larger of the two paths' per-frame RMSE p95 "
           "(medians beside it). Best at 2x: the lowest error among candidates at up to twice the ms (itself "
           "included); qualifies: error <= 1.25x that (tools/defaults_rule.h). The pick: the cheapest that "
           "qualifies.\n\n| settings | ms | orbit median | orbit p95 | fly-over median | fly-over p95 | error | "
           "best at 2x | qualifies |\n|---|---|---|---|---|---|---|---|---|\n";
}

// The table, the CSV and the pick line.
std::string results(const std::vector<Candidate>& cands, const std::vector<Measured>& ms, const std::string& out) {
    std::vector<CostError> ce;
    for (const Measured& m : ms)
        ce.push_back({m.ms, m.error});
    const DefaultsRuleResult rule = apply_defaults_rule(ce);
    ReportFile csv(out + "/defaults.csv");
    csv << "shadow_spp,bounce_spp,denoise,history,sandbox_now,ms,orbit_median,orbit_p95,fly_median,fly_p95,error,"
           "best_at_2x,qualifies,pick\n";
    std::string md;
    char line[512];
    for (size_t i = 0; i < cands.size(); ++i) {
        const Candidate& c = cands[i];
        const Measured& m = ms[i];
        const bool pick = rule.pick == i;
        std::snprintf(line, sizeof line, "| %s | %.3f | %.4f | %.4f | %.4f | %.4f | %.4f | %.4f | %s |\n",
                      name_of(c).c_str(), m.ms, m.median[0], m.p95[0], m.median[1], m.p95[1], m.error,
                      rule.best_within[i], rule.qualifies[i] ? (pick ? "yes: the pick" : "yes") : "no");
        md += line;
        std::printf("  %s", line);
        csv << c.g.spp << ',' << c.g.bounce_spp << ',' << int(c.g.denoise) << ',' << c.g.history << ','
            << int(c.sandbox_now) << ',' << m.ms << ',' << m.median[0] << ',' << m.p95[0] << ',' << m.median[1]
            << ',' << m.p95[1] << ',' << m.error << ',' << rule.best_within[i] << ',' << int(rule.qualifies[i])
            << ',' << int(pick) << '\n';
    }
    if (rule.pick) {
        const size_t p = *rule.pick;
        std::snprintf(line, sizeof line, "\nThe pick: %s, %.3f ms, error %.4f (best at 2x: %.4f).\n",
                      name_of(cands[p]).c_str(), ms[p].ms, ms[p].error, rule.best_within[p]);
        md += line;
        std::printf("  %s", line + 1);
    }
    return md;
}

} // namespace

std::string run_defaults_bench(render::Renderer& r, const engine::LoadedScene& scene, const DefaultsBenchInfo& info) {
    const auto start = std::chrono::steady_clock::now();
    const uint32_t n = std::max(info.frames, 4u);
    const uint32_t bounces = ::vx::RenderSettings{}.max_bounces;
    const std::vector<CameraPath> paths = moving_paths(scene, info.camera, n);
    uint64_t ref_frames = 0, cand_frames = 0, timing_frames = 0;
    render::RenderSettings ref_base = info.base;
    ref_base.seed += kReferenceSeed;
    std::vector<std::vector<render::ImageF>> refs(paths.size());
    for (size_t p = 0; p < paths.size(); ++p)
        for (uint32_t i = 0; i < n; ++i)
            refs[p].push_back(
                path_reference(r, ref_base, bounces, info.reference_spp, paths[p].poses[i], i % 2, &ref_frames));
    const std::vector<Candidate> cands = candidates();
    std::vector<render::RenderSettings> settings;
    std::vector<Measured> measured;
    for (const Candidate& c : cands) {
        settings.push_back(with_game_settings(info.base, c.g, bounces));
        measured.push_back(measure(r, settings.back(), paths, refs, &cand_frames));
        std::printf("  %s: error %.4f\n", name_of(c).c_str(), measured.back().error);
    }
    time_candidates(r, settings, paths, measured, &timing_frames);
    std::string md = intro(info, bounces, n) + results(cands, measured, info.out);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    char line[256];
    std::snprintf(line, sizeof line,
                  "Frames rendered: %llu (references %llu, candidates %llu with warm-up, timing %llu) in %.1f s.\n",
                  (unsigned long long)(ref_frames + cand_frames + timing_frames), (unsigned long long)ref_frames,
                  (unsigned long long)cand_frames, (unsigned long long)timing_frames, s);
    md += line;
    std::printf("  %s", line);
    return md;
}

} // namespace vx::tools
