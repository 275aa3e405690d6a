// The cell test of the packet walks (surface/cell_walk_packet.cpp, cone/cone_packet.cpp,
// safety_cc/safety_cc_packet.cpp, common/pyramid_walk_packet.cpp), per Highway target: included
// by their foreach_target translation units once per target (Highway's -inl.h convention: the
// guard toggles with HWY_TARGET_TOGGLE).
// firstHitInCell (cell_intersect.h) decides "the segment meets S in the cell" by four float sign
// tests (the height above each triangle plane at both ends); these are the same operations in
// the same order, lane by lane. The cell walks take the root (in double) per flagged lane, in
// scalar code (once per ray); the pyramid walk, whose cell tests are its per-lane cost, takes all
// of firstHitInCell in SIMD (FirstHitInCell).
#if defined(RELIEF_SURFACE_CELL_TEST_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_CELL_TEST_INL_H_
#undef RELIEF_SURFACE_CELL_TEST_INL_H_
#else
#define RELIEF_SURFACE_CELL_TEST_INL_H_
#endif

#include <hwy/highway.h>
#include <relief/core/math.h>
#include <relief/surface/lane_gather-inl.h>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace cell_test {
namespace hn = hwy::HWY_NAMESPACE;

// The lanes' rays (origin and direction).
template <class VF>
struct LaneRays {
    VF ox, oy, oz, dx, dy, dz;
};

// A cell's two triangle planes across lanes (Surface::cellCorners and planesFromCorners): the
// corner z00 is heights[offset] in the padded heights (rows of `stride`).
template <class VF>
struct LanePlanes {
    VF firstZ0, firstSx, firstSy, secondZ0, secondSx, secondSy;
};

template <class DF, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE LanePlanes<VF> CellPlanesAt(DF df, const float* heights, VI offset, VI stride) {
    VF z00, z10, z01, z11;
    lane_gather::GatherPairs(df, heights, offset, z00, z10);
    lane_gather::GatherPairs(df, heights, hn::Add(offset, stride), z01, z11);
    const auto lowDiagonal = hn::Le(hn::Add(z00, z11), hn::Add(z10, z01));
    return {z00,
            hn::Sub(z10, z00),
            hn::IfThenElse(lowDiagonal, hn::Sub(z11, z10), hn::Sub(z01, z00)),
            hn::IfThenElse(lowDiagonal, z00, hn::Sub(hn::Add(z10, z01), z11)),
            hn::Sub(z11, z01),
            hn::IfThenElse(lowDiagonal, hn::Sub(z01, z00), hn::Sub(z11, z10))};
}

// firstHitOnPlane's height of the ray above a plane at t: origin.z + t·d.z −
// plane.at(ou + t·d.x, ov + t·d.y), with (ou, ov) the origin relative to the cell's centre.
template <class VF>
HWY_INLINE VF AbovePlane(VF z0, VF sx, VF sy, const LaneRays<VF>& r, VF ou, VF ov, VF t) {
    const VF u = hn::Add(ou, hn::Mul(t, r.dx)), v = hn::Add(ov, hn::Mul(t, r.dy));
    const VF plane = hn::Add(hn::Add(z0, hn::Mul(sx, u)), hn::Mul(sy, v));
    return hn::Sub(hn::Add(r.oz, hn::Mul(t, r.dz)), plane);
}

// firstHitOnPlane's line a + b·t in double for the lanes, with a and b as the scalar code forms
// them: −a/b rounded to float, and −1 where b < 0 (else +1).
template <class D, class VF>
HWY_INLINE void PlaneRootsIn(D dd, VF ox, VF oy, VF oz, VF dx, VF dy, VF dz, VF cellX, VF cellY,
                             VF z0, VF sx, VF sy, hn::Vec<D>& root, hn::Vec<D>& sign) {
    const auto du = hn::Sub(ox, cellX), dv = hn::Sub(oy, cellY);
    const auto a = hn::Sub(oz, hn::Add(hn::Add(z0, hn::Mul(sx, du)), hn::Mul(sy, dv)));
    const auto b = hn::Sub(hn::Sub(dz, hn::Mul(sx, dx)), hn::Mul(sy, dy));
    root = hn::Div(hn::Neg(a), b);
    sign = hn::IfThenElse(hn::Lt(b, hn::Zero(dd)), hn::Set(dd, -1.0), hn::Set(dd, 1.0));
}

