#pragma once
// safety-cc's march (SafetyTracer<ConeShape>::trace, safety_common/safety_march.h) for packets
// of rays: SIMD lanes (Google Highway; 16 / 8 / 4 floats), each lane marching its own ray in
// lockstep with masks; a lane whose ray is done takes the batch's next ray.
// Invariant: per lane the same float operations in the same order as the scalar march (compiled
//   with -ffp-contract=off), so hit, t, position, steps and fetches are the scalar tracer's bit
//   for bit.
// Vectorized: in each pass a lane does one of three things: a cell of one of its cell walks (the
//   entry walk up to the first centerline, a naive step, the final cells between the last two
//   test positions, the walk to the exit: cellsHit's exits and sign tests,
//   surface/cell_test-inl.h), a jump (the map fetch, a gather of r, z0 and s_c, the
//   cylinder-cone step, the height above S where it lands), or a bisection step (the height
//   above S at the midpoint); the hand-overs between them are selects. A walk that ends and
//   resumes the march jumps in the same pass (on rough maps, r = 0, the march is a naive step
//   per centerline: one pass each, not two).
// Memory: the map (16 bytes per texel and class: 64 MiB at 1024²) misses the caches, so the
//   texel of a lane's next fetch is prefetched as soon as its centerline is known (a jump's
//   target, where a walk resumes, a new ray's first centerline): its load overlaps the height
//   gathers and the other packet's pass instead of stalling the jump.
// Per lane, scalar: the setup where a ray may fall back (φ_max < 90°, exterior maps) and for a
//   chunk's tail (class, first and last centerline: SafetyTracer::setUp; otherwise the same
//   operations across lanes, 64 rays at a time; the clip is SIMD, surface/ray_feed-inl.h), the
//   copy of a start into its lane, the rays the march gives to the exact walk (outside
//   φ_max, exterior maps with an interior origin, near-vertical rays: cellsHit over the span, as
//   trace does), the root once the signs say a cell holds the hit (firstHitInCell, in double),
//   the floor rule at the box exit.
// Scope: clamp mode, no iteration cap, the reference's final test (view-dependent=0); the row
//   keeps the scalar march otherwise.
#include <relief/techniques/safety_cc/safety_cc.h>

#include <span>

namespace relief {

// Whether safetyCcMarchPackets can trace with this tracer (its options, clamp mode, offsets in
// int32).
bool packetSafetyCcSupports(const SafetyCcTracer& tracer);

// hits[k] = tracer.trace(rays[k]), bit for bit (fallbacks() counts the same rays).
void safetyCcMarchPackets(const SafetyCcTracer& tracer, std::span<const Ray> rays,
                          std::span<Hit> hits);

}  // namespace relief
