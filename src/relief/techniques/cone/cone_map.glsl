// The cone map shared by cone and relaxed-cone — GLSL twin of relief::ConeMap::at and
// decodeCones (cone/cone_common.{h,cpp}): the map array "cones" (2 channels, a and c), decoded
// per fetch exactly as decodeCones decodes it once (bits and sqrt are the technique's
// parameters, cMax the map's "cone-max"), and the cell cursor of the exact parts (cellAt).

// ConeMap::at: the entry of the texel whose footprint holds (x, y), nearest texel.
int coneWrap(int i, int n) { return edge() == kEdgeClamp ? clamp(i, 0, n - 1) : wrapIndex(i, n); }

vec2 coneAt(float x, float y) {
    const int i = coneWrap(int(floor(x)), kMapWidth[kMapCones]);
    const int j = coneWrap(int(floor(y)), kMapHeight[kMapCones]);
    float a = mapTexel(kMapCones, i, j, 0), r = mapTexel(kMapCones, i, j, 1);
    if (paramInt(kParamBits) < 32) {
        precise float decoded = a * depth() * (1.0 + kConeDecodeMargin);
        a = decoded;
    }
    if (paramInt(kParamSqrt) != 0) {
        precise float squared = r * r;
        r = squared;
    }
    precise float c = r * kMapParamConeMax * (1.0 - kConeDecodeMargin);
    return vec2(a, c);
}

// coneStep: the largest dt that keeps the ray in the frustum of (a, c) from height z.
float coneStep(float z, float a, float c, float horizontal, float dz) {
    precise float room = c * (z - a);
    precise float closing = horizontal - c * dz;
    if (closing <= 0.0) return room >= 0.0 ? kInfinity : 0.0;
    return divide(room, closing);
}

struct CellSpan {
    int ci, cj;
    float tb;
};

float exitAlong(int cell, float origin, float dir) {
    if (dir == 0.0) return kInfinity;
    precise float distance = float(cell) + (dir > 0.0 ? 1.5 : 0.5) - origin;
    return divide(distance, dir);
}

CellSpan cellAt(Ray ray, float t, float tEnd) {
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    const vec3 p = at(ray, t);
    precise float px = p.x - 0.5, py = p.y - 0.5;
    int ci = int(floor(px)), cj = int(floor(py));
    float tx = exitAlong(ci, o.x, d.x), ty = exitAlong(cj, o.y, d.y);
    if (tx <= t) {  // on the edge: move on
        ci += d.x > 0.0 ? 1 : -1;
        tx = exitAlong(ci, o.x, d.x);
    }
    if (ty <= t) {
        cj += d.y > 0.0 ? 1 : -1;
        ty = exitAlong(cj, o.y, d.y);
    }
    if (edge() == kEdgeClamp) {
        ci = clamp(ci, -1, width() - 1);
        cj = clamp(cj, -1, height() - 1);
    }
    return CellSpan(ci, cj, max(t, min(min(tx, ty), tEnd)));
}

bool exitsThroughFloor(Ray ray, float tExit) {
    precise float zExit = ray.origin.z + tExit * ray.direction.z;
    precise float zRounding = 4.0 * kFloatEpsilon * (abs(ray.origin.z) + depth());
    return ray.direction.z < 0.0 && zExit <= zRounding;
}

Hit hitAt(Ray ray, float t, Hit hit) {
    hit.hit = true;
    hit.t = t;
    hit.position = at(ray, t);
    return hit;
}