// Promotes the lanes to double (two vectors of doubles per vector of floats; one for the
// single-lane target), solves each plane's line there and demotes −a/b and the sign of b back.
template <class DF, class VF>
HWY_INLINE void PlaneRoots(DF df, const LaneRays<VF>& r, VF cellX, VF cellY, VF z0, VF sx, VF sy,
                           VF& root, VF& sign) {
#if HWY_TARGET == HWY_SCALAR
    const hn::Rebind<double, DF> dd;
    const auto up = [&](VF v) { return hn::PromoteTo(dd, v); };
    hn::Vec<decltype(dd)> rootD, signD;
    PlaneRootsIn(dd, up(r.ox), up(r.oy), up(r.oz), up(r.dx), up(r.dy), up(r.dz), up(cellX),
                 up(cellY), up(z0), up(sx), up(sy), rootD, signD);
    root = hn::DemoteTo(df, rootD);
    sign = hn::DemoteTo(df, signD);
#else
    const hn::Half<DF> dh;
    const hn::Rebind<double, decltype(dh)> dd;
    hn::Vec<decltype(dd)> rootLo, signLo, rootHi, signHi;
    const auto lo = [&](VF v) { return hn::PromoteTo(dd, hn::LowerHalf(dh, v)); };
    const auto hi = [&](VF v) { return hn::PromoteTo(dd, hn::UpperHalf(dh, v)); };
    PlaneRootsIn(dd, lo(r.ox), lo(r.oy), lo(r.oz), lo(r.dx), lo(r.dy), lo(r.dz), lo(cellX),
                 lo(cellY), lo(z0), lo(sx), lo(sy), rootLo, signLo);
    PlaneRootsIn(dd, hi(r.ox), hi(r.oy), hi(r.oz), hi(r.dx), hi(r.dy), hi(r.dz), hi(cellX),
                 hi(cellY), hi(z0), hi(sx), hi(sy), rootHi, signHi);
    root = hn::Combine(df, hn::DemoteTo(dh, rootHi), hn::DemoteTo(dh, rootLo));
    sign = hn::Combine(df, hn::DemoteTo(dh, signHi), hn::DemoteTo(dh, signLo));
#endif
}

// A segment [ta, tb] of the lanes' rays over a cell: the cell's planes and firstHitOnPlane's
// four heights of the ray above them at the segment's ends (float sign tests decide "certainly
// misses"; the roots only where a lane may meet S).
template <class VF>
struct CellSegment {
    LanePlanes<VF> planes;
    VF cellX, cellY;                      // the cell's centre
    VF firstA, firstB, secondA, secondB;  // above the first / second plane at ta / tb
};

template <class DF, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE CellSegment<VF> MeasureSegment(DF df, const float* heights, VI offset, VI stride,
                                          VF fci, VF fcj, const LaneRays<VF>& r, VF ta, VF tb) {
    const LanePlanes<VF> p = CellPlanesAt(df, heights, offset, stride);
    const VF half = hn::Set(df, 0.5f);
    const VF cellX = hn::Add(fci, half), cellY = hn::Add(fcj, half);
    const VF ou = hn::Sub(r.ox, cellX), ov = hn::Sub(r.oy, cellY);
    return {p,
            cellX,
            cellY,
            AbovePlane(p.firstZ0, p.firstSx, p.firstSy, r, ou, ov, ta),
            AbovePlane(p.firstZ0, p.firstSx, p.firstSy, r, ou, ov, tb),
            AbovePlane(p.secondZ0, p.secondSx, p.secondSy, r, ou, ov, ta),
            AbovePlane(p.secondZ0, p.secondSx, p.secondSy, r, ou, ov, tb)};
}

// Per lane: true where the segment certainly misses S in the cell (every height above the
// planes > 0); elsewhere (NaN included) firstHitInCell decides, and there it returns a t in
// [ta, tb] unless NaN: a lane not flagged here hits, or has NaN in its segment.
template <class DF, class VF = hn::Vec<DF>>
HWY_INLINE hn::Mask<DF> SegmentMisses(DF df, const CellSegment<VF>& s) {
    const VF zero = hn::Zero(df);
    return hn::And(hn::And(hn::Gt(s.firstA, zero), hn::Gt(s.firstB, zero)),
                   hn::And(hn::Gt(s.secondA, zero), hn::Gt(s.secondB, zero)));
}

template <class DF, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE hn::Mask<DF> SegmentMissesCell(DF df, const float* heights, VI offset, VI stride,
                                         VF fci, VF fcj, const LaneRays<VF>& r, VF ta, VF tb) {
    return SegmentMisses(df, MeasureSegment(df, heights, offset, stride, fci, fcj, r, ta, tb));
}

