#pragma once
// safety-sd — precomputed safety distances (cylinders), all rays.
// Paper: Baboud, Eisemann & Seidel, "Precomputed Safety Shapes for Efficient and Accurate
//   Height-field Rendering" (TVCG 2011): §5.2.2 marching on one centerline family per ray class,
//   §6.1 safety distance from the closest limiting triangle, §6.2.5 viewing-angle restriction.
// Guarantee: for every texel τ and class (x+, x−, y+, y−), no ray of the class that passes
//   strictly above S on τ's centerline segment s_τ crosses S twice within r centerlines, where
//   r is the offset of the closest column holding a limiting triangle (exactly, by the σ test on
//   three points; no ray sampling). The tracer is exact (same hit/miss as `exact`, |Δt| ≤ 1e-3;
//   the last interval is the reference's own cell test) and never overshoots.
// exterior=1 (§6.2, clamp mode): distances for exterior rays only (cyl_ext) — the first column
//   holding an exterior-limiting triangle (safety_common/safety_exterior.h: exact line-space
//   test, blockers behind s_τ); rays whose origin is inside the box (below its highest sample)
//   take the exact walk and are counted in fallbacks(). Recorded as the map attribute
//   "exterior"; maps baked for all rays are refused when exterior=1 is asked.
// Map: "sd", W×H, 4 channels (r per class, in centerlines, float-coded integers ≤ 255) or 1
//   channel (isotropic: the minimum). In memory uint16 per texel and class.
// Build cost: per texel and class, the wedge of columns 0..r (≈ 2r² triangles), cells whose
//   planes cannot rise above s_τ skipped by a bound (flat land is cheap); parallel over rows.
//   Memory 8 bytes per texel (directional). Times: docs/safety.md.
// Steps = centerline positions + bisection steps + cells walked; fetches = map reads + 2 height
//   samples per centerline test + 4 per cell.
// Departures: rays enter through any box face; the stretch from the entry to the first
//   centerline and from the last one to the exit is walked cell by cell; rays crossing fewer
//   than 3 centerlines (near-vertical) take the exact walk; a zero distance is one naive step
//   (the reference's cell test, which includes the paper's extra test on the other centerline
//   family); rays outside φ_max take the exact walk and are counted (fallbacks()); distances are
//   capped at 255 (max(W, H) in repeat mode); in clamp mode the half-texel border strips and the solid's walls follow
//   DESIGN §1, in repeat mode the scan wraps around.
#include <relief/techniques/safety_common/safety_params.h>

namespace relief {

using SafetySdTracer = safety::SafetyTracer<safety::DistanceShape>;

inline constexpr std::span<const ParamSpec> kSafetySdParams = safety::kSafetyParams;
Result<std::unique_ptr<Tracer>> createSafetySd(const TechniqueInput& input);
Result<TechniqueMaps> buildSafetySdMaps(const TechniqueInput& input);
// The tracer itself (tests and bench use it without the registry's type erasure).
Result<SafetySdTracer> makeSafetySdTracer(const TechniqueInput& input);

}  // namespace relief
