#pragma once
// The pyramid walk shared by `quadtree`, `maxmip` and `quadtree-oriented`: one loop, three
// choices (what bounds a node, what to do after leaving a node, and caps).
//
// The cursor t moves along the ray; (px, py) is a level-0 index whose bits ≥ L locate the node
// holding the cursor at the current level L, (px >> L, py >> L) — the paper's "the cursor is
// always in the correct node", kept in integers. Descending settles one more bit per axis (is
// the cursor in the low or the high half of the node?), so at level 0 (px, py) is its cell.
//
// Each iteration tests one node: the bound gives the first t in the node's segment where the
// ray may be on or below S; if there is one, the cursor moves there and the walk descends (at
// level 0: the exact two-triangle test of the cell, `firstHitInCell`); otherwise the cursor
// moves to the node's exit and the walk steps to the neighbouring node, then ascends as the
// policy says. The neighbour is found by an integer step of the index (the paper's
// "boundary offset" delta, without an epsilon). Everything skipped lies above a bound ≥ S, and
// every cell the ray crosses below its bound gets the reference's own cell test, so the result
// is the reference's first hit (up to float rounding of t).
//
// Which side of a cell edge the ray is on is always decided in t, with the reference's formula
// for the t at which the ray crosses the edge (boundaryT), never from a float position: far from
// the origin a position within an ulp of an edge rounds onto it, and a ray running along the edge
// would then be walked in the wrong row of cells (seen at 4096², fixed, and kept in the tests).
//
// Over texel boxes (MaxPyramid::overTexels, the quadtree paper's surface) the same walk runs on
// the texel grid (edges at integers, PyramidLayout::edge = 0): a level-0 node's bound is its box,
// so entering it is the hit, and with no slack the walk returns firstTexelBoxHit's t. CPU only:
// the GLSL twin walks cells.
#include <relief/surface/cell_intersect.h>
#include <relief/surface/texel_boxes.h>
#include <relief/techniques/common/max_pyramid.h>
#include <relief/techniques/technique.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace relief {

// After leaving a node through a side.
enum class Ascent {
    None,      // stay at the level (Schroders & van Gulik's Algorithm 1: never go up)
    Parent,    // as None, but one level up when the neighbour lies in another parent
    Ancestor,  // straight up to the child of the common ancestor (Tevs et al.: a ray tracer)
};

struct WalkLimits {
    int maxSteps = 0;         // 0 = none; at the cap the walk reports a hit at the cursor
    bool boxSurface = false;  // reaching a level-0 node is a hit (always so over texel boxes)
    bool fromRoot = false;    // start at the root whatever the rest says (startsAtRoot)
};

// Per-ray constants.
struct WalkRay {
    vec3 o, d;
    float invX, invY, invZ;
    int stepX, stepY;
    float tEnter, tExit;
    int exitMaskX, exitMaskY;  // a node's exit side: high (-1) or low (0)
    // Height tolerance of the bound tests: the float error of the ray's z and of S's planes, so
    // that no node is skipped where the reference's cell test could still report a hit.
    float slack;
    float depth;
    float edge;  // PyramidLayout::edge: 0.5 cells, 0 texels

    vec3 at(float t) const { return o + t * d; }
};

// Where the walk is: cursor t, current level, the level-0 index of the cursor's node (bits ≥
// level; pyramid indices), the global cell index of pyramid index 0 (repeat: the tile's), and
// the t at which the ray leaves the node along each axis (kept up to date, not recomputed).
struct WalkCursor {
    float t;
    int level;
    int px, py;
    int baseX, baseY;
    float exitX, exitY;
};

// The node under test: its first level-0 index per axis (it spans 2^level of them, fewer at the
// end of a row), and the cursor's tile base.
struct NodeBox {
    int level, nx, ny;
    int loX, loY;
    int baseX, baseY;

    // Texel position of the lower corner of the node's nominal 2^L square.
    float x0() const { return float(baseX + loX) + 0.5f; }
    float y0() const { return float(baseY + loY) + 0.5f; }
};

struct NodeExit {
    float tx, ty, t;  // crossing of the x side, of the y side, and the exit (clipped to the box)
};

inline constexpr float kWalkSlack = 5e-7f;

