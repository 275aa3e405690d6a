// The canonical surface S. Mirrors relief::Surface (src/relief/surface/surface.{h,cpp}):
// sampleZ, cellCorners, planesFromCorners, cellPlanes, heightAt, bilinearZ, clip, cellOfX/Y.
// The heights are Surface::paddedHeights(), (W+2)×(H+2) floats already scaled by D, in a storage
// buffer read exactly (no texture filtering), so GLSL and C++ see the same numbers.

layout(std430, binding = kHeightsBinding) readonly buffer Heights { float heights[]; };

int width() { return surfaceUniforms.size.x; }
int height() { return surfaceUniforms.size.y; }
float depth() { return surfaceUniforms.depth; }
float maxZ() { return surfaceUniforms.maxZ; }
int edge() { return surfaceUniforms.edge; }

// z = z0 + sx·u + sy·v over a cell's local coordinates.
struct CellPlane {
    float z0;
    float sx;
    float sy;
};
float at(CellPlane plane, float u, float v) {
    precise float z = plane.z0 + plane.sx * u + plane.sy * v;
    return z;
}

// S = max(first, second) over the cell.
struct CellPlanes {
    CellPlane first;
    CellPlane second;
};
float at(CellPlanes planes, float u, float v) {
    return max(at(planes.first, u, v), at(planes.second, u, v));
}

struct CellCorners {
    float z00;
    float z10;
    float z01;
    float z11;
};

CellPlanes planesFromCorners(CellCorners c) {
    if (c.z00 + c.z11 <= c.z10 + c.z01) {  // 00–11 is the lower diagonal (ties included)
        return CellPlanes(CellPlane(c.z00, c.z10 - c.z00, c.z11 - c.z10),
                          CellPlane(c.z00, c.z11 - c.z01, c.z01 - c.z00));
    }
    return CellPlanes(CellPlane(c.z00, c.z10 - c.z00, c.z01 - c.z00),
                      CellPlane(c.z10 + c.z01 - c.z11, c.z11 - c.z01, c.z11 - c.z10));
}

struct RayInterval {
    float tEnter;
    float tExit;
};
bool empty(RayInterval r) { return !(r.tEnter <= r.tExit); }

// GLSL's % is undefined for negative operands: wrap with non-negative ones only.
int wrapIndex(int i, int n) { return i >= 0 ? i % n : n - 1 - (-1 - i) % n; }

int wrapColumn(int i) {
    return edge() == kEdgeClamp ? clamp(i, -1, width()) : wrapIndex(i, width());
}
int wrapRow(int j) {
    return edge() == kEdgeClamp ? clamp(j, -1, height()) : wrapIndex(j, height());
}
int cellColumn(int ci) { return edge() == kEdgeClamp ? ci : wrapColumn(ci); }
int cellRow(int cj) { return edge() == kEdgeClamp ? cj : wrapRow(cj); }
int clampCellX(int ci) { return edge() == kEdgeClamp ? clamp(ci, -1, width() - 1) : ci; }
int clampCellY(int cj) { return edge() == kEdgeClamp ? clamp(cj, -1, height() - 1) : cj; }

int cellOfX(float x) { return clampCellX(int(floor(x - 0.5))); }
int cellOfY(float y) { return clampCellY(int(floor(y - 0.5))); }

float sampleZ(int i, int j) {
    return heights[(wrapRow(j) + 1) * (width() + 2) + wrapColumn(i) + 1];
}

CellCorners cellCorners(int ci, int cj) {
    const int stride = width() + 2;
    const int k = (cellRow(cj) + 1) * stride + cellColumn(ci) + 1;
    return CellCorners(heights[k], heights[k + 1], heights[k + stride], heights[k + stride + 1]);
}

CellPlanes cellPlanes(int ci, int cj) { return planesFromCorners(cellCorners(ci, cj)); }

float heightAt(float x, float y) {
    const int ci = cellOfX(x), cj = cellOfY(y);
    return at(cellPlanes(ci, cj), x - (float(ci) + 0.5), y - (float(cj) + 0.5));
}

float bilinearZ(float x, float y) {
    const int ci = cellOfX(x), cj = cellOfY(y);
    precise float u = clamp(x - (float(ci) + 0.5), 0.0, 1.0);
    precise float v = clamp(y - (float(cj) + 0.5), 0.0, 1.0);
    const CellCorners c = cellCorners(ci, cj);
    precise float z =
        (1.0 - v) * ((1.0 - u) * c.z00 + u * c.z10) + v * ((1.0 - u) * c.z01 + u * c.z11);
    return z;
}

// Intersects [lo, hi] with the slab [a, b] along one axis.
bool clipSlab(float origin, float direction, float a, float b, inout float lo, inout float hi) {
    if (direction == 0.0) return origin >= a && origin <= b;
    precise float inv = divide(1.0, direction);
    precise float t0 = (a - origin) * inv, t1 = (b - origin) * inv;
    if (t0 > t1) {
        const float swap = t0;
        t0 = t1;
        t1 = swap;
    }
    lo = max(lo, t0);
    hi = min(hi, t1);
    return lo <= hi;
}

RayInterval clip(Ray ray) {
    RayInterval r = RayInterval(0.0, ray.tMax);
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    if (max(max(abs(o.x), abs(o.y)), abs(o.z)) > kMaxOriginCoordinate) return RayInterval(0.0, -1.0);
    bool inside = clipSlab(o.z, d.z, 0.0, depth(), r.tEnter, r.tExit);
    if (edge() == kEdgeClamp) {
        inside = inside && clipSlab(o.x, d.x, 0.0, float(width()), r.tEnter, r.tExit) &&
                 clipSlab(o.y, d.y, 0.0, float(height()), r.tEnter, r.tExit);
    } else {
        precise float horizontal = squareRoot(d.x * d.x + d.y * d.y);
        precise float travel = kRepeatTravelFactor * float(max(width(), height()));
        precise float tTravel = divide(travel, horizontal);
        if (horizontal > 0.0) r.tExit = min(r.tExit, tTravel);
    }
    // Above the highest sample and rising: nothing can be hit.
    precise float tTop = divide(maxZ() - o.z, d.z);
    if (d.z > 0.0) r.tExit = min(r.tExit, max(r.tEnter, tTop));
    if (!inside) return RayInterval(0.0, -1.0);
    return r;
}
