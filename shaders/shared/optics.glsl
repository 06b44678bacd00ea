// Optics of a see-through block's surface, shared by the ray tracer (rt_common.glsl) and the raster
// baseline (raster.frag): the Fresnel equations. A block's index of refraction comes with its
// material (Material::optics.w, render/material_table.h's refractive_index). GLSL only.
#ifndef VX_OPTICS_GLSL
#define VX_OPTICS_GLSL

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
