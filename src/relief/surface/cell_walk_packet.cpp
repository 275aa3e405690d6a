// The packet cell walk (cell_walk_packet.h): compiled once per Highway target (foreach_target.h
// re-includes this file), with -ffp-contract=off (CMakeLists.txt) so that no target fuses a
// multiply and an add the scalar walk keeps apart.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "relief/surface/cell_walk_packet.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>
#include <relief/surface/cell_test-inl.h>
#include <relief/surface/cell_walk.h>
#include <relief/surface/cell_walk_packet.h>
#include <relief/surface/packet_lanes-inl.h>
#include <relief/surface/ray_feed-inl.h>

#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace cell_walk {

using namespace packet_lanes;  // DF, DI, VF, VI, MF, MI, kLanes

// The lanes' state, structure of arrays, read into vectors when lanes change rays.
struct Packet {
    alignas(64) float ta[kLanes], tb[kLanes];
    alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    alignas(64) float invX[kLanes], invY[kLanes], exitX[kLanes], exitY[kLanes];
    // ci, cj: the cell; wi, wj: its column and row in the padded heights, wrapped (repeat mode
    // only)
    alignas(64) int32_t ci[kLanes], cj[kLanes], wi[kLanes], wj[kLanes];
    alignas(64) int32_t stepX[kLanes], stepY[kLanes], steps[kLanes], active[kLanes];
    alignas(64) int32_t candidate[kLanes], done[kLanes];
    alignas(64) float tc[kLanes];
    size_t index[kLanes];
};

struct Walk {
    const Surface& s;
    const float* heights;  // paddedHeights()
    std::span<const Ray> rays;
    std::span<Hit> hits;
    ray_feed::RayFeed feed{s, rays, hits};  // the rays, clipped a chunk at a time

    // Puts the batch's next ray that enters the box into `lane` (as cellsHit starts it), or parks
    // the lane.
    void fill(Packet& p, size_t lane) {
        size_t i;
        RayInterval span;
        if (!feed.next(i, span)) return park(p, lane);
        const Ray& ray = rays[i];
        const vec3 start = ray.at(span.tEnter);
        const int ci = s.cellOfX(start.x), cj = s.cellOfY(start.y);
        const bool clamp = s.edge() == EdgeMode::Clamp;
        p.ta[lane] = span.tEnter;
        p.tb[lane] = span.tExit;
        packet_lanes::setCellWalkRay(p, lane, ray);
        p.ci[lane] = ci;
        p.cj[lane] = cj;
        p.wi[lane] = clamp ? ci : texelIndex(ci, s.width(), EdgeMode::Repeat);
        p.wj[lane] = clamp ? cj : texelIndex(cj, s.height(), EdgeMode::Repeat);
        p.steps[lane] = 0;
        p.active[lane] = -1;
        p.index[lane] = i;
    }

    // An idle lane: on cell (-1, -1), whose corners are in the array, and not moving.
    static void park(Packet& p, size_t lane) {
        p.active[lane] = 0;
        p.ci[lane] = p.cj[lane] = p.wi[lane] = p.wj[lane] = -1;
        p.stepX[lane] = p.stepY[lane] = 0;
        p.tb[lane] = p.ta[lane] = 0.0f;
    }

    // cellsHit's loop in every active lane until the batch is done. kRepeat: the surface's
    // repeat mode, compiled in (in clamp mode a cell's padded column and row are its own, +1, so
    // the wrapped ones wi, wj are work only repeat needs).
    template <bool kRepeat>
    void run(Packet& p) {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1);
        const VF zero = hn::Zero(df);
        const int32_t width = s.width(), height = s.height();
        const VI stride = hn::Set(di, width + 2);
        const VI lastX = hn::Set(di, width - 1), lastY = hn::Set(di, height - 1);
        const VI columns = hn::Set(di, width), rows = hn::Set(di, height);
        const VI minusOne = hn::Set(di, -1);