inline WalkRay makeWalkRay(const Ray& ray, const RayInterval& span, const Surface& s,
                           const PyramidLayout& layout) {
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    // Texel boxes: a level-0 node's bound is its box, and max is exact: no slack.
    const float extent = layout.texels() ? 0.0f
                                         : std::abs(o.x) + std::abs(o.y) + std::abs(o.z) +
                                               span.tExit + s.depth();
    return {o,
            d,
            1.0f / d.x,
            1.0f / d.y,
            1.0f / d.z,
            d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0),
            d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0),
            span.tEnter,
            span.tExit,
            d.x > 0.0f ? -1 : 0,
            d.y > 0.0f ? -1 : 0,
            kWalkSlack * extent,
            s.depth(),
            layout.edge};
}

// t where the ray crosses the edge x = edgeCell + edge (the reference's formula, bit for bit:
// cells' edge 0.5 as in cell_walk.h, texels' 0 as in texel_boxes.cpp).
inline float boundaryT(int edgeCell, float edge, float origin, float inverse) {
    return (float(edgeCell) + edge - origin) * inverse;
}

inline int floorMod(int a, int n) {
    const int r = a % n;
    return r < 0 ? r + n : r;
}

// t at which the ray leaves, along one axis, the node of `level` that holds index p (+inf when
// the ray does not move along that axis).
inline float sideExitT(int p, int level, int cells, int base, int step, int exitMask, float edge,
                       float origin, float inverse) {
    if (step == 0) return kInfinity;
    const int lo = (p >> level) << level;
    const int hi = std::min(lo + (1 << level), cells);
    return boundaryT(base + lo + ((hi - lo) & exitMask), edge, origin, inverse);
}

inline void updateExits(const PyramidLayout& layout, const WalkRay& r, WalkCursor& c, bool x,
                        bool y) {
    if (x)
        c.exitX =
            sideExitT(c.px, c.level, layout.cellsX, c.baseX, r.stepX, r.exitMaskX, r.edge,
                                r.o.x, r.invX);
    if (y)
        c.exitY =
            sideExitT(c.py, c.level, layout.cellsY, c.baseY, r.stepY, r.exitMaskY, r.edge,
                                r.o.y, r.invY);
}

// The cell (pyramid index per axis, and its tile's base) that holds the point at t, as the walk
// starts in it, from the position: so at the ray's ends only (on the box's faces, or at tMax),
// and one cell further along the ray (`ahead`) where the position may have rounded back over an
// edge that the walk, deciding in t, has crossed.
// Both are inlined where they are used (the packet walk's fill, compiled per SIMD target): an
// out-of-line copy is one symbol for every target, and the baseline one (std::floor without
// SSE4.1) took 17 % of a primary view's time.
struct StartCell {
    int px, py, baseX, baseY;
};
[[gnu::always_inline]] inline StartCell startCell(const Surface& s, const PyramidLayout& layout,
                                                  const WalkRay& r, float t, bool ahead) {
    const vec3 at = r.at(t);
    int ci = s.cellOfX(at.x), cj = s.cellOfY(at.y);
    if (layout.texels()) {  // the texel holding the point (as firstTexelBoxHit finds the entry)
        ci = int(std::floor(at.x));
        cj = int(std::floor(at.y));
    }
    if (ahead) {
        ci += r.stepX;
        cj += r.stepY;
    }
    if (layout.repeat) {
        const int px = floorMod(ci, layout.cellsX), py = floorMod(cj, layout.cellsY);
        return {px, py, ci - px, cj - py};
    }
    return {std::clamp(ci - layout.firstCell, 0, layout.cellsX - 1),
            std::clamp(cj - layout.firstCell, 0, layout.cellsY - 1), layout.firstCell,
            layout.firstCell};
}

