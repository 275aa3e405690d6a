// cone — conservative cone step mapping with an exact cell finish, on textures. Port of
// relief::ConeTracer::trace (src/relief/techniques/cone/cone.h, safeStepMarch): the same cone
// steps, the same exact cell test where a step stalls, the same step count.
// Maps: `heights` (R32F, h in [0, 1]) and `cones`, the bake's "cones" array as RG32F: (a, c) per
// texel, float texel units when bits = 32, codes in [0, 1] when bits = 16 / 8 (a UNORM
// texture of the export reads the same). Both nearest (texelFetch): interpolating cones between
// texels would not be conservative.
// Contract (variant safe): never past the first hit; with max-steps high enough it is the
// exact first hit. Shadows: the same march toward the light (exact as well).
// requires: common.glsl

const float kConeStall = 0.1;  // ConeLimits::stall (texels)

// The first hit of a texel-space ray (any direction): ConeTracer::trace.
ReliefHit reliefConeTrace(sampler2D heights, sampler2D cones, ReliefRay ray, ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 d = ray.direction;
    float horizontal = sqrt(d.x * d.x + d.y * d.y);
    float t = span.x;
    int steps = 0;
    for (int k = 0; k < p.maxSteps; ++k) {
        ++steps;
        vec3 q = ray.origin + t * d;
        vec2 cone = reliefConeAt(cones, q.x, q.y, p);
        if (q.z >= cone.x && q.z > 0.0) {  // on the floor the cell test decides (cone.h)
            float dt = reliefConeStep(q.z, cone.x, cone.y, horizontal, d.z);
            if (dt >= kConeStall) {
                if (t + dt >= span.y)  // leaves the box without meeting S inside it
                    return reliefExitsThroughFloor(ray, span.y, p)
                               ? reliefHitAt(ray, span.y, steps, p)
                               : reliefNoHit(steps);
                t += dt;
                continue;
            }
        }
        // Exact: the cell the ray is in, up to where it leaves it.
        ReliefCellSpan cell = reliefCellAt(ray, t, span.y, p);
        float th = reliefFirstHitInCell(heights, ray, cell.ci, cell.cj, t, cell.tb, p);
        if (th <= cell.tb) return reliefHitAt(ray, th, steps, p);
        if (cell.tb >= span.y)
            return reliefExitsThroughFloor(ray, span.y, p) ? reliefHitAt(ray, span.y, steps, p)
                                                           : reliefNoHit(steps);
        t = cell.tb;
    }
    return reliefHitAt(ray, t, steps, p);  // capped: the last position, never past the first hit
}

ReliefHit reliefCone(sampler2D heights, sampler2D cones, vec2 uv, vec3 viewDirTangent,
                     ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    return reliefConeTrace(heights, cones, ray, p);
}

// 1 = lit, 0 = S lies between the hit and the light (a light at or below the surface plane: 0).
float reliefConeShadow(sampler2D heights, sampler2D cones, ReliefHit hit, vec3 lightDirTangent,
                       ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    ReliefHit blocker = reliefConeTrace(heights, cones, ray, p);
    // A capped march (hit at its last position) has not proved the way free: shadowed.
    return blocker.hit ? 0.0 : 1.0;
}
