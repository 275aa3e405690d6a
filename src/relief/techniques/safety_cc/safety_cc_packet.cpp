// The packet cylinder-cone march (safety_cc_packet.h): compiled once per Highway target
// (foreach_target.h re-includes this file), with -ffp-contract=off (CMakeLists.txt) so that no
// target fuses a multiply and an add the scalar march keeps apart.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "relief/techniques/safety_cc/safety_cc_packet.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>
#include <relief/surface/cell_test-inl.h>
#include <relief/surface/cell_walk.h>
#include <relief/surface/packet_lanes-inl.h>
#include <relief/surface/ray_feed-inl.h>
#include <relief/techniques/safety_cc/safety_cc_packet.h>

#include <algorithm>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace safety_cc_march {


using namespace packet_lanes;  // DF, DI, VF, VI, MF, MI, kLanes
using Walk = SafetyCcTracer::Walk;

// What a lane does in the next pass.
enum Phase : int32_t { kCells = 0, kJump = 1, kBisect = 2 };

// The lanes' state, structure of arrays: every pass loads what it needs and stores what changed
// (the state is too large for the registers of AVX2).
struct Packet {
    // The ray, and cellsHit's per-ray constants.
    alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    alignas(64) float invX[kLanes], invY[kLanes], exitX[kLanes], exitY[kLanes];
    alignas(64) int32_t stepX[kLanes], stepY[kLanes];
    // The march (Walk), and where its class's map and the heights lie along A and B.
    alignas(64) float oA[kLanes], oB[kLanes], dB[kLanes], invA[kLanes], rise[kLanes];
    alignas(64) float tEnter[kLanes], tExit[kLanes];
    alignas(64) int32_t k0[kLanes], sign[kLanes], count[kLanes], lenA[kLanes], lenB[kLanes];
    alignas(64) int32_t texelBase[kLanes], texelA[kLanes], texelB[kLanes];
    alignas(64) int32_t heightA[kLanes], heightB[kLanes];
    // Where the lane is: a cell walk over [ta, tb] in cell (ci, cj), then the march from
    // centerline `resume` (or, toExit, the end of the ray); a jump from n; a bisection of
    // (lo, hi).
    alignas(64) int32_t phase[kLanes], n[kLanes], lo[kLanes], hi[kLanes];
    alignas(64) float ta[kLanes], tb[kLanes];
    alignas(64) int32_t ci[kLanes], cj[kLanes], resume[kLanes], toExit[kLanes];
    alignas(64) int32_t steps[kLanes], fetches[kLanes], active[kLanes];
    // Written in a pass with events, for its scalar part (which reads only those lanes): a cell
    // that may hold the hit, a walk to the exit that ended.
    alignas(64) int32_t candidate[kLanes], exitEnds[kLanes], pastEnd[kLanes];
    alignas(64) int32_t cellI[kLanes], cellJ[kLanes];
    alignas(64) float cellTa[kLanes], cellTc[kLanes];
    size_t index[kLanes];
};

struct March {
    const SafetyCcTracer& tracer;
    const Surface& s;
    const float* heights;      // paddedHeights()
    const float* texels;       // ConeTexel as 4 floats: z0, s_c, r (int32), z_c
    const int32_t* radii;      // texels' r, at the same indices
    bool positiveDistance;
    std::span<const Ray> rays;
    std::span<Hit> hits;
    ray_feed::RayFeed feed{s, rays, hits};  // the rays, clipped a chunk at a time

    // Where a class's map and the heights lie along its axes A and B: map.at(cls, i, j) and
    // sampleZ(i, j), with (i, j) = (a, b) on axis 0, (b, a) on axis 1.
    struct ClassLayout {
        int32_t lenA, lenB, texelBase, texelA, texelB, heightA, heightB;
    };
    ClassLayout classLayout(int cls) const {
        const int width = s.width(), height = s.height(), axis = cls / 2;
        const int mapClass = tracer.shape().map().classes == 1 ? 0 : cls;
        return {axis == 0 ? width : height, axis == 0 ? height : width,
                mapClass * height * width,  axis == 0 ? 1 : width,
                axis == 0 ? width : 1,      axis == 0 ? 1 : width + 2,
                axis == 0 ? width + 2 : 1};
    }
    const ClassLayout layouts[4] = {classLayout(0), classLayout(1), classLayout(2), classLayout(3)};
    // How many lanes must want a jump or a bisection step before a pass takes them (see pass):
    // 5 of 8 lanes, the best of 1, 3, 5, 6 and 8 on AVX2 (docs/benchmarks-packets.md,
    // 2026-12-07, stop 42); the same share of other widths.
    const size_t probeBatch = BatchOf(5);
    // Whether no ray can fall back on the exact walk for its direction or origin (φ_max = 90°, no
    // exterior maps): the starts are then made across lanes.
    const bool startsAcrossLanes = !std::isfinite(safety::tanPhiMax(tracer.options().phiMaxDeg)) &&
                                   !tracer.options().exterior;

