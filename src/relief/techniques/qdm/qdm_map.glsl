// The quadratic displacement map — GLSL twin of relief::QdmMap (qdm_map.h): the map array "qdm"
// (4 channels a, b, c, h per texel, float32), QdmMap::at and reach, qdmProfile, parabolaStep,
// and of quadricStep and referenceSpan (qdm.h); the exact parts' cell cursor is
// surface/cell_cursor.glsl (shared with cone and relaxed-cone).
// requires: surface/cell_cursor.glsl

struct QdmTexel {
    float a;
    float b;
    float c;
    float h;
};

// QdmMap::at: the entry of the texel whose footprint holds (x, y), nearest texel.
int qdmWrap(int i, int n) { return edge() == kEdgeClamp ? clamp(i, 0, n - 1) : wrapIndex(i, n); }

QdmTexel qdmAt(float x, float y) {
    const int i = qdmWrap(int(floor(x)), kMapWidth[kMapQdm]);
    const int j = qdmWrap(int(floor(y)), kMapHeight[kMapQdm]);
    return QdmTexel(mapTexel(kMapQdm, i, j, 0), mapTexel(kMapQdm, i, j, 1),
                    mapTexel(kMapQdm, i, j, 2), mapTexel(kMapQdm, i, j, 3));
}

// qdmProfile: f(x), nondecreasing; the parabola's top beyond c.
float qdmProfile(QdmTexel q, float x) {
    if (x <= q.a) {
        if (!(q.a > 0.0)) return 0.0;
        precise float bx = q.b * x;
        return divide(bx, q.a);
    }
    const float nearest = q.c < x ? q.c : x;  // std::min(x, q.c)
    precise float u = nearest - q.a;
    precise float f = q.b + u * (2.0 * (q.c - q.a) - u);
    return f;
}

// QdmMap::reach: kInfinity when the profile clears the highest point of S at max-distance.
float qdmReach(QdmTexel q) {
    const float maxDistance = kMapParamMaxDistance > 0.0 ? kMapParamMaxDistance : kInfinity;
    if (maxDistance == kInfinity) return kInfinity;
    precise float room = maxZ() - q.h;
    if (qdmProfile(q, maxDistance) >= room) return kInfinity;
    return maxDistance;
}

// parabolaStep (Algorithm 2 from the junction on, as qdm_map.h says why).
float parabolaStep(QdmTexel q, float h0, float horizontal, float dz) {
    if (!(horizontal > 0.0)) return kInfinity;
    const float tJunction = divide(q.a, horizontal);
    precise float above = h0 + dz * tJunction - q.b;
    if (!(above > 0.0)) return tJunction;
    precise float halfB = 0.5 * dz - (q.c - q.a) * horizontal;
    if (halfB >= 0.0) return kInfinity;
    precise float A = horizontal * horizontal;
    precise float disc = halfB * halfB - A * above;
    if (disc < 0.0) return kInfinity;
    precise float denominator = -halfB + squareRoot(disc);
    precise float t = tJunction + divide(above, denominator);
    return t;
}

// quadricStep: the largest dt the profile of an apex at height q.h allows from height z.
float quadricStep(QdmTexel q, float z, float horizontal, float dz, float reach) {
    precise float h0 = z - q.h;
    const float slope = q.a > 0.0 ? divide(q.b, q.a) : 0.0;
    precise float closing = slope * horizontal - dz;
    const float tLine = closing > 0.0 ? divide(h0, closing) : kInfinity;
    float dt;
    precise float lineTravel = tLine * horizontal;
    if (lineTravel <= q.a) {
        dt = tLine;  // the line segment (alpha ≤ 1)
    } else {
        dt = parabolaStep(q, h0, horizontal, dz);
        precise float travel = dt * horizontal;
        if (!(travel <= q.c)) {  // past the top: the flat part
            precise float top = q.b + (q.c - q.a) * (q.c - q.a);
            precise float rise = top - h0;
            dt = dz < 0.0 ? divide(rise, dz) : kInfinity;
        }
    }
    if (!(horizontal > 0.0)) return dt;
    const float reachT = divide(reach, horizontal);
    return reachT < dt ? reachT : dt;  // std::min(dt, reachT)
}

// referenceSpan's boundary: cell edges times 1/d, as ExactTracer computes them.
float qdmBoundary(int cell, float o, float d, bool entering) {
    if (d == 0.0) return entering ? -kInfinity : kInfinity;
    const float inverse = divide(1.0, d);
    precise float b = (float(cell) + ((d > 0.0) != entering ? 1.5 : 0.5) - o) * inverse;
    return b;
}

// referenceSpan: [ta, tb] of cell (ci, cj) along the ray (std::max / std::min of lists: the
// first extreme in order).
vec2 referenceSpan(Ray ray, int ci, int cj, RayInterval span) {
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    float ta = span.tEnter;
    const float ax = qdmBoundary(ci, o.x, d.x, true);
    if (ta < ax) ta = ax;
    const float ay = qdmBoundary(cj, o.y, d.y, true);
    if (ta < ay) ta = ay;
    float tb = qdmBoundary(ci, o.x, d.x, false);
    const float by = qdmBoundary(cj, o.y, d.y, false);
    if (by < tb) tb = by;
    if (span.tExit < tb) tb = span.tExit;
    return vec2(ta, ta < tb ? tb : ta);  // {ta, std::max(ta, tb)}
}
