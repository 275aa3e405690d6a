// The max-pyramid walk of maxmip, quadtree and quadtree-oriented, on textures. Port of walkPyramid and its helpers
// (src/relief/techniques/common/pyramid_walk.h and its compute twin pyramid_walk.glsl): the same
// loop, the same conservative node tests (the ray below the node's maximum + slack, or below its
// oriented plane), the exact cell test at the leaves, the same step count.
// Map: `pyramid`, the bake's max pyramid, arrays "level0".."level<top>" as the mip levels of one
// R32F texture (level L at lod L, node (x, y) at texel (x, y); a texture larger than a level is
// fine, texels outside it are never read), nearest. The pyramid covers the cells: (W+1)×(H+1)
// in clamp mode (first cell −1), W×H in repeat mode. Baked with bits 16 / 8 (quadtree, maxmip):
// an R16 / R8 UNORM texture of codes of D; set p.bits.
// requires: common.glsl

const int kAscentNone = 0;      // Ascent::None: stay at the level after a jump (the paper)
const int kAscentParent = 1;    // Ascent::Parent: up one level on entering a new parent
const int kAscentAncestor = 2;  // Ascent::Ancestor: up to the common ancestor (maxmip)
const float kWalkSlack = 5e-7;  // pyramid_walk.h: the node test's rounding margin per unit
const int kLeafFetches = 4;     // the cell's corners
const float kPyramidDecodeMargin = 9.5367431640625e-7;  // max_pyramid.h: 2^-20
const int kReliefWalkGuard = 1048576;  // a cap valid rays never reach (max-steps 0 = none)

// bit_width(x) for x >= 0 (findMSB(x) + 1 where GLSL 4.00 has it).
int reliefBitWidth(int x) {
    int n = 0;
    for (int k = 0; k < 31; ++k)
        if ((x >> k) != 0) n = k + 1;
    return n;
}

struct ReliefPyramid {
    int cellsX;
    int cellsY;
    int firstCell;
    int levels;
    bool repeat;
};

ReliefPyramid reliefPyramidLayout(ReliefParams p) {  // PyramidLayout::of
    bool repeat = p.edge == kReliefRepeat;
    int cellsX = int(p.mapSize.x) + (repeat ? 0 : 1), cellsY = int(p.mapSize.y) + (repeat ? 0 : 1);
    return ReliefPyramid(cellsX, cellsY, repeat ? 0 : -1,
                         reliefBitWidth(max(cellsX, cellsY) - 1) + 1, repeat);
}

struct ReliefWalkRay {
    vec3 o;
    vec3 d;
    vec3 inv;
    int stepX, stepY;
    float tEnter, tExit;
    int exitMaskX, exitMaskY;  // a node's exit side: high (-1) or low (0)
    float slack;
};

struct ReliefCursor {
    float t;
    int level;
    int px, py;
    int baseX, baseY;
};

struct ReliefNode {
    int level, nx, ny;
    int loX, hiX, loY, hiY;
};

float reliefBoundaryT(int edgeCell, float origin, float inverse) {
    return (float(edgeCell) + 0.5 - origin) * inverse;
}

ReliefNode reliefNodeBox(ReliefPyramid pyramid, ReliefCursor c) {
    int nx = c.px >> c.level, ny = c.py >> c.level;
    int loX = nx << c.level, loY = ny << c.level;
    return ReliefNode(c.level, nx, ny, loX, min(loX + (1 << c.level), pyramid.cellsX), loY,
                      min(loY + (1 << c.level), pyramid.cellsY));
}

// Where the ray leaves the node: (tx, ty, t).
vec3 reliefNodeExit(ReliefWalkRay r, ReliefNode b, ReliefCursor c) {
    int edgeX = c.baseX + b.loX + ((b.hiX - b.loX) & r.exitMaskX);
    int edgeY = c.baseY + b.loY + ((b.hiY - b.loY) & r.exitMaskY);
    float tx = r.stepX != 0 ? reliefBoundaryT(edgeX, r.o.x, r.inv.x) : kReliefInfinity;
    float ty = r.stepY != 0 ? reliefBoundaryT(edgeY, r.o.y, r.inv.y) : kReliefInfinity;
    return vec3(tx, ty, max(c.t, min(min(tx, ty), r.tExit)));
}

