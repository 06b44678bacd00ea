#include "bench_render_equal_error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "bench_render_frames.h"
#include "cli_common.h"
#include "equal_error_pick.h"
#include "render/image_metrics.h"

namespace vx::tools {
namespace {

// The references' sample seed: far from the measured frames' (base.seed on), so their noise is
// independent (as scripts/measure_sampling.py's).
constexpr uint32_t kReferenceSeed = 1000;

// One feature set's search: its candidates (measured or skipped) and its target.
struct FeatureSet {
    const char* name = ""; // CSV: "shadows" or "shadows+reflections".
    std::vector<EqualErrorCandidate> candidates;
    size_t thesis = 0; // Index of 25 spp (bounce spp 25 with reflections), raw.
    size_t skipped = 0;
    double target() const { return candidates[thesis].rmse; }
};

// A report row: a thesis row of Table 6.3, the feature set it is searched in, the thesis's ratio.
struct ThesisRow {
    const char* name;
    size_t set; // Index into the feature sets.
    double thesis_ratio;
};

struct Search {
    render::Renderer& r;
    const EqualErrorBenchInfo& info;
    uint64_t frames = 0; // Rendered so far, but for warm-up frames.
    uint64_t warmup = 0; // Warm-up frames (each configuration's info.warmup_s, the first second).
};

render::RenderSettings candidate_settings(const EqualErrorBenchInfo& info, uint32_t bounces,
                                          const EqualErrorCandidate& c) {
    render::RenderSettings s = info.base;
    s.mode = render::ShadingMode::Full;
    s.max_bounces = bounces;
    s.shadow_samples = c.spp;
    s.bounce_shadow_samples = bounces > 0 && !c.by_weight ? c.bounce_spp : c.spp;
    s.samples_by_weight = c.by_weight;
    s.weight_exponent = c.weight_exponent;
    s.denoise = c.denoise;
    s.light_cache = c.light_cache;
    s.accumulate = 1; // One frame: no history.
    return s;
}

// A feature set's reference in both metrics.
struct Reference {
    render::ImageF rgba8;   // The 8-bit output.
    render::ImageF display; // Before the rounding (render::display_float).
};

// Frame time (median of info.repeat frames at base.seed) and the root mean square over
// info.seeds sample seeds of the one-frame RMSE, in both metrics. The error frames are rendered
// again after the timed ones: their G-buffer read-back stays out of the timing.
void measure(Search& ctx, const Reference& reference, uint32_t bounces, EqualErrorCandidate& c) {
    render::RenderSettings s = candidate_settings(ctx.info, bounces, c);
    render::RenderImage timed;
    c.cold_ms = time_frames(ctx.r, s, ctx.info.camera, ctx.info.repeat, &timed).frame;
    ctx.frames += 1 + ctx.info.repeat;
    const Timing warm = time_frames(ctx.r, s, ctx.info.camera, ctx.info.repeat, &timed, ctx.info.warmup_s);
    c.frame_ms = warm.frame;
    ctx.warmup += warm.warmup_frames;
    ctx.frames += ctx.info.repeat;
    double sum8 = 0, sum_display = 0;
    for (uint32_t k = 0; k < ctx.info.seeds; ++k) {
        s.seed = ctx.info.base.seed + k;
        render::GBufferImage g;
        const render::RenderImage img = bench_frame(ctx.r, s, ctx.info.camera, &g);
        ++ctx.frames;
        const double e8 = render::rmse(render::to_float(img), reference.rgba8);
        const double ed = render::rmse(render::display_float(g), reference.display);
        sum8 += e8 * e8;
        sum_display += ed * ed;
    }
    c.rmse_8bit = std::sqrt(sum8 / ctx.info.seeds);
    c.rmse_display = std::sqrt(sum_display / ctx.info.seeds);
    c.rmse = ctx.info.display_metric ? c.rmse_display : c.rmse_8bit;
}

std::string candidate_name(const EqualErrorCandidate& c) {
    std::string name = std::to_string(c.spp) + " spp";
    if (c.bounce_spp > 0)
        name += ", bounce spp " + std::to_string(c.bounce_spp);
    if (c.by_weight)
        name += " by weight" + weight_exponent_text(c.weight_exponent);
    return name + (c.denoise ? ", denoised" : ", raw") + (c.light_cache ? ", light cache" : "");
}

// The thesis's configuration first (it sets the target), then the rest in order, each skipped
// when a cheaper-or-equal one already meets the target (equal_error_skip()).
FeatureSet search_set(Search& ctx, const char* name, uint32_t bounces) {
    FeatureSet set{name, equal_error_candidates(bounces > 0)};
    render::RenderSettings ref_s = ctx.info.base;
    ref_s.max_bounces = bounces;
    ref_s.seed = kReferenceSeed;
    render::GBufferImage ref_g;
    const render::RenderImage ref_img = render_reference(ctx.r, ref_s, ctx.info.camera, ctx.info.reference_spp, 0, &ref_g);
    const Reference reference{render::to_float(ref_img), render::display_float(ref_g)};
    ctx.frames += reference_frames(ctx.info.reference_spp);
    for (size_t i = 0; i < set.candidates.size(); ++i) {
        const EqualErrorCandidate& c = set.candidates[i];
        if (c.spp == kThesisSpp && c.bounce_spp == (bounces > 0 ? kThesisSpp : 0) && !c.denoise && !c.light_cache &&
            !c.by_weight)
            set.thesis = i;
    }
    measure(ctx, reference, bounces, set.candidates[set.thesis]);
    std::printf("  equal error, %s: target (%s) RMSE %.5f at %.3f ms (cold %.3f)\n", name,
                candidate_name(set.candidates[set.thesis]).c_str(), set.target(),
                set.candidates[set.thesis].frame_ms, set.candidates[set.thesis].cold_ms);
    for (EqualErrorCandidate& c : set.candidates) {
        if (c.rmse >= 0) // The target, measured first.
            continue;
        const EqualErrorCandidate* best = cheapest_meeting(set.candidates, set.target());
        if (equal_error_skip(c, set.candidates, best ? best->frame_ms : -1)) {
            ++set.skipped;
            continue;
        }
        measure(ctx, reference, bounces, c);
        std::printf("  equal error, %s: %s: frame %.3f ms (cold %.3f), RMSE %.5f (display %.5f, 8-bit %.5f)\n",
                    name, candidate_name(c).c_str(), c.frame_ms, c.cold_ms, c.rmse, c.rmse_display, c.rmse_8bit);
    }
    return set;
}

std::string ratio_text(double v, double to) {
    char buf[32];
    std::snprintf(buf, sizeof buf, v > 0 && to > 0 ? "%.2f" : "n/a", v / to);
    return buf;
}

std::string rows_table(const std::vector<FeatureSet>& sets, double flat_ms) {
    const std::vector<ThesisRow> rows = {
        {"shadows", 0, 8.14}, {"shadows + reflections", 1, 19.12}, {"all on (+ thesis's denoiser)", 1, 34.82}};
    std::string md = "| thesis row | target RMSE | cheapest meeting it | RMSE | frame ms | x RT flat | thesis x | "
                     "met |\n|---|---|---|---|---|---|---|---|\n";
    char line[512];
    for (const ThesisRow& row : rows) {
        const FeatureSet& set = sets[row.set];
        const double target = set.target();
        const EqualErrorCandidate* best = cheapest_meeting(set.candidates, target);
        const double x = best && flat_ms > 0 ? best->frame_ms / flat_ms : -1;
        std::snprintf(line, sizeof line, "| %s | %.5f | %s | %.5f | %.3f | %s | %.2f | %s |\n", row.name, target,
                      best ? candidate_name(*best).c_str() : "none", best ? best->rmse : -1.0,
                      best ? best->frame_ms : -1.0, best ? ratio_text(best->frame_ms, flat_ms).c_str() : "n/a",
                      row.thesis_ratio, x < 0 ? "n/a" : x <= row.thesis_ratio ? "yes" : "no");
        md += line;
        std::printf("  %s", line);
    }
    return md;
}

std::string candidates_table(const std::vector<FeatureSet>& sets, double flat_ms, std::ofstream& csv) {
    std::string md = "\n| features | configuration | frame ms | x RT flat | cold ms | RMSE | meets target | "
                     "RMSE display | RMSE 8-bit |\n|---|---|---|---|---|---|---|---|---|\n";
    csv << "feature_set,spp,bounce_spp,denoise,frame_ms,rmse,target_rmse,flat_ms,light_cache,rmse_display,"
           "rmse_8bit,by_weight,cold_ms,weight_exponent\n";
    char line[512];
    for (const FeatureSet& set : sets)
        for (const EqualErrorCandidate& c : set.candidates) {
            if (c.rmse < 0)
                continue; // Skipped.
            std::snprintf(line, sizeof line, "| %s | %s | %.3f | %s | %.3f | %.5f | %s | %.5f | %.5f |\n",
                          set.name, candidate_name(c).c_str(), c.frame_ms, ratio_text(c.frame_ms, flat_ms).c_str(),
                          c.cold_ms, c.rmse, c.rmse <= set.target() ? "yes" : "no", c.rmse_display, c.rmse_8bit);
            md += line;
            csv << set.name << ',' << c.spp << ',' << c.bounce_spp << ',' << (c.denoise ? 1 : 0) << ',' << c.frame_ms
                << ',' << c.rmse << ',' << set.target() << ',' << flat_ms << ',' << (c.light_cache ? 1 : 0) << ','
                << c.rmse_display << ',' << c.rmse_8bit << ',' << (c.by_weight ? 1 : 0) << ',' << c.cold_ms
                << ',' << c.weight_exponent << '\n';
        }
    return md;
}

} // namespace

uint64_t equal_error_frames_at_most(const EqualErrorBenchInfo& info) {
    const uint64_t per = 1 + 2 * uint64_t(info.repeat) + info.seeds;
    const uint64_t candidates = equal_error_candidates(false).size() + equal_error_candidates(true).size();
    return 2 * uint64_t(reference_frames(info.reference_spp)) + 2 * uint64_t(info.repeat) + candidates * per;
}

std::string run_equal_error_bench(render::Renderer& r, const EqualErrorBenchInfo& info) {
    Search ctx{r, info};
    render::RenderSettings flat = info.base;
    flat.mode = render::ShadingMode::Flat;
    flat.shadow_samples = 0;
    flat.max_bounces = 0;
    // An idle GPU's clocks ramp up over its first second of work: on the H200 (device call 55) a
    // first flat row took 2.93 ms, 1.58 ms after other work. So frames for a second first, and
    // the flat row timed again at the end; the ratios take the faster (the larger ratios).
    // Those warm-up frames are counted apart: equal_error_frames_at_most() bounds the others.
    const auto warm_until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (std::chrono::steady_clock::now() < warm_until) {
        bench_frame(r, flat, info.camera);
        ++ctx.warmup;
    }
    render::RenderImage img;
    const Timing flat_first_t = time_frames(r, flat, info.camera, info.repeat, &img, info.warmup_s);
    const double flat_first = flat_first_t.frame;
    ctx.warmup += flat_first_t.warmup_frames;
    ctx.frames += info.repeat;
    std::printf("  equal error: RT flat %.3f ms; at most %llu frames\n", flat_first,
                (unsigned long long)equal_error_frames_at_most(info));
    std::vector<FeatureSet> sets;
    sets.push_back(search_set(ctx, "shadows", 0));
    sets.push_back(search_set(ctx, "shadows+reflections", info.reflections));
    const Timing flat_last_t = time_frames(r, flat, info.camera, info.repeat, &img, info.warmup_s);
    const double flat_last = flat_last_t.frame;
    ctx.warmup += flat_last_t.warmup_frames;
    ctx.frames += info.repeat;
    const double flat_ms = flat_first > 0 && flat_last > 0 ? std::min(flat_first, flat_last) : -1.0;
    std::printf("  equal error: RT flat again %.3f ms; ratios to %.3f ms\n", flat_last, flat_ms);
    const size_t skipped = sets[0].skipped + sets[1].skipped;
    char head[2048];
    std::snprintf(head, sizeof head,
                  "## Table 6.3 at equal error\n\nLighting: %s. Target per row: the one-frame RMSE of the thesis's "
                  "configuration (25 shadow samples at every hit, raw) against a reference of the same features (%u "
                  "samples per pixel, no filter, sample seed %u); RMSE is the root mean square over %u sample seeds, "
                  "of %s. "
                  "Candidates: the same features, shadow spp 1-25, bounce spp {1, 2, 4, 8, 16, spp} or every hit's by its weight, denoiser off and on, "
                  "light cache off and on, "
                  "one frame each (no history); %zu skipped (a candidate with no more samples already cost at least "
                  "the cheapest meeting the target). The all-on row searches the same features (the denoiser is a "
                  "candidate setting). Frame ms: GPU medians of %u frames, after a second of frames at the start "
                  "and %.2f s of each configuration's own (cold ms: the same medians right after the previous "
                  "configuration's error frames, with one frame before them); RT flat %.3f ms "
                  "(timed first and last: %.3f and %.3f ms; the faster), %u reflection bounces. "
                  "Frames rendered: %llu, and %llu to warm up.\n\n",
                  info.lighting == "thesis" ? "thesis (one area light)" : "default (sun, sky light, area light)",
                  reference_frames(info.reference_spp) * 8, kReferenceSeed, info.seeds,
                  info.display_metric ? "the output before its 8-bit rounding" : "the 8-bit output", skipped,
                  info.repeat, info.warmup_s, flat_ms, flat_first, flat_last, info.reflections,
                  (unsigned long long)ctx.frames, (unsigned long long)ctx.warmup);
    std::string md = head + rows_table(sets, flat_ms);
    ReportFile csv(info.out + "/equal_error.csv");
    md += candidates_table(sets, flat_ms, csv);
    std::printf("  equal error: %llu frames rendered (and %llu to warm up), %zu candidates skipped; wrote "
                "%s/equal_error.csv\n",
                (unsigned long long)ctx.frames, (unsigned long long)ctx.warmup, skipped, info.out.c_str());
    return md;
}

} // namespace vx::tools
