// The pyramid walk shared by quadtree, maxmip and quadtree-oriented — GLSL twin of
// src/relief/techniques/common/pyramid_walk.h (walkPyramid and its helpers): the same names,
// the same loop, the same step and fetch counts. The C++ template arguments become arguments
// (the Ascent policy, kAscent*) and a function the technique file defines after this one
// (boundEnter: the bound of its node, MaxBound::enter being maxBoundEnter here).
// The max pyramid is the map arrays "level0".. (max_pyramid_maps.cpp): kMapLevel0 + level.
// Departure: the loop has a cap that valid rays never reach (a NaN ray must not hang the GPU).

struct PyramidLayout {
    int cellsX;
    int cellsY;
    int firstCell;
    int levels;
    bool repeat;
};

PyramidLayout pyramidLayout() {  // PyramidLayout::of
    PyramidLayout pyramid;
    pyramid.repeat = edge() == kEdgeRepeat;
    pyramid.firstCell = pyramid.repeat ? 0 : -1;
    pyramid.cellsX = width() + (pyramid.repeat ? 0 : 1);
    pyramid.cellsY = height() + (pyramid.repeat ? 0 : 1);
    const int largest = max(pyramid.cellsX, pyramid.cellsY);
    pyramid.levels = findMSB(largest - 1) + 2;  // bit_width(largest - 1) + 1
    return pyramid;
}
int widthAt(PyramidLayout pyramid, int level) { return ((pyramid.cellsX - 1) >> level) + 1; }
int heightAt(PyramidLayout pyramid, int level) { return ((pyramid.cellsY - 1) >> level) + 1; }
int topLevel(PyramidLayout pyramid) { return pyramid.levels - 1; }

struct WalkLimits {
    int maxSteps;
    bool boxSurface;
};

struct WalkRay {
    vec3 o;
    vec3 d;
    float invX, invY, invZ;
    int stepX, stepY;
    float tEnter, tExit;
    int exitMaskX, exitMaskY;  // a node's exit side: high (-1) or low (0)
    float slack;
    float depth;
};

vec3 at(WalkRay r, float t) {
    precise vec3 p = r.o + t * r.d;
    return p;
}

struct WalkCursor {
    float t;
    int level;
    int px, py;
    int baseX, baseY;
};

struct NodeBox {
    int level, nx, ny;
    int loX, hiX, loY, hiY;
    int baseX, baseY;
};

struct NodeExit {
    float tx, ty, t;
};

WalkRay makeWalkRay(Ray ray, RayInterval span) {
    const vec3 o = ray.origin;
    const vec3 d = ray.direction;
    precise float extent = abs(o.x) + abs(o.y) + abs(o.z) + span.tExit + depth();
    precise float slack = kWalkSlack * extent;
    return WalkRay(o, d, divide(1.0, d.x), divide(1.0, d.y), divide(1.0, d.z),
                   d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0), d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0),
                   span.tEnter, span.tExit, d.x > 0.0 ? -1 : 0, d.y > 0.0 ? -1 : 0, slack, depth());
}

float boundaryT(int edgeCell, float origin, float inverse) {
    precise float t = (float(edgeCell) + 0.5 - origin) * inverse;
    return t;
}

// startCell and startCursor (pyramid_walk.h): the cell at t, one further along the ray where
// `ahead`; the root or the smallest node over the cells where the ray enters and leaves the box.
struct StartCell {
    int px, py, baseX, baseY;
};
StartCell startCell(PyramidLayout pyramid, WalkRay r, float t, bool ahead) {
    const vec3 p = at(r, t);
    int ci = cellOfX(p.x), cj = cellOfY(p.y);
    if (ahead) {
        ci += r.stepX;
        cj += r.stepY;
    }
    if (pyramid.repeat) {
        const int px = wrapIndex(ci, pyramid.cellsX);  // floorMod (GLSL's % is undefined below 0)
        const int py = wrapIndex(cj, pyramid.cellsY);
        return StartCell(px, py, ci - px, cj - py);
    }
    return StartCell(clamp(ci - pyramid.firstCell, 0, pyramid.cellsX - 1),
                     clamp(cj - pyramid.firstCell, 0, pyramid.cellsY - 1), pyramid.firstCell,
                     pyramid.firstCell);
}

