// The GLSL 3.30 sources: the organ (per-pixel Blinn, SPEC R19, with bump mapping), metal tools
// (Blinn plus a cube-map reflection) and plain coloured markers.
#pragma once

namespace hapticut::render::shaders {

// One vertex layout for everything: position, normal, uv. Lighting is done in view space.
inline constexpr const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec2 aUv;
layout(location = 3) in float aWound;
uniform mat4 uModel, uView, uProjection;
out vec3 vPosition;   // view space
out vec3 vNormal;     // view space
out vec3 vWorldNormal;
out vec3 vWorldPosition;
out vec2 vUv;
out float vWound;
void main() {
    vec4 world = uModel * vec4(aPosition, 1.0);
    vec4 view = uView * world;
    vPosition = view.xyz;
    vNormal = mat3(uView) * mat3(uModel) * aNormal;  // rigid transforms and uniform scale only
    vWorldNormal = mat3(uModel) * aNormal;
    vWorldPosition = world.xyz;
    vUv = aUv;
    vWound = aWound;
    gl_Position = uProjection * view;
}
)";

// Two lights fixed to the camera (a key light above left, a dim fill from the right), as a surgeon's
// head lamp would be. I = I_l (k_d (N.L) + k_s (N.H)^shininess), summed over the lights, plus ambient.
inline constexpr const char* kLightingCommon = R"(
uniform vec3 uLightDirection[2];  // towards the light, view space
uniform vec3 uLightColour[2];
uniform vec3 uAmbient;
uniform float uShininess;
uniform bool uMonochrome;  // anaglyph: each eye sees through a colour filter, so draw in grey
vec4 finish(vec3 colour, float alpha) {
    if (uMonochrome) colour = vec3(dot(colour, vec3(0.45, 0.35, 0.2)) * 1.6);
    return vec4(colour, alpha);
}
vec3 blinn(vec3 N, vec3 V, vec3 kd, float ks) {
    vec3 colour = uAmbient * kd;
    for (int i = 0; i < 2; ++i) {
        vec3 L = normalize(uLightDirection[i]);
        vec3 H = normalize(L + V);
        float diffuse = max(dot(N, L), 0.0);
        float specular = diffuse > 0.0 ? pow(max(dot(N, H), 0.0), uShininess) : 0.0;
        colour += uLightColour[i] * (kd * diffuse + ks * specular);
    }
    return colour;
}
)";

inline constexpr const char* kOrganFragment = R"(
uniform sampler2D uDiffuse;   // k_d
uniform sampler2D uDetail;    // r: k_s, g: height
uniform float uUvScale;
uniform float uBumpHeight_m;  // height of the texture's white, 0 turns bump mapping off
uniform vec3 uInsideColour;   // back faces: the inside of an opened wound
in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;
in float vWound;
out vec4 fragColour;

// Bump mapping without tangents (Mikkelsen 2010, "Bump mapping unparametrized surfaces on the GPU"):
// the height's screen-space gradient, lifted to the surface through the position's derivatives.
vec3 bumped(vec3 N, vec2 uv) {
    vec3 dpdx = dFdx(vPosition), dpdy = dFdy(vPosition);
    vec2 duvdx = dFdx(uv), duvdy = dFdy(uv);
    float h = texture(uDetail, uv).g;
    float dhdx = (texture(uDetail, uv + duvdx).g - h) * uBumpHeight_m;
    float dhdy = (texture(uDetail, uv + duvdy).g - h) * uBumpHeight_m;
    vec3 r1 = cross(dpdy, N), r2 = cross(N, dpdx);
    float det = dot(dpdx, r1);
    if (abs(det) < 1e-20) return N;
    vec3 gradient = sign(det) * (dhdx * r1 + dhdy * r2);
    return normalize(abs(det) * N - gradient);
}

void main() {
    vec3 N = normalize(vNormal);
    vec3 V = normalize(-vPosition);
    if (vWound > 1.5) {
        // A wound's wall: raw, wet tissue, darker toward the bottom, streaked along the cut.
        if (!gl_FrontFacing) N = -N;
        float streak = texture(uDetail, vec2(vUv.x * 0.37, vUv.y * 0.11)).g;
        vec3 wall = uInsideColour * (0.85 - 0.55 * vUv.y) * (0.8 + 0.35 * streak);
        fragColour = finish(blinn(N, V, wall, 0.5 * (1.0 - vUv.y)), 1.0);
        return;
    }
    vec2 uv = vUv * uUvScale;
    vec3 kd = texture(uDiffuse, uv).rgb;
    float ks = texture(uDetail, uv).r;
    // Along a wound's lips the tissue is raw and bloody: darker, redder, wetter.
    float wound = smoothstep(0.0, 1.0, min(vWound, 1.0));
    kd = mix(kd, uInsideColour * 0.45, wound);
    ks = mix(ks, 1.0, 0.6 * wound);
    if (!gl_FrontFacing) {  // looking into the wound: raw, darker, duller tissue
        N = -N;
        kd = uInsideColour * (0.6 + 0.4 * kd.r);
        ks *= 0.3;
    } else if (uBumpHeight_m > 0.0) {
        N = bumped(N, uv);
    }
    fragColour = finish(blinn(N, V, kd, ks), 1.0);
}
)";

inline constexpr const char* kMetalFragment = R"(
uniform samplerCube uEnvironment;
uniform vec3 uBaseColour;
uniform vec3 uCameraPosition;  // world
uniform float uReflectivity;
in vec3 vPosition;
in vec3 vNormal;
in vec3 vWorldNormal;
in vec3 vWorldPosition;
out vec4 fragColour;
void main() {
    vec3 N = normalize(vNormal);
    vec3 V = normalize(-vPosition);
    if (!gl_FrontFacing) N = -N;
    vec3 lit = blinn(N, V, uBaseColour, 0.9);
    vec3 I = normalize(vWorldPosition - uCameraPosition);
    vec3 Nw = normalize(vWorldNormal) * (gl_FrontFacing ? 1.0 : -1.0);
    vec3 reflected = texture(uEnvironment, reflect(I, Nw)).rgb;
    float fresnel = uReflectivity + (1.0 - uReflectivity) * pow(1.0 - max(dot(N, V), 0.0), 5.0);
    fragColour = finish(mix(lit, reflected * uBaseColour * 1.6, fresnel), 1.0);
}
)";

inline constexpr const char* kFlatFragment = R"(
uniform vec4 uColour;
in vec3 vPosition;
in vec3 vNormal;
out vec4 fragColour;
void main() {
    vec3 N = normalize(vNormal);
    if (!gl_FrontFacing) N = -N;
    float light = 0.45 + 0.55 * max(dot(N, normalize(vec3(-0.3, 0.6, 0.75))), 0.0);
    fragColour = finish(uColour.rgb * light, uColour.a);
}
)";

}  // namespace hapticut::render::shaders