// The walk starts at the entry cell, at the root (`fromRoot`) or at the smallest node that holds
// the cells where the ray enters and leaves the box. Above that node the root's walk only descends
// (the node holds the ray's whole footprint, so no ancestor's test can do more than it does) or
// misses (then so does the node's own test, its max being no higher): the walk from there on is the
// same, less those descents, and finds the same hits. A short ray (a shadow ray from the box's top
// to a point, a steep view) skips most of the pyramid's height this way.
[[gnu::always_inline]] inline WalkCursor startCursor(const Surface& s, const PyramidLayout& layout,
                                                     const WalkRay& r, bool fromRoot) {
    const StartCell entry = startCell(s, layout, r, r.tEnter, false);
    WalkCursor c{r.tEnter, layout.topLevel(), entry.px, entry.py, entry.baseX, entry.baseY, 0, 0};
    if (!fromRoot) {
        const StartCell exit = startCell(s, layout, r, r.tExit, true);
        if (exit.baseX == entry.baseX && exit.baseY == entry.baseY)
            c.level = std::min(
                c.level,
                int(std::bit_width(unsigned((entry.px ^ exit.px) | (entry.py ^ exit.py)))));
    }
    updateExits(layout, r, c, true, true);
    return c;
}

inline NodeBox nodeBox(const PyramidLayout& layout, const WalkCursor& c) {
    NodeBox b;
    b.level = c.level;
    b.nx = c.px >> c.level;
    b.ny = c.py >> c.level;
    b.loX = b.nx << c.level;
    b.loY = b.ny << c.level;
    b.baseX = c.baseX;
    b.baseY = c.baseY;
    return b;
}

inline NodeExit nodeExit(const WalkRay& r, const WalkCursor& c) {
    return {c.exitX, c.exitY, std::max(c.t, std::min({c.exitX, c.exitY, r.tExit}))};
}

// First t in [t, tOut] where the ray is at or below height `top`, or kInfinity.
inline float enterBelow(float top, const WalkRay& r, float t, float tOut) {
    return enterBelow(top, r.o, r.d, r.invZ, t, tOut);  // texel_boxes.h: the box column test
}

// The flat bound of `quadtree` and `maxmip`: the node's maximum (one fetch).
class MaxBound {
public:
    explicit MaxBound(const MaxPyramid& pyramid) : m_pyramid(&pyramid) {}
    float enter(const NodeBox& b, const WalkRay& r, float t, float tOut) const {
        return enterBelow(m_pyramid->at(b.level, b.nx, b.ny) + r.slack, r, t, tOut);
    }

private:
    const MaxPyramid* m_pyramid;
};

inline Hit makeHit(const Ray& ray, float t, int steps, int fetches) {
    Hit hit;
    hit.hit = true;
    hit.t = t;
    hit.position = ray.at(t);
    hit.steps = steps;
    hit.fetches = fetches;
    return hit;
}

inline Hit makeMiss(int steps, int fetches) {
    Hit hit;
    hit.steps = steps;
    hit.fetches = fetches;
    return hit;
}

// The reference's rule at the end of the walk (exact.h): leaving through the bottom face means
// reaching z = 0 ≤ S, a hit, even where rounding left the last cell test a hair above a floor of
// zero samples.
inline bool leavesThroughFloor(float oz, float dz, float tExit, float depth) {
    const float zExit = oz + tExit * dz;
    const float zRounding = 4.0f * std::numeric_limits<float>::epsilon() * (std::abs(oz) + depth);
    return dz < 0.0f && zExit <= zRounding;
}
inline bool leavesThroughFloor(const WalkRay& r) {
    return leavesThroughFloor(r.o.z, r.d.z, r.tExit, r.depth);
}

// The reference's cell test on the cursor's cell, over the ray's whole span in the cell (its
// ends computed as the reference computes them): the first hit, or kInfinity.
inline float leafHit(const Surface& s, const Ray& ray, const WalkRay& r, const WalkCursor& c) {
    const int ci = c.baseX + c.px, cj = c.baseY + c.py;
    float ta = r.tEnter, tb = r.tExit;
    if (r.stepX != 0) {
        ta = std::max(ta, boundaryT(r.stepX > 0 ? ci : ci + 1, r.edge, r.o.x, r.invX));
        tb = std::min(tb, boundaryT(r.stepX > 0 ? ci + 1 : ci, r.edge, r.o.x, r.invX));
    }
    if (r.stepY != 0) {
        ta = std::max(ta, boundaryT(r.stepY > 0 ? cj : cj + 1, r.edge, r.o.y, r.invY));
        tb = std::min(tb, boundaryT(r.stepY > 0 ? cj + 1 : cj, r.edge, r.o.y, r.invY));
    }
    tb = std::max(ta, tb);
    const float t = firstHitInCell(s.cellPlanes(ci, cj), ray, ci, cj, ta, tb);
    return t <= tb ? t : kInfinity;
}

