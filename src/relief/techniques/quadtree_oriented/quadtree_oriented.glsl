// quadtree-oriented — GLSL twin of relief::QuadtreeOrientedTracer::trace (quadtree_oriented.h):
// walkPyramid with the Parent policy and OrientedBound (the flat max as a pre-test, then the
// node's plane, enterBelowPlane). Maps: "level0" (the flat pyramid's finest level) and
// "oriented1".. (c00, c10, c01, zmax per node).
// requires: common/pyramid_walk.glsl

float enterBelowPlane(float c00, float c10, float c01, float zmax, NodeBox b, WalkRay r, float t,
                      float tOut) {
    const float scale = divide(1.0, float(1 << b.level));  // kInverseSides
    precise float sx = (c10 - c00) * scale, sy = (c01 - c00) * scale;
    const vec3 p = at(r, t);
    const float x0 = float(b.baseX + b.loX) + 0.5, y0 = float(b.baseY + b.loY) + 0.5;
    precise float above = p.z - (c00 + sx * (p.x - x0) + sy * (p.y - y0)) - r.slack;
    if (above <= 0.0) return t;
    precise float rate = r.d.z - sx * r.d.x - sy * r.d.y;  // d(above)/dt
    if (rate >= 0.0) return kInfinity;
    precise float tPlane = t - divide(above, rate);
    if (tPlane > tOut) return kInfinity;
    precise float zPlane = r.o.z + tPlane * r.d.z;
    precise float top = zmax + r.slack;
    if (r.d.z > 0.0 && zPlane > top) return kInfinity;
    return tPlane;
}

// OrientedBound::enter.
float boundEnter(NodeBox b, WalkRay r, float t, float tOut) {
    if (b.level == 0) return maxBoundEnter(b, r, t, tOut, false);
    const int map = kMapOriented1 + b.level - 1;
    const float c00 = mapTexel(map, b.nx, b.ny, 0), c10 = mapTexel(map, b.nx, b.ny, 1);
    const float c01 = mapTexel(map, b.nx, b.ny, 2), zmax = mapTexel(map, b.nx, b.ny, 3);
    precise float top = zmax + r.slack;
    const float tIn = enterBelow(top, r, t, tOut);
    if (tIn > tOut) return tIn;
    return enterBelowPlane(c00, c10, c01, zmax, b, r, tIn, tOut);
}

Hit trace(Ray ray) {
    return walkPyramid(kAscentParent, ray, WalkLimits(paramInt(kParamMaxSteps), false));
}
