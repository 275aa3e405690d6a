#pragma once
// Exterior rays (§6.2 of the safety-shapes paper): the limiting-triangle test restricted to rays
// whose viewpoint is outside the relief's box, which gives longer safety distances.
//
// What is tested. For texel τ (segment s_τ at a = a0) and triangle T of its wedge, T is
// *exterior-limiting* iff some line ℓ of the class lies in T's plane P_T, crosses T, passes
// strictly above S on s_τ, and traced backward from s_τ stays above S until it leaves the box
// (it never meets S at a < a0). Only that backward part matters: between s_τ and T the ray may
// cross S once, that is the point. Why this suffices (the paper's "tilting" made precise): let a
// ray r of the class pass q above s_τ, reach q without meeting S (exterior), and cross S a
// second time at p on T'. r is below P_T' before p, so q is below P_T' and its vertical
// projection q' onto P_T' is above S. The line ℓ' through q' and p lies in P_T', has r's
// horizontal direction, is above r before p by (1 − t)·(q'_z − q_z) > 0, hence strictly above S
// on its whole backward part, and rises less steeply than r (φ_max keeps holding). So ℓ' is a
// limit line with a margin, and a test with closed blockers still finds it.
//
// How. In P_T, oriented lines of the class form a 2D set (two-slab dual). The initial set is
// π(σ) ∩ π^{x+} ∩ π(T): lines through the part σ of s_τ where P_T is above S (one or two
// intervals), with directions in the class wedge (narrowed by φ_max to one or two arcs of
// slopes), crossing one of two edges of T. Every blocker b — the segment P_T ∩ T' for a triangle
// T' of S behind s_τ (a ≤ a0) inside the shaft of those lines — is subtracted: lines that pass
// both its endpoints on the same side remain, 0, 1 or 2 convex pieces. T is limiting iff a piece
// survives. Convex sets of lines are kept as lists of primal points (one half-plane of the dual
// per point: "lines passing above / below this point"; the two class-wedge bounds are points at
// infinity, homogeneous w = 0), so every decision is an orientation sign of three primal points:
// no duality transform is computed. Borderline decisions keep lines (conservative: a triangle
// may be called limiting when it is not, never the reverse).
//
// Departures from the paper: blockers are taken behind s_τ only (the paper's Fig. 20 shaft runs
// between s_τ and T: lines crossing S there are exactly the ones that make T limiting, so they
// must not be removed); hence the cache R_T of §6.2.6 would be per (T, column of τ), and it is not
// implemented: instead the search stops at the first escaped line (a witness) or when nothing is
// left. Witnesses are also looked for directly: after 0, 1, 3, 7, … columns the centroid line
// of each piece is traced backward against S (limiting tests outnumber the others ~3:1).
// Blockers that leave a piece whole are recognized from its cached vertex lines without a copy,
// and cells with all four corners on one side of P_T are skipped unbuilt. Cost (two threads,
// fbm): cyl_ext 36.7 s at 512², 299 s at 1024²; cone_ext's planes 242 s at 512². Clamp edge
// mode only: with a tiling relief the box is infinite in x, y,
// exterior rays come only from above and their backward blocker search is unbounded.
#include <relief/techniques/safety_common/safety_maps.h>

#include <atomic>
#include <cstdint>
#include <vector>

namespace relief::safety {

// A point of P_T in the class frame's (a, b), homogeneous: w = 1 a point, w = 0 the direction
// (a, b) at infinity.
struct PlanePoint {
    double a, b, w;
};

// The line through two primal points, as l1·a + l2·b + l3·w = 0; norm = |l1| + |l2| + |l3|.
struct PrimalLine {
    double l1 = 0.0, l2 = 0.0, l3 = 0.0, norm = 0.0;
};

// Oriented lines (direction +a) passing with `point` on one side: side +1 = the point is above
// or on the line (b ≥ ℓ(a); for a direction (1, m): m ≥ the line's slope), −1 = below or on.
// toNext: the polygon's vertex between this edge and the next (the line through both points),
// kept up to date by linesThroughSegment and clipLines, since every blocker tests every vertex.
struct LineHalfPlane {
    PlanePoint point;
    int side;
    PrimalLine toNext{};
};

// A convex set of lines: its dual edges in cyclic order; consecutive edges meet at the line
// through their two points.
using LinePolygon = std::vector<LineHalfPlane>;

// Lines crossing the vertical segment {a0} × [y0, y1] with slopes in [lo, hi].
LinePolygon linesThroughSegment(double a0, double y0, double y1, double lo, double hi);
// Intersects with a half-plane; false when nothing is left.
bool clipLines(LinePolygon& lines, const LineHalfPlane& h);

// A blocker: a segment of S ∩ P_T in P_T's (a, b).
struct BlockerSegment {
    PlanePoint p, q;
};

// Removes from every piece the lines crossing the blocker (each piece leaves 0, 1 or 2).
void subtractBlocker(std::vector<LinePolygon>& pieces, const BlockerSegment& blocker);

// A line of P_T in slope–intercept form: b = c + m·(a − a0).
struct DualLine {
    double m, c;
};

// The exterior test over one surface (clamp mode). Thread-safe; holds block maxima of the cells
// so that the blocker search skips low terrain 16 cells at a time.
class ExteriorVisibility {
public:
    // traceWitnesses: look for a witness line by tracing (off only for the test that checks it
    // changes no answer).
    explicit ExteriorVisibility(const Surface& surface, bool traceWitnesses = true);

    // Is T exterior-limiting for the texel of `seg` (frame f), rays with slope ≤ tanPhi?
    // Callers first check isLimiting (all rays): exterior-limiting implies it.
    bool limiting(const Frame& f, const SegmentHeights& seg, const LocalTriangle& t,
                  double tanPhi) const;

    // Counters (all threads): triangles tested, found limiting by a traced witness line, and
    // blockers subtracted.
    uint64_t tests() const { return m_tests.load(std::memory_order_relaxed); }
    uint64_t witnessed() const { return m_witnessed.load(std::memory_order_relaxed); }
    uint64_t blockers() const { return m_blockers.load(std::memory_order_relaxed); }

private:
    // The blockers of (τ, T) in local column ac, for lines through s_τ with slopes in
    // [mlo, mhi]. False when the column is outside the box.
    bool columnBlockers(const Frame& f, const SegmentHeights& seg, const LocalTriangle& t,
                        int ac, double mlo, double mhi, std::vector<BlockerSegment>& out) const;
    // Highest and lowest cell corner of 16-cell blocks of one world line.
    struct Block {
        float lo, hi;
    };
    const Block& block(bool xClass, int line, int cell) const;
    // Witnesses: a line of P_T (through s_τ at a0) traced backward from `from`; the centroid
    // line of each piece.
    bool escapesBackward(const Frame& f, const LocalTriangle& t, double a0, double from,
                         const DualLine& line) const;
    bool someLineTracedOut(const Frame& f, const LocalTriangle& t, double a0, double from,
                           const std::vector<LinePolygon>& pieces) const;

    const Surface& m_surface;
    bool m_traceWitnesses;
    int m_blocksY, m_blocksX;
    std::vector<Block> m_alongY, m_alongX;  // [line + 1][(cell + 1) / 16], cells -1 .. n-1
    mutable std::atomic<uint64_t> m_tests{0}, m_witnessed{0}, m_blockers{0};
};

}  // namespace relief::safety
