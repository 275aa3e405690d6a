#pragma once
// safety-cc — precomputed hybrid cylinder-cone safety shapes, all rays.
// Paper: Baboud, Eisemann & Seidel, "Precomputed Safety Shapes for Efficient and Accurate
//   Height-field Rendering" (TVCG 2011): §6.3 cylinder-cone, marched as in §5.2.2 (see
//   safety-sd), slope by the conservative N-buffer scan of §6.3.2.
// Guarantee: per texel and class, the cylinder of radius r (safety-sd's distance) plus the
//   slanted plane z = z_c + s_c·(a − r) above every vertex of every triangle that rays of the
//   class from s_τ can reach beyond r (all treated as limiting: conservative), so a ray that
//   stays above the plane beyond r cannot cross S twice. Exact tracer, never overshoots.
// Map: "cc<class>" (cc x+, cc x-, cc y+, cc y-; or one "cc" when isotropic), W×H, 3 channels:
//   r (centerlines), z_c (texels), s_c (texels of height per centerline). The tracer keeps
//   z0 = z_c − r·s_c.
// Build cost: safety-sd's scan, then per texel and class a scan over abscissas r+1.. with two
//   N-buffer lookups each (max over 2^l windows across the class axis, ⌊log2 N⌋ ≤ 9 levels,
//   one orientation in memory at a time, 4 bytes × levels × texels), stopped as soon as no
//   later abscissa can raise s_c (the highest sample bounds them all). Times: docs/safety.md.
// Steps/fetches: as safety-sd (one map read = one texel's r, z0, s_c).
// Batches (clamp mode, no cap, view-dependent=0) go through the SIMD packet march
//   (safety_cc_packet.h), the same hits bit for bit, unless the ISA is baseline or
//   RELIEF_PACKETS=0.
// Departures: the step is i = max(r, ⌊max(p_z − z0, 0)/(s_c − s_d)⌋) with ⌊⌋ where the paper
//   writes ⌈⌉: the ceiling lands up to one centerline below the slanted plane, where a thin
//   ridge inside that last column can be crossed twice and missed; s_c − s_d ≤ 0 (a ray rising
//   at least as fast as the cone) never leaves the shape: the step reaches the exit. z_c is the
//   highest vertex of columns r and r+1 (the paper's "triangles at distance r"); the plane is
//   raised by 1e-6 relative so float evaluation stays above it. Beyond 256 abscissas (repeat
//   mode, wide maps) the slope is raised so the plane clears the highest sample. The rest as
//   safety-sd, including exterior=1 (r = cyl_ext; the slope stays the N-buffer's over all
//   vertices: the paper's cyl_ext + cone_all). exterior-slope=1 (needs exterior=1): the slope
//   over exterior-limiting triangles only (cyl_ext + cone_ext, exact, slow build): columns whose
//   N-buffer maximum cannot raise the slope are skipped, the exterior test runs only on
//   triangles that would raise it. Attribute "exterior-slope".
#include <relief/techniques/safety_common/safety_params.h>

namespace relief {

using SafetyCcTracer = safety::SafetyTracer<safety::ConeShape>;

inline constexpr std::span<const ParamSpec> kSafetyCcParams = safety::kSafetyCcParamList;
Result<std::unique_ptr<Tracer>> createSafetyCc(const TechniqueInput& input);
Result<TechniqueMaps> buildSafetyCcMaps(const TechniqueInput& input);
Result<SafetyCcTracer> makeSafetyCcTracer(const TechniqueInput& input);

}  // namespace relief
