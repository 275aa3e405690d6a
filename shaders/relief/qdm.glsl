// qdm — quadratic displacement maps (Kiglics, Valasek, Bálint & Bán 2023). Port of
// relief::QdmTracer::trace (src/relief/techniques/qdm/qdm.h) and QdmMap (qdm_map.h): steps by
// the revolved profile (a cone up to a, a parabola up to c, flat beyond) of an apex at height h,
// the exact cell test over the cell's whole span where a step stalls.
// Maps: `heights` (R32F, h in [0, 1]) and `qdm`, the bake's "qdm" array as RGBA32F: (a, b, c, h)
// per texel in texel units, nearest. p.maxZ = D × the map's highest height (qdm's reach test;
// D is safe but steps less far), p.maxDistance = the map's "max-distance".
// Contract: conservative (never past the first hit; exact once converged). Shadows: the same
// march toward the light.
// requires: safe_step_march.glsl

ReliefHit reliefQdm(sampler2D heights, sampler2D qdm, vec2 uv, vec3 viewDirTangent,
                    ReliefParams p) {
    return reliefSafeStepView(heights, qdm, kReliefMarchQdm, uv, viewDirTangent, p);
}

float reliefQdmShadow(sampler2D heights, sampler2D qdm, ReliefHit hit, vec3 lightDirTangent,
                      ReliefParams p) {
    return reliefSafeStepShadow(heights, qdm, kReliefMarchQdm, hit, lightDirTangent, p);
}
