// The cell cursor of the map-stepping tracers' exact parts (cone, relaxed-cone, qdm) — GLSL twin
// of cellAt, exitsThroughFloor and hitAt in src/relief/surface/cell_cursor.h: the cell a ray is
// in at t and where it leaves it, whether leaving the box is a floor hit, and a Hit at t. A
// shader names it on a `// requires: surface/cell_cursor.glsl` line.

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
