// The centerline march of safety-sd and safety-cc (precomputed safety shapes, Baboud, Eisemann &
// Seidel 2011 §5.2.2). Port of relief::safety::SafetyTracer<Shape>::trace
// (src/relief/techniques/safety_common/safety_march.h): the ray walks the centerlines of its
// major axis, jumping by the safety distance of the shape at the texel it is over, bisects a
// jump that ends below S, and finishes with the exact cell walk; rays outside φ_max (or, with
// exterior maps, from inside the box) take the exact cell walk all the way. The Shape template
// argument becomes `kind` (DistanceShape: safety-sd, ConeShape: safety-cc) and its maps the
// samplers m0..m3 (the four ray classes' cones; safety-sd's one distance map in m0).
// requires: common.glsl

const int kMinCenterlines = 3;   // safety_march.h: fewer centerlines take the exact walk
const int kFarStep = 1048576;    // safety_march.h: a step that leaves every map

// ---- The centerline march (SafetyTracer<ConeShape>::trace) ----

struct ReliefWalk {
    int axis, sign, cls, k0, count;
    float oA, oB, dB, invA, rise, tEnter, tExit;
};

float reliefWalkT(ReliefWalk w, int n) {
    return clamp((float(w.k0 + w.sign * n) - w.oA) * w.invA, w.tEnter, w.tExit);
}

float reliefSampleAB(sampler2D heights, int axis, int a, int b, ReliefParams p) {
    return axis == 0 ? reliefSampleZ(heights, a, b, p) : reliefSampleZ(heights, b, a, p);
}

// How far the ray is above S on centerline n (S linear along the centerline there).
float reliefAboveAt(sampler2D heights, ReliefRay ray, ReliefWalk w, int n, ReliefParams p) {
    float t = reliefWalkT(w, n);
    float b = w.oB + t * w.dB;
    float fb = floor(b);
    int a = w.k0 + w.sign * n, ib = int(fb);
    float z0 = reliefSampleAB(heights, w.axis, a, ib, p);
    float z1 = reliefSampleAB(heights, w.axis, a, ib + 1, p);
    return ray.origin.z + t * ray.direction.z - (z0 + (b - fb) * (z1 - z0));
}

const int kReliefSafetySd = 0;  // DistanceShape: m0 = "sd"
const int kReliefSafetyCc = 1;  // ConeShape: m0..m3 = "ccx+", "ccx-", "ccy+", "ccy-"

// ConeShape::step at a texel of the ray's class: i = max(r, ⌊max(z − z0, 0) / (s_c − s)⌋).
int reliefConeShapeStep(vec3 cc, float z, float slope) {
    float r = cc.x, z0 = cc.y - cc.x * cc.z;  // as coneMapFromArrays
    float above = z - z0;
    if (above <= 0.0) return int(r);
    float closing = cc.z - slope;
    if (closing <= 0.0) return kFarStep;  // the ray rises at least as fast as the cone
    return max(int(r), int(min(above / closing, float(kFarStep))));
}

// Shape::step at centerline n: the distance to jump (in centerlines).
int reliefSafetyStep(sampler2D m0, sampler2D m1, sampler2D m2, sampler2D m3, int kind,
                     ReliefRay ray, ReliefWalk w, int n, ReliefParams p) {
    float t = reliefWalkT(w, n);
    int a = w.k0 + w.sign * n, b = int(floor(w.oB + t * w.dB + 0.5));
    ivec2 texel = reliefSampleIndex(w.axis == 0 ? a : b, w.axis == 0 ? b : a, p);
    int step;
    if (kind == kReliefSafetySd) {  // DistanceShape: the stored distance of the ray's class
        vec4 e = texelFetch(m0, texel, 0);
        step = int(p.isotropic != 0 ? e.x : e[w.cls]);
    } else {
        vec3 cc = w.cls == 0   ? texelFetch(m0, texel, 0).rgb
                  : w.cls == 1 ? texelFetch(m1, texel, 0).rgb
                  : w.cls == 2 ? texelFetch(m2, texel, 0).rgb
                               : texelFetch(m3, texel, 0).rgb;
        step = reliefConeShapeStep(cc, ray.origin.z + t * ray.direction.z, w.rise);
    }
    return p.positiveDistance != 0 ? max(step, 1) : step;
}

// View-dependent form (§7): S linear along the ray between centerlines lo and hi.
bool reliefLinearHit(sampler2D heights, ReliefRay ray, ReliefWalk w, int lo, int hi,
                     out float tHit, ReliefParams p) {
    float ta = reliefWalkT(w, lo), tb = reliefWalkT(w, hi);
    float t0 = ta, z0 = reliefAboveAt(heights, ray, w, lo, p);
    float t1 = tb, z1 = reliefAboveAt(heights, ray, w, hi, p);
    float ba = w.oB + ta * w.dB, bb = w.oB + tb * w.dB;
    if (floor(ba) != floor(bb)) {  // crosses a centerline of the other family
        float c = max(floor(ba), floor(bb));
        float tc = clamp((c - w.oB) / w.dB, min(ta, tb), max(ta, tb));
        float a = (w.axis == 0 ? ray.origin.x : ray.origin.y) - 0.5 +
                  tc * (w.axis == 0 ? ray.direction.x : ray.direction.y);
        float fa = floor(a);
        float s0 = reliefSampleAB(heights, w.axis, int(fa), int(c), p);
        float s1 = reliefSampleAB(heights, w.axis, int(fa) + 1, int(c), p);
        float zc = ray.origin.z + tc * ray.direction.z - (s0 + (a - fa) * (s1 - s0));
        if (zc <= 0.0) {
            t1 = tc;
            z1 = zc;
        } else {
            t0 = tc;
            z0 = zc;
        }
    }
    tHit = t0;
    if (z0 <= 0.0) return true;
    if (z1 > 0.0) return false;
    tHit = t0 + (t1 - t0) * (z0 / (z0 - z1));
    return true;
}

