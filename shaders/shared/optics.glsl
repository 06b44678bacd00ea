// Optics of a see-through block's surface, shared by the ray tracer (rt_common.glsl) and the raster
// baseline (raster.frag): its index of refraction and the Fresnel equations. GLSL only.
#ifndef VX_OPTICS_GLSL
#define VX_OPTICS_GLSL

// The index of refraction of a see-through block of normal-incidence reflectance r against air,
// ((n - 1) / (n + 1))^2 = r (water 0.02: n 1.33; glass 0.04: n 1.5); r = 0: 1, a block that only
// tints and bends nothing.
float vx_index(float r) {
    float s = sqrt(clamp(r, 0.0, 0.999));
    return (1.0 + s) / (1.0 - s);
}

// The share of light mirrored where a ray meets, at cosine cos_i to the normal, an interface into a
// medium of relative index eta = n_t / n_i: the Fresnel equations for unpolarised light (Pharr et
// al., PBRT 4th ed., 9.3.1), exact, 1 past the critical angle (total internal reflection, eta < 1).
// Schlick's approximation is not used: it mirrors (1 - cos)^5 even at eta = 1.
float vx_fresnel_eta(float cos_i, float eta) {
    if (eta == 1.0)
        return 0.0;
    float c = clamp(cos_i, 0.0, 1.0);
    float sin2_t = (1.0 - c * c) / (eta * eta);
    if (sin2_t >= 1.0 || c <= 0.0)
        return 1.0;
    float ct = sqrt(1.0 - sin2_t); // The refracted ray's cosine.
    float rs = (c - eta * ct) / (c + eta * ct), rp = (eta * c - ct) / (eta * c + ct);
    return 0.5 * (rs * rs + rp * rp);
}

#endif
