// The packet cone march (cone_packet.h): compiled once per Highway target (foreach_target.h
// re-includes this file), with -ffp-contract=off (CMakeLists.txt) so that no target fuses a
// multiply and an add the scalar march keeps apart.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "relief/techniques/cone/cone_packet.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>
#include <relief/surface/cell_test-inl.h>
#include <relief/surface/packet_lanes-inl.h>
#include <relief/surface/ray_feed-inl.h>
#include <relief/techniques/cone/cone_packet.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

namespace cone_march {

using namespace packet_lanes;  // DF, DI, VF, VI, MF, MI, kLanes

struct Packet {
    alignas(64) float t[kLanes], tExit[kLanes], horizontal[kLanes];
    alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    // cellFetches: the cell tests' corners (a step's cone fetch comes first in every step),
    // counted in memory: a ray's fetches are its steps plus these.
    alignas(64) int32_t steps[kLanes], cellFetches[kLanes], active[kLanes];
    // Written for the scalar part: the lanes that may end, the cell tested and its span.
    alignas(64) int32_t leaves[kLanes], candidate[kLanes], cellExit[kLanes], ci[kLanes], cj[kLanes];
    alignas(64) float to[kLanes], tStart[kLanes];  // the cell test's span [tStart, to]
    size_t index[kLanes];
};

struct March {
    const Surface& s;
    const float* cones;    // (a, c) per texel
    const float* heights;  // paddedHeights()
    ConeLimits limits;
    std::span<const Ray> rays;
    std::span<Hit> hits;
    ray_feed::RayFeed feed{s, rays, hits};  // the rays, clipped a chunk at a time
    // How many lanes wait for a cell test together (see step): 3 of 8 lanes, the best of 1–5 on
    // AVX2 (docs/benchmarks-packets.md, 2026-12-07, stop 42); the same share of other widths.
    const size_t testBatch = BatchOf(3);

    // Puts the batch's next ray that enters the box into `lane` (as safeStepMarch starts it), or
    // parks the lane (at t = 0 on a valid texel, never done).
    void fill(Packet& p, size_t lane) {
        size_t i;
        RayInterval span;
        if (!feed.next(i, span)) return park(p, lane);
        const Ray& ray = rays[i];
        const vec3& d = ray.direction;
        p.t[lane] = span.tEnter;
        p.tExit[lane] = span.tExit;
        p.horizontal[lane] = std::sqrt(d.x * d.x + d.y * d.y);
        setLaneRay(p, lane, ray);
        p.steps[lane] = p.cellFetches[lane] = 0;
        p.active[lane] = -1;
        p.index[lane] = i;
    }

    static void park(Packet& p, size_t lane) {
        p.active[lane] = 0;
        p.t[lane] = p.tExit[lane] = p.horizontal[lane] = 0.0f;
        p.ox[lane] = p.oy[lane] = 0.5f;
        p.oz[lane] = p.dx[lane] = p.dy[lane] = p.dz[lane] = 0.0f;
        p.steps[lane] = p.cellFetches[lane] = 0;
    }

    // The exit of cell `cell` along one axis (cellAt's exitAlong).
    static VF exitAlong(VI cell, VF origin, VF dir) {
        const DF df;
        const VF inf = hn::Set(df, kInfinity);
        const VF side = hn::IfThenElse(hn::Gt(dir, hn::Zero(df)), hn::Set(df, 1.5f),
                                       hn::Set(df, 0.5f));
        const VF t = hn::Sub(hn::Add(hn::ConvertTo(df, cell), side), origin) / dir;
        return hn::IfThenElse(hn::Eq(dir, hn::Zero(df)), inf, t);
    }

