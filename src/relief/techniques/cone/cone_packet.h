#pragma once
// cone's march (ConeTracer::trace: safeStepMarch with cone steps and whole-cell tests) for
// packets of rays: SIMD lanes (Google Highway; 16 / 8 / 4 floats), each lane marching its own ray
// in lockstep with masks; a lane whose ray is done takes the batch's next ray. Two packets take
// turns step by step (three once the map outgrows the caches), so one packet's gathers are in
// flight while another computes (the march is bound by the latency of its dependent fetches);
// each step also prefetches the texel its next step reads, as soon as the position is known.
// Invariant: per lane the same float operations in the same order as the scalar march (compiled
//   with -ffp-contract=off), so hit, t, position, steps and fetches are the scalar tracer's bit
//   for bit; the iteration cap included.
// Vectorized: the position, the map fetch (a gather of a and c), the cone step, the cell the ray is
//   in and its exit (cellAt), the cell's corners, planes and sign tests (surface/cell_test-inl.h).
// Per lane, scalar: the setup (|d.xy|; the clip is SIMD, surface/ray_feed-inl.h), the root
//   once the signs say the cell holds the hit (firstHitInCell, in double), the floor rule at the
//   box exit, the capped end.
// Scope: clamp mode (repeat wraps texel indices by a modulo the scalar code takes in int; the row
//   keeps the scalar march there).
#include <relief/techniques/cone/cone.h>

#include <span>

namespace relief {

// Whether coneMarchPackets can trace this surface and map (clamp mode, offsets in int32).
bool packetConeMarchSupports(const Surface& surface, const ConeMap& map);

// hits[k] = ConeTracer(surface, map, limits).trace(rays[k]), bit for bit. packets: how many
// packets take turns, 2 or 3 (0: by the cone map's size, three beyond 32 MiB).
void coneMarchPackets(const Surface& surface, const ConeMap& map, ConeLimits limits,
                      std::span<const Ray> rays, std::span<Hit> hits, int packets = 0);

}  // namespace relief