bool reliefSafetySpan(sampler2D heights, ReliefRay ray, ReliefWalk w, int lo, int hi,
                      out float tHit, inout int steps, ReliefParams p) {
    if (p.viewDependent != 0) return reliefLinearHit(heights, ray, w, lo, hi, tHit, p);
    return reliefCellsHit(heights, ray, reliefWalkT(w, lo), reliefWalkT(w, hi), false, tHit, steps,
                          p);
}

// The first hit of a texel-space ray (any direction).
ReliefHit reliefSafetyTrace(sampler2D heights, sampler2D m0, sampler2D m1, sampler2D m2,
                            sampler2D m3, int kind, ReliefRay ray, ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    vec3 o = ray.origin, d = ray.direction;
    float tHit;
    int steps = 0;
    // rayWithinPhiMax (a hair stricter than the build) and originIsExterior.
    bool withinPhi = p.phiMax >= 90.0 ||
                     d.z <= (tan(radians(p.phiMax)) - 1e-6) * sqrt(d.x * d.x + d.y * d.y);
    bool served = p.exterior == 0 || o.z >= p.maxZ || o.z <= 0.0 || o.x <= 0.0 || o.y <= 0.0 ||
                  o.x >= p.mapSize.x || o.y >= p.mapSize.y;
    if (!withinPhi || !served) {
        bool hit = reliefCellsHit(heights, ray, span.x, span.y, true, tHit, steps, p);
        return reliefHitIf(hit, ray, tHit, steps, p);
    }
    ReliefWalk w;
    w.axis = abs(d.x) >= abs(d.y) ? 0 : 1;
    float dA = w.axis == 0 ? d.x : d.y;
    w.sign = dA > 0.0 ? 1 : -1;
    w.cls = 2 * w.axis + (w.sign < 0 ? 1 : 0);
    w.oA = (w.axis == 0 ? o.x : o.y) - 0.5;
    w.oB = (w.axis == 0 ? o.y : o.x) - 0.5;
    w.dB = w.axis == 0 ? d.y : d.x;
    w.invA = 1.0 / dA;
    w.rise = d.z * abs(w.invA);
    w.tEnter = span.x;
    w.tExit = span.y;
    float aEnter = w.oA + span.x * dA, aExit = w.oA + span.y * dA;
    bool nearVertical = dA == 0.0 || isinf(aEnter) || isnan(aEnter) || isinf(aExit) || isnan(aExit);
    w.k0 = 0;
    w.count = 0;
    if (!nearVertical) {
        w.k0 = int(w.sign > 0 ? ceil(aEnter) : floor(aEnter));
        int kL = int(w.sign > 0 ? floor(aExit) : ceil(aExit));
        w.count = (kL - w.k0) * w.sign;
    }
    if (nearVertical || w.count < kMinCenterlines) {  // near-vertical: a handful of cells
        bool hit = reliefCellsHit(heights, ray, span.x, span.y, true, tHit, steps, p);
        return reliefHitIf(hit, ray, tHit, steps, p);
    }
    if (reliefCellsHit(heights, ray, span.x, reliefWalkT(w, 0), false, tHit, steps, p))
        return reliefHitAt(ray, tHit, steps, p);  // up to the first centerline
    float margin = 1e-4 * (1.0 + p.maxZ);
    int cap = p.maxSteps > 0 ? p.maxSteps : kReliefCellGuard;
    int n = 0;
    for (int guard = 0; guard < kReliefCellGuard && n < w.count; ++guard) {
        if (steps >= cap) return reliefHitAt(ray, reliefWalkT(w, n), steps, p);  // the cursor
        int step = reliefSafetyStep(m0, m1, m2, m3, kind, ray, w, n, p);
        if (step == 0) {  // the naive step, the other family's crossing tested exactly
            if (reliefSafetySpan(heights, ray, w, n, n + 1, tHit, steps, p))
                return reliefHitAt(ray, tHit, steps, p);
            ++n;
            continue;
        }
        ++steps;
        int m = min(n + min(step, kFarStep), w.count);
        if (reliefAboveAt(heights, ray, w, m, p) > margin) {
            n = m;
            continue;
        }
        int lo = n, hi = m;
        for (int k = 0; k < 32 && hi - lo > 1; ++k) {
            ++steps;
            int mid = lo + (hi - lo) / 2;
            if (reliefAboveAt(heights, ray, w, mid, p) > margin) lo = mid; else hi = mid;
        }
        if (reliefSafetySpan(heights, ray, w, lo, hi, tHit, steps, p))
            return reliefHitAt(ray, tHit, steps, p);
        n = hi;  // a false alarm within the margin: above S there after all
    }
    // From the last centerline to the exit.
    bool hit = reliefCellsHit(heights, ray, reliefWalkT(w, w.count), span.y, true, tHit, steps, p);
    return reliefHitIf(hit, ray, tHit, steps, p);
}

// The view ray's march (descending only), and the shadow query on the same march.
ReliefHit reliefSafetyView(sampler2D heights, sampler2D m0, sampler2D m1, sampler2D m2,
                           sampler2D m3, int kind, vec2 uv, vec3 viewDirTangent, ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    return reliefSafetyTrace(heights, m0, m1, m2, m3, kind, ray, p);
}

float reliefSafetyShadowQuery(sampler2D heights, sampler2D m0, sampler2D m1, sampler2D m2,
                              sampler2D m3, int kind, ReliefHit hit, vec3 lightDirTangent,
                              ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    return reliefSafetyTrace(heights, m0, m1, m2, m3, kind, ray, p).hit ? 0.0 : 1.0;
}
