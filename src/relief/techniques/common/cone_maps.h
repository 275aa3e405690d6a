#pragma once
// Shared by `cone` and `relaxed-cone` (and `qdm`, for the safe apex): the cone map (one apex
// height and one cone ratio per texel), its builders and its 8/16/32-bit encodings.
//
// Texel (i, j) has the footprint F = [i, i+1] × [j, j+1] (its sample sits at the centre). A map
// entry (a, c) describes the frustum K = {(x, y, z) : dist((x, y), F) ≤ c·(z − a)}: the cone of
// ratio c (horizontal / vertical) swept over F, starting at height a. A point (x, y) with a
// degenerate F (a single point) is the published cone with its apex at (x, y, a).
//
// Builders (ConeKind):
//   SafeStrict     a = max of S over F; c = largest ratio with S never inside K. Proof of the
//                  bound used, for every cell B with corner maximum M_B > a:
//                    - B disjoint from F: S ≤ M_B over B and dist ≥ dist(F, B), so
//                      c ≤ dist(F, B) / (M_B − a) suffices;
//                    - B overlapping F: for q in B let f = clamp(q, F), which lies in B ∩ F;
//                      each plane P of B is ≤ S ≤ a at f, so P(q) ≤ a + |∇P|·|q − f|, i.e.
//                      S(q) ≤ a + G_B·dist(q, F) with G_B the steeper plane gradient of B;
//                      c ≤ 1 / G_B suffices.
//                  a itself: S is convex inside each cell, so its maximum over each quarter of
//                  F is at a corner of the quarter: a = max of S at the 9 points of F's
//                  half-texel grid.
//   FaithfulStrict Dummer 2006: apex at the sample, a = h(i, j), c = min over samples q with
//                  h_q > a of |q − apex| / (h_q − a). Approximate: S between samples can enter
//                  the cone, and positions away from the texel centre are not covered.
//   FaithfulRelaxed Policarpo & Oliveira 2007: apex at the sample; for each sample B higher than
//                  the apex, the ray from the box top above the apex through B is followed past
//                  B until it leaves the solid at C; c = min |C − apex| / (z_C − a).
// Relaxed walks: 98 % of the candidate rays stay in the solid up to where the ratio reaches c
// (fbm 1024²). A walk is skipped when a bound proves that S stays above the ray over every cell
// it would test, per candidate and over whole pyramid nodes: directional first (SampleDrops: the
// walk only meets cells of the quadrant of its direction; over the first one, a plane through the
// sample bounds S from below; over the others, each cell's lowest corner, stored per sample,
// quadrant and reach as the least descent that stays below them, 50 bytes per cell), then
// isotropic (the ray descends faster than the steepest plane within reach: max filters of the
// cell slopes, 6 window sizes, 24 bytes per cell). Level-1 nodes are tried before they are
// pushed. Maps equal the full walks' to the bit.
// Search: a max pyramid over the cells (common/max_pyramid.h; the published maps, whose
// candidates are samples, one over the cells' 00 corners, MaxPyramid::overCellOrigins, and
// distances to the node's samples). A node is skipped when its
// maximum is ≤ a or dist(F, node) ≥ c·(max − a) (no cell in it can lower c; tested squared with
// a 1e-5 margin so that rounding never skips the cell that sets c). Per texel: c starts at the
// ratio of the cell that set the previous texel's c (texels go boustrophedon through a run of
// rows, so that is a neighbour; any cell's ratio is one of the values minimized over, so this
// only prunes more), the descent starts at the finest level whose nodes are wider than
// R = c·(max S − a) (only nodes within R of F), children are tested before they are pushed and
// visited nearest first, and the cells of a level-1 node are evaluated in place. The relaxed
// walk tests every cell over its whole span whatever c is. Result: the brute force's minimum
// to the bit (cone_test.cpp), not only within a tolerance. Repeat mode visits the tile copies
// the largest possible cone can reach (copies beyond R cost one range test).
// Cost, fbm 1024², depth 0.1·size, two threads on a quiet machine (docs/cones.md): safe 0.7 s
// wall / 1.4 CPU-s, faithful strict 1.9 / 3.6, faithful relaxed 25 / 49 (2026-12-03; on a 2-core
// Intel Xeon 2026-12-04: relaxed 38.6 → 23.0 CPU-s with the directional rejects, 12 s wall
// when quiet); about 4.5× (safe) to 12.5× (relaxed) per doubling of the side, since cone radii
// in texels grow with the depth.
// Memory: the max pyramid (≈ 4/3 floats per cell) plus the map; relaxed: 74 bytes per cell more.
//
// Encoding (MapArray "cones", 2 channels): bits 32 stores a and c as floats in texel units.
// bits 16 / 8 store a / D rounded UP and c / cMax (or sqrt(c / cMax) with `sqrt`) rounded
// DOWN to the code grid k / (2^bits − 1): a higher apex and a narrower cone are both subsets of
// the built frustum, so quantization never widens it. cMax is stored in the map's parameters.
#include <relief/core/error.h>
#include <relief/core/huge_pages.h>
#include <relief/io/map_file.h>
#include <relief/surface/cell_intersect.h>
#include <relief/techniques/technique.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace relief {

