// The mesh preview's fragment shader (src/relief/preview/mesh_renderer.cpp). Its program text is
// "#version 330 core", the engine shader library (common.glsl + the row's file), the row's
// sampler uniforms, RELIEF_TRACE(uv, viewDir, params) and RELIEF_SHADOW(hit, light, params)
// (the row's two functions with its samplers), then this file.
// Tangent space as the library takes it: x along +u and z along the normal in u units, y along
// +v in v units; one u unit is vUvScale.x in world units, one v unit vUvScale.y.
uniform ReliefParams params;
uniform mat4 clipFromWorld;
uniform vec3 eye;
uniform vec3 towardsLight;  // unit, world
uniform int object;         // 1: the relief, 2: the crossing square (MeshPixel)
uniform int shadows;
uniform int hasColor;
uniform sampler2D colorMap;   // sRGB, mipmapped
uniform sampler2D normalMap;  // texel-space normals of the heights, mipmapped
uniform float exposure;
uniform float specular;
in vec3 vWorld;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;
in vec2 vUvScale;
layout(location = 0) out vec4 outColor;
layout(location = 1) out vec4 outInfo;  // distance from the eye, object, steps

vec3 srgbEncode(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

vec3 shade(vec3 base, vec3 n, vec3 toEye, float lit) {
    float diffuse = max(dot(n, towardsLight), 0.0) * lit;
    vec3 h = normalize(towardsLight + normalize(toEye));
    float highlight = specular * pow(max(dot(n, h), 0.0), 48.0) * lit;
    float ambient = 0.18 + 0.07 * n.z;  // a sky a little brighter than the ground
    return exp2(exposure) * (base * (ambient + diffuse) + vec3(highlight));
}

void main() {
    // Footprint of the mesh's uv (before discard: derivatives need every pixel of the quad).
    vec2 dx = dFdx(vUv), dy = dFdy(vUv);
    if (object == 2) {
        outColor = vec4(srgbEncode(shade(vec3(0.25, 0.45, 0.75), vec3(0, 0, 1), eye - vWorld, 1.0)),
                        1.0);
        outInfo = vec4(length(vWorld - eye), 2.0, 0.0, 0.0);
        gl_FragDepth = gl_FragCoord.z;
        return;
    }
    vec3 n = normalize(vNormal);
    vec3 t = normalize(vTangent.xyz - n * dot(n, vTangent.xyz));
    vec3 b = (vTangent.w < 0.0 ? -1.0 : 1.0) * cross(n, t);
    float su = vUvScale.x, sv = vUvScale.y;
    vec3 toEye = eye - vWorld;
    vec3 viewDir = vec3(dot(toEye, t) / su, dot(toEye, b) / sv, dot(toEye, n) / su);
    ReliefHit hit = RELIEF_TRACE(vUv, viewDir, params);
    if (!hit.hit) discard;  // the ray left the relief: a silhouette
    // The hit in world space on the fragment's tangent plane; its depth is the pixel's.
    vec3 world = vWorld + t * (su * (hit.uv.x - vUv.x)) + b * (sv * (hit.uv.y - vUv.y)) -
                 n * (su * hit.depth);
    vec4 clip = clipFromWorld * vec4(world, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);

    vec3 lightTangent = vec3(dot(towardsLight, t) / su, dot(towardsLight, b) / sv,
                             dot(towardsLight, n) / su);
    float lit = shadows != 0 ? RELIEF_SHADOW(hit, lightTangent, params) : 1.0;
    // Texel-space normal to world: the inverse transpose of texel → world (su/W, sv/H, su/W).
    vec3 nt = textureGrad(normalMap, hit.uv, dx, dy).xyz;
    vec3 nw = normalize(t * (nt.x * params.mapSize.x / su) + b * (nt.y * params.mapSize.y / sv) +
                        n * (nt.z * params.mapSize.x / su));
    vec3 base = hasColor != 0 ? textureGrad(colorMap, hit.uv, dx, dy).rgb : vec3(0.7);
    outColor = vec4(srgbEncode(shade(base, nw, eye - world, lit)), 1.0);
    outInfo = vec4(length(world - eye), 1.0, float(hit.steps), 0.0);
}