    // cellAt (cell_cursor.h) across lanes, clamp mode: the cell at position (px, py) of ray
    // parameter t, and where the ray leaves it (≤ tEnd).
    void cellAt(VF t, VF px, VF py, VF ox, VF oy, VF dx, VF dy, VF tEnd, VI& ci, VI& cj,
                VF& tb) const {
        const DF df;
        const DI di;
        const VF half = hn::Set(df, 0.5f);
        const VI one = hn::Set(di, 1), minusOne = hn::Set(di, -1);
        ci = hn::ConvertTo(di, hn::Floor(hn::Sub(px, half)));
        cj = hn::ConvertTo(di, hn::Floor(hn::Sub(py, half)));
        VF tx = exitAlong(ci, ox, dx), ty = exitAlong(cj, oy, dy);
        // On the edge: move on.
        const MF moveX = hn::Le(tx, t), moveY = hn::Le(ty, t);
        const VI stepX = hn::IfThenElse(hn::RebindMask(di, hn::Gt(dx, hn::Zero(df))), one, minusOne);
        const VI stepY = hn::IfThenElse(hn::RebindMask(di, hn::Gt(dy, hn::Zero(df))), one, minusOne);
        ci = hn::IfThenElse(hn::RebindMask(di, moveX), hn::Add(ci, stepX), ci);
        cj = hn::IfThenElse(hn::RebindMask(di, moveY), hn::Add(cj, stepY), cj);
        tx = hn::IfThenElse(moveX, exitAlong(ci, ox, dx), tx);
        ty = hn::IfThenElse(moveY, exitAlong(cj, oy, dy), ty);
        ci = hn::Min(hn::Max(ci, minusOne), hn::Set(di, s.width() - 1));  // std::clamp
        cj = hn::Min(hn::Max(cj, minusOne), hn::Set(di, s.height() - 1));
        // std::max(t, std::min({tx, ty, tEnd}))
        VF m = tx;
        m = hn::IfThenElse(hn::Lt(ty, m), ty, m);
        m = hn::IfThenElse(hn::Lt(tEnd, m), tEnd, m);
        tb = hn::IfThenElse(hn::Lt(t, m), m, t);
    }

    Hit laneHit(const Packet& p, size_t k) const {
        Hit hit;
        hit.steps = p.steps[k];
        hit.fetches = p.steps[k] + p.cellFetches[k];
        return hit;
    }

    // One packet's lanes between steps, in registers.
    struct Lanes {
        MI act;
        VF t, tExit, horizontal, ox, oy, oz, dx, dy, dz;
        VI steps;
    };

    static void load(const Packet& p, Lanes& r) {
        const DF df;
        const DI di;
        r.act = hn::MaskFromVec(hn::Load(di, p.active));
        r.t = hn::Load(df, p.t);
        r.tExit = hn::Load(df, p.tExit);
        r.horizontal = hn::Load(df, p.horizontal);
        r.ox = hn::Load(df, p.ox);
        r.oy = hn::Load(df, p.oy);
        r.oz = hn::Load(df, p.oz);
        r.dx = hn::Load(df, p.dx);
        r.dy = hn::Load(df, p.dy);
        r.dz = hn::Load(df, p.dz);
        r.steps = hn::Load(di, p.steps);
    }