inline constexpr int kLeafFetches = 4;  // the cell's corners

// `quadtree`'s and `maxmip`'s surface option (WalkLimits::boxSurface, maxPyramidFor).
inline constexpr ParamSpec kBoxSurfaceParam = {
    "box-surface", 0, 0, 2, true,
    "0 = S; 1 = cell boxes at the corner maximum, stop at the first level-0 node (approximate); "
    "2 = the quadtree paper's surface, texel boxes at the sample height (exact on them, "
    "approximate on S; CPU only)",
    ParamRole::Variant};

// What common/pyramid_walk.glsl and the three walks' GLSL read (their rows' glslConstants).
inline constexpr GlslConstant kPyramidWalkGlslConstants[] = {
    {"kAscentNone", double(int(Ascent::None)), true},
    {"kAscentParent", double(int(Ascent::Parent)), true},
    {"kAscentAncestor", double(int(Ascent::Ancestor)), true},
    {"kWalkSlack", double(kWalkSlack), false},
    {"kLeafFetches", double(kLeafFetches), true},
    {"kPyramidDecodeMargin", double(kPyramidDecodeMargin), false},
};

// Along one axis, the child half (low or high) of [lo, lo + 2·half) that holds the ray at t:
// decided by when the ray crosses the middle (the reference's t; at t itself it has crossed,
// unless `tieBefore`). A truncated node's nominal high half may not exist. The child's exit is
// the middle or the parent's exit.
inline void settleHalf(float t, float edge, float origin, float inverse, int step, int base, int lo,
                       int half, int cells, int& index, float& exitT, bool tieBefore = false) {
    const bool exists = lo + half < cells;
    const int middle = base + lo + half;
    if (step == 0) {
        index = lo + (exists && origin >= float(middle) + edge ? half : 0);
        return;
    }
    const float tMiddle = boundaryT(middle, edge, origin, inverse);
    const bool crossed = tieBefore ? t > tMiddle : t >= tMiddle;
    const bool high = exists && (step > 0 ? crossed : !crossed);
    index = lo + (high ? half : 0);
    if (exists && high == (step < 0)) exitT = tMiddle;  // leaving through the middle
}

// Moves the cursor to tIn and into the child that holds it.
inline void descend(const PyramidLayout& layout, const WalkRay& r, const NodeBox& b, float tIn,
                    WalkCursor& c) {
    c.t = tIn;
    --c.level;
    const int half = 1 << c.level;
    settleHalf(tIn, r.edge, r.o.x, r.invX, r.stepX, c.baseX, b.loX, half, layout.cellsX, c.px,
               c.exitX);
    // Texel boxes are not continuous at a corner: where the ray crosses an x edge and the y
    // middle at the same t, firstTexelBoxHit visits the texel beyond x first (its ties go to x,
    // as `advance`'s do), so the y half is the one before the middle.
    bool tieBefore = false;
    if (layout.texels() && r.stepX != 0) {
        const int lo = (c.px >> c.level) << c.level;
        const int entry = r.stepX > 0 ? lo : std::min(lo + half, layout.cellsX);
        tieBefore = boundaryT(c.baseX + entry, r.edge, r.o.x, r.invX) == tIn;
    }
    settleHalf(tIn, r.edge, r.o.y, r.invY, r.stepY, c.baseY, b.loY, half, layout.cellsY, c.py,
               c.exitY, tieBefore);
}

// The paper's forms start at the root: Schroders & van Gulik's Algorithm 1 (Ascent::None, which
// never goes up), the fixed loop of max-steps (its iterations count from the root) and the box
// stops and surfaces (box-surface, the paper variants the claims are judged with). The exact
// walk starts below it (startCursor).
template <Ascent kAscent>
bool startsAtRoot(const WalkLimits& limits) {
    return kAscent == Ascent::None || limits.maxSteps > 0 || limits.boxSurface || limits.fromRoot;
}

