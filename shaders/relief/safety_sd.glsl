// safety-sd — precomputed safety distances (Baboud, Eisemann & Seidel 2011 §5.2.2, §6.1). Port
// of relief::SafetySdTracer::trace (src/relief/techniques/safety_sd/safety_sd.h):
// SafetyTracer<DistanceShape> (safety_march.glsl), the stored distance of the ray's class.
// Maps: `heights` (R32F, h in [0, 1]) and `sd`, the bake's "sd" array: RGBA32F, one distance per
// ray class (x+, x-, y+, y-), or R32F with p.isotropic = 1 for an isotropic bake; nearest.
// p.maxZ, p.phiMax, p.exterior as for safety-cc. Contract: exact (p.maxSteps = 0);
// view-dependent and positive-distance are approximate. Shadows: the same march to the light.
// requires: safety_march.glsl

ReliefHit reliefSafetySd(sampler2D heights, sampler2D sd, vec2 uv, vec3 viewDirTangent,
                         ReliefParams p) {
    return reliefSafetyView(heights, sd, sd, sd, sd, kReliefSafetySd, uv, viewDirTangent, p);
}

float reliefSafetySdShadow(sampler2D heights, sampler2D sd, ReliefHit hit, vec3 lightDirTangent,
                           ReliefParams p) {
    return reliefSafetyShadowQuery(heights, sd, sd, sd, sd, kReliefSafetySd, hit,
                                   lightDirTangent, p);
}