    // The exact test of the cell the ray is in, from p.tStart to where it leaves it (cellAt), in
    // the lanes p.candidate: p.ci, p.cj, p.to the cell and the test's end, p.candidate the lanes
    // whose segment may meet S there, p.cellExit those at the box's exit. Out of line: its
    // vectors would otherwise crowd the registers of the march's loop, which takes it in a
    // fraction of its steps.
    HWY_NOINLINE void cellTests(Packet& p) const {
        const DF df;
        const DI di;
        const VI oneI = hn::Set(di, 1), minusOne = hn::Set(di, -1);
        const VF inf = hn::Set(df, kInfinity);
        const VI stride = hn::Set(di, s.width() + 2);
        const MI tests = hn::MaskFromVec(hn::Load(di, p.candidate));
        const VF t = hn::Load(df, p.tStart), tExit = hn::Load(df, p.tExit);
        const VF ox = hn::Load(df, p.ox), oy = hn::Load(df, p.oy), oz = hn::Load(df, p.oz);
        const VF dx = hn::Load(df, p.dx), dy = hn::Load(df, p.dy), dz = hn::Load(df, p.dz);
        const VF px = hn::Add(ox, hn::Mul(t, dx)), py = hn::Add(oy, hn::Mul(t, dy));
        VI ci, cj;
        VF to;
        cellAt(t, px, py, ox, oy, dx, dy, tExit, ci, cj, to);
        ci = hn::IfThenElse(tests, ci, minusOne);  // others: a cell in the array
        cj = hn::IfThenElse(tests, cj, minusOne);
        hn::Store(hn::Add(hn::Load(di, p.cellFetches), hn::IfThenElseZero(tests, hn::Set(di, 4))),
                  di, p.cellFetches);
        const VI offset = hn::Add(hn::Mul(hn::Add(cj, oneI), stride), hn::Add(ci, oneI));
        const MF misses = cell_test::SegmentMissesCell(df, heights, offset, stride,
                                                       hn::ConvertTo(df, ci), hn::ConvertTo(df, cj),
                                                       {ox, oy, oz, dx, dy, dz}, t, to);
        // A miss gives th = ∞, still a hit when to = ∞: the scalar test decides there.
        const MI candidate =
            hn::AndNot(hn::RebindMask(di, hn::And(misses, hn::Lt(to, inf))), tests);
        hn::Store(ci, di, p.ci);
        hn::Store(cj, di, p.cj);
        hn::Store(to, df, p.to);
        hn::Store(hn::VecFromMask(di, candidate), di, p.candidate);
        hn::Store(hn::VecFromMask(di, hn::And(tests, hn::RebindMask(di, hn::Ge(to, tExit)))), di,
                  p.cellExit);
    }

    // One turn of safeStepMarch's loop in every active lane of p; false once no lane is active.
    HWY_INLINE bool step(Packet& p, Lanes& r) {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1);
        const VF zero = hn::Zero(df), inf = hn::Set(df, kInfinity);
        const VF stall = hn::Set(df, limits.stall);
        const VI maxSteps = hn::Set(di, limits.maxSteps);
        const VI lastX = hn::Set(di, s.width() - 1), lastY = hn::Set(di, s.height() - 1);
        const VI width = hn::Set(di, s.width());
        const MI act = r.act;
        const VF t = r.t, tExit = r.tExit, ox = r.ox, oy = r.oy, oz = r.oz, dx = r.dx,
                 dy = r.dy, dz = r.dz;

        // The map's texel at (x, y) (ConeMap::at, clamp mode), as the index of its a.
        const auto texelAt = [&](VF x, VF y) {
            const VI ix = hn::Min(hn::Max(hn::ConvertTo(di, hn::Floor(x)), zeroI), lastX);
            const VI iy = hn::Min(hn::Max(hn::ConvertTo(di, hn::Floor(y)), zeroI), lastY);
            return hn::ShiftLeft<1>(hn::Add(hn::Mul(iy, width), ix));
        };
        // p = ray.at(t); the map's texel there
        const VF px = hn::Add(ox, hn::Mul(t, dx)), py = hn::Add(oy, hn::Mul(t, dy));
        const VF pz = hn::Add(oz, hn::Mul(t, dz));
        const VI texel = texelAt(px, py);
        VF a, c;
        lane_gather::GatherPairs(df, cones, texel, a, c);
        // coneStep where the position is in the frustum and above the floor, else -∞
        const VF room = hn::Mul(c, hn::Sub(pz, a));
        const VF closing = hn::Sub(r.horizontal, hn::Mul(c, dz));
        const VF opening = hn::IfThenElse(hn::Ge(room, zero), inf, zero);
        const VF cone = hn::IfThenElse(hn::Le(closing, zero), opening, room / closing);
        const MF inFrustum = hn::And(hn::Ge(pz, a), hn::Gt(pz, zero));
        const VF dt = hn::IfThenElse(inFrustum, cone, hn::Set(df, -kInfinity));
        const MI stepping = hn::And(act, hn::RebindMask(di, hn::Ge(dt, stall)));
        const VF stepped = hn::Add(t, dt);
        const MI leaves = hn::And(stepping, hn::RebindMask(di, hn::Ge(stepped, tExit)));
        // Lanes that stall take the exact test of their cell, four corners and both planes: a
        // vector's work however few lanes need it. They wait, their state unchanged, until
        // testBatch of them (or every active lane) do, and take it together; a waiting lane
        // repeats this step exactly, and its steps and fetches are counted once.
        const MI stalls = hn::AndNot(stepping, act);
        const bool testNow = BatchReady(stalls, act, testBatch);
        const MI tests = testNow ? stalls : hn::AndNot(act, act);
        const MI counted = testNow ? act : hn::AndNot(stalls, act);
        r.steps = hn::Add(r.steps, hn::IfThenElseZero(counted, oneI));

