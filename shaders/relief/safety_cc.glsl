// safety-cc — precomputed safety shapes, cylinder-cone form (Baboud, Eisemann & Seidel 2011
// §6.3). Port of relief::SafetyCcTracer::trace (src/relief/techniques/safety_cc/safety_cc.h):
// SafetyTracer<ConeShape> (safety_march.glsl), i = max(r, ⌊max(z − z0, 0) / (s_c − s)⌋).
// Maps: `heights` (R32F, h in [0, 1]) and the four ray classes' cones, the bake's arrays "ccx+",
// "ccx-", "ccy+", "ccy-" as RGB32F (r, z_c, s_c per texel), nearest; an isotropic bake has one
// array "cc": bind it to all four. p.maxZ = D × the highest height, p.phiMax and p.exterior =
// the map's "phi-max" and "exterior". Contract: exact (p.maxSteps = 0); view-dependent and
// positive-distance are the paper's approximate forms. Shadows: the same march toward the light.
// requires: safety_march.glsl

ReliefHit reliefSafetyCc(sampler2D heights, sampler2D ccxPlus, sampler2D ccxMinus,
                         sampler2D ccyPlus, sampler2D ccyMinus, vec2 uv, vec3 viewDirTangent,
                         ReliefParams p) {
    return reliefSafetyView(heights, ccxPlus, ccxMinus, ccyPlus, ccyMinus, kReliefSafetyCc, uv,
                            viewDirTangent, p);
}

float reliefSafetyCcShadow(sampler2D heights, sampler2D ccxPlus, sampler2D ccxMinus,
                           sampler2D ccyPlus, sampler2D ccyMinus, ReliefHit hit,
                           vec3 lightDirTangent, ReliefParams p) {
    return reliefSafetyShadowQuery(heights, ccxPlus, ccxMinus, ccyPlus, ccyMinus,
                                   kReliefSafetyCc, hit, lightDirTangent, p);
}
