#pragma once
// Shared by `safety-sd` and `safety-cc` (Baboud, Eisemann & Seidel, "Precomputed Safety Shapes
// for Efficient and Accurate Height-field Rendering", TVCG 2011): the four ray classes, the
// limiting-triangle test of §6.1 (with the viewing-angle restriction of §6.2.5), the safety
// distance map and the cylinder-cone map of §6.3 (slope by an N-buffer scan), and their on-disk
// form. The tracers live in safety_march.h.
// Cost: time O(r) to O(r²) cell tests per texel and class (pruned by plane-bound pyramids) and a
// slope scan of up to 256 columns (N-buffer lookups, runs skipped by a sample pyramid). Peak
// memory of a bake, measured: safety-sd 58 bytes per texel, safety-cc 82–85 (its arrays 48, the
// radii 8, one N-buffer orientation 16, the surface 8); the 10800×5400 earth map 3.4 (extrapolated)
// / 4.76 GB.
//
// Coordinates: sample coordinates X = x − 0.5, Y = y − 0.5 (sample (i, j) at integer (i, j)).
// Class c has a local frame (a, b): a grows along the class's direction, b across it; for x±
// the b axis is world Y, for y± it is world X (never mirrored), so a texel's local position is
// (a0, b0) = (±i, j) or (±j, i). Texel τ's segment s_τ is {a = a0, b ∈ [b0 − ½, b0 + ½]}.
#include <relief/core/huge_pages.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace relief::safety {

// Ray classes of §5.2.2 (r ∈ x+ iff d_x ≥ |d_y|, …), in map order.
enum RayClass : int { kXPlus = 0, kXMinus = 1, kYPlus = 2, kYMinus = 3 };
inline constexpr int kClassCount = 4;
inline constexpr const char* kClassNames[kClassCount] = {"x+", "x-", "y+", "y-"};

// Largest stored safety distance (centerlines): "nothing limiting within it". Beyond it the
// scan would cost O(r²) per texel for little gain (the cone covers far steps); repeat mode
// also caps it at max(W, H).
inline constexpr int kMaxDistance = 255;
// Cone slope scan: abscissas beyond r + kConeScan are covered by raising the slope so that the
// slanted plane passes the highest sample there (repeat mode, or maps wider than this).
inline constexpr int kConeScan = 256;

struct BuildOptions {
    // §6.2.5: only rays whose elevation angle (signed, negative = downward) is below φ_max
    // count; 90 = no restriction, the paper's Table 1 uses −45 (rays descending at 45° or more).
    double phiMaxDeg = 90.0;
    bool isotropic = false;   // one shape for the four classes (the minimum)
    int maxDistance = kMaxDistance;
    // §6.2: only exterior rays (viewpoint outside the box) count: cyl_ext. Clamp mode only.
    bool exterior = false;
    // Cone slope over exterior-limiting triangles only (cone_ext, exact); else the N-buffer
    // slope over every vertex (cone_all). Needs `exterior`.
    bool exteriorSlope = false;
};

// Options the surface cannot serve (exterior rays need clamp mode); ok otherwise.
Status checkBuildOptions(const Surface& surface, const BuildOptions& options);

// tan φ_max, +∞ for 90° (no restriction).
double tanPhiMax(double phiMaxDeg);

// One value per texel and class: the safety distance r (§6.1).
struct DistanceMap {
    int width = 0, height = 0, classes = 0;  // classes: 4 (directional) or 1 (isotropic)
    std::vector<uint16_t> r;                 // [class][row][column]

    int at(int cls, int i, int j) const {
        return r[(size_t(classes == 1 ? 0 : cls) * size_t(height) + size_t(j)) * size_t(width) +
                 size_t(i)];
    }
};

// The isotropic map of a directional one: per texel the minimum over the four classes.
DistanceMap isotropicMinimum(const DistanceMap& directional);

// The hybrid shape of §6.3 for one texel and class: the cylinder of radius r and the slanted
// plane z = z_c + s_c·(a − r) (a in centerlines from the texel); z0 = z_c − r·s_c is what the
// tracer uses.
struct ConeTexel {
    float z0 = 0.0f;
    float slope = 0.0f;  // s_c
    int32_t r = 0;
    float zc = 0.0f;
};

// The cylinder-cone map of §6.3 (the cone rows' map is relief::ConeMap, common/cone_maps.h).
struct CylinderConeMap {
    int width = 0, height = 0, classes = 0;
    std::vector<ConeTexel> texels;  // [class][row][column]

    const ConeTexel& at(int cls, int i, int j) const {
        return texels[(size_t(classes == 1 ? 0 : cls) * size_t(height) + size_t(j)) *
                          size_t(width) +
                      size_t(i)];
    }
};

// The tracers' gathers on 2 MiB pages where the kernel allows (core/huge_pages.h).
inline void adviseHugePages(const DistanceMap& map) {
    relief::adviseHugePages(map.r.data(), map.r.size() * sizeof(uint16_t));
}
inline void adviseHugePages(const CylinderConeMap& map) {
    relief::adviseHugePages(map.texels.data(), map.texels.size() * sizeof(ConeTexel));
}