template <Ascent kAscent>
int levelAfterStep(const PyramidLayout& layout, int level, int from, int to, bool seam) {
    if constexpr (kAscent == Ascent::None) {
        return level;
    } else if constexpr (kAscent == Ascent::Parent) {
        const bool newParent = seam || (from >> (level + 1)) != (to >> (level + 1));
        return newParent ? std::min(level + 1, layout.topLevel()) : level;
    } else {
        if (seam) return layout.topLevel();
        return int(std::bit_width(unsigned(from ^ to))) - 1;  // highest level where they differ
    }
}

// Steps one level-0 index along an axis; false when the ray leaves the map (clamp). In repeat
// mode the index wraps into the next tile and `seam` is set.
inline bool stepIndex(int step, int cells, bool repeat, int& index, int& base, bool& seam) {
    if (index >= 0 && index < cells) return true;
    if (!repeat) return false;
    index -= step * cells;
    base += step * cells;
    seam = true;
    return true;
}

// Moves the cursor to the node's exit and into the neighbouring node; false on leaving.
template <Ascent kAscent>
bool advance(const PyramidLayout& layout, const WalkRay& r, const NodeBox& b, const NodeExit& e,
             WalkCursor& c) {
    if (e.t >= r.tExit) return false;
    c.t = e.t;
    bool seam = false;
    const bool alongX = e.tx <= e.ty;
    int from, to;
    if (alongX) {
        from = c.px;
        to = c.px = r.stepX > 0 ? std::min(b.loX + (1 << b.level), layout.cellsX) : b.loX - 1;
        if (!stepIndex(r.stepX, layout.cellsX, layout.repeat, c.px, c.baseX, seam)) return false;
    } else {
        from = c.py;
        to = c.py = r.stepY > 0 ? std::min(b.loY + (1 << b.level), layout.cellsY) : b.loY - 1;
        if (!stepIndex(r.stepY, layout.cellsY, layout.repeat, c.py, c.baseY, seam)) return false;
    }
    const int level = levelAfterStep<kAscent>(layout, c.level, from, to, seam);
    const bool ascended = level != c.level;
    c.level = level;
    updateExits(layout, r, c, alongX || ascended, !alongX || ascended);
    return true;
}

// The walk. Bound: `float enter(const NodeBox&, const WalkRay&, float t, float tOut)`, the
// first t in [t, tOut] where the ray may be on or below S in the node (> tOut: none), one fetch.
template <Ascent kAscent, class Bound>
Hit walkPyramid(const Surface& s, const PyramidLayout& layout, const Bound& bound, const Ray& ray,
                const WalkLimits& limits) {
    const RayInterval span = s.clip(ray);
    if (span.empty()) return Hit{};
    const WalkRay r = makeWalkRay(ray, span, s, layout);
    if (layout.texels() && r.o.z + r.tEnter * r.d.z <= floorTolerance(r.o.z, r.depth))
        return makeHit(ray, r.tEnter, 0, 0);  // entering through the floor, as firstTexelBoxHit
    WalkCursor c = startCursor(s, layout, r, startsAtRoot<kAscent>(limits));
    const int maxSteps = limits.maxSteps > 0 ? limits.maxSteps : std::numeric_limits<int>::max();
    int steps = 0, fetches = 0;
    for (;;) {
        if (steps == maxSteps) return makeHit(ray, c.t, steps, fetches);
        ++steps;
        ++fetches;
        const NodeBox b = nodeBox(layout, c);
        const NodeExit e = nodeExit(r, c);
        const float tIn = bound.enter(b, r, c.t, e.t);
        if (tIn <= e.t) {
            if (c.level > 0) {
                descend(layout, r, b, tIn, c);
                continue;
            }
            if (limits.boxSurface || layout.texels()) return makeHit(ray, tIn, steps, fetches);
            fetches += kLeafFetches;
            const float tHit = leafHit(s, ray, r, c);
            if (tHit < kInfinity) return makeHit(ray, tHit, steps, fetches);
        }
        if (!advance<kAscent>(layout, r, b, e, c))
            return leavesThroughFloor(r) ? makeHit(ray, r.tExit, steps, fetches)
                                         : makeMiss(steps, fetches);
    }
}

}  // namespace relief