// The first t in [t, tOut] where the ray is at or below height `top`, or kReliefInfinity.
float reliefEnterBelow(float top, ReliefWalkRay r, float t, float tOut) {
    if (r.d.z < 0.0) {
        if (r.o.z + tOut * r.d.z > top) return kReliefInfinity;
        return clamp((top - r.o.z) * r.inv.z, t, tOut);
    }
    return r.o.z + t * r.d.z <= top ? t : kReliefInfinity;
}

const int kReliefBoundMax = 0;       // MaxBound: the node's maximum (maxmip, quadtree)
const int kReliefBoundOriented = 1;  // OrientedBound: the max, then the node's plane

// enterBelowPlane (quadtree-oriented): where the ray goes below the node's plane through
// (c00, c10, c01) at its corners, rising rays only up to the node's maximum.
float reliefEnterBelowPlane(vec4 node, ReliefNode b, ReliefCursor c, ReliefWalkRay r, float t,
                            float tOut) {
    float scale = 1.0 / float(1 << b.level);
    float sx = (node.y - node.x) * scale, sy = (node.z - node.x) * scale;
    vec3 q = r.o + t * r.d;
    float x0 = float(c.baseX + b.loX) + 0.5, y0 = float(c.baseY + b.loY) + 0.5;
    float above = q.z - (node.x + sx * (q.x - x0) + sy * (q.y - y0)) - r.slack;
    if (above <= 0.0) return t;
    float rate = r.d.z - sx * r.d.x - sy * r.d.y;  // d(above)/dt
    if (rate >= 0.0) return kReliefInfinity;
    float tPlane = t - above / rate;
    if (tPlane > tOut) return kReliefInfinity;
    if (r.d.z > 0.0 && r.o.z + tPlane * r.d.z > node.w + r.slack) return kReliefInfinity;
    return tPlane;
}

// The bound's enter: the first t in [t, tOut] where the ray may be on or below S in the node
// (> tOut: none); one fetch. `oriented` holds levels 1.. at lods 0.. (OrientedBound). With
// p.bits 16 / 8 the maxima are codes of D, decoded as decodePyramidCode (max_pyramid.h).
float reliefBoundEnter(sampler2D pyramid, sampler2D oriented, int bound, ReliefNode b,
                       ReliefCursor c, ReliefWalkRay r, float t, float tOut, ReliefParams p) {
    if (bound == kReliefBoundMax || b.level == 0) {
        float top = texelFetch(pyramid, ivec2(b.nx, b.ny), b.level).r;
        if (p.bits < 32) top = top * p.depth * (1.0 + kPyramidDecodeMargin);
        return reliefEnterBelow(top + r.slack, r, t, tOut);
    }
    vec4 node = texelFetch(oriented, ivec2(b.nx, b.ny), b.level - 1);
    float tIn = reliefEnterBelow(node.w + r.slack, r, t, tOut);
    if (tIn > tOut) return tIn;
    return reliefEnterBelowPlane(node, b, c, r, tIn, tOut);
}

float reliefLeafHit(sampler2D heights, ReliefRay ray, ReliefWalkRay r, ReliefCursor c,
                    ReliefParams p) {
    int ci = c.baseX + c.px, cj = c.baseY + c.py;
    float ta = r.tEnter, tb = r.tExit;
    if (r.stepX != 0) {
        ta = max(ta, reliefBoundaryT(r.stepX > 0 ? ci : ci + 1, r.o.x, r.inv.x));
        tb = min(tb, reliefBoundaryT(r.stepX > 0 ? ci + 1 : ci, r.o.x, r.inv.x));
    }
    if (r.stepY != 0) {
        ta = max(ta, reliefBoundaryT(r.stepY > 0 ? cj : cj + 1, r.o.y, r.inv.y));
        tb = min(tb, reliefBoundaryT(r.stepY > 0 ? cj + 1 : cj, r.o.y, r.inv.y));
    }
    tb = max(ta, tb);
    float t = reliefFirstHitInCell(heights, ray, ci, cj, ta, tb, p);
    return t <= tb ? t : kReliefInfinity;
}

