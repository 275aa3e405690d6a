// The marching of §5.2.2 shared by safety-sd and safety-cc — GLSL twin of
// relief::safety::SafetyTracer<Shape>::trace and its helpers (safety_common/safety_march.h): the
// same names, loops, steps and fetches. The Shape template argument becomes shapeStep, defined
// by the technique file after this one (DistanceShape::step, ConeShape::step).
// Departures: rays outside φ_max (or, with exterior maps, from inside the box) are not counted (fallbacks() is a CPU statistic), and the φ_max
// test uses a float tan of the maps' "phi-max" (the C++ a double one): a ray within rounding of
// that bound may take the exact walk on one side only, with the same hit and other step counts.
// requires: surface/cell_walk.glsl

int shapeStep(int cls, int i, int j, float z, float slope);

struct Walk {
    int axis, sign, cls, k0, count;
    float oA, oB, dB, invA, rise, tEnter, tExit;
};

float tOf(Walk w, int n) {
    precise float t = (float(w.k0 + w.sign * n) - w.oA) * w.invA;
    return clamp(t, w.tEnter, w.tExit);
}

// rayWithinPhiMax with the maps' φ_max.
bool rayWithinPhiMax(vec3 d) {
    if (kMapParamPhiMax >= 90.0) return true;
    const double tanPhi = double(tan(radians(kMapParamPhiMax)));
    precise double horizontal = sqrt(double(d.x) * double(d.x) + double(d.y) * double(d.y));
    precise double bound = (tanPhi - 1e-6LF) * horizontal;
    return double(d.z) <= bound;
}

// originIsExterior: exterior-ray maps ("exterior" = 1) serve rays from outside the open box or
// from above the highest sample; other origins take the exact walk.
bool originServed(vec3 o) {
#ifdef HAS_kMapParamExterior
    if (kMapParamExterior == 0.0) return true;
#else
    return true;  // maps baked before exterior-ray maps existed are all-ray maps
#endif
    return o.z >= maxZ() || o.z <= 0.0 || o.x <= 0.0 || o.y <= 0.0 || o.x >= float(width()) ||
           o.y >= float(height());
}

float safetyMargin() {
    precise float margin = 1e-4 * (1.0 + maxZ());
    return margin;
}

float sampleAB(int axis, int a, int b) { return axis == 0 ? sampleZ(a, b) : sampleZ(b, a); }

float aboveAt(Ray ray, Walk w, int n, inout Hit hit) {
    const float t = tOf(w, n);
    precise float b = w.oB + t * w.dB;
    const float fb = floor(b);
    const int a = w.k0 + w.sign * n, ib = int(fb);
    const float z0 = sampleAB(w.axis, a, ib), z1 = sampleAB(w.axis, a, ib + 1);
    hit.fetches += 2;
    precise float above = ray.origin.z + t * ray.direction.z - (z0 + (b - fb) * (z1 - z0));
    return above;
}

int fetchStep(Ray ray, Walk w, int n, inout Hit hit) {
    const float t = tOf(w, n);
    int a = w.k0 + w.sign * n;
    precise float bCentre = w.oB + t * w.dB + 0.5;
    int b = int(floor(bCentre));
    const int lenA = w.axis == 0 ? width() : height();
    const int lenB = w.axis == 0 ? height() : width();
    if (edge() == kEdgeRepeat) {
        a = wrapIndex(a, lenA);
        b = wrapIndex(b, lenB);
    } else {
        a = clamp(a, 0, lenA - 1);
        b = clamp(b, 0, lenB - 1);
    }
    ++hit.fetches;
    precise float z = ray.origin.z + t * ray.direction.z;
    const int step = w.axis == 0 ? shapeStep(w.cls, a, b, z, w.rise)
                                 : shapeStep(w.cls, b, a, z, w.rise);
    return paramInt(kParamPositiveDistance) != 0 ? max(step, 1) : step;
}

