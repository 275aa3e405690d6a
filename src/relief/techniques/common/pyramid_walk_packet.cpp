// The packet walk (pyramid_walk_packet.h): compiled once per Highway target (foreach_target.h
// re-includes this file), with -ffp-contract=off (CMakeLists.txt) so that no target fuses a
// multiply and an add the scalar walk keeps apart.
// Targets: AVX-512 (16 lanes), AVX2 (8), SSE4 (4) and the portable fallback (1); SSSE3 and
// AVX3_DL would add compile time and nothing this walk uses.
#ifndef HWY_DISABLED_TARGETS
#define HWY_DISABLED_TARGETS (HWY_SSSE3 | HWY_AVX3_DL)
#endif
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "relief/techniques/common/pyramid_walk_packet.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep

#include <hwy/highway.h>
#include <relief/surface/cell_test-inl.h>
#include <relief/surface/packet_lanes-inl.h>
#include <relief/surface/ray_feed-inl.h>
#include <relief/techniques/common/pyramid_walk.h>
#include <relief/techniques/common/pyramid_walk_packet.h>

#include <algorithm>
#include <cstdint>

HWY_BEFORE_NAMESPACE();
namespace relief {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using namespace packet_lanes;  // DF, DI, VF, VI, MF, MI, kLanes

// The lanes' state, structure of arrays: the cursor (WalkCursor) and the ray's constants
// (WalkRay), read into vectors when lanes change rays; the scalar parts read them by lane (no
// copy of the WalkRay itself: written field by field and read back whole, it stalled the store
// buffer).
struct Packet {
    alignas(64) float t[kLanes], exitX[kLanes], exitY[kLanes];
    alignas(64) int32_t level[kLanes], px[kLanes], py[kLanes], baseX[kLanes], baseY[kLanes];
    alignas(64) float ox[kLanes], oy[kLanes], oz[kLanes], dx[kLanes], dy[kLanes], dz[kLanes];
    alignas(64) float tEnter[kLanes];
    alignas(64) float invX[kLanes], invY[kLanes], invZ[kLanes], tExit[kLanes], slack[kLanes];
    alignas(64) int32_t stepX[kLanes], stepY[kLanes];
    // leafFetches: the cell tests' corners, counted in memory (a ray's fetches are its steps,
    // one node each, plus these), so that the loop carries one counter, not two.
    alignas(64) int32_t active[kLanes], steps[kLanes], leafFetches[kLanes];
    alignas(64) int32_t leafHit[kLanes];
    alignas(64) float leafT[kLanes];
    size_t index[kLanes];
};

struct Walk {
    const Surface& s;
    const PyramidLayout& layout;
    const float* values;
    // Each level's first value in `values`, padded for whole-vector loads.
    alignas(64) int32_t levelOffset[PyramidLayout::kMaxLevels + kLanes];
    std::span<const Ray> rays;
    std::span<Hit> hits;
    ray_feed::RayFeed feed{s, rays, hits};            // the rays, clipped a chunk at a time
    // How many lanes wait for a cell test together (see run): 3 of 8 lanes, the best of 1–4 on
    // AVX2 (docs/benchmarks-packets.md, 2026-12-07); the same share of other widths.
    const size_t leafBatch = BatchOf(3);
    const float* heights = s.paddedHeights().data();  // the cell tests' corners

    // The feed's current chunk's starts (makeWalkRay and startCursor per ray), made a chunk at a
    // time: across lanes in clamp mode, the same operations in the same order as the scalar
    // set-up, which makes the rest (the chunk's tail; every ray in repeat mode, whose floorMod
    // needs an integer division per lane). A lane's set-up was a fifth of a primary view's time.
    struct Starts {
        static constexpr size_t kChunk = ray_feed::RayFeed::kChunk;
        alignas(64) float exitX[kChunk], exitY[kChunk], invX[kChunk], invY[kChunk], invZ[kChunk],
            slack[kChunk];
        alignas(64) int32_t level[kChunk], px[kChunk], py[kChunk], baseX[kChunk], baseY[kChunk],
            stepX[kChunk], stepY[kChunk];
        size_t chunk = ~size_t(0);  // the chunk's first ray
    } starts{};