int reliefChildIndex(float t, float origin, float inverse, int step, int base, int lo,
                     int halfSize, int cells) {
    int middle = base + lo + halfSize;
    bool high = step > 0   ? t >= reliefBoundaryT(middle, origin, inverse)
                : step < 0 ? t < reliefBoundaryT(middle, origin, inverse)
                           : origin >= float(middle) + 0.5;
    return min(lo + (high ? halfSize : 0), cells - 1);
}

int reliefLevelAfterStep(int ascent, ReliefPyramid pyramid, int level, int from, int to,
                         bool seam) {
    int top = pyramid.levels - 1;
    if (ascent == kAscentNone) return level;
    if (ascent == kAscentParent) {
        bool newParent = seam || (from >> (level + 1)) != (to >> (level + 1));
        return newParent ? min(level + 1, top) : level;
    }
    if (seam) return top;
    return reliefBitWidth(from ^ to) - 1;  // the highest level where they differ
}

// One index step out of a node along an axis; false when it leaves the box (clamp mode).
bool reliefStepIndex(int step, int cells, bool repeat, inout int index, inout int base,
                     inout bool seam) {
    if (index >= 0 && index < cells) return true;
    if (!repeat) return false;
    index -= step * cells;
    base += step * cells;
    seam = true;
    return true;
}

bool reliefAdvance(int ascent, ReliefPyramid pyramid, ReliefWalkRay r, ReliefNode b, vec3 e,
                   inout ReliefCursor c) {
    if (e.z >= r.tExit) return false;
    c.t = e.z;
    bool seam = false;
    int from, to;
    if (e.x <= e.y) {
        from = c.px;
        c.px = r.stepX > 0 ? b.hiX : b.loX - 1;
        to = c.px;
        if (!reliefStepIndex(r.stepX, pyramid.cellsX, pyramid.repeat, c.px, c.baseX, seam))
            return false;
    } else {
        from = c.py;
        c.py = r.stepY > 0 ? b.hiY : b.loY - 1;
        to = c.py;
        if (!reliefStepIndex(r.stepY, pyramid.cellsY, pyramid.repeat, c.py, c.baseY, seam))
            return false;
    }
    c.level = reliefLevelAfterStep(ascent, pyramid, c.level, from, to, seam);
    return true;
}

