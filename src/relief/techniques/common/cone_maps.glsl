// The cone map shared by cone and relaxed-cone — GLSL twin of relief::ConeMap::at and
// decodeCones (common/cone_maps.{h,cpp}): the map array "cones" (2 channels, a and c), decoded
// per fetch exactly as decodeCones decodes it once (bits and sqrt are the technique's
// parameters, cMax the map's "cone-max"); the exact parts' cell cursor is surface/cell_cursor.glsl.
// requires: surface/cell_cursor.glsl

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