    void makeStarts() {
        const DF df;
        const DI di;
        const size_t n = hn::Lanes(df), begin = feed.chunkBegin();
        const size_t count = feed.chunkEnd() - begin;
        const size_t whole = layout.repeat ? 0 : count / n * n;
        const VF zero = hn::Zero(df), one = hn::Set(df, 1.0f), half = hn::Set(df, 0.5f);
        const VF edge = hn::Set(df, layout.edge), depth = hn::Set(df, s.depth());
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1), minusOne = hn::Set(di, -1);
        const VI lastCellX = hn::Set(di, s.width() - 1), lastCellY = hn::Set(di, s.height() - 1);
        const VI firstCell = hn::Set(di, layout.firstCell);
        const VI cellsX = hn::Set(di, layout.cellsX), cellsY = hn::Set(di, layout.cellsY);
        const VI lastX = hn::Set(di, layout.cellsX - 1), lastY = hn::Set(di, layout.cellsY - 1);
        for (size_t k = 0; k < whole; k += n) {
            const auto field = [&](int32_t c) {  // the chunk's rays: small gather offsets
                return ray_feed::GatherRayField(df, rays.data(), begin + k, c);
            };
            const VF ox = field(0), oy = field(1), oz = field(2);
            const VF dx = field(3), dy = field(4), dz = field(5);
            const VF tEnter = hn::Load(df, feed.chunkEnter() + k);
            const VF tExit = hn::Load(df, feed.chunkExit() + k);
            // makeWalkRay
            const VF invX = hn::Div(one, dx), invY = hn::Div(one, dy), invZ = hn::Div(one, dz);
            const auto sign = [&](VF d) {
                return hn::IfThenElse(
                    hn::RebindMask(di, hn::Gt(d, zero)), oneI,
                    hn::IfThenElseZero(hn::RebindMask(di, hn::Lt(d, zero)), minusOne));
            };
            const VI stepX = sign(dx), stepY = sign(dy);
            const VF extent = hn::Add(
                hn::Add(hn::Add(hn::Add(hn::Abs(ox), hn::Abs(oy)), hn::Abs(oz)), tExit), depth);
            const VF slack = hn::Mul(hn::Set(df, kWalkSlack), extent);
            // startCell (clamp): cellOfX of the position, one further along the ray if `ahead`.
            // Lanes that miss the box take 0 (their position may be anything, NaN or far away:
            // the single-lane target converts with a plain cast).
            const MF entered = hn::Le(tEnter, tExit);  // !span.empty()
            const auto cell = [&](VF o, VF d, VF t, VI lastCell, VI step, VI last, bool ahead) {
                const VF x = hn::IfThenElseZero(entered, hn::Add(o, hn::Mul(t, d)));
                VI c = hn::ConvertTo(di, hn::Floor(hn::Sub(x, half)));
                c = hn::Min(hn::Max(c, minusOne), lastCell);
                if (ahead) c = hn::Add(c, step);
                return hn::Min(hn::Max(hn::Sub(c, firstCell), zeroI), last);
            };
            const VI px = cell(ox, dx, tEnter, lastCellX, stepX, lastX, false);
            const VI py = cell(oy, dy, tEnter, lastCellY, stepY, lastY, false);
            const VI qx = cell(ox, dx, tExit, lastCellX, stepX, lastX, true);
            const VI qy = cell(oy, dy, tExit, lastCellY, stepY, lastY, true);
            // bit_width((px ^ qx) | (py ^ qy)): the float's exponent + 1 (exact below 2^22)
            const VI differ = hn::Or(hn::Xor(px, qx), hn::Xor(py, qy));
            const VI exponent = hn::Sub(
                hn::ShiftRight<23>(hn::BitCast(di, hn::ConvertTo(df, differ))), hn::Set(di, 126));
            const VI level = hn::Min(hn::IfThenElseZero(hn::Ne(differ, zeroI), exponent),
                                     hn::Set(di, layout.topLevel()));
            hn::Store(sideExit(px, level, cellsX, firstCell, stepX, edge, ox, invX), df,
                      starts.exitX + k);
            hn::Store(sideExit(py, level, cellsY, firstCell, stepY, edge, oy, invY), df,
                      starts.exitY + k);
            hn::Store(invX, df, starts.invX + k);
            hn::Store(invY, df, starts.invY + k);
            hn::Store(invZ, df, starts.invZ + k);
            hn::Store(slack, df, starts.slack + k);
            hn::Store(level, di, starts.level + k);
            hn::Store(px, di, starts.px + k);
            hn::Store(py, di, starts.py + k);
            hn::Store(firstCell, di, starts.baseX + k);
            hn::Store(firstCell, di, starts.baseY + k);
            hn::Store(stepX, di, starts.stepX + k);
            hn::Store(stepY, di, starts.stepY + k);
        }
        for (size_t k = whole; k < count; ++k) {  // lane by lane
            const RayInterval span{feed.chunkEnter()[k], feed.chunkExit()[k]};
            if (span.empty()) continue;
            const WalkRay r = makeWalkRay(rays[begin + k], span, s, layout);
            const WalkCursor c = startCursor(s, layout, r, false);  // the defaults: no cap
            starts.exitX[k] = c.exitX;
            starts.exitY[k] = c.exitY;
            starts.invX[k] = r.invX;
            starts.invY[k] = r.invY;
            starts.invZ[k] = r.invZ;
            starts.slack[k] = r.slack;
            starts.level[k] = c.level;
            starts.px[k] = c.px;
            starts.py[k] = c.py;
            starts.baseX[k] = c.baseX;
            starts.baseY[k] = c.baseY;
            starts.stepX[k] = r.stepX;
            starts.stepY[k] = r.stepY;
        }
        starts.chunk = begin;
    }