        VF tNext = hn::IfThenElse(hn::RebindMask(df, stepping), stepped, t);
        const MI none = hn::AndNot(act, act);
        MI candidate = none, cellExit = none;
        // Out of line, through p: the cell, the test's span and its verdicts stay there for the
        // lanes that may end below.
        const bool tested = !hn::AllFalse(di, tests);
        if (tested) {
            hn::Store(t, df, p.tStart);
            hn::Store(hn::VecFromMask(di, tests), di, p.candidate);
            cellTests(p);
            candidate = hn::MaskFromVec(hn::Load(di, p.candidate));
            cellExit = hn::MaskFromVec(hn::Load(di, p.cellExit));
            tNext = hn::IfThenElse(hn::RebindMask(df, tests), hn::Load(df, p.to), tNext);
        }
        // The next step's texel, asked for now: its load then overlaps the rest of this step
        // and the other packet's (the gather at the top of the next step would wait for it).
        // At most tExit: a step may be infinite (a ray that rises faster than its cone opens).
        {
            const VF tAhead = hn::Min(tNext, tExit);
            PrefetchLanes(cones, texelAt(hn::Add(ox, hn::Mul(tAhead, dx)),
                                         hn::Add(oy, hn::Mul(tAhead, dy))));
        }
        const MI capped = hn::And(act, hn::Eq(r.steps, maxSteps));
        const MI mayEnd = hn::Or(hn::Or(leaves, candidate), hn::Or(cellExit, capped));
        if (hn::AllFalse(di, mayEnd)) {
            r.t = tNext;
            return true;
        }

        // Lanes that may end here, one by one (safeStepMarch's order); p.t: where each goes on.
        hn::Store(tNext, df, p.t);
        hn::Store(r.steps, di, p.steps);
        hn::Store(hn::VecFromMask(di, leaves), di, p.leaves);
        if (!tested) {  // no lane tested a cell: none of the cell test's verdicts hold
            hn::Store(hn::VecFromMask(di, none), di, p.candidate);
            hn::Store(hn::VecFromMask(di, none), di, p.cellExit);
        }
        ForEachLane(mayEnd, [&](size_t k) {
            const size_t i = p.index[k];
            const Ray& ray = rays[i];
            bool finished = false;
            if (p.leaves[k]) {
                const Hit hit = laneHit(p, k);
                hits[i] =
                    exitsThroughFloor(s, ray, p.tExit[k]) ? hitAt(ray, p.tExit[k], hit) : hit;
                finished = true;
            } else {
                if (p.candidate[k]) {
                    const float th = firstHitInCell(s.cellPlanes(p.ci[k], p.cj[k]), ray, p.ci[k],
                                                    p.cj[k], p.tStart[k], p.to[k]);
                    if (th <= p.to[k]) {
                        hits[i] = hitAt(ray, th, laneHit(p, k));
                        finished = true;
                    }
                }
                if (!finished && p.cellExit[k]) {
                    const Hit hit = laneHit(p, k);
                    hits[i] = exitsThroughFloor(s, ray, p.tExit[k]) ? hitAt(ray, p.tExit[k], hit)
                                                                    : hit;
                    finished = true;
                }
                if (!finished && p.steps[k] >= limits.maxSteps) {
                    // capped: the last position, never past the first hit
                    hits[i] = hitAt(ray, p.t[k], laneHit(p, k));
                    finished = true;
                }
            }
            if (finished) fill(p, k);
        });
        const bool any = !hn::AllFalse(di, hn::MaskFromVec(hn::Load(di, p.active)));
        if (any) load(p, r);
        return any;
    }

