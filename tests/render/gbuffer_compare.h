// Comparing the G-buffers of one frame traced two ways that must agree (split into passes, or
// checked for see-through faces first): different pipeline variants or passes are different
// programs. Lavapipe (LLVM) compiles them to the same arithmetic, so their values agree bit for
// bit. NVIDIA's compiler may contract or order the arithmetic differently per variant: on the
// H100 (driver 580.159.04) 2 to 3 of 1,600 pixels' G-buffer values differed while the 8-bit
// images agreed byte for byte (docs/render_report.md, stop 58). So equal on Mesa, and within a
// few roundings of each image's storage elsewhere; the largest difference is printed either way.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "render/renderer.h"

namespace vx::render::test {

// How two images of one G-buffer part differ: the pixels with any channel unequal, and the largest
// difference of a channel in units of `step` relative to the larger magnitude (a float storage's
// rounding) plus `floor` absolute (a fixed-point one's).
struct GBufferPartDiff {
    size_t pixels = 0;
    double worst = 0.0; // Largest |a - b| / (step * max(|a|, |b|) + floor): 1 is one rounding.
};

template <class V>
GBufferPartDiff gbuffer_part_diff(const std::vector<V>& a, const std::vector<V>& b, double step,
                                  double floor) {
    GBufferPartDiff d;
    EXPECT_EQ(a.size(), b.size());
    for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
        if (a[i] == b[i])
            continue;
        ++d.pixels;
        for (int c = 0; c < V::length(); ++c) {
            const double x = a[i][c], y = b[i][c];
            const double rounding = step * std::max(std::abs(x), std::abs(y)) + floor;
            d.worst = std::max(d.worst, std::abs(x - y) / rounding);
        }
    }
    return d;
}

// Whether G-buffers a and b of the same frame agree: equal value for value where `driver_info`
// (DeviceInfo::driver_info) names Mesa, else within kRoundings roundings of each part's storage
// (half floats: 2^-11 relative, 6e-8 near 0; the albedo's bytes: 1/255; the normal and depth's
// floats: 2^-23 relative or absolute; the display's floats went through half floats). `what`
// names the case in the message.
inline ::testing::AssertionResult same_gbuffer(const GBufferImage& a, const GBufferImage& b,
                                               const std::string& driver_info, const std::string& what) {
    constexpr double kRoundings = 4.0, kHalf = 1.0 / 2048.0, kFloat = 1.0 / 8388608.0;
    constexpr double kHalfTiny = 6e-8; // A half float's smallest step (its subnormals).
    const bool exact = driver_info.find("Mesa") != std::string::npos;
    const struct {
        const char* name;
        GBufferPartDiff d;
    } parts[] = {{"radiance", gbuffer_part_diff(a.radiance, b.radiance, kHalf, kHalfTiny)},
                 {"albedo", gbuffer_part_diff(a.albedo, b.albedo, 0.0, 1.0 / 255.0)},
                 {"normal_depth", gbuffer_part_diff(a.normal_depth, b.normal_depth, kFloat, kFloat)},
                 {"reflected", gbuffer_part_diff(a.reflected, b.reflected, kHalf, kHalfTiny)},
                 {"display", gbuffer_part_diff(a.display, b.display, kHalf, kHalfTiny)}};
    std::string report;
    bool ok = true;
    for (const auto& p : parts) {
        if (p.d.pixels == 0)
            continue;
        char line[160];
        std::snprintf(line, sizeof line, "%s%s: %zu pixels differ, at most %.3g roundings",
                      report.empty() ? "" : "; ", p.name, p.d.pixels, p.d.worst);
        report += line;
        ok = ok && !exact && p.d.worst <= kRoundings;
    }
    if (!report.empty())
        std::printf("%s (%s): %s\n", what.c_str(), driver_info.c_str(), report.c_str());
    if (ok)
        return ::testing::AssertionSuccess();
    const char* why = exact ? " (Mesa: must be equal)" : " (over the rounding allowed)";
    return ::testing::AssertionFailure() << what << ": " << report << why;
}

} // namespace vx::render::test