    // Puts the batch's next ray that needs a walk into `lane` (as walkPyramid starts it), or
    // parks the lane (a valid level-0 node, so that its gathers stay in the pyramid).
    void fill(Packet& p, size_t lane) {
        size_t i;
        RayInterval span;
        if (!feed.next(i, span)) {
            p.active[lane] = 0;
            p.level[lane] = 0;
            p.px[lane] = p.py[lane] = 0;
            return;
        }
        if (feed.chunkBegin() != starts.chunk) makeStarts();
        const size_t k = i - starts.chunk;
        p.t[lane] = span.tEnter;
        p.exitX[lane] = starts.exitX[k];
        p.exitY[lane] = starts.exitY[k];
        p.level[lane] = starts.level[k];
        p.px[lane] = starts.px[k];
        p.py[lane] = starts.py[k];
        p.baseX[lane] = starts.baseX[k];
        p.baseY[lane] = starts.baseY[k];
        setLaneRay(p, lane, rays[i]);
        p.tEnter[lane] = span.tEnter;
        p.invX[lane] = starts.invX[k];
        p.invY[lane] = starts.invY[k];
        p.invZ[lane] = starts.invZ[k];
        p.tExit[lane] = span.tExit;
        p.slack[lane] = starts.slack[k];
        p.stepX[lane] = starts.stepX[k];
        p.stepY[lane] = starts.stepY[k];
        p.active[lane] = -1;
        p.steps[lane] = 0;
        p.leafFetches[lane] = 0;
        p.index[lane] = i;
    }

    // walkPyramid's loop in every active lane until the batch is done; finished lanes take new
    // rays. The lanes' state stays in registers, through memory only for the scalar parts.
    // kRepeat: the layout's repeat mode, compiled in (clamp mode has no seams, and its bases stay
    // the first cell: a step's seam arithmetic is work only repeat needs).
    template <Ascent kAscent, bool kRepeat>
    void run(Packet& p) {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1);
        const VF inf = hn::Set(df, kInfinity);
        const VF edge = hn::Set(df, layout.edge);
        const VI cellsX = hn::Set(di, layout.cellsX), cellsY = hn::Set(di, layout.cellsY);

