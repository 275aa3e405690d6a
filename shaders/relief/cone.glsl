// cone — conservative cone step mapping with an exact cell finish, on textures. Port of
// relief::ConeTracer::trace (src/relief/techniques/cone/cone.h, safeStepMarch): the same cone
// steps, the same exact cell test where a step stalls, the same step count.
// Maps: `heights` (R32F, h in [0, 1]) and `cones`, the bake's "cones" array as RG32F: (a, c) per
// texel, float texel units when bits = 32, codes in [0, 1] when bits = 16 / 8 (a UNORM
// texture of the export reads the same). Both nearest (texelFetch): interpolating cones between
// texels would not be conservative.
// Contract (variant safe): never past the first hit; with max-steps high enough it is the
// exact first hit. Shadows: the same march toward the light (exact as well).
// requires: safe_step_march.glsl

ReliefHit reliefCone(sampler2D heights, sampler2D cones, vec2 uv, vec3 viewDirTangent,
                     ReliefParams p) {
    return reliefSafeStepView(heights, cones, kReliefMarchCone, uv, viewDirTangent, p);
}

float reliefConeShadow(sampler2D heights, sampler2D cones, ReliefHit hit, vec3 lightDirTangent,
                       ReliefParams p) {
    return reliefSafeStepShadow(heights, cones, kReliefMarchCone, hit, lightDirTangent, p);
}
