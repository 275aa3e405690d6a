// The loop the conservative step maps share (cone: safe cones; qdm: cone + revolved parabola).
// Port of safeStepMarch (src/relief/techniques/common/safe_step_march.h): from where the ray
// enters the box, step by the map's safe distance while that is at least the stall length;
// otherwise test the cell the ray is in exactly and go on from where it leaves the cell. Never
// past the first hit; at the cap, the last position (still before the first hit). The C++
// template arguments (the safe step, the cell range) become `kind`.
// requires: common.glsl

const int kReliefMarchCone = 0;  // map: the "cones" array (cone.glsl)
const int kReliefMarchQdm = 1;   // map: the "qdm" array (qdm.glsl)
const float kConeStall = 0.1;    // ConeLimits::stall (texels)

// ---- The quadratic displacement map (qdm_map.h, qdm.h) ----

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

// ---- The march ----

// The safe distance along the ray from `pos` (ConeTracer's and QdmTracer's safe steps), or
// -kReliefInfinity where only the cell test may decide.
float reliefSafeStep(int kind, sampler2D map, vec3 pos, float horizontal, float dz,
                     ReliefParams p) {
    if (kind == kReliefMarchCone) {
        vec2 cone = reliefConeAt(map, pos.x, pos.y, p);
        // On the floor (z <= 0) the cell test decides: a ray from below meets the solid there.
        return pos.z >= cone.x && pos.z > 0.0
                   ? reliefConeStep(pos.z, cone.x, cone.y, horizontal, dz)
                   : -kReliefInfinity;
    }
    vec4 q = reliefQdmAt(map, pos.x, pos.y, p);
    // On the apex height the ray may touch S: the cell test decides.
    return pos.z > q.w ? (1.0 - kQdmShorten) *
                             reliefQdmStep(q, pos.z, horizontal, dz, reliefQdmReach(q, p))
                       : -kReliefInfinity;
}

// The first hit of a texel-space ray (any direction): safeStepMarch.
ReliefHit reliefSafeStepMarch(sampler2D heights, sampler2D map, int kind, ReliefRay ray,
                              ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 d = ray.direction;
    float horizontal = sqrt(d.x * d.x + d.y * d.y);
    float stall = kind == kReliefMarchCone ? kConeStall : kQdmStall;
    float t = span.x;
    int steps = 0;
    for (int k = 0; k < p.maxSteps; ++k) {
        ++steps;
        float dt = reliefSafeStep(kind, map, ray.origin + t * d, horizontal, d.z, p);
        if (dt >= stall) {
            if (t + dt >= span.y)  // leaves the box without meeting S inside it
                return reliefHitIf(reliefExitsThroughFloor(ray, span.y, p), ray, span.y, steps, p);
            t += dt;
            continue;
        }
        // Exact: the cell the ray is in; cone tests it from t, qdm over its whole span.
        ReliefCellSpan cell = reliefCellAt(ray, t, span.y, p);
        vec2 range = kind == kReliefMarchCone ? vec2(t, cell.tb)
                                              : reliefQdmCellSpan(ray, cell.ci, cell.cj, span);
        float th = reliefFirstHitInCell(heights, ray, cell.ci, cell.cj, range.x, range.y, p);
        if (th <= range.y) return reliefHitAt(ray, th, steps, p);
        if (range.y >= span.y)
            return reliefHitIf(reliefExitsThroughFloor(ray, span.y, p), ray, span.y, steps, p);
        t = range.y > t ? range.y : cell.tb;
    }
    return reliefHitAt(ray, t, steps, p);  // capped: the last position, never past the first hit
}

// The view ray's march (descending only), and the shadow query on the same march: 1 = lit, 0 =
// S lies between the hit and the light, or a capped march proved nothing.
ReliefHit reliefSafeStepView(sampler2D heights, sampler2D map, int kind, vec2 uv,
                             vec3 viewDirTangent, ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    return reliefSafeStepMarch(heights, map, kind, ray, p);
}

float reliefSafeStepShadow(sampler2D heights, sampler2D map, int kind, ReliefHit hit,
                           vec3 lightDirTangent, ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    return reliefSafeStepMarch(heights, map, kind, ray, p).hit ? 0.0 : 1.0;
}