        MI act = hn::MaskFromVec(zeroI);
        VF t = inf, exitX = inf, exitY = inf, ox = inf, oy = inf, oz = inf, dz = inf, invX = inf,
           invY = inf, invZ = inf, tExit = inf, slack = inf;
        // Clamp mode: every lane's bases are the first cell (a constant, not state).
        const VI firstCell = hn::Set(di, layout.firstCell);
        VI level = zeroI, px = zeroI, py = zeroI, baseX = firstCell, baseY = firstCell,
           stepX = zeroI, stepY = zeroI, steps = zeroI;
        const auto reload = [&] {
            act = hn::MaskFromVec(hn::Load(di, p.active));
            t = hn::Load(df, p.t);
            exitX = hn::Load(df, p.exitX);
            exitY = hn::Load(df, p.exitY);
            level = hn::Load(di, p.level);
            px = hn::Load(di, p.px);
            py = hn::Load(di, p.py);
            if constexpr (kRepeat) {
                baseX = hn::Load(di, p.baseX);
                baseY = hn::Load(di, p.baseY);
            }
            ox = hn::Load(df, p.ox);
            oy = hn::Load(df, p.oy);
            oz = hn::Load(df, p.oz);
            dz = hn::Load(df, p.dz);
            invX = hn::Load(df, p.invX);
            invY = hn::Load(df, p.invY);
            invZ = hn::Load(df, p.invZ);
            tExit = hn::Load(df, p.tExit);
            slack = hn::Load(df, p.slack);
            stepX = hn::Load(di, p.stepX);
            stepY = hn::Load(di, p.stepY);
            steps = hn::Load(di, p.steps);
        };
        // What changes during the walk (the rest only in `fill`).
        const auto spill = [&] {
            hn::Store(t, df, p.t);
            hn::Store(exitX, df, p.exitX);
            hn::Store(exitY, df, p.exitY);
            hn::Store(level, di, p.level);
            hn::Store(px, di, p.px);
            hn::Store(py, di, p.py);
            if constexpr (kRepeat) {
                hn::Store(baseX, di, p.baseX);
                hn::Store(baseY, di, p.baseY);
            }
            hn::Store(steps, di, p.steps);
        };
        reload();
        if (hn::AllFalse(di, act)) return;  // the batch's rays all miss the box
        for (;;) {
        // nodeBox
        const VI nx = (px >> level), ny = (py >> level);
        const VI loX = (nx << level), loY = (ny << level);
        // nodeExit: std::max(t, std::min({exitX, exitY, tExit}))
        VF m = exitX;
        m = hn::IfThenElse(hn::Lt(exitY, m), exitY, m);
        m = hn::IfThenElse(hn::Lt(tExit, m), tExit, m);
        const VF et = hn::IfThenElse(hn::Lt(t, m), m, t);

        // MaxBound::enter: the node's max + slack, then enterBelow.
        const VI offset = nodeOffset(level, nx, ny);
        const VF top = hn::Add(lane_gather::GatherLanes(df, values, offset), slack);
        prefetchChildren(level, nx, ny, offset);
        const VF zOut = hn::Add(oz, hn::Mul(et, dz));
        const VF cross = hn::Mul(hn::Sub(top, oz), invZ);
        const VF clamped =  // std::clamp(cross, t, et)
            hn::IfThenElse(hn::Lt(cross, t), t, hn::IfThenElse(hn::Lt(et, cross), et, cross));
        const VF downIn = hn::IfThenElse(hn::Gt(zOut, top), inf, clamped);
        const VF upIn = hn::IfThenElse(hn::Le(hn::Add(oz, hn::Mul(t, dz)), top), t, inf);
        const VF tIn = hn::IfThenElse(hn::Lt(dz, hn::Zero(df)), downIn, upIn);

        const MI below = hn::And(act, hn::RebindMask(di, hn::Le(tIn, et)));
        const MI atLeaf = hn::Eq(level, zeroI);
        const MI descends = hn::AndNot(atLeaf, below);
        // Lanes at level 0 whose cell may hold the hit wait until leafBatch of them (or every
        // active lane) do, and take the cell test together: the test (four gathers, two roots in
        // double) costs a whole vector's work however few lanes need it. A waiting lane's state
        // stays as it is, so it repeats this step exactly; its steps are counted once.
        const MI atLeafBelow = hn::And(below, atLeaf);
        const bool testCells = BatchReady(atLeafBelow, act, leafBatch);
        const MI none = hn::AndNot(act, act);
        const MI leaf = testCells ? atLeafBelow : none;
        const MI frozen = testCells ? none : atLeafBelow;
        const MI counted = hn::AndNot(frozen, act);
        steps = hn::Add(steps, hn::IfThenElseZero(counted, oneI));

        // Level 0: the reference's cell test across the lanes `leaf` (out of line, from the
        // lanes' state in memory).
        MI leafHits = none;
        if (!hn::AllFalse(di, leaf)) {
            hn::Store(px, di, p.px);
            hn::Store(py, di, p.py);
            if constexpr (kRepeat) {
                hn::Store(baseX, di, p.baseX);
                hn::Store(baseY, di, p.baseY);
            }
            hn::Store(hn::VecFromMask(di, leaf), di, p.leafHit);
            leafCellTests<kRepeat>(p);
            leafHits = hn::MaskFromVec(hn::Load(di, p.leafHit));
        }

        // descend (settleHalf per axis; no texel ties: the pyramid is over cells)
        const VI levelDown = hn::Sub(level, oneI);
        const VI half = (oneI << hn::Max(levelDown, zeroI));  // level-0 lanes don't descend
        VI pxD, pyD;
        VF exitXD, exitYD;
        settleHalf(tIn, edge, ox, invX, stepX, baseX, loX, half, cellsX, exitX, pxD, exitXD);
        settleHalf(tIn, edge, oy, invY, stepY, baseY, loY, half, cellsY, exitY, pyD, exitYD);

        // advance<kAscent>, in the lanes that neither descend nor hit
        const MI advances = hn::AndNot(hn::Or(hn::Or(descends, leafHits), frozen), act);
        // (skipped when no lane advances: a quarter of a primary view's iterations only descend)
        VI levelA = level, pxA = px, pyA = py, baseXA = baseX, baseYA = baseY;  // levelAfterStep
        VF exitXA = exitX, exitYA = exitY;
        MI leaves = none;
        if (!hn::AllFalse(di, advances)) {
            const MI pastEnd = hn::RebindMask(di, hn::Ge(et, tExit));
            const MI alongX = hn::RebindMask(di, hn::Le(exitX, exitY));
            const VI size = (oneI << level);
            const VI toX = hn::IfThenElse(hn::Gt(stepX, zeroI), hn::Min(hn::Add(loX, size), cellsX),
                                          hn::Sub(loX, oneI));
            const VI toY = hn::IfThenElse(hn::Gt(stepY, zeroI), hn::Min(hn::Add(loY, size), cellsY),
                                          hn::Sub(loY, oneI));
            const VI from = hn::IfThenElse(alongX, px, py);
            const VI to = hn::IfThenElse(alongX, toX, toY);
            const VI cells = hn::IfThenElse(alongX, cellsX, cellsY);
            const VI step = hn::IfThenElse(alongX, stepX, stepY);
            const MI inside = hn::AndNot(hn::Lt(to, zeroI), hn::Lt(to, cells));
            // Repeat: a step across the map's edge wraps to the other side and moves the base.
            MI seam = none;
            VI toWrapped = to;
            if constexpr (kRepeat) {
                seam = hn::Not(inside);
                const VI shift = hn::IfThenElse(hn::Gt(step, zeroI), cells, hn::Neg(cells));  // step·cells
                toWrapped = hn::IfThenElse(seam, hn::Sub(to, shift), to);
                const VI baseShift = hn::IfThenElseZero(seam, shift);
                baseXA = hn::Add(baseX, hn::IfThenElseZero(alongX, baseShift));
                baseYA = hn::Add(baseY, hn::IfThenElseZero(hn::Not(alongX), baseShift));
            }
            const VI topLevel = hn::Set(di, layout.topLevel());
            if constexpr (kAscent == Ascent::Parent) {
                const VI levelUp = hn::Add(level, oneI);
                MI newParent = hn::Ne((from >> levelUp), (to >> levelUp));
                if constexpr (kRepeat) newParent = hn::Or(seam, newParent);
                levelA = hn::IfThenElse(newParent, hn::Min(levelUp, topLevel), level);
            } else {
                // bit_width(from ^ to) - 1: the exponent of the float (exact: indices < 2^23, and
                // from ^ to ≥ 1 in every lane that stays)
                const VI bits = hn::BitCast(di, hn::ConvertTo(df, hn::Xor(from, to)));
                levelA = hn::Sub(hn::ShiftRight<23>(bits), hn::Set(di, 127));
                if constexpr (kRepeat) levelA = hn::IfThenElse(seam, topLevel, levelA);
            }
            const MI ascended = hn::Ne(levelA, level);
            pxA = hn::IfThenElse(alongX, toWrapped, px);
            pyA = hn::IfThenElse(alongX, py, toWrapped);
            exitXA = hn::IfThenElse(
                hn::RebindMask(df, hn::Or(alongX, ascended)),
                sideExit(pxA, levelA, cellsX, baseXA, stepX, edge, ox, invX),
                exitX);
            exitYA = hn::IfThenElse(
                hn::RebindMask(df, hn::Or(hn::Not(alongX), ascended)),
                sideExit(pyA, levelA, cellsY, baseYA, stepY, edge, oy, invY),
                exitY);
            leaves = hn::And(advances, kRepeat ? pastEnd : hn::Or(pastEnd, hn::Not(inside)));
        }

        // The new state: descended, advanced, or (hit, left, parked) as it was.
        const MF descendsF = hn::RebindMask(df, descends), advancesF = hn::RebindMask(df, advances);
        const auto pick = [&](auto d, auto mDown, auto mAdvance, auto down, auto advanced,
                              auto same) {
            (void)d;
            return hn::IfThenElse(mDown, down, hn::IfThenElse(mAdvance, advanced, same));
        };
        t = pick(df, descendsF, advancesF, tIn, et, t);
        exitX = pick(df, descendsF, advancesF, exitXD, exitXA, exitX);
        exitY = pick(df, descendsF, advancesF, exitYD, exitYA, exitY);
        level = pick(di, descends, advances, levelDown, levelA, level);
        px = pick(di, descends, advances, pxD, pxA, px);
        py = pick(di, descends, advances, pyD, pyA, py);
        if constexpr (kRepeat) {
            baseX = hn::IfThenElse(advances, baseXA, baseX);
            baseY = hn::IfThenElse(advances, baseYA, baseY);
        }

        // Rays done: a cell hit, or leaving the box (the floor rule decides).
        const MI done = hn::Or(leafHits, leaves);
        if (hn::AllFalse(di, done)) continue;
        spill();
        hn::Store(hn::VecFromMask(di, leafHits), di, p.leafHit);
        ForEachLane(done, [&](size_t k) {
            const size_t i = p.index[k];
            const Ray& ray = rays[i];
            const int fetches = p.steps[k] + p.leafFetches[k];
            if (p.leafHit[k])
                hits[i] = makeHit(ray, p.leafT[k], p.steps[k], fetches);
            else
                hits[i] = leavesThroughFloor(p.oz[k], p.dz[k], p.tExit[k], s.depth())
                              ? makeHit(ray, p.tExit[k], p.steps[k], fetches)
                              : makeMiss(p.steps[k], fetches);
            fill(p, k);
        });
        if (hn::AllFalse(di, hn::MaskFromVec(hn::Load(di, p.active)))) return;
        reload();
        }
    }

    // The reference's cell test (leafHit) in the lanes p.leafHit, over the ray's whole span in
    // the cell (its ends as the reference computes them): p.leafHit becomes the lanes that hit,
    // p.leafT their t. Out of line: the test's two dozen vectors would otherwise crowd the
    // registers of the walk's loop, which takes it in a fifth of its iterations.
    template <bool kRepeat>
    HWY_NOINLINE void leafCellTests(Packet& p) const {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di), oneI = hn::Set(di, 1);
        const VF inf = hn::Set(df, kInfinity), edge = hn::Set(df, layout.edge);
        const MI leaf = hn::MaskFromVec(hn::Load(di, p.leafHit));
        hn::Store(hn::Add(hn::Load(di, p.leafFetches),
                          hn::IfThenElseZero(leaf, hn::Set(di, kLeafFetches))),
                  di, p.leafFetches);
        const VI px = hn::Load(di, p.px), py = hn::Load(di, p.py);
        const VI baseX = kRepeat ? hn::Load(di, p.baseX) : hn::Set(di, layout.firstCell);
        const VI baseY = kRepeat ? hn::Load(di, p.baseY) : hn::Set(di, layout.firstCell);
        const VF ox = hn::Load(df, p.ox), oy = hn::Load(df, p.oy);
        const VI ci = hn::Add(baseX, px), cj = hn::Add(baseY, py);
        VF ta = hn::Load(df, p.tEnter), tb = hn::Load(df, p.tExit);
        // std::max(ta, boundaryT(near side)), std::min(tb, boundaryT(far side)), per axis
        const auto clipAxis = [&](VI step, VI cell, VF origin, VF inverse) {
            const MI up = hn::Gt(step, zeroI);
            const VI next = hn::Add(cell, oneI);
            const VF nearT = boundaryT(hn::IfThenElse(up, cell, next), edge, origin, inverse);
            const VF farT = boundaryT(hn::IfThenElse(up, next, cell), edge, origin, inverse);
            const MF moves = hn::RebindMask(df, hn::Not(hn::Eq(step, zeroI)));
            ta = hn::IfThenElse(hn::And(moves, hn::Lt(ta, nearT)), nearT, ta);
            tb = hn::IfThenElse(hn::And(moves, hn::Lt(farT, tb)), farT, tb);
        };
        clipAxis(hn::Load(di, p.stepX), ci, ox, hn::Load(df, p.invX));
        clipAxis(hn::Load(di, p.stepY), cj, oy, hn::Load(df, p.invY));
        tb = hn::IfThenElse(hn::Lt(ta, tb), tb, ta);
        // The cell's corners in the padded heights: clamp, cells -1..W-1 (column ci + 1);
        // repeat, pyramid index px is the wrapped cell (column px + 1).
        const VI column = hn::Add(kRepeat ? px : ci, oneI);
        const VI row = hn::Add(kRepeat ? py : cj, oneI);
        const VI heightStride = hn::Set(di, s.width() + 2);
        const cell_test::LaneRays<VF> r{ox,
                                        oy,
                                        hn::Load(df, p.oz),
                                        hn::Load(df, p.dx),
                                        hn::Load(df, p.dy),
                                        hn::Load(df, p.dz)};
        const auto segment = cell_test::MeasureSegment(
            df, heights, hn::Add(hn::Mul(row, heightStride), column), heightStride,
            hn::ConvertTo(df, ci), hn::ConvertTo(df, cj), r, ta, tb);
        // The roots (in double: four divisions) only where a lane may meet S; a lane that
        // certainly misses would get t = ∞ from them.
        const MI mayMeet =
            hn::AndNot(hn::RebindMask(di, cell_test::SegmentMisses(df, segment)), leaf);
        MI hits = hn::AndNot(leaf, leaf);
        if (!hn::AllFalse(di, mayMeet)) {
            const VF th = cell_test::FirstHitOnSegment(df, segment, r, ta, tb);
            hits = hn::And(mayMeet, hn::RebindMask(di, hn::And(hn::Le(th, tb), hn::Lt(th, inf))));
            hn::Store(th, df, p.leafT);
        }
        hn::Store(hn::VecFromMask(di, hits), di, p.leafHit);
    }

    // Where node (nx, ny) of `level` lies in `values` (TiledIndex<2>: 4×4 nodes per 64-byte
    // line). Tiles per row: TiledIndex<2>::of(widthAt(level)), computed rather than gathered
    // (the gather of the node's value is the walk's critical path; it should wait on no other).
    HWY_INLINE VI nodeOffset(VI level, VI nx, VI ny) const {
        const DI di;
        const VI three = hn::Set(di, 3);
        const VI lastX = hn::Set(di, layout.cellsX - 1);
        const VI tiles = hn::Add(hn::ShiftRight<2>(lastX >> level), hn::Set(di, 1));
        const VI tile = hn::Add(hn::Mul(hn::ShiftRight<2>(ny), tiles), hn::ShiftRight<2>(nx));
        return hn::Add(hn::Add(lookupLevel(levelOffset, level), hn::ShiftLeft<4>(tile)),
                       hn::Add(hn::ShiftLeft<2>(hn::And(ny, three)), hn::And(nx, three)));
    }

    // The four children of each lane's node share one line of the tiled level below: it is
    // fetched ahead, so that a descent's gather finds it in cache (each step waits on its
    // gather's slowest lane; the prefetches only cost issue slots). Level-0 lanes: their node.
    HWY_INLINE void prefetchChildren(VI level, VI nx, VI ny, VI offset) const {
        const DI di;
        const MI atLeaf = hn::Eq(level, hn::Zero(di));
        const VI childLevel = hn::Sub(level, hn::IfThenZeroElse(atLeaf, hn::Set(di, 1)));
        const VI child = nodeOffset(childLevel, hn::ShiftLeft<1>(nx), hn::ShiftLeft<1>(ny));
        PrefetchLanes(values, hn::IfThenElse(atLeaf, offset, child));
    }

    // table[level] by lane: lookups in registers over the table's whole vectors (a handful of
    // levels per vector), no memory gather.
    VI lookupLevel(const int32_t* table, VI level) const {
        const DI di;
        const int n = int(hn::Lanes(di));
        if (layout.levels <= 2 * n) {  // one or two vectors (AVX2 up to 16 levels, AVX-512 32)
            const auto indices = hn::IndicesFromVec(di, hn::And(level, hn::Set(di, n - 1)));
            const VI first = hn::TableLookupLanes(hn::Load(di, table), indices);
            if (layout.levels <= n) return first;
            const VI second = hn::TableLookupLanes(hn::Load(di, table + n), indices);
            return hn::IfThenElse(hn::Lt(level, hn::Set(di, n)), first, second);
        }
        VI result = hn::Zero(di);
        for (int first = 0; first < layout.levels; first += n) {
            const VI k = hn::Sub(level, hn::Set(di, first));
            const MI here = hn::AndNot(hn::Lt(k, hn::Zero(di)), hn::Lt(k, hn::Set(di, n)));
            const VI v = hn::TableLookupLanes(
                hn::Load(di, table + first), hn::IndicesFromVec(di, hn::And(k, hn::Set(di, n - 1))));
            result = hn::IfThenElse(here, v, result);
        }
        return result;
    }

    // settleHalf (pyramid_walk.h) across lanes: the child's index and, where it leaves through
    // the middle, its exit.
    static void settleHalf(VF t, VF edge, VF origin, VF inverse, VI step, VI base, VI lo, VI half,
                           VI cells, VF exitT, VI& index, VF& childExit) {
        const DF df;
        const DI di;
        const VI zeroI = hn::Zero(di);
        const MI exists = hn::Lt(hn::Add(lo, half), cells);
        const VF middle = hn::Add(hn::ConvertTo(df, hn::Add(hn::Add(base, lo), half)), edge);
        const MI still = hn::Eq(step, zeroI);
        const MI stillHigh = hn::And(exists, hn::RebindMask(di, hn::Ge(origin, middle)));
        const VF tMiddle = hn::Mul(hn::Sub(middle, origin), inverse);
        const MI crossed = hn::RebindMask(di, hn::Ge(t, tMiddle));
        const MI backward = hn::Lt(step, zeroI);
        const MI movingHigh = hn::And(exists, hn::Xor(crossed, backward));
        const MI high = hn::Or(hn::And(still, stillHigh), hn::AndNot(still, movingHigh));
        index = hn::Add(lo, hn::IfThenElseZero(high, half));
        const MI throughMiddle =
            hn::AndNot(still, hn::And(exists, hn::Not(hn::Xor(movingHigh, backward))));
        childExit = hn::IfThenElse(hn::RebindMask(df, throughMiddle), tMiddle, exitT);
    }

    // boundaryT (pyramid_walk.h): where the ray crosses the edge of cell `edgeCell` along an axis.
    static VF boundaryT(VI edgeCell, VF edge, VF origin, VF inverse) {
        const DF df;
        return hn::Mul(hn::Sub(hn::Add(hn::ConvertTo(df, edgeCell), edge), origin), inverse);
    }

    // sideExitT across lanes.
    static VF sideExit(VI p, VI level, VI cells, VI base, VI step, VF edge, VF origin, VF inverse) {
        const DF df;
        const DI di;
        // Lanes whose result is discarded (not advancing) may carry any level; a shift by it is
        // undefined in C++ (the portable target shifts lane by lane), so it is clamped to the
        // pyramid's range, which changes no lane that is used.
        const VI shift = hn::Min(hn::Max(level, hn::Zero(di)), hn::Set(di, 30));
        const VI lo = ((p >> shift) << shift);
        const VI hi = hn::Min(hn::Add(lo, (hn::Set(di, 1) << shift)), cells);
        // The exit side: high (WalkRay::exitMask -1) where the ray moves up, else low.
        const VI exitMask = hn::VecFromMask(di, hn::Gt(step, hn::Zero(di)));
        const VI edgeCell = hn::Add(hn::Add(base, lo), hn::And(hn::Sub(hi, lo), exitMask));
        const VF tEdge = boundaryT(edgeCell, edge, origin, inverse);
        return hn::IfThenElse(hn::RebindMask(df, hn::Eq(step, hn::Zero(di))),
                              hn::Set(df, kInfinity), tEdge);
    }
};