    // The feed's current chunk's starts (SafetyTracer::setUp, the reciprocals of cellsHit, the
    // entry walk's span and first cell), made a chunk at a time: across lanes where
    // startsAcrossLanes, the same operations in the same order as setUp and Surface::cellOfX; lane by
    // lane, by setUp itself, for the chunk's tail and the other options. A lane's start was a
    // seventh of the march's time.
    struct Starts {
        static constexpr size_t kChunk = ray_feed::RayFeed::kChunk;
        alignas(64) float oA[kChunk], oB[kChunk], dB[kChunk], invA[kChunk], rise[kChunk];
        alignas(64) float invX[kChunk], invY[kChunk], firstT[kChunk];
        alignas(64) int32_t k0[kChunk], sign[kChunk], count[kChunk], cls[kChunk];
        alignas(64) int32_t marches[kChunk], ci[kChunk], cj[kChunk];
        size_t chunk = ~size_t(0);  // the chunk's first ray
    } starts{};

    void makeStarts() {
        const DF df;
        const DI di;
        const size_t n = hn::Lanes(df), begin = feed.chunkBegin();
        const size_t count = feed.chunkEnd() - begin;
        const size_t whole = startsAcrossLanes ? count / n * n : 0;
        const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f);
        const VI oneI = hn::Set(di, 1), minusOne = hn::Set(di, -1);
        const VI lastX = hn::Set(di, s.width() - 1), lastY = hn::Set(di, s.height() - 1);
        for (size_t k = 0; k < whole; k += n) {
            const auto field = [&](int32_t c) {  // the chunk's rays: small gather offsets
                return ray_feed::GatherRayField(df, rays.data(), begin + k, c);
            };
            const VF ox = field(0), oy = field(1), dx = field(3), dy = field(4), dz = field(5);
            const VF tEnter = hn::Load(df, feed.chunkEnter() + k);
            const VF tExit = hn::Load(df, feed.chunkExit() + k);
            // setUp: the axis A of the larger horizontal component, its direction and class
            const MF alongY = hn::Lt(hn::Abs(dx), hn::Abs(dy));
            const VF dA = hn::IfThenElse(alongY, dy, dx);
            const MF forward = hn::Gt(dA, zero);
            const VI sign = hn::IfThenElse(hn::RebindMask(di, forward), oneI, minusOne);
            const VI cls = hn::Add(hn::IfThenElseZero(hn::RebindMask(di, alongY), hn::Set(di, 2)),
                                   hn::IfThenZeroElse(hn::RebindMask(di, forward), oneI));
            const VF oA = hn::Sub(hn::IfThenElse(alongY, oy, ox), half);
            const VF oB = hn::Sub(hn::IfThenElse(alongY, ox, oy), half);
            const VF invA = hn::Div(one, dA);
            const MF entered = hn::Le(tEnter, tExit);  // !span.empty()
            const VF aEnterRay = hn::Add(oA, hn::Mul(tEnter, dA));
            const VF aExitRay = hn::Add(oA, hn::Mul(tExit, dA));
            const MF flat = hn::Or(hn::Eq(dA, zero), hn::Not(hn::And(hn::IsFinite(aEnterRay),
                                                                     hn::IsFinite(aExitRay))));
            // Lanes that miss the box or are flat never march: 0 keeps their conversions to
            // int defined (such a ray's position may be anything, NaN or far away).
            const MF spans = hn::AndNot(flat, entered);
            const VF aEnter = hn::IfThenElseZero(spans, aEnterRay);
            const VF aExit = hn::IfThenElseZero(spans, aExitRay);
            const VI k0 = hn::ConvertTo(
                di, hn::IfThenElse(forward, hn::Ceil(aEnter), hn::Floor(aEnter)));
            const VI kL = hn::ConvertTo(
                di, hn::IfThenElse(forward, hn::Floor(aExit), hn::Ceil(aExit)));
            const VI centerlines = hn::Mul(hn::Sub(kL, k0), sign);
            const MI marches = hn::And(
                hn::RebindMask(di, spans),
                hn::Not(hn::Lt(centerlines, hn::Set(di, safety::kMinCenterlines))));
            // Walk::tOf(0), and the entry walk's first cell: that of ray.at(tEnter)
            const VF t0 = hn::Mul(hn::Sub(hn::ConvertTo(df, k0), oA), invA);
            const VF firstT = hn::IfThenElse(hn::Lt(t0, tEnter), tEnter,
                                             hn::IfThenElse(hn::Lt(tExit, t0), tExit, t0));
            const auto cellOf = [&](VF o, VF d, VI last) {
                const VF x = hn::IfThenElseZero(entered, hn::Add(o, hn::Mul(tEnter, d)));
                return hn::Min(hn::Max(hn::ConvertTo(di, hn::Floor(hn::Sub(x, half))), minusOne),
                               last);
            };
            hn::Store(oA, df, starts.oA + k);
            hn::Store(oB, df, starts.oB + k);
            hn::Store(hn::IfThenElse(alongY, dx, dy), df, starts.dB + k);
            hn::Store(invA, df, starts.invA + k);
            hn::Store(hn::Mul(dz, hn::Abs(invA)), df, starts.rise + k);
            hn::Store(hn::Div(one, dx), df, starts.invX + k);
            hn::Store(hn::Div(one, dy), df, starts.invY + k);
            hn::Store(firstT, df, starts.firstT + k);
            hn::Store(k0, di, starts.k0 + k);
            hn::Store(sign, di, starts.sign + k);
            hn::Store(centerlines, di, starts.count + k);
            hn::Store(cls, di, starts.cls + k);
            hn::Store(hn::VecFromMask(di, marches), di, starts.marches + k);
            hn::Store(cellOf(ox, dx, lastX), di, starts.ci + k);
            hn::Store(cellOf(oy, dy, lastY), di, starts.cj + k);
        }
        for (size_t k = whole; k < count; ++k) {  // lane by lane
            const RayInterval span{feed.chunkEnter()[k], feed.chunkExit()[k]};
            if (span.empty()) continue;
            const Ray& ray = rays[begin + k];
            Walk w;
            starts.marches[k] = tracer.setUp(ray, span, w) ? -1 : 0;
            if (!starts.marches[k]) continue;
            starts.oA[k] = w.oA;
            starts.oB[k] = w.oB;
            starts.dB[k] = w.dB;
            starts.invA[k] = w.invA;
            starts.rise[k] = w.rise;
            starts.invX[k] = 1.0f / ray.direction.x;
            starts.invY[k] = 1.0f / ray.direction.y;
            starts.firstT[k] = w.tOf(0);
            starts.k0[k] = w.k0;
            starts.sign[k] = w.sign;
            starts.count[k] = w.count;
            starts.cls[k] = w.cls;
            starts.ci[k] = s.cellOfX(ray.origin.x + span.tEnter * ray.direction.x);
            starts.cj[k] = s.cellOfY(ray.origin.y + span.tEnter * ray.direction.y);
        }
        starts.chunk = begin;
    }

    // Puts the batch's next ray that the march follows into `lane` (as trace starts it), or parks
    // the lane; the rays it hands to the exact walk are traced here, as trace does.
    void fill(Packet& p, size_t lane) {
        for (;;) {
            size_t i;
            RayInterval span;
            if (!feed.next(i, span)) return park(p, lane);
            if (feed.chunkBegin() != starts.chunk) makeStarts();
            const size_t k = i - starts.chunk;
            const Ray& ray = rays[i];
            if (!starts.marches[k]) {
                Hit hit;
                cellsHit(s, ray, span.tEnter, span.tExit, true, hit);
                hits[i] = hit;
                continue;
            }
            packet_lanes::setCellWalkRay(p, lane, ray, starts.invX[k], starts.invY[k]);
            p.oA[lane] = starts.oA[k];
            p.oB[lane] = starts.oB[k];
            p.dB[lane] = starts.dB[k];
            p.invA[lane] = starts.invA[k];
            p.rise[lane] = starts.rise[k];
            p.tEnter[lane] = span.tEnter;
            p.tExit[lane] = span.tExit;
            p.k0[lane] = starts.k0[k];
            p.sign[lane] = starts.sign[k];
            p.count[lane] = starts.count[k];
            const ClassLayout& c = layouts[starts.cls[k]];
            p.lenA[lane] = c.lenA;
            p.lenB[lane] = c.lenB;
            p.texelBase[lane] = c.texelBase;
            p.texelA[lane] = c.texelA;
            p.texelB[lane] = c.texelB;
            p.heightA[lane] = c.heightA;
            p.heightB[lane] = c.heightB;
            p.n[lane] = p.lo[lane] = p.hi[lane] = 0;
            p.steps[lane] = p.fetches[lane] = 0;
            p.active[lane] = -1;
            p.index[lane] = i;
            // The walk up to the first centerline, then the march from centerline 0.
            const float firstT = starts.firstT[k];
            p.phase[lane] = kCells;
            p.ta[lane] = span.tEnter;
            p.tb[lane] = firstT;
            p.ci[lane] = starts.ci[k];
            p.cj[lane] = starts.cj[k];
            p.resume[lane] = 0;
            p.toExit[lane] = 0;
            // The march's first fetch, at centerline 0 once the entry cells are walked: asked
            // for now (fetchStep's texel; see pass's texelOf).
            const int a = std::clamp(starts.k0[k], 0, c.lenA - 1);
            const int b = std::clamp(int(std::floor(starts.oB[k] + firstT * starts.dB[k] + 0.5f)),
                                     0, c.lenB - 1);
            hwy::Prefetch(texels + 4 * (c.texelBase + a * c.texelA + b * c.texelB));
            return;
        }
    }

    // An idle lane: every index it gathers from stays in its array.
    static void park(Packet& p, size_t lane) {
        p.active[lane] = 0;
        p.phase[lane] = kCells;
        p.ox[lane] = p.oy[lane] = p.oz[lane] = p.dx[lane] = p.dy[lane] = p.dz[lane] = 0.0f;
        p.invX[lane] = p.invY[lane] = p.exitX[lane] = p.exitY[lane] = 0.0f;
        p.stepX[lane] = p.stepY[lane] = 0;
        p.oA[lane] = p.oB[lane] = p.dB[lane] = p.invA[lane] = p.rise[lane] = 0.0f;
        p.tEnter[lane] = p.tExit[lane] = p.ta[lane] = p.tb[lane] = 0.0f;
        p.k0[lane] = p.count[lane] = p.n[lane] = p.lo[lane] = p.hi[lane] = 0;
        p.sign[lane] = 1;
        p.lenA[lane] = p.lenB[lane] = 1;
        p.texelBase[lane] = p.texelA[lane] = p.texelB[lane] = 0;
        p.heightA[lane] = p.heightB[lane] = 0;
        p.ci[lane] = p.cj[lane] = -1;
        p.resume[lane] = p.toExit[lane] = 0;
        p.steps[lane] = p.fetches[lane] = 0;
    }

    // One pass of the march in every active lane; false once no lane has a ray left.
    bool pass(Packet& p) {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1), twoI = hn::Set(di, 2),
                 fourI = hn::Set(di, 4), minusOne = hn::Set(di, -1);
        const VF zero = hn::Zero(df), half = hn::Set(df, 0.5f);
        const VF margin = hn::Set(df, tracer.margin());
        const VF farStep = hn::Set(df, float(safety::kFarStep));
        const VI farStepI = hn::Set(di, safety::kFarStep);
        const VI stride = hn::Set(di, s.width() + 2);
        const VI lastX = hn::Set(di, s.width() - 1), lastY = hn::Set(di, s.height() - 1);
        const MI none = hn::MaskFromVec(zeroI);

        // Walk::tOf(n) across lanes.
        const auto tOf = [&](VI nV) {
            const VF a = hn::ConvertTo(
                df, hn::Add(hn::Load(di, p.k0), hn::Mul(hn::Load(di, p.sign), nV)));
            const VF t = hn::Mul(hn::Sub(a, hn::Load(df, p.oA)), hn::Load(df, p.invA));
            const VF lo = hn::Load(df, p.tEnter), hi = hn::Load(df, p.tExit);
            return hn::IfThenElse(hn::Lt(t, lo), lo, hn::IfThenElse(hn::Lt(hi, t), hi, t));
        };

        // fetchStep's texel (as the 4-float index of its z0): the map's texel nearest the
        // position on centerline nV, at t = tOf(nV), clamped into the class's map.
        const auto texelOf = [&](VI nV, VF t) {
            const VI a = hn::Min(
                hn::Max(hn::Add(hn::Load(di, p.k0), hn::Mul(hn::Load(di, p.sign), nV)), zeroI),
                hn::Sub(hn::Load(di, p.lenA), oneI));
            const VF bF = hn::Add(hn::Load(df, p.oB), hn::Mul(t, hn::Load(df, p.dB)));
            const VI b = hn::Min(hn::Max(hn::ConvertTo(di, hn::Floor(hn::Add(bF, half))), zeroI),
                                 hn::Sub(hn::Load(di, p.lenB), oneI));
            return hn::ShiftLeft<2>(hn::Add(hn::Load(di, p.texelBase),
                                            hn::Add(hn::Mul(a, hn::Load(di, p.texelA)),
                                                    hn::Mul(b, hn::Load(di, p.texelB)))));
        };

        {
            const MI act = hn::MaskFromVec(hn::Load(di, p.active));
            const VI phase = hn::Load(di, p.phase);
            const MI walking = hn::And(act, hn::Eq(phase, hn::Set(di, kCells)));
            MI jumping = hn::And(act, hn::Eq(phase, hn::Set(di, kJump)));
            const MI bisecting = hn::And(act, hn::Eq(phase, hn::Set(di, kBisect)));
            VI steps = hn::Load(di, p.steps), fetches = hn::Load(di, p.fetches);
            // Lanes that begin a cell walk at the end of this pass, and its span and sequel.
            MI begins = none;
            VF beginTa = zero, beginTb = zero;
            VI beginResume = zeroI, beginToExit = zeroI;
            MI events = none;

            if (!hn::AllFalse(di, walking)) {
                // One cell of cellsHit (cell_test-inl.h): its exits, the segment [ta, tc] against
                // S, the next cell.
                const VF ta = hn::Load(df, p.ta), tb = hn::Load(df, p.tb);
                const VI ci = hn::Load(di, p.ci), cj = hn::Load(di, p.cj);
                const VI offset = hn::Add(hn::Mul(hn::Add(cj, oneI), stride), hn::Add(ci, oneI));
                const auto cell = cell_test::StepCell(
                    df, walking, heights, offset, stride, ci, cj,
                    {hn::Load(df, p.ox), hn::Load(df, p.oy), hn::Load(df, p.oz),
                     hn::Load(df, p.dx), hn::Load(df, p.dy), hn::Load(df, p.dz)},
                    ta, tb, hn::Load(df, p.invX), hn::Load(df, p.invY), hn::Load(df, p.exitX),
                    hn::Load(df, p.exitY), hn::Load(di, p.stepX), hn::Load(di, p.stepY));
                const VF tc = cell.tc;
                const MI candidate = cell.candidate, pastEnd = cell.pastEnd;
                const VI ciNext = cell.ciNext, cjNext = cell.cjNext;
                steps = hn::Add(steps, hn::IfThenElseZero(walking, oneI));
                fetches = hn::Add(fetches, hn::IfThenElseZero(walking, fourI));
                const MI leaves = hn::Or(hn::Or(hn::Lt(ciNext, minusOne), hn::Gt(ciNext, lastX)),
                                         hn::Or(hn::Lt(cjNext, minusOne), hn::Gt(cjNext, lastY)));
                const MI ends = hn::Or(pastEnd, hn::And(walking, leaves));
                const MI goesOn = hn::AndNot(ends, walking);
                hn::Store(hn::IfThenElse(hn::RebindMask(df, goesOn), tc, ta), df, p.ta);
                hn::Store(hn::IfThenElse(goesOn, ciNext, ci), di, p.ci);
                hn::Store(hn::IfThenElse(goesOn, cjNext, cj), di, p.cj);

                // A walk that ends without a hit: the march goes on from `resume`, or (no
                // centerline left) walks to the exit; a walk to the exit ends the ray.
                const MI toExit = hn::MaskFromVec(hn::Load(di, p.toExit));
                const MI exitEnds = hn::And(ends, toExit);
                const MI resumes = hn::AndNot(toExit, ends);
                const VI resume = hn::Load(di, p.resume), count = hn::Load(di, p.count);
                const MI lastOne = hn::And(resumes, hn::Not(hn::Lt(resume, count)));
                hn::Store(hn::IfThenElse(resumes, resume, hn::Load(di, p.n)), di, p.n);
                hn::Store(hn::IfThenElse(hn::AndNot(lastOne, resumes), hn::Set(di, kJump), phase),
                          di, p.phase);
                begins = lastOne;
                beginTa = tOf(count);
                beginTb = hn::Load(df, p.tExit);
                beginToExit = hn::VecFromMask(di, lastOne);

                // A walk that ends here and resumes the march jumps in this same pass (the
                // lane's operations in the same order, one pass fewer per naive step); not
                // where the cell may hold the hit, which the scalar part decides first.
                jumping = hn::Or(jumping, hn::AndNot(candidate, hn::AndNot(lastOne, resumes)));
                events = hn::Or(candidate, exitEnds);
                if (!hn::AllFalse(di, events)) {
                    hn::Store(hn::VecFromMask(di, candidate), di, p.candidate);
                    hn::Store(hn::VecFromMask(di, exitEnds), di, p.exitEnds);
                    hn::Store(hn::VecFromMask(di, pastEnd), di, p.pastEnd);
                    hn::Store(ci, di, p.cellI);
                    hn::Store(cj, di, p.cellJ);
                    hn::Store(ta, df, p.cellTa);
                    hn::Store(tc, df, p.cellTc);
                }
            }

            // The probes (a jump's fetch and landing, a bisection step) are a vector's work however
            // few lanes take one, and most passes have lanes in both phases: the lanes that want a
            // probe wait, their state unchanged, until probeBatch of them do or no lane walks a
            // cell this pass (so that a pass always moves some lane on). A lane's steps are the
            // same, only later.
            const MI probing0 = hn::Or(jumping, bisecting);
            const size_t probes = hn::CountTrue(di, probing0);
            if (probes >= probeBatch || (probes > 0 && hn::AllFalse(di, walking))) {
                const VI nV = hn::Load(di, p.n), count = hn::Load(di, p.count);
                const VI loV = hn::Load(di, p.lo), hiV = hn::Load(di, p.hi);
                const VI k0 = hn::Load(di, p.k0), sign = hn::Load(di, p.sign);
                const VI lenA = hn::Load(di, p.lenA), lenB = hn::Load(di, p.lenB);
                const VF oB = hn::Load(df, p.oB), dB = hn::Load(df, p.dB);
                const VF oz = hn::Load(df, p.oz), dz = hn::Load(df, p.dz);
                MI jumps = none;
                VI m = nV;
                if (!hn::AllFalse(di, jumping)) {
                    // fetchStep: the map's texel nearest the position on centerline n.
                    const VF t = tOf(nV);
                    fetches = hn::Add(fetches, hn::IfThenElseZero(jumping, oneI));
                    const VF z = hn::Add(oz, hn::Mul(t, dz));
                    const VI texel = texelOf(nV, t);
                    VF z0, slope;
                    lane_gather::GatherPairs(df, texels, texel, z0, slope);
                    const VI r = lane_gather::GatherLanes(di, radii, texel);
                    // ConeShape::step
                    const VF above = hn::Sub(z, z0);
                    const VF closing = hn::Sub(slope, hn::Load(df, p.rise));
                    VF q = hn::Div(above, closing);
                    q = hn::IfThenElse(hn::Lt(farStep, q), farStep, q);
                    VI step = hn::IfThenElse(
                        hn::RebindMask(di, hn::Le(above, zero)), r,
                        hn::IfThenElse(hn::RebindMask(di, hn::Le(closing, zero)), farStepI,
                                       hn::Max(r, hn::ConvertTo(di, q))));
                    if (positiveDistance) step = hn::Max(step, oneI);
                    // i = 0: the naive step, the cells up to the next centerline.
                    const MI naive = hn::And(jumping, hn::Eq(step, zeroI));
                    begins = hn::Or(begins, naive);
                    beginTa = hn::IfThenElse(hn::RebindMask(df, naive), t, beginTa);
                    beginTb = hn::IfThenElse(hn::RebindMask(df, naive), tOf(hn::Add(nV, oneI)),
                                             beginTb);
                    beginResume = hn::IfThenElse(naive, hn::Add(nV, oneI), beginResume);
                    jumps = hn::AndNot(naive, jumping);
                    m = hn::Min(hn::Add(nV, step), count);
                    steps = hn::Add(steps, hn::IfThenElseZero(jumps, oneI));
                }
                steps = hn::Add(steps, hn::IfThenElseZero(bisecting, oneI));
                const VI mid = hn::Add(loV, hn::ShiftRight<1>(hn::Sub(hiV, loV)));
                const VI target = hn::IfThenElse(jumps, m, mid);
                const MI probing = hn::Or(jumps, bisecting);
                fetches = hn::Add(fetches, hn::IfThenElseZero(probing, twoI));

                // aboveAt(target): the ray's height above S there (linear between two samples).
                const VF t = tOf(target);
                // A jump that lands above S fetches the map at its target next pass: ask for
                // that texel now, so its load overlaps this one's (the map is 16 bytes per
                // texel and class, far larger than the caches; the heights are not).
                PrefetchLanes(texels, texelOf(target, t));
                const VF bF = hn::Add(oB, hn::Mul(t, dB));
                const VF fb = hn::Floor(bF);
                const VI ib = hn::ConvertTo(di, fb);
                const VI a = hn::Min(hn::Max(hn::Add(k0, hn::Mul(sign, target)), minusOne), lenA);
                const VI ib0 = hn::Min(hn::Max(ib, minusOne), lenB);
                const VI ib1 = hn::Min(hn::Max(hn::Add(ib, oneI), minusOne), lenB);
                const VI rowA = hn::Mul(hn::Add(a, oneI), hn::Load(di, p.heightA));
                const VI heightB = hn::Load(di, p.heightB);
                const VF s0 = lane_gather::GatherLanes(
                    df, heights, hn::Add(rowA, hn::Mul(hn::Add(ib0, oneI), heightB)));
                const VF s1 = lane_gather::GatherLanes(
                    df, heights, hn::Add(rowA, hn::Mul(hn::Add(ib1, oneI), heightB)));
                const VF aboveS = hn::Sub(hn::Add(oz, hn::Mul(t, dz)),
                                          hn::Add(s0, hn::Mul(hn::Sub(bF, fb), hn::Sub(s1, s0))));
                const MI up = hn::RebindMask(di, hn::Gt(aboveS, margin));

                // A jump that lands above S moves on (past the last centerline: the walk to the
                // exit); one below brackets the crossing; the bisection halves it down to two
                // adjacent centerlines, whose cells the final walk tests.
                const MI jumpUp = hn::And(jumps, up);
                const MI toEnd = hn::And(jumpUp, hn::Not(hn::Lt(m, count)));
                const VI newLo = hn::IfThenElse(jumps, nV, hn::IfThenElse(up, mid, loV));
                const VI newHi = hn::IfThenElse(jumps, m, hn::IfThenElse(up, hiV, mid));
                const MI bracket = hn::Or(hn::AndNot(up, jumps), bisecting);
                const MI narrowed = hn::And(bracket, hn::Lt(hn::Sub(newHi, newLo), twoI));
                hn::Store(hn::IfThenElse(jumpUp, m, nV), di, p.n);
                hn::Store(hn::IfThenElse(bracket, newLo, loV), di, p.lo);
                hn::Store(hn::IfThenElse(bracket, newHi, hiV), di, p.hi);
                hn::Store(hn::IfThenElse(hn::AndNot(narrowed, bracket), hn::Set(di, kBisect),
                                         hn::Load(di, p.phase)),
                          di, p.phase);
                begins = hn::Or(begins, hn::Or(toEnd, narrowed));
                beginTa = hn::IfThenElse(hn::RebindMask(df, toEnd), tOf(count), beginTa);
                beginTb = hn::IfThenElse(hn::RebindMask(df, toEnd), hn::Load(df, p.tExit), beginTb);
                beginToExit = hn::IfThenElse(toEnd, minusOne, beginToExit);
                beginTa = hn::IfThenElse(hn::RebindMask(df, narrowed), tOf(newLo), beginTa);
                beginTb = hn::IfThenElse(hn::RebindMask(df, narrowed), tOf(newHi), beginTb);
                beginResume = hn::IfThenElse(narrowed, newHi, beginResume);
            }

            if (!hn::AllFalse(di, begins)) {
                // beginCells across lanes: the cell of ray.at(ta) (Surface::cellOfX, clamp mode).
                const auto cellOf = [&](const float* origin, const float* direction, VI last) {
                    const VF x = hn::Add(hn::Load(df, origin),
                                         hn::Mul(beginTa, hn::Load(df, direction)));
                    return hn::Min(hn::Max(hn::ConvertTo(di, hn::Floor(hn::Sub(x, half))), minusOne),
                                   last);
                };
                const VI ci = cellOf(p.ox, p.dx, lastX), cj = cellOf(p.oy, p.dy, lastY);
                // The fetch where the march resumes after these cells, asked for now.
                PrefetchLanes(texels, texelOf(beginResume, tOf(beginResume)));
                const MF beginsF = hn::RebindMask(df, begins);
                hn::Store(hn::IfThenElse(begins, hn::Set(di, kCells), hn::Load(di, p.phase)), di,
                          p.phase);
                hn::Store(hn::IfThenElse(beginsF, beginTa, hn::Load(df, p.ta)), df, p.ta);
                hn::Store(hn::IfThenElse(beginsF, beginTb, hn::Load(df, p.tb)), df, p.tb);
                hn::Store(hn::IfThenElse(begins, ci, hn::Load(di, p.ci)), di, p.ci);
                hn::Store(hn::IfThenElse(begins, cj, hn::Load(di, p.cj)), di, p.cj);
                hn::Store(hn::IfThenElse(begins, beginResume, hn::Load(di, p.resume)), di,
                          p.resume);
                hn::Store(hn::IfThenElse(begins, beginToExit, hn::Load(di, p.toExit)), di,
                          p.toExit);
            }
            hn::Store(steps, di, p.steps);
            hn::Store(fetches, di, p.fetches);
            if (hn::AllFalse(di, events)) return true;

            // Lanes whose cell may hold the hit (the root, scalar) or whose ray ends here: only
            // the lanes flagged (a branch per flagged lane, not one per lane).
            ForEachLane(events, [&](size_t k) {
                const size_t i = p.index[k];
                const Ray& ray = rays[i];
                Hit hit;
                hit.steps = p.steps[k];
                hit.fetches = p.fetches[k];
                bool finished = false;
                if (p.candidate[k]) {
                    const float tc = p.cellTc[k];
                    const float th = firstHitInCell(s.cellPlanes(p.cellI[k], p.cellJ[k]), ray,
                                                    p.cellI[k], p.cellJ[k], p.cellTa[k], tc);
                    if (th <= tc) {
                        setHit(ray, th, hit);
                        finished = true;
                    }
                }
                if (!finished && p.exitEnds[k]) {
                    // cellsHit's rule at the box exit (toExit)
                    if (p.pastEnd[k] && exitsThroughFloor(s, ray, p.tb[k]))
                        setHit(ray, p.tb[k], hit);
                    finished = true;
                }
                if (finished) {
                    hits[i] = hit;
                    fill(p, k);
                }
            });
            return !hn::AllFalse(di, hn::MaskFromVec(hn::Load(di, p.active)));
        }
    }
};

}  // namespace safety_cc_march