bool linearHit(Ray ray, Walk w, int lo, int hi, inout Hit hit) {
    const float ta = tOf(w, lo), tb = tOf(w, hi);
    const float za = aboveAt(ray, w, lo, hit), zb = aboveAt(ray, w, hi, hit);
    float t0 = ta, z0 = za, t1 = tb, z1 = zb;
    precise float ba = w.oB + ta * w.dB, bb = w.oB + tb * w.dB;
    if (floor(ba) != floor(bb)) {  // crosses a centerline of the other family
        const float c = max(floor(ba), floor(bb));
        const float tc = clamp(divide(c - w.oB, w.dB), min(ta, tb), max(ta, tb));
        precise float a = (w.axis == 0 ? ray.origin.x : ray.origin.y) - 0.5 +
                          tc * (w.axis == 0 ? ray.direction.x : ray.direction.y);
        const float fa = floor(a);
        const float s0 = sampleAB(w.axis, int(fa), int(c));
        const float s1 = sampleAB(w.axis, int(fa) + 1, int(c));
        hit.fetches += 2;
        precise float zc = ray.origin.z + tc * ray.direction.z - (s0 + (a - fa) * (s1 - s0));
        if (zc <= 0.0) {
            t1 = tc;
            z1 = zc;
        } else {
            t0 = tc;
            z0 = zc;
        }
    }
    if (z0 <= 0.0) {
        setHit(ray, t0, hit);
        return true;
    }
    if (z1 > 0.0) return false;
    precise float t = t0 + (t1 - t0) * divide(z0, z0 - z1);
    setHit(ray, t, hit);
    return true;
}

bool finalHit(Ray ray, Walk w, int lo, int hi, inout Hit hit) {
    if (paramInt(kParamViewDependent) != 0) return linearHit(ray, w, lo, hi, hit);
    return cellsHit(ray, tOf(w, lo), tOf(w, hi), false, hit);
}

Hit safetyTrace(Ray ray) {
    Hit hit = noHit();
    const RayInterval span = clip(ray);
    if (empty(span)) return hit;
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    if (!rayWithinPhiMax(d) || !originServed(o)) {
        cellsHit(ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    Walk w;
    w.axis = abs(d.x) >= abs(d.y) ? 0 : 1;
    const float dA = w.axis == 0 ? d.x : d.y;
    w.sign = dA > 0.0 ? 1 : -1;
    w.cls = 2 * w.axis + (w.sign < 0 ? 1 : 0);
    w.oA = (w.axis == 0 ? o.x : o.y) - 0.5;
    w.oB = (w.axis == 0 ? o.y : o.x) - 0.5;
    w.dB = w.axis == 0 ? d.y : d.x;
    w.invA = divide(1.0, dA);
    precise float rise = d.z * abs(w.invA);
    w.rise = rise;
    w.tEnter = span.tEnter;
    w.tExit = span.tExit;
    precise float aEnter = w.oA + span.tEnter * dA, aExit = w.oA + span.tExit * dA;
    const bool nearVertical = dA == 0.0 || isinf(aEnter) || isnan(aEnter) || isinf(aExit) || isnan(aExit);
    w.k0 = 0;
    w.count = 0;
    if (!nearVertical) {
        w.k0 = int(w.sign > 0 ? ceil(aEnter) : floor(aEnter));
        const int kL = int(w.sign > 0 ? floor(aExit) : ceil(aExit));
        w.count = (kL - w.k0) * w.sign;
    }
    if (nearVertical || w.count < kMinCenterlines) {  // near-vertical: a handful of cells
        cellsHit(ray, span.tEnter, span.tExit, true, hit);
        return hit;
    }
    if (cellsHit(ray, span.tEnter, tOf(w, 0), false, hit)) return hit;  // up to the first one
    const int maxSteps = paramInt(kParamMaxSteps);
    const bool viewDependent = paramInt(kParamViewDependent) != 0;
    const float margin = safetyMargin();
    int n = 0;
    while (n < w.count) {
        if (maxSteps > 0 && hit.steps >= maxSteps) {
            setHit(ray, tOf(w, n), hit);  // approximate: the cursor
            return hit;
        }
        const int step = fetchStep(ray, w, n, hit);
        if (step == 0) {  // the naive step, the other family's crossing tested exactly
            if (viewDependent ? linearHit(ray, w, n, n + 1, hit)
                              : cellsHit(ray, tOf(w, n), tOf(w, n + 1), false, hit))
                return hit;
            ++n;
            continue;
        }
        ++hit.steps;
        const int m = min(n + min(step, kFarStep), w.count);
        if (aboveAt(ray, w, m, hit) > margin) {
            n = m;
            continue;
        }
        int lo = n, hi = m;
        while (hi - lo > 1) {
            ++hit.steps;
            const int mid = lo + (hi - lo) / 2;
            if (aboveAt(ray, w, mid, hit) > margin) lo = mid; else hi = mid;
        }
        if (finalHit(ray, w, lo, hi, hit)) return hit;
        n = hi;  // a false alarm within the margin: above S there after all
    }
    cellsHit(ray, tOf(w, w.count), span.tExit, true, hit);  // from the last centerline to the exit
    return hit;
}
