#pragma once
// The median of timing samples, for the tools, benchmarks and bench programs that print them (one
// definition, so every report means the same thing). Pure function: thread-safe.

#include <algorithm>
#include <vector>

namespace vx {

// The middle value of `v` (the mean of the two middle ones for an even count); -1 when empty,
// which the callers print as "no figure" (times are never negative).
inline double median(std::vector<double> v) {
    if (v.empty())
        return -1;
    const size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
    const double upper = v[mid];
    if (v.size() % 2)
        return upper;
    return 0.5 * (*std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)) + upper);
}

} // namespace vx
