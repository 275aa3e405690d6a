#pragma once
// The pyramid walk (pyramid_walk.h) for packets of rays: SIMD lanes (Google Highway; 16 floats on
// AVX-512, 8 on AVX2, 4 on SSE4), each lane running its own ray's walk in lockstep with masks
// (SPMD, as ISPC does). A lane whose ray is done takes the batch's next ray.
// Invariant: per lane the same float operations in the same order as the scalar walk (compiled
//   with -ffp-contract=off), so hit, t, position, steps and fetches are bit-identical to
//   walkPyramid<Ascent::Parent> (quadtree's default) and <Ascent::Ancestor> (maxmip's).
//   min/max/clamp are written as the selects std::min/max/clamp are (NaN and ±0 alike).
// Vectorized: node max gathers, the bound (enterBelow), descent, exits, index steps, ascent;
//   each step prefetches its node's children's line (no value changes); the level-0 cell tests
//   (leafHit: corners, planes, signs, roots in double) in batches of waiting lanes, out of line;
//   in clamp mode the rays' setup (makeWalkRay, startCursor) across lanes a chunk of the feed at
//   a time (the clip is SIMD too, surface/ray_feed-inl.h).
// Per lane, scalar: the setup in repeat mode and the end of a ray (makeHit, the floor exit rule).
// Scope: no iteration cap, S (not boxes), a pyramid over cells; the rows' other parameters keep
//   the scalar walk. Targets: AVX-512, AVX2, SSE4, a portable fallback, picked at run time.
// Cost: one vector iteration per packet step; on AVX2 bound by micro-operations, not memory, at
//   1.4–1.7× the scalar walk (docs/benchmarks-packets.md, stop 45).
#include <relief/core/isa.h>
#include <relief/core/math.h>
#include <relief/techniques/common/max_pyramid.h>
#include <relief/techniques/common/pyramid_walk.h>

#include <span>

namespace relief {

// Whether walkPyramidPackets can trace over this pyramid (over cells, offsets fit in int32).
bool packetWalkSupports(const MaxPyramid& pyramid);

// hits[k] = walkPyramid<ascent>(surface, pyramid.layout(), MaxBound(pyramid), rays[k], {}),
// bit for bit; ascent Parent (quadtree) or Ancestor (maxmip).
void walkPyramidPackets(const Surface& surface, const MaxPyramid& pyramid,
                        std::span<const Ray> rays, std::span<Hit> hits,
                        Ascent ascent = Ascent::Parent);

// The Highway target the dispatch picks on this machine ("AVX2", "SSE4", "EMU128", ...).
const char* packetWalkTarget();

// A pyramid row's default walk over a batch (PacketBatchTracer's packet path): Impl has
// surface() and pyramid().
template <Ascent kAscent, class Impl>
void walkRowPackets(const Impl& impl, std::span<const Ray> rays, std::span<Hit> hits) {
    walkPyramidPackets(impl.surface(), impl.pyramid(), rays, hits, kAscent);
}

}  // namespace relief