void WalkPackets(const Surface& surface, const MaxPyramid& pyramid, std::span<const Ray> rays,
                 std::span<Hit> hits, Ascent ascent) {
    Walk walk{surface, pyramid.layout(), pyramid.values(), {}, rays, hits};
    for (int level = 0; level < pyramid.layout().levels; ++level) {
        walk.levelOffset[level] = int32_t(pyramid.levelValues(level) - pyramid.values());
        // what run computes in place of a lookup
        RELIEF_CHECK(pyramid.levelTilesPerRow(level) ==
                     (((pyramid.layout().cellsX - 1) >> level) >> 2) + 1);
    }
    Packet p{};
    for (size_t k = 0; k < kLanes; ++k) {
        p.active[k] = p.level[k] = p.px[k] = p.py[k] = 0;
        if (k < hn::Lanes(DF())) walk.fill(p, k);
    }
    const bool repeat = pyramid.layout().repeat;
    if (ascent == Ascent::Ancestor)
        repeat ? walk.run<Ascent::Ancestor, true>(p) : walk.run<Ascent::Ancestor, false>(p);
    else
        repeat ? walk.run<Ascent::Parent, true>(p) : walk.run<Ascent::Parent, false>(p);
}

const char* TargetName() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace relief
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace relief {

HWY_EXPORT(WalkPackets);
HWY_EXPORT(TargetName);

bool packetWalkSupports(const MaxPyramid& pyramid) {
    // Gather offsets are int32; Ancestor's bit_width goes through a float (exact below 2^23).
    const PyramidLayout& layout = pyramid.layout();
    return !layout.texels() && layout.cellsX < (1 << 22) && layout.cellsY < (1 << 22) &&
           pyramid.bytes() / sizeof(float) < size_t(std::numeric_limits<int32_t>::max());
}

void walkPyramidPackets(const Surface& surface, const MaxPyramid& pyramid,
                        std::span<const Ray> rays, std::span<Hit> hits, Ascent ascent) {
    RELIEF_CHECK(ascent == Ascent::Parent || ascent == Ascent::Ancestor);
    HWY_DYNAMIC_DISPATCH(WalkPackets)(surface, pyramid, rays, hits, ascent);
}

const char* packetWalkTarget() { return HWY_DYNAMIC_DISPATCH(TargetName)(); }

}  // namespace relief
#endif  // HWY_ONCE