        MI act = hn::MaskFromVec(zeroI);
        VF ta = zero, tb = zero, ox = zero, oy = zero, oz = zero, dx = zero, dy = zero, dz = zero,
           invX = zero, invY = zero, exitX = zero, exitY = zero;
        VI ci = zeroI, cj = zeroI, wi = zeroI, wj = zeroI, stepX = zeroI, stepY = zeroI,
           steps = zeroI;
        const auto reload = [&] {
            act = hn::MaskFromVec(hn::Load(di, p.active));
            ta = hn::Load(df, p.ta);
            tb = hn::Load(df, p.tb);
            ox = hn::Load(df, p.ox);
            oy = hn::Load(df, p.oy);
            oz = hn::Load(df, p.oz);
            dx = hn::Load(df, p.dx);
            dy = hn::Load(df, p.dy);
            dz = hn::Load(df, p.dz);
            invX = hn::Load(df, p.invX);
            invY = hn::Load(df, p.invY);
            exitX = hn::Load(df, p.exitX);
            exitY = hn::Load(df, p.exitY);
            ci = hn::Load(di, p.ci);
            cj = hn::Load(di, p.cj);
            wi = hn::Load(di, p.wi);
            wj = hn::Load(di, p.wj);
            stepX = hn::Load(di, p.stepX);
            stepY = hn::Load(di, p.stepY);
            steps = hn::Load(di, p.steps);
        };
        // What changes during the walk (the rest only in `fill`).
        const auto spill = [&] {
            hn::Store(ta, df, p.ta);
            hn::Store(ci, di, p.ci);
            hn::Store(cj, di, p.cj);
            if constexpr (kRepeat) {
                hn::Store(wi, di, p.wi);
                hn::Store(wj, di, p.wj);
            }
            hn::Store(steps, di, p.steps);
        };
        reload();
        if (hn::AllFalse(di, act)) return;  // the batch's rays all miss the box
        for (;;) {
            // One cell of cellsHit (cell_test-inl.h): its exits, the segment [ta, tc] against S.
            const VI offset = kRepeat
                                  ? hn::Add(hn::Mul(hn::Add(wj, oneI), stride), hn::Add(wi, oneI))
                                  : hn::Add(hn::Mul(hn::Add(cj, oneI), stride), hn::Add(ci, oneI));
            const auto cell = cell_test::StepCell(df, act, heights, offset, stride, ci, cj,
                                                  {ox, oy, oz, dx, dy, dz}, ta, tb, invX, invY,
                                                  exitX, exitY, stepX, stepY);
            const VF tc = cell.tc;
            const MI candidate = cell.candidate, pastEnd = cell.pastEnd, alongX = cell.alongX;
            const VI ciNext = cell.ciNext, cjNext = cell.cjNext;
            steps = hn::Add(steps, hn::IfThenElseZero(act, oneI));
            // The next cell's padded column and row, and in clamp mode whether it leaves the
            // cells.
            VI wiNext = wi, wjNext = wj;
            MI leaves = hn::AndNot(act, act);  // none (repeat)
            if constexpr (!kRepeat) {
                leaves = hn::Or(hn::Or(hn::Lt(ciNext, minusOne), hn::Gt(ciNext, lastX)),
                                hn::Or(hn::Lt(cjNext, minusOne), hn::Gt(cjNext, lastY)));
            } else {
                // Wrapped: columns and rows stay in [0, W) and [0, H).
                wiNext = hn::Add(wi, hn::IfThenElseZero(alongX, stepX));
                wjNext = hn::Add(wj, hn::IfThenElseZero(hn::Not(alongX), stepY));
                wiNext = hn::IfThenElse(hn::Eq(wiNext, columns), zeroI, wiNext);
                wiNext = hn::IfThenElse(hn::Lt(wiNext, zeroI), lastX, wiNext);
                wjNext = hn::IfThenElse(hn::Eq(wjNext, rows), zeroI, wjNext);
                wjNext = hn::IfThenElse(hn::Lt(wjNext, zeroI), lastY, wjNext);
            }
            const MI exits = hn::Or(pastEnd, hn::And(act, leaves));

            if (hn::AllFalse(di, hn::Or(candidate, exits))) {
                ta = hn::IfThenElse(hn::RebindMask(df, act), tc, ta);
                ci = hn::IfThenElse(act, ciNext, ci);
                cj = hn::IfThenElse(act, cjNext, cj);
                if constexpr (kRepeat) {
                    wi = hn::IfThenElse(act, wiNext, wi);
                    wj = hn::IfThenElse(act, wjNext, wj);
                }
                continue;
            }

            // Lanes that may end here, one by one: the hit (scalar firstHitInCell), the exit.
            spill();
            hn::Store(tc, df, p.tc);
            hn::Store(hn::VecFromMask(di, candidate), di, p.candidate);
            hn::Store(hn::VecFromMask(di, exits), di, p.done);
            uint64_t finished = 0;  // lanes whose hit is written: bit k
            ForEachLane(hn::Or(candidate, exits), [&](size_t k) {
                const size_t i = p.index[k];
                const Ray& ray = rays[i];
                Hit hit;
                hit.steps = p.steps[k];
                hit.fetches = 4 * p.steps[k];
                if (p.candidate[k]) {
                    const float tCell = p.tc[k];
                    const float t = firstHitInCell(s.cellPlanes(p.ci[k], p.cj[k]), ray, p.ci[k],
                                                   p.cj[k], p.ta[k], tCell);
                    if (t <= tCell) {
                        setHit(ray, t, hit);
                        hits[i] = hit;
                        finished |= uint64_t(1) << k;
                        return;
                    }
                }
                if (!p.done[k]) return;
                if (p.tc[k] >= p.tb[k] && exitsThroughFloor(s, ray, p.tb[k]))
                    setHit(ray, p.tb[k], hit);  // cellsHit's rule at the box exit (toExit)
                hits[i] = hit;
                finished |= uint64_t(1) << k;
            });
            // Lanes that go on move to their next cell; finished ones take new rays.
            const MI goesOn = hn::AndNot(hn::MaskFromVec(hn::Load(di, p.done)), act);
            hn::Store(hn::IfThenElse(hn::RebindMask(df, goesOn), tc, ta), df, p.ta);
            hn::Store(hn::IfThenElse(goesOn, ciNext, ci), di, p.ci);
            hn::Store(hn::IfThenElse(goesOn, cjNext, cj), di, p.cj);
            if constexpr (kRepeat) {
                hn::Store(hn::IfThenElse(goesOn, wiNext, wi), di, p.wi);
                hn::Store(hn::IfThenElse(goesOn, wjNext, wj), di, p.wj);
            }
            ForEachLane(finished, [&](size_t k) { fill(p, k); });
            if (hn::AllFalse(di, hn::MaskFromVec(hn::Load(di, p.active)))) return;
            reload();
        }
    }
};

}  // namespace cell_walk

void CellsHitPackets(const Surface& surface, std::span<const Ray> rays, std::span<Hit> hits) {
    using namespace cell_walk;
    Walk walk{surface, surface.paddedHeights().data(), rays, hits};
    Packet p{};
    for (size_t k = 0; k < kLanes; ++k) {
        Walk::park(p, k);
        if (k < hn::Lanes(DF())) walk.fill(p, k);
    }
    if (surface.edge() == EdgeMode::Repeat)
        walk.run<true>(p);
    else
        walk.run<false>(p);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(CellsHitPackets);

bool packetCellWalkSupports(const Surface& surface) {
    const size_t padded = surface.paddedHeights().size();
    return padded + size_t(surface.width()) + 4 < size_t(std::numeric_limits<int32_t>::max());
}

void cellsHitPackets(const Surface& surface, std::span<const Ray> rays, std::span<Hit> hits) {
    HWY_DYNAMIC_DISPATCH(CellsHitPackets)(surface, rays, hits);
}

}  // namespace relief
#endif  // HWY_ONCE