WalkCursor startCursor(PyramidLayout pyramid, WalkRay r, bool fromRoot) {
    const StartCell entry = startCell(pyramid, r, r.tEnter, false);
    WalkCursor c = WalkCursor(r.tEnter, topLevel(pyramid), entry.px, entry.py, entry.baseX,
                              entry.baseY);
    if (!fromRoot) {
        const StartCell leave = startCell(pyramid, r, r.tExit, true);
        if (leave.baseX == entry.baseX && leave.baseY == entry.baseY)
            c.level = min(c.level, findMSB((entry.px ^ leave.px) | (entry.py ^ leave.py)) + 1);
    }
    return c;
}

NodeBox nodeBox(PyramidLayout pyramid, WalkCursor c) {
    NodeBox b;
    b.level = c.level;
    b.nx = c.px >> c.level;
    b.ny = c.py >> c.level;
    b.loX = b.nx << c.level;
    b.loY = b.ny << c.level;
    b.hiX = min(b.loX + (1 << c.level), pyramid.cellsX);
    b.hiY = min(b.loY + (1 << c.level), pyramid.cellsY);
    b.baseX = c.baseX;
    b.baseY = c.baseY;
    return b;
}

NodeExit nodeExit(WalkRay r, NodeBox b, WalkCursor c) {
    const int edgeX = c.baseX + b.loX + ((b.hiX - b.loX) & r.exitMaskX);
    const int edgeY = c.baseY + b.loY + ((b.hiY - b.loY) & r.exitMaskY);
    const float tx = r.stepX != 0 ? boundaryT(edgeX, r.o.x, r.invX) : kInfinity;
    const float ty = r.stepY != 0 ? boundaryT(edgeY, r.o.y, r.invY) : kInfinity;
    return NodeExit(tx, ty, max(c.t, min(min(tx, ty), r.tExit)));
}

// First t in [t, tOut] where the ray is at or below height `top`, or kInfinity.
float enterBelow(float top, WalkRay r, float t, float tOut) {
    if (r.d.z < 0.0) {
        precise float zOut = r.o.z + tOut * r.d.z;
        if (zOut > top) return kInfinity;
        precise float tTop = (top - r.o.z) * r.invZ;
        return clamp(tTop, t, tOut);
    }
    precise float z = r.o.z + t * r.d.z;
    return z <= top ? t : kInfinity;
}

// MaxBound::enter: the node's maximum (one fetch); `codes`: stored as bits 16 / 8 codes of D,
// decoded as decodePyramidCode (max_pyramid.h) decodes them once.
float maxBoundEnter(NodeBox b, WalkRay r, float t, float tOut, bool codes) {
    precise float stored = mapTexel(kMapLevel0 + b.level, b.nx, b.ny, 0);
    precise float decoded = stored * r.depth * (1.0 + kPyramidDecodeMargin);
    precise float top = (codes ? decoded : stored) + r.slack;
    return enterBelow(top, r, t, tOut);
}

// Defined by the technique file: the first t in [t, tOut] where the ray may be on or below S in
// the node (> tOut: none), one fetch.
float boundEnter(NodeBox b, WalkRay r, float t, float tOut);

Hit makeHit(Ray ray, float t, int steps, int fetches) {
    return Hit(true, t, at(ray, t), steps, fetches);
}

Hit makeMiss(int steps, int fetches) { return Hit(false, kInfinity, vec3(0.0), steps, fetches); }

bool leavesThroughFloor(WalkRay r) {
    precise float zExit = r.o.z + r.tExit * r.d.z;
    precise float zRounding = 4.0 * kFloatEpsilon * (abs(r.o.z) + r.depth);
    return r.d.z < 0.0 && zExit <= zRounding;
}

float leafHit(Ray ray, WalkRay r, WalkCursor c) {
    const int ci = c.baseX + c.px, cj = c.baseY + c.py;
    float ta = r.tEnter, tb = r.tExit;
    if (r.stepX != 0) {
        ta = max(ta, boundaryT(r.stepX > 0 ? ci : ci + 1, r.o.x, r.invX));
        tb = min(tb, boundaryT(r.stepX > 0 ? ci + 1 : ci, r.o.x, r.invX));
    }
    if (r.stepY != 0) {
        ta = max(ta, boundaryT(r.stepY > 0 ? cj : cj + 1, r.o.y, r.invY));
        tb = min(tb, boundaryT(r.stepY > 0 ? cj + 1 : cj, r.o.y, r.invY));
    }
    tb = max(ta, tb);
    const float t = firstHitInCell(cellPlanes(ci, cj), ray, ci, cj, ta, tb);
    return t <= tb ? t : kInfinity;
}