void SafetyCcMarchPackets(const SafetyCcTracer& tracer, std::span<const Ray> rays,
                          std::span<Hit> hits) {
    using namespace safety_cc_march;
    const Surface& surface = tracer.surface();
    const auto& texels = tracer.shape().map().texels;
    March march{tracer,
                surface,
                surface.paddedHeights().data(),
                &texels.data()->z0,
                &texels.data()->r,
                tracer.options().positiveDistance,
                rays,
                hits};
    // Two packets in turn: while one waits for its gathers, the other's pass can run (the
    // passes of one packet depend on each other, those of two do not).
    Packet packets[2] = {};
    bool alive[2] = {false, false};
    for (int q = 0; q < 2; ++q)
        for (size_t k = 0; k < kLanes; ++k) {
            March::park(packets[q], k);
            if (k < hn::Lanes(DF())) march.fill(packets[q], k);
            alive[q] = alive[q] || packets[q].active[k] != 0;
        }
    while (alive[0] || alive[1])
        for (int q = 0; q < 2; ++q)
            if (alive[q]) alive[q] = march.pass(packets[q]);
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(SafetyCcMarchPackets);

// The gathers index ConeTexel's fields as 4-byte words.
static_assert(sizeof(safety::ConeTexel) == 4 * sizeof(float) &&
              offsetof(safety::ConeTexel, z0) == 0 && offsetof(safety::ConeTexel, slope) == 4 &&
              offsetof(safety::ConeTexel, r) == 8);

bool packetSafetyCcSupports(const SafetyCcTracer& tracer) {
    const Surface& surface = tracer.surface();
    const safety::MarchOptions& options = tracer.options();
    const auto& map = tracer.shape().map();
    const size_t limit = size_t(std::numeric_limits<int32_t>::max());
    return surface.edge() == EdgeMode::Clamp && options.maxSteps == 0 &&
           !options.viewDependent && map.width == surface.width() &&
           map.height == surface.height() && 4 * map.texels.size() + 4 < limit &&
           surface.paddedHeights().size() + 2 * size_t(surface.width()) + 8 < limit;
}

void safetyCcMarchPackets(const SafetyCcTracer& tracer, std::span<const Ray> rays,
                          std::span<Hit> hits) {
    HWY_DYNAMIC_DISPATCH(SafetyCcMarchPackets)(tracer, rays, hits);
}

}  // namespace relief
#endif  // HWY_ONCE
