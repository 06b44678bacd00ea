#version 460
#extension GL_GOOGLE_include_directive : require
// A shadow ray that reaches its end unblocked: the light sample is visible.
#include "shared/rt_common.glsl"

layout(location = 1) rayPayloadInEXT ShadowPayload shadow;

void main() {
    shadow.visible = 1u;
}
