// qdm — quadratic displacement maps (Kiglics, Valasek, Bálint & Bán 2023). Port of
// relief::QdmTracer::trace (src/relief/techniques/qdm/qdm.h) and QdmMap (qdm_map.h): steps by
// the revolved profile (a cone up to a, a parabola up to c, flat beyond) of an apex at height h,
// the exact cell test over the cell's whole span where a step stalls. With p.variant = 1 (maps
// baked with `--param variant=1`: set it from the map's "variant" parameter, which selects the
// map and so the tracer) it is relief::QdmPaperTracer::trace (qdm_paper.h) instead: the paper's
// Algorithm 1 (line to (a, b) while alpha ≤ 1, else Algorithm 2's root) until a step is shorter
// than kQdmPaperEpsilon, the cap is reached or the ray is not above the texel's h; the hit is
// where it stops (no exact finish). Rising rays (shadows) take the reference cell walk.
// Maps: `heights` (R32F, h in [0, 1]) and `qdm`, the bake's "qdm" array as RGBA32F: (a, b, c, h)
// per texel in texel units, nearest. p.maxZ = D × the map's highest height (qdm's reach test;
// D is safe but steps less far), p.maxDistance = the map's "max-distance".
// Contract: variant 0 conservative (never past the first hit; exact once converged); variant 1
// approximate (may step past a hit). Shadows: the same march toward the light.
// requires: safe_step_march.glsl

const float kQdmPaperEpsilon = 1e-3;  // qdm_paper.h: Algorithm 1's "t > ε" (texels)

// paperStep (qdm_paper.h): from h0 above the apex, the line to (a, b) if the ray meets it with
// alpha ≤ 1, else the smaller root of the parabola (kReliefInfinity when there is none).
float reliefQdmPaperStep(vec4 q, float h0, float horizontal, float dz) {
    if (q.x > 0.0) {
        float t = h0 / (q.y / q.x * horizontal - dz);
        if (t * horizontal / q.x <= 1.0) return t;
    }
    float A = horizontal * horizontal;
    float halfB = 0.5 * (dz - 2.0 * q.z * horizontal);
    float C = h0 - q.y - q.x * q.x + 2.0 * q.x * q.z;
    float disc = halfB * halfB - A * C;
    if (disc < 0.0) return kReliefInfinity;
    float x = C / (-halfB + sqrt(disc));
    return abs(x) < kReliefInfinity ? x : kReliefInfinity;  // std::isfinite
}

// QdmPaperTracer::trace: a texel-space ray, any direction.
ReliefHit reliefQdmPaperMarch(sampler2D heights, sampler2D qdm, ReliefRay ray, ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 d = ray.direction;
    int steps = 0;
    if (d.z >= 0.0) {  // the reference walk (ExactTracer::trace)
        float tHit;
        bool hit = reliefCellsHit(heights, ray, span.x, span.y, true, tHit, steps, p);
        return reliefHitIf(hit, ray, tHit, steps, p);
    }
    float horizontal = sqrt(d.x * d.x + d.y * d.y);
    float t = span.x, dt = kReliefInfinity;
    while (steps < p.maxSteps && dt > kQdmPaperEpsilon) {
        vec3 pos = ray.origin + t * d;
        vec4 q = reliefQdmAt(qdm, pos.x, pos.y, p);
        if (!(pos.z > q.w)) break;  // not above the heightfield
        dt = reliefQdmPaperStep(q, pos.z - q.w, horizontal, d.z);
        ++steps;
        t = max(t + dt, span.x);  // never back before the box entry
        if (!(t < span.y)) break;
    }
    if (!(t < span.y))
        return reliefHitIf(reliefExitsThroughFloor(ray, span.y, p), ray, span.y, steps, p);
    return reliefHitAt(ray, t, steps, p);
}

ReliefHit reliefQdm(sampler2D heights, sampler2D qdm, vec2 uv, vec3 viewDirTangent,
                    ReliefParams p) {
    if (p.variant == 1)
        return reliefQdmPaperMarch(heights, qdm, reliefViewRay(uv, viewDirTangent, p), p);
    return reliefSafeStepView(heights, qdm, kReliefMarchQdm, uv, viewDirTangent, p);
}

float reliefQdmShadow(sampler2D heights, sampler2D qdm, ReliefHit hit, vec3 lightDirTangent,
                      ReliefParams p) {
    if (p.variant != 1)
        return reliefSafeStepShadow(heights, qdm, kReliefMarchQdm, hit, lightDirTangent, p);
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    return reliefQdmPaperMarch(heights, qdm, ray, p).hit ? 0.0 : 1.0;
}
