// Auto exposure's metering (render_types.h, ExposureMeter), shared by raygen.rgen and, with the
// light cache, light_cache.comp (whichever finishes the pixel meters it). Needs
// GL_EXT_buffer_reference and the FrameParams block.

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

