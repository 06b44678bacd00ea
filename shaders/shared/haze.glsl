// Aerial perspective of Full shading (FrameParams::haze, raygen.rgen): haze with distance towards
// the sky colour. Single scattering in a medium whose extinction is sigma at and below a base
// height and sigma * exp(-falloff * h) at height h above it: exponential height fog, whose optical
// depth along a straight segment has a closed form (Wenzel, "Real-time Atmospheric Effects in
// Games", SIGGRAPH 2006; Hillaire, "Physically Based and Unified Volumetric Rendering in
// Frostbite", SIGGRAPH 2015). A segment of optical depth tau passes T = exp(-tau) of the light
// behind it (Beer-Lambert) and adds what it scatters towards the eye. The medium (scattering
// only, isotropic) is lit by the uniform sky's light, the same that the sky term's rays see
// (sky * sky_light), so that is sky * sky_light * (1 - T): with sky_light 1 far terrain fades
// into the sky colour and a ray that leaves the world sees the sky unchanged. Without the sky
// term (sky_light 0, or the view sealed off from the sky) the haze only absorbs. The sun's own
// in-scattering, a glow around it, is left out.
// TODO: the air is taken to see the whole sky. Where the view is not sealed off (sky_access) but
// the air is dark, as in a large cave open to the sky somewhere, far walls take on sky colour
// too (under 2% within 100 blocks at the defaults); tracing the segment's view of the sky would
// fix it at a ray or more per segment, and add noise.
#ifndef VX_SHADERS_HAZE_GLSL
#define VX_SHADERS_HAZE_GLSL

// Optical depth of a straight segment of length len (blocks) from height h0 to h1 above the base
// height (blocks); sigma: extinction per block at and below the base, falloff: per block above.
float vx_haze_depth(float sigma, float falloff, float h0, float h1, float len) {
    float lo = min(h0, h1), hi = max(h0, h1);
    // The part at or below the base, where the extinction is constant.
    float below = hi <= 0.0 ? len : (lo >= 0.0 ? 0.0 : len * -lo / (hi - lo));
    // Above it the mean of exp(-falloff h) over heights [a, b] is exp(-falloff a) (1 - e^-x) / x,
    // x = falloff (b - a); its series near 0, where the quotient loses its digits.
    float a = max(lo, 0.0), x = falloff * (max(hi, 0.0) - a);
    float mean = x < 1e-3 ? 1.0 - x * (0.5 - x / 6.0) : (1.0 - exp(-x)) / x;
    return sigma * (below + (len - below) * exp(-falloff * a) * mean);
}

// The transmittance of the segment from `origin` (relative to the render origin, as every
// shader position) along unit `dir` for `len`
// blocks, under FrameParams::haze.
float vx_haze_transmittance(vec3 origin, vec3 dir, float len) {
    float h0 = frame.haze.z + origin.y;
    return exp(-vx_haze_depth(frame.haze.x, frame.haze.y, h0, h0 + dir.y * len, len));
}

#endif