int childIndex(float t, float origin, float inverse, int step, int base, int lo, int halfSize,
               int cells) {
    const int middle = base + lo + halfSize;
    const bool high = step > 0   ? t >= boundaryT(middle, origin, inverse)
                      : step < 0 ? t < boundaryT(middle, origin, inverse)
                                 : origin >= float(middle) + 0.5;
    return min(lo + (high ? halfSize : 0), cells - 1);
}

void descend(PyramidLayout pyramid, WalkRay r, NodeBox b, float tIn, inout WalkCursor c) {
    c.t = tIn;
    --c.level;
    const int halfSize = 1 << c.level;
    c.px = childIndex(tIn, r.o.x, r.invX, r.stepX, c.baseX, b.loX, halfSize, pyramid.cellsX);
    c.py = childIndex(tIn, r.o.y, r.invY, r.stepY, c.baseY, b.loY, halfSize, pyramid.cellsY);
}

int levelAfterStep(int ascent, PyramidLayout pyramid, int level, int from, int to, bool seam) {
    if (ascent == kAscentNone) return level;
    if (ascent == kAscentParent) {
        const bool newParent = seam || (from >> (level + 1)) != (to >> (level + 1));
        return newParent ? min(level + 1, topLevel(pyramid)) : level;
    }
    if (seam) return topLevel(pyramid);
    return findMSB(from ^ to);  // bit_width(from ^ to) - 1: the highest level where they differ
}

bool stepIndex(int step, int cells, bool repeat, inout int index, inout int base, inout bool seam) {
    if (index >= 0 && index < cells) return true;
    if (!repeat) return false;
    index -= step * cells;
    base += step * cells;
    seam = true;
    return true;
}

bool advance(int ascent, PyramidLayout pyramid, WalkRay r, NodeBox b, NodeExit e,
             inout WalkCursor c) {
    if (e.t >= r.tExit) return false;
    c.t = e.t;
    bool seam = false;
    int from, to;
    if (e.tx <= e.ty) {
        from = c.px;
        c.px = r.stepX > 0 ? b.hiX : b.loX - 1;
        to = c.px;
        if (!stepIndex(r.stepX, pyramid.cellsX, pyramid.repeat, c.px, c.baseX, seam)) return false;
    } else {
        from = c.py;
        c.py = r.stepY > 0 ? b.hiY : b.loY - 1;
        to = c.py;
        if (!stepIndex(r.stepY, pyramid.cellsY, pyramid.repeat, c.py, c.baseY, seam)) return false;
    }
    c.level = levelAfterStep(ascent, pyramid, c.level, from, to, seam);
    return true;
}

Hit walkPyramid(int ascent, Ray ray, WalkLimits limits) {
    const RayInterval span = clip(ray);
    if (empty(span)) return noHit();
    const PyramidLayout pyramid = pyramidLayout();
    const WalkRay r = makeWalkRay(ray, span);
    // startsAtRoot (pyramid_walk.h): the paper's forms
    const bool fromRoot = ascent == kAscentNone || limits.maxSteps > 0 || limits.boxSurface;
    WalkCursor c = startCursor(pyramid, r, fromRoot);
    const int maxSteps = limits.maxSteps > 0 ? limits.maxSteps : kIntMax;
    int steps = 0, fetches = 0;
    for (int guard = 0; guard < (1 << 26); ++guard) {
        if (steps == maxSteps) return makeHit(ray, c.t, steps, fetches);
        ++steps;
        ++fetches;
        const NodeBox b = nodeBox(pyramid, c);
        const NodeExit e = nodeExit(r, b, c);
        const float tIn = boundEnter(b, r, c.t, e.t);
        if (tIn <= e.t) {
            if (c.level > 0) {
                descend(pyramid, r, b, tIn, c);
                continue;
            }
            if (limits.boxSurface) return makeHit(ray, tIn, steps, fetches);
            fetches += kLeafFetches;
            const float tHit = leafHit(ray, r, c);
            if (tHit < kInfinity) return makeHit(ray, tHit, steps, fetches);
        }
        if (!advance(ascent, pyramid, r, b, e, c))
            return leavesThroughFloor(r) ? makeHit(ray, r.tExit, steps, fetches)
                                         : makeMiss(steps, fetches);
    }
    return makeMiss(steps, fetches);
}