enum class ConeKind { SafeStrict, FaithfulStrict, FaithfulRelaxed };

struct ConeEncoding {
    int bits = 32;          // 32, 16 or 8
    bool sqrtRatio = false;  // store sqrt(c / cMax)
};

// Decoded map: (a, c) per texel in texel units, what the tracers read.
class ConeMap {
public:
    ConeMap(int width, int height, EdgeMode edge, std::vector<vec2> texels)
        : m_width(width), m_height(height), m_edge(edge), m_texels(std::move(texels)) {
        adviseHugePages(m_texels.data(), m_texels.size() * sizeof(vec2));
    }

    int width() const { return m_width; }
    int height() const { return m_height; }
    // The entry of the texel whose footprint holds (x, y) (any one of them on a shared edge).
    vec2 at(float x, float y) const {
        return m_texels[size_t(texelIndex(int(std::floor(y)), m_height, m_edge)) * size_t(m_width) +
                        size_t(texelIndex(int(std::floor(x)), m_width, m_edge))];
    }
    const std::vector<vec2>& texels() const { return m_texels; }

private:
    int m_width, m_height;
    EdgeMode m_edge;
    std::vector<vec2> m_texels;
};

// The largest ratio a map may hold (cones wider than the box are useless; in repeat mode it also
// bounds how many tile copies the builder visits).
float coneRatioMax(const Surface& surface);

// (a, c) per texel, unencoded. Parallel over rows (relief's parallelRanges). `skipProvenWalks`
// (FaithfulRelaxed): skip the walks the slope bound proves find nothing; off only for the test
// that checks it changes nothing.
std::vector<vec2> buildCones(const Surface& surface, ConeKind kind, bool skipProvenWalks = true);
// Θ(N⁴) oracles for tests: the same definitions without the pyramid (small maps only).
std::vector<vec2> buildConesBruteForce(const Surface& surface, ConeKind kind);
// The SafeStrict apex of texel (i, j): the max of S over its footprint (shared with qdm).
float safeApexHeight(const Surface& surface, int i, int j);

// The texels as stored at `encoding` (rounded towards the safe side), and back. Decoding 16/8-bit
// codes widens the rounding margin by this much (also the GLSL decode, common/cone_maps.glsl).
inline constexpr float kConeDecodeMargin = 1.0f / float(1 << 20);
// What common/cone_maps.glsl reads (relaxed-cone's glslConstants; cone's row adds kConeStall).
inline constexpr GlslConstant kConeMapGlslConstants[] = {
    {"kConeDecodeMargin", double(kConeDecodeMargin), false},
};
MapArray encodeCones(const Surface& surface, const std::vector<vec2>& cones,
                     const ConeEncoding& encoding);
ConeMap decodeCones(const Surface& surface, const MapArray& array, const ConeEncoding& encoding);

// Parameters shared by both techniques' create/buildMaps.
// `bits` must be 8, 16 or 32.
Status checkConeParams(const ParamValues& params, std::string_view technique);
ConeEncoding encodingFrom(const ParamValues& params);
std::map<std::string, std::string> mapParameters(const Surface& surface, int variant,
                                                 const ConeEncoding& encoding);
// The map to trace with: built now, or taken from input.maps after checking sizes, channels and
// that it was baked with the same variant / bits / sqrt.
Result<std::shared_ptr<const ConeMap>> coneMapFor(const TechniqueInput& input,
                                                  std::string_view technique, ConeKind kind,
                                                  int variant);
Result<TechniqueMaps> coneTechniqueMaps(const TechniqueInput& input, std::string_view technique,
                                        ConeKind kind, int variant);

// ---- hot helper shared by the tracers --------------------------------------------------------

// Largest dt such that ray.at(t + dt) stays in the frustum of (a, c) from a position at height
// z inside the footprint; kInfinity when the ray never leaves it. `horizontal` = |d.xy|.
inline float coneStep(float z, float a, float c, float horizontal, float dz) {
    const float room = c * (z - a);
    const float closing = horizontal - c * dz;
    if (closing <= 0.0f) return room >= 0.0f ? kInfinity : 0.0f;
    return room / closing;
}

}  // namespace relief