    // safeStepMarch's loop until the batch is done, in kPackets packets taking turns: each step's
    // gathers wait on the previous step's, so the other packets keep the memory busy meanwhile.
    template <size_t kPackets>
    void run(Packet (&packets)[kPackets]) {
        const DI di;
        Lanes lanes[kPackets];
        bool live[kPackets];
        size_t alive = 0;
        for (size_t k = 0; k < kPackets; ++k) {
            load(packets[k], lanes[k]);
            live[k] = !hn::AllFalse(di, lanes[k].act);
            alive += live[k];
        }
        while (alive > 0) {
            for (size_t k = 0; k < kPackets; ++k) {
                if (live[k] && !step(packets[k], lanes[k])) {
                    live[k] = false;
                    --alive;
                }
            }
        }
    }
};

}  // namespace cone_march

void ConeMarchPackets(const Surface& surface, const ConeMap& map, ConeLimits limits,
                      std::span<const Ray> rays, std::span<Hit> hits, int packets) {
    using namespace cone_march;
    March march{surface, &map.texels().data()->x, surface.paddedHeights().data(), limits, rays,
                hits};
    // Two packets in turn while the maps stay in the caches; three once the cone map is larger
    // than kThreePacketBytes, where each step waits on memory (4096² on the family-23 EPYC:
    // primary rays +7–12 %, shadow rays +4–22 %; at 1024² a third packet gained nothing, −15 to
    // +13 % over two rounds and mostly slower, docs/benchmarks-packets.md).
    constexpr size_t kThreePacketBytes = size_t(32) << 20;
    const auto start = [&](auto& packets) {
        for (Packet& p : packets) {
            for (size_t k = 0; k < kLanes; ++k) {
                March::park(p, k);
                if (k < hn::Lanes(DF())) march.fill(p, k);
            }
        }
        march.run(packets);
    };
    if (packets == 0)
        packets = map.texels().size() * sizeof(map.texels()[0]) > kThreePacketBytes ? 3 : 2;
    if (packets == 3) {
        Packet three[3]{};
        start(three);
    } else {
        Packet two[2]{};
        start(two);
    }
}

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(ConeMarchPackets);

bool packetConeMarchSupports(const Surface& surface, const ConeMap& map) {
    const size_t limit = size_t(std::numeric_limits<int32_t>::max());
    return surface.edge() == EdgeMode::Clamp && map.width() == surface.width() &&
           map.height() == surface.height() && 2 * map.texels().size() + 2 < limit &&
           surface.paddedHeights().size() + size_t(surface.width()) + 4 < limit;
}

void coneMarchPackets(const Surface& surface, const ConeMap& map, ConeLimits limits,
                      std::span<const Ray> rays, std::span<Hit> hits, int packets) {
    RELIEF_CHECK(packets == 0 || packets == 2 || packets == 3);
    HWY_DYNAMIC_DISPATCH(ConeMarchPackets)(surface, map, limits, rays, hits, packets);
}

}  // namespace relief
#endif  // HWY_ONCE
