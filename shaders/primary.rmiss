#version 460
#extension GL_GOOGLE_include_directive : require
// Primary and reflection rays that leave the world see the sky.
#include "shared/rt_common.glsl"

layout(location = 0) rayPayloadInEXT HitPayload payload;

void main() {
    payload.t = -1.0;
}
