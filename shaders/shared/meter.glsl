// Auto exposure's metering (render_types.h, ExposureMeter) and the Full-mode output step, shared
// by raygen.rgen and, with the light cache, light_cache.comp (whichever finishes the pixel).
// Needs GL_EXT_buffer_reference, the FrameParams block, out_image and tonemap.h.

layout(buffer_reference, std430, buffer_reference_align = 8) buffer MeterBuffer { ExposureMeter meter; };

// Auto exposure's sample of this pixel (render_types.h, ExposureMeter): one pixel of each
// kMeterStride x kMeterStride block, so the sums stay within 32 bits. A pixel no light reaches
// is not counted: there is nothing in it to expose for, and at log2 0 it would drag the
// average down to kMeterLogMin (a night view of black terrain would blow its sky out).
void meter(ivec2 px, vec3 c) {
    if (frame.exposure.y == 0.0 || (px.x % int(kMeterStride)) != 0 || (px.y % int(kMeterStride)) != 0)
        return;
    float y = vx_luminance(c);
    if (!(y > 0.0))
        return;
    float l = clamp(log2(y), kMeterLogMin, kMeterLogMax);
    MeterBuffer m = MeterBuffer(frame.exposure_meter);
    atomicAdd(m.meter.log_sum, uint((l - kMeterLogMin) * kMeterScale + 0.5));
    atomicAdd(m.meter.count, 1u);
}

// The Full-mode pixel's last step (render/gbuffer.h): meter it, then store the exposed,
// tone-mapped output, unless the denoiser runs (FrameParams exposure.z): its last pass writes the
// output, which this frame's would only be overwritten.
void finish_full_pixel(ivec2 px, vec3 c) {
    meter(px, c);
    if (frame.exposure.z == 0.0)
        imageStore(out_image, px, vec4(vx_display(c, frame.exposure.x), 1.0));
}