// ---- Builders (parallel over rows; wrap-around in repeat mode) ----

DistanceMap buildDistanceMap(const Surface& surface, const BuildOptions& options);
// The slanted planes for the radii in `radii` (directional or isotropic, as options say).
CylinderConeMap buildConeMap(const Surface& surface, const DistanceMap& radii,
                             const BuildOptions& options);

// buildConeMap straight into the arrays coneMapToArrays makes of it (the same bytes), never
// holding the map: 48 instead of 64 + 48 bytes per texel at the end of a bake.
TechniqueMaps buildConeArrays(const std::string& technique, const Surface& surface,
                              const DistanceMap& radii, const BuildOptions& options);

// ---- Single-texel pieces, exposed for the tests ----

// buildDistanceMap without its plane-bound pruning (the scan it replaced): the same map, slower
// where distances are large; the tests' reference.
DistanceMap buildDistanceMapReference(const Surface& surface, const BuildOptions& options);
// buildConeMap without skipping slope-scan runs: the same map; the tests' reference.
CylinderConeMap buildConeMapReference(const Surface& surface, const DistanceMap& radii,
                                      const BuildOptions& options);

// The local frame of one class.
struct Frame {
    int cls;
    // World sample coordinates of local (a, b).
    void world(double a, double b, double& X, double& Y) const;
    // Local coordinates of world sample coordinates.
    void local(double X, double Y, double& a, double& b) const;
    // World cell holding the local cell [ac, ac+1] × [bc, bc+1].
    void worldCell(int ac, int bc, int& ci, int& cj) const;
    // Local position (a0, b0) of world texel (i, j).
    void texel(int i, int j, int& a0, int& b0) const;
};

// A triangle of S in a class's local frame: vertices (a, b, z), plane z = z0 + pa·a + pb·b.
struct LocalTriangle {
    std::array<double, 3> a, b, z;
    double z0, pa, pb;
};

// The (up to two) triangles of world cell (ci, cj) in the frame; false for cells outside the box
// in clamp mode.
bool cellTriangles(const Surface& surface, const Frame& frame, int ci, int cj,
                   std::array<LocalTriangle, 2>& out);

// The centerline heights of s_τ at b0 − ½, b0, b0 + ½.
struct SegmentHeights {
    int a0, b0;
    double lo, mid, hi;
    double at(double b) const;  // S on s_τ (piecewise linear, kink at b0)
};
SegmentHeights segmentHeights(const Surface& surface, const Frame& frame, int i, int j);

// Allowed in-plane directions m = tan θ (θ from the class axis) for a plane of local gradient
// (pa, pb): the class wedge |θ| ≤ π/4 minus the directions along which the plane rises
// faster than tanPhi. Up to two intervals [lo, hi]; returns their count.
int allowedDirections(double pa, double pb, double tanPhi, double (&lo)[2], double (&hi)[2]);

// §6.1 with §6.2.5: is T limiting for τ, i.e. does some ray of the class (slope ≤ tanPhi)
// start strictly above S on s_τ, lie in T's plane and cross T? Exact: the point set σ_τ,T is
// an interval of s_τ and S − P_T is linear on each half of s_τ, so three points decide.
bool isLimiting(const SegmentHeights& seg, const LocalTriangle& t, double tanPhi);

// The safety distance of world texel (i, j) for class `cls` by the paper's scan (closest
// column holding a limiting triangle), without the pruning the builder uses; `exterior`:
// exterior-limiting triangles only (safety_exterior.h).
int safetyDistanceDirect(const Surface& surface, int cls, int i, int j, double tanPhi,
                         int maxDistance, bool exterior = false);

// Test oracle for the cone slope: vertices read one by one instead of the N-buffer. With
// limitingOnly, only vertices of limiting triangles bound the plane (the paper's exact slope,
// never above the conservative one).
float coneSlopeDirect(const Surface& surface, int cls, int i, int j, int r, float zc,
                      double tanPhi, bool limitingOnly);

// ---- On disk (TechniqueMaps) ----

TechniqueMaps distanceMapToArrays(const std::string& technique, const DistanceMap& map,
                                  const BuildOptions& options);
TechniqueMaps coneMapToArrays(const std::string& technique, const CylinderConeMap& map,
                              const BuildOptions& options);
Result<DistanceMap> distanceMapFromArrays(const TechniqueMaps& maps, int width, int height);
Result<CylinderConeMap> coneMapFromArrays(const TechniqueMaps& maps, int width, int height);
// The build options recorded in baked maps ("phi-max", "isotropic").
Result<BuildOptions> optionsFromArrays(const TechniqueMaps& maps);

// TechniqueInfo::mapSummary of safety-sd and safety-cc: "mean_r", the mean safety distance over
// texels and classes (docs/safety.md), from either encoding; empty for maps of neither.
std::vector<std::pair<std::string, double>> mapSummary(const TechniqueMaps& maps);

}  // namespace relief::safety
