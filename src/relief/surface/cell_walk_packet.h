#pragma once
// The reference cell walk (cell_walk.h, the `exact` row) for packets of rays: SIMD lanes (Google
// Highway; 16 floats on AVX-512, 8 on AVX2, 4 on SSE4), each lane walking its own ray's cells in
// lockstep with masks; a lane whose ray is done takes the batch's next ray.
// Invariant: per lane the same float operations in the same order as cellsHit over the clipped
//   span (compiled with -ffp-contract=off), so hit, t, position, steps and fetches are the scalar
//   walk's bit for bit.
// Vectorized: the cell's exits (tx, ty, tc), its four corners (gathers from the padded heights),
//   both triangle planes and the four sign tests that decide whether the segment meets S in the
//   cell, the step to the next cell and the clamp-mode exit.
// Per lane, scalar: the setup (first cell; the clip is SIMD, ray_feed-inl.h), the hit itself
//   once the signs say the cell holds one (firstHitInCell, its root in double, one cell per
//   ray), and the floor rule at the exit.
// Cost: one vector iteration per cell for 16 (8, 4) rays; the scalar walk's unpredictable
//   branch (which face the ray leaves through) becomes a select.
#include <relief/surface/surface.h>

#include <span>

namespace relief {

// Whether cellsHitPackets can trace this surface (gather offsets in int32).
bool packetCellWalkSupports(const Surface& surface);

// hits[k] = the exact row's hit for rays[k] (clip, then cellsHit over the span to the exit),
// bit for bit.
void cellsHitPackets(const Surface& surface, std::span<const Ray> rays, std::span<Hit> hits);

}  // namespace relief