// One cell of cellsHit (cell_walk.h) in the lanes `act`: the cell's exits from its index (tx,
// ty), the segment's end tc = max(ta, min(tx, ty, tb)), the lanes whose segment [ta, tc] may meet
// S there (firstHitInCell decides; a miss gives t = ∞, still a hit when tc = ∞, so those lanes
// are left to it too), the lanes at the walk's end (tc ≥ tb), and the next cell (tx ≤ ty: across
// x). The cell's corners are at `offset` in the padded heights.
template <class VF, class VI, class MI>
struct CellStep {
    VF tc;
    MI candidate, pastEnd, alongX;
    VI ciNext, cjNext;
};

template <class DF, class MI, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE CellStep<VF, VI, MI> StepCell(DF df, MI act, const float* heights, VI offset,
                                         VI stride, VI ci, VI cj, const LaneRays<VF>& r, VF ta,
                                         VF tb, VF invX, VF invY, VF exitX, VF exitY, VI stepX,
                                         VI stepY) {
    const hn::RebindToSigned<DF> di;
    const VI zeroI = hn::Zero(di);
    const VF inf = hn::Set(df, kInfinity);
    const VF fci = hn::ConvertTo(df, ci), fcj = hn::ConvertTo(df, cj);
    const VF tx = hn::IfThenElse(hn::RebindMask(df, hn::Eq(stepX, zeroI)), inf,
                                 hn::Mul(hn::Sub(hn::Add(fci, exitX), r.ox), invX));
    const VF ty = hn::IfThenElse(hn::RebindMask(df, hn::Eq(stepY, zeroI)), inf,
                                 hn::Mul(hn::Sub(hn::Add(fcj, exitY), r.oy), invY));
    // std::max(ta, std::min({tx, ty, tb}))
    VF m = tx;
    m = hn::IfThenElse(hn::Lt(ty, m), ty, m);
    m = hn::IfThenElse(hn::Lt(tb, m), tb, m);
    const VF tc = hn::IfThenElse(hn::Lt(ta, m), m, ta);
    const auto misses = SegmentMissesCell(df, heights, offset, stride, fci, fcj, r, ta, tc);
    const MI alongX = hn::RebindMask(di, hn::Le(tx, ty));
    return {tc,
            hn::AndNot(hn::RebindMask(di, hn::And(misses, hn::Lt(tc, inf))), act),
            hn::And(act, hn::RebindMask(di, hn::Ge(tc, tb))),
            alongX,
            hn::Add(ci, hn::IfThenElseZero(alongX, stepX)),
            hn::Add(cj, hn::IfThenElseZero(hn::Not(alongX), stepY))};
}

// firstHitInCell across lanes, bit for bit, on a measured segment: the smallest t in [ta, tb]
// where the ray is on or below S in the cell, or kInfinity; the float sign tests as above, the
// root in double as the scalar code solves it.
template <class DF, class VF = hn::Vec<DF>>
HWY_INLINE VF FirstHitOnSegment(DF df, const CellSegment<VF>& s, const LaneRays<VF>& r, VF ta,
                                VF tb) {
    const VF zero = hn::Zero(df), inf = hn::Set(df, kInfinity);
    const auto onPlane = [&](VF z0, VF sx, VF sy, VF above0, VF above1) {  // firstHitOnPlane
        VF root, sign;
        PlaneRoots(df, r, s.cellX, s.cellY, z0, sx, sy, root, sign);
        // std::clamp(float(-a / b), ta, tb) where b < 0, else tb
        const VF clamped = hn::IfThenElse(hn::Lt(root, ta), ta,
                                          hn::IfThenElse(hn::Lt(tb, root), tb, root));
        const VF solved = hn::IfThenElse(hn::Lt(sign, zero), clamped, tb);
        const VF beyond = hn::IfThenElse(hn::Gt(above1, zero), inf, solved);
        return hn::IfThenElse(hn::Le(above0, zero), ta, beyond);
    };
    const LanePlanes<VF>& p = s.planes;
    const VF t0 = onPlane(p.firstZ0, p.firstSx, p.firstSy, s.firstA, s.firstB);
    const VF t1 = onPlane(p.secondZ0, p.secondSx, p.secondSy, s.secondA, s.secondB);
    return hn::IfThenElse(hn::Eq(t0, ta), t0, hn::IfThenElse(hn::Lt(t1, t0), t1, t0));
}

}  // namespace cell_test
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_CELL_TEST_INL_H_
