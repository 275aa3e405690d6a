// qdm — quadratic displacement maps (Kiglics, Valasek, Bálint & Bán 2023). Port of
// relief::QdmTracer::trace (src/relief/techniques/qdm/qdm.h) and QdmMap (qdm_map.h): steps by
// the revolved profile (a cone up to a, a parabola up to c, flat beyond) of an apex at height h,
// the exact cell test over the cell's whole span where a step stalls.
// Maps: `heights` (R32F, h in [0, 1]) and `qdm`, the bake's "qdm" array as RGBA32F: (a, b, c, h)
// per texel in texel units, nearest. p.maxZ = D × the map's highest height (qdm's reach test;
// D is safe but steps less far), p.maxDistance = the map's "max-distance".
// Contract: conservative (never past the first hit; exact once converged). Shadows: the same
// march toward the light.
// requires: common.glsl

const float kQdmStall = 0.1;     // QdmLimits::stall
const float kQdmShorten = 1e-4;  // QdmLimits::shorten

// QdmMap::at: (a, b, c, h) of the texel whose footprint holds (x, y).
vec4 reliefQdmAt(sampler2D qdm, float x, float y, ReliefParams p) {
    return texelFetch(qdm, reliefSampleIndex(int(floor(x)), int(floor(y)), p), 0);
}

// qdmProfile: f(x), nondecreasing; the parabola's top beyond c.
float reliefQdmProfile(vec4 q, float x) {
    if (x <= q.x) return q.x > 0.0 ? q.y * x / q.x : 0.0;
    float u = min(x, q.z) - q.x;
    return q.y + u * (2.0 * (q.z - q.x) - u);
}

// QdmMap::reach: kReliefInfinity when the profile clears the highest point of S at max-distance.
float reliefQdmReach(vec4 q, ReliefParams p) {
    if (!(p.maxDistance > 0.0)) return kReliefInfinity;
    if (reliefQdmProfile(q, p.maxDistance) >= p.maxZ - q.w) return kReliefInfinity;
    return p.maxDistance;
}

// parabolaStep (Algorithm 2): the smaller root on the parabola's side of the junction.
float reliefQdmParabolaStep(vec4 q, float h0, float horizontal, float dz) {
    float halfB = 0.5 * dz - q.z * horizontal;
    if (halfB >= 0.0) return kReliefInfinity;
    float A = horizontal * horizontal;
    float C = h0 - q.y - q.x * q.x + 2.0 * q.x * q.z;
    float disc = halfB * halfB - A * C;
    if (disc < 0.0) return kReliefInfinity;
    float t = C / (-halfB + sqrt(disc));
    return t * horizontal >= q.x ? t : kReliefInfinity;
}

// quadricStep: the largest dt the profile of an apex at height q.w allows from height z.
float reliefQdmStep(vec4 q, float z, float horizontal, float dz, float reach) {
    float h0 = z - q.w;
    float slope = q.x > 0.0 ? q.y / q.x : 0.0;
    float closing = slope * horizontal - dz;
    float tLine = closing > 0.0 ? h0 / closing : kReliefInfinity;
    float dt;
    if (tLine * horizontal <= q.x) {
        dt = tLine;  // the line segment
    } else {
        dt = reliefQdmParabolaStep(q, h0, horizontal, dz);
        if (!(dt * horizontal <= q.z)) {  // past the top: the flat part
            float top = q.y + (q.z - q.x) * (q.z - q.x);
            dt = dz < 0.0 ? (top - h0) / dz : kReliefInfinity;
        }
    }
    if (!(horizontal > 0.0)) return dt;
    return min(dt, reach / horizontal);
}

// referenceSpan's boundary: a cell edge along one axis.
float reliefQdmBoundary(int cell, float o, float d, bool entering) {
    if (d == 0.0) return entering ? -kReliefInfinity : kReliefInfinity;
    return (float(cell) + ((d > 0.0) != entering ? 1.5 : 0.5) - o) * (1.0 / d);
}

// referenceSpan: [ta, tb] of cell (ci, cj) along the ray, inside the box span.
vec2 reliefQdmCellSpan(ReliefRay ray, int ci, int cj, vec2 span) {
    vec3 o = ray.origin, d = ray.direction;
    float ta = max(span.x, max(reliefQdmBoundary(ci, o.x, d.x, true),
                                reliefQdmBoundary(cj, o.y, d.y, true)));
    float tb = min(min(reliefQdmBoundary(ci, o.x, d.x, false),
                       reliefQdmBoundary(cj, o.y, d.y, false)), span.y);
    return vec2(ta, max(ta, tb));
}

// The first hit of a texel-space ray (any direction): QdmTracer::trace.
ReliefHit reliefQdmTrace(sampler2D heights, sampler2D qdm, ReliefRay ray, ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 d = ray.direction;
    float horizontal = sqrt(d.x * d.x + d.y * d.y);
    float keep = 1.0 - kQdmShorten;
    float t = span.x;
    int steps = 0;
    for (int k = 0; k < p.maxSteps; ++k) {
        ++steps;
        vec3 pos = ray.origin + t * d;
        vec4 q = reliefQdmAt(qdm, pos.x, pos.y, p);
        if (pos.z > q.w) {  // on the apex height the ray may touch S: the cell test decides
            float dt = keep * reliefQdmStep(q, pos.z, horizontal, d.z, reliefQdmReach(q, p));
            if (dt >= kQdmStall) {
                if (t + dt >= span.y)  // leaves the box without meeting S inside it
                    return reliefExitsThroughFloor(ray, span.y, p)
                               ? reliefHitAt(ray, span.y, steps, p)
                               : reliefNoHit(steps);
                t += dt;
                continue;
            }
        }
        // Exact: the cell the ray is in, from where it entered it to where it leaves it.
        ReliefCellSpan cell = reliefCellAt(ray, t, span.y, p);
        vec2 cellSpan = reliefQdmCellSpan(ray, cell.ci, cell.cj, span);
        float th = reliefFirstHitInCell(heights, ray, cell.ci, cell.cj, cellSpan.x, cellSpan.y, p);
        if (th <= cellSpan.y) return reliefHitAt(ray, th, steps, p);
        if (cellSpan.y >= span.y)
            return reliefExitsThroughFloor(ray, span.y, p) ? reliefHitAt(ray, span.y, steps, p)
                                                           : reliefNoHit(steps);
        t = cellSpan.y > t ? cellSpan.y : cell.tb;
    }
    return reliefHitAt(ray, t, steps, p);  // capped: the last position, never past the first hit
}

ReliefHit reliefQdm(sampler2D heights, sampler2D qdm, vec2 uv, vec3 viewDirTangent,
                    ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    return reliefQdmTrace(heights, qdm, ray, p);
}

// 1 = lit, 0 = S lies between the hit and the light (or the capped march proved nothing).
float reliefQdmShadow(sampler2D heights, sampler2D qdm, ReliefHit hit, vec3 lightDirTangent,
                      ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    return reliefQdmTrace(heights, qdm, ray, p).hit ? 0.0 : 1.0;
}