// walkPyramid<ascent> with the bound: the first hit of a texel-space ray in any direction.
ReliefHit reliefPyramidWalk(sampler2D heights, sampler2D pyramid, sampler2D oriented, int bound,
                            ReliefRay ray, int ascent, ReliefParams p) {
    vec2 span = reliefClip(ray, p);
    if (!(span.x <= span.y)) return reliefNoHit(0);
    ReliefPyramid tree = reliefPyramidLayout(p);
    vec3 o = ray.origin, d = ray.direction;
    float extent = abs(o.x) + abs(o.y) + abs(o.z) + span.y + p.depth;
    ReliefWalkRay r = ReliefWalkRay(o, d, vec3(1.0) / d, d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0),
                                    d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0), span.x, span.y,
                                    d.x > 0.0 ? -1 : 0, d.y > 0.0 ? -1 : 0, kWalkSlack * extent);
    // The start cursor: the entry cell, at the root.
    vec3 entry = o + span.x * d;
    int ci = reliefClampCellX(int(floor(entry.x - 0.5)), p);
    int cj = reliefClampCellY(int(floor(entry.y - 0.5)), p);
    ReliefCursor c = ReliefCursor(span.x, tree.levels - 1, 0, 0, tree.firstCell,
                                  tree.firstCell);
    if (tree.repeat) {
        c.px = reliefWrapIndex(ci, tree.cellsX);
        c.py = reliefWrapIndex(cj, tree.cellsY);
        c.baseX = ci - c.px;
        c.baseY = cj - c.py;
    } else {
        c.px = ci - tree.firstCell;
        c.py = cj - tree.firstCell;
    }
    // Below the root (pyramid_walk.h, startCursor and startsAtRoot): unless the walk is the
    // paper's Algorithm 1 or its fixed loop, it starts at the smallest node holding the cells
    // where the ray enters and leaves the box.
    if (ascent != kAscentNone && p.maxSteps <= 0) {
        vec3 leave = o + span.y * d;
        // one cell further along the ray: the position may have rounded back over an edge
        int ei = reliefClampCellX(int(floor(leave.x - 0.5)), p) + r.stepX;
        int ej = reliefClampCellY(int(floor(leave.y - 0.5)), p) + r.stepY;
        int ex = clamp(ei - tree.firstCell, 0, tree.cellsX - 1);
        int ey = clamp(ej - tree.firstCell, 0, tree.cellsY - 1);
        bool sameTile = true;
        if (tree.repeat) {
            ex = reliefWrapIndex(ei, tree.cellsX);
            ey = reliefWrapIndex(ej, tree.cellsY);
            sameTile = ei - ex == c.baseX && ej - ey == c.baseY;
        }
        if (sameTile) c.level = min(c.level, reliefBitWidth((c.px ^ ex) | (c.py ^ ey)));
    }
    int cap = p.maxSteps > 0 ? p.maxSteps : kReliefWalkGuard;
    int steps = 0;
    for (int k = 0; k < cap; ++k) {
        ++steps;
        ReliefNode b = reliefNodeBox(tree, c);
        vec3 e = reliefNodeExit(r, b, c);
        float tIn = reliefBoundEnter(pyramid, oriented, bound, b, c, r, c.t, e.z, p);
        if (tIn <= e.z) {
            if (c.level > 0) {  // descend into the child that holds the ray at tIn
                c.t = tIn;
                --c.level;
                int halfSize = 1 << c.level;
                c.px = reliefChildIndex(tIn, r.o.x, r.inv.x, r.stepX, c.baseX, b.loX, halfSize,
                                        tree.cellsX);
                c.py = reliefChildIndex(tIn, r.o.y, r.inv.y, r.stepY, c.baseY, b.loY, halfSize,
                                        tree.cellsY);
                continue;
            }
            float tHit = reliefLeafHit(heights, ray, r, c, p);
            if (tHit < kReliefInfinity) return reliefHitAt(ray, tHit, steps, p);
        }
        if (!reliefAdvance(ascent, tree, r, b, e, c))
            return reliefHitIf(reliefExitsThroughFloor(ray, span.y, p), ray, span.y, steps, p);
    }
    // Capped (max-steps > 0, the paper's fixed loop): a hit at the cursor.
    return reliefHitIf(p.maxSteps > 0, ray, c.t, steps, p);
}

// The walk from a view ray (descending only), and the shadow query on the same walk.
ReliefHit reliefPyramidView(sampler2D heights, sampler2D pyramid, sampler2D oriented, int bound,
                            vec2 uv, vec3 viewDirTangent, int ascent, ReliefParams p) {
    ReliefRay ray = reliefViewRay(uv, viewDirTangent, p);
    if (!(ray.direction.z < 0.0)) return reliefNoHit(0);
    return reliefPyramidWalk(heights, pyramid, oriented, bound, ray, ascent, p);
}

float reliefPyramidShadow(sampler2D heights, sampler2D pyramid, sampler2D oriented, int bound,
                          ReliefHit hit, vec3 lightDirTangent, int ascent, ReliefParams p) {
    if (!hit.hit) return 1.0;
    ReliefRay ray = reliefShadowRay(hit, lightDirTangent, p);
    if (ray.direction.z <= 0.0) return 0.0;
    return reliefPyramidWalk(heights, pyramid, oriented, bound, ray, ascent, p).hit ? 0.0 : 1.0;
}
