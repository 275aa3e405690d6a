// The cell test of the packet walks (surface/cell_walk_packet.cpp, cone/cone_packet.cpp), per
// Highway target: included by their foreach_target translation units once per target (Highway's
// -inl.h convention: the guard toggles with HWY_TARGET_TOGGLE).
// firstHitInCell (cell_intersect.h) decides "the segment meets S in the cell" by four float sign
// tests (the height above each triangle plane at both ends); these are the same operations in
// the same order, lane by lane. The root itself (in double) stays scalar: it is computed once per
// ray, for the lanes these tests flag.
#if defined(RELIEF_SURFACE_CELL_TEST_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef RELIEF_SURFACE_CELL_TEST_INL_H_
#undef RELIEF_SURFACE_CELL_TEST_INL_H_
#else
#define RELIEF_SURFACE_CELL_TEST_INL_H_
#endif

#include <hwy/highway.h>

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

// Per lane: true where the segment [ta, tb] of the ray certainly misses S in cell (fci, fcj)
// (its index as floats), whose corner z00 is heights[offset] in the padded heights (rows of
// `stride`): every one of firstHitOnPlane's four heights above the planes is > 0. Elsewhere
// (NaN included) firstHitInCell decides.
template <class DF, class VF = hn::Vec<DF>, class VI = hn::Vec<hn::RebindToSigned<DF>>>
HWY_INLINE hn::Mask<DF> SegmentMissesCell(DF df, const float* heights, VI offset, VI stride,
                                         VF fci, VF fcj, const LaneRays<VF>& r, VF ta, VF tb) {
    const hn::RebindToSigned<DF> di;
    const VI one = hn::Set(di, 1);
    // Surface::cellCorners and planesFromCorners.
    const VF z00 = hn::GatherIndex(df, heights, offset);
    const VF z10 = hn::GatherIndex(df, heights, hn::Add(offset, one));
    const VF z01 = hn::GatherIndex(df, heights, hn::Add(offset, stride));
    const VF z11 = hn::GatherIndex(df, heights, hn::Add(hn::Add(offset, stride), one));
    const auto lowDiagonal = hn::Le(hn::Add(z00, z11), hn::Add(z10, z01));
    const VF firstSx = hn::Sub(z10, z00);
    const VF firstSy = hn::IfThenElse(lowDiagonal, hn::Sub(z11, z10), hn::Sub(z01, z00));
    const VF secondZ0 = hn::IfThenElse(lowDiagonal, z00, hn::Sub(hn::Add(z10, z01), z11));
    const VF secondSx = hn::Sub(z11, z01);
    const VF secondSy = hn::IfThenElse(lowDiagonal, hn::Sub(z01, z00), hn::Sub(z11, z10));
    // firstHitOnPlane: origin.z + t·d.z − plane.at(ou + t·d.x, ov + t·d.y)
    const VF half = hn::Set(df, 0.5f);
    const VF ou = hn::Sub(r.ox, hn::Add(fci, half)), ov = hn::Sub(r.oy, hn::Add(fcj, half));
    const auto above = [&](VF z0, VF sx, VF sy, VF t) {
        const VF u = hn::Add(ou, hn::Mul(t, r.dx)), v = hn::Add(ov, hn::Mul(t, r.dy));
        const VF plane = hn::Add(hn::Add(z0, hn::Mul(sx, u)), hn::Mul(sy, v));
        return hn::Sub(hn::Add(r.oz, hn::Mul(t, r.dz)), plane);
    };
    const VF zero = hn::Zero(df);
    return hn::And(hn::And(hn::Gt(above(z00, firstSx, firstSy, ta), zero),
                           hn::Gt(above(z00, firstSx, firstSy, tb), zero)),
                   hn::And(hn::Gt(above(secondZ0, secondSx, secondSy, ta), zero),
                           hn::Gt(above(secondZ0, secondSx, secondSy, tb), zero)));
}

}  // namespace cell_test
}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#endif  // RELIEF_SURFACE_CELL_TEST_INL_H_
