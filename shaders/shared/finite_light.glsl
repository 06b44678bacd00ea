// The raygen shader's finite lights (included by raygen.rgen after shared/raygen_emitters.glsl):
// next-event estimation of the area light and of the emissive blocks' faces, one function for
// both. shade() calls it in one loop, once per kind, so that its shadow ray and its walk through
// water (light_through()) have one call site each: lavapipe compiles every call site of a trace
// as a copy with its own traversal, and the cold pipeline compile grows with each. The loop is
// marked [[unroll]], which lavapipe ignores and the NVIDIA driver needs (shade() says why).

const uint kLightArea = 0u;  // The rectangular area light (frame.light_*).
const uint kLightFaces = 1u; // The emissive faces of the nearest emitter chunks (frame.emitter_quads).

// Irradiance at `pos` (camera-relative; normal n) from the lights of `kind`, and the fraction of
// its samples that saw light. Samples are uniform in a rectangle's solid angle where area
// sampling's weight would vary much over it and that is well defined (shared/rect_light.h), else
// uniform over its area. The area light lights both its sides; zero samples there: shadows off,
// one unshadowed sample at its centre. A face is drawn per sample among kEmitterCandidates
// (draw_candidates(): resampled importance), and lights its outer side alone. From inside water
// or glass (hit_index() > 1) the light is bent where it enters (light_through()). Clears and
// fills g_m1, g_m2 (estimator_variance()) with the samples' luminance: the area light's
// including its emission, the faces' as they are.
vec4 finite_light(uint kind, vec3 pos, vec3 n, uint samples, uint seed) {
    g_m1 = g_m2 = 0.0;
    g_probe_off = false;
    bool area_kind = kind == kLightArea;
    if (area_kind && dot(frame.light_emission.xyz, vec3(1.0)) <= 0.0)
        return vec4(0.0);
    bool shadows = samples > 0u;
    uint count = area_kind ? max(samples, 1u) : samples;
    if (count == 0u)
        return vec4(0.0);
    vec3 eu = frame.light_edge_u.xyz, ev = frame.light_edge_v.xyz, corner = frame.light_corner.xyz;
    vec3 ln = cross(eu, ev); // The light's unit normal.
    float area = length(ln);
    ln /= max(area, 1e-30);
    RectView view;
    view.valid = false;
    if (area_kind && shadows)
        view = near_rect_view(pos, corner, eu, ev);
    float index = hit_index();
    bool bends = shadows && index != 1.0;
    EmitterQuads quads = EmitterQuads(frame.emitter_quads);
    vec3 sum = vec3(0.0);
    uint seen = 0u;
    for (uint s = 0u; s < count; ++s) {
        // A face's emission and the weight of its choice, total / target (draw_candidates()).
        vec3 emission = vec3(1.0);
        float total = 1.0, target = 1.0;
        if (!area_kind) {
            uint chosen;
            uint rng = vx_hash(seed ^ vx_hash(g_pixel.x + vx_hash(g_pixel.y + vx_hash(s))));
            total = draw_candidates(pos, n, rng, chosen, target);
            if (total <= 0.0)
                continue;
            EmitterQuad q = quads.q[chosen];
            eu = q.edge_u.xyz;
            ev = q.edge_v.xyz;
            corner = q.corner.xyz;
            area = q.corner.w;
            ln = cross(eu, ev) / area;
            // By solid angle where the face is near: area sampling's cos / d^2 would make the
            // floor beside a lamp a field of fireflies.
            view = near_rect_view(pos, corner, eu, ev);
            emission = q.emission.xyz;
        }
        vec2 uv = shadows ? sample2(s, count, seed) : vec2(0.5);
        vec3 to_light = view.valid ? vx_rect_sample(view, uv.x, uv.y) : corner + uv.x * eu + uv.y * ev - pos;
        float d2 = dot(to_light, to_light), dist = sqrt(d2);
        vec3 l = to_light / dist;
        float cos_s = dot(n, l); // At the receiver; at the light:
        float cos_l = area_kind ? abs(dot(ln, l)) : -dot(cross(eu, ev), l) / area;
        // NaN too: a sample exactly at the shading point has no direction.
        if (!(cos_s > 0.0) || (!area_kind && !(cos_l > 0.0)))
            continue;
        vec3 x;
        bool straight = true;
        if (bends) {
            if (area_kind && view.valid && cos_l < 1e-6)
                continue;
            // A face's walk stops short of it (that face would block it).
            vec3 through = light_through(pos, n, pos + to_light, ln, !area_kind, g_hit_inside, index,
                                         area_kind ? 0.0 : 1e-3, straight);
            // Over the pdf per unit area: solid angle d^2 / cos at the light, or the area.
            float inverse_pdf = view.valid ? view.solid_angle * d2 / cos_l : area;
            x = area_kind ? through * inverse_pdf : through * emission * (inverse_pdf * total / target);
        }
        if (straight) {
            // A face's ray stops short of it, as the walk. A lamp behind glass: the ray ends inside
            // the glass, which absorbs on to its end.
            float reach = area_kind ? dist : dist * (1.0 - 1e-4) - 1e-3;
            vec3 pass = shadows ? trace_shadow(pos, l, reach, g_hit_inside) : vec3(1.0);
            // Over the pdf: 1 / solid angle, or d^2 / (area cos at the light).
            float geometry = view.valid ? cos_s * view.solid_angle : cos_s * cos_l * area / d2;
            x = area_kind ? pass * geometry : pass * emission * (geometry * total / target);
        }
        if (x == vec3(0.0))
            continue;
        ++seen;
        sum += x;
        add_sample(area_kind ? x * frame.light_emission.xyz : x);
    }
    vec3 scale = area_kind ? frame.light_emission.xyz : vec3(1.0);
    return vec4(sum * scale / float(count), float(seen) / float(count));
}
