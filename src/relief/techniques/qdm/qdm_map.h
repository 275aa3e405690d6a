#pragma once
// The quadratic displacement map: (a, b, c, h) per texel (see qdm.h for the guarantee), its
// builders (fast pyramid staircase and the paper's all-cells oracle), the profile it encodes
// and the stable parabola root of Algorithm 2.
//
// Why the fit holds. For texel F with apex h, every cell B with corner maximum M_B > h gives a
// point (r_B, v_B) = (dist(F, B), M_B − h): S ≤ M_B over B and dist(q, F) ≥ r_B there. A cell
// overlapping F (r_B = 0) gives S(q) ≤ h + G_B·dist(q, F) (cone_maps.h, G_B its steeper plane
// gradient), capped at v_B: it adds the slope constraint s ≥ G_B and the point (v_B / G_B, v_B).
// So g(x) = max over the points with r ≤ x (and the overlapping cells' min(G x, v)) bounds
// S − h at footprint distance x, and a nondecreasing f ≥ g is a valid profile.
//   Cone (the paper's search): s = max v / r over the points with r ≤ a, a = height-ratio ·
//   max(S) / s, taken in order of r. Parabola: P_c(x) = b + (x − a)(2c − a − x) up to c, flat
//   at its top beyond; for x > a its value only grows with c, so each point (r, v) beyond a
//   with v > b needs c ≥ c_j, the smallest c with the nondecreasing P_c ≥ v at r:
//   c_j = (a + r)/2 + (v − b) / (2(r − a)) if v − b ≥ (r − a)², else a + sqrt(v − b).
//   c = max c_j. The profile is concave beyond a, so meeting the vertices of the points' upper
//   convex bound meets every point: the convex search gives the same c as the plain one.
//   Only the staircase of points higher than every nearer point matters (a point dominated by
//   a nearer, higher one changes neither s nor c), and no point under the profile reached so
//   far (s, c only grow), which is what lets the fast builder prune pyramid nodes while walking
//   them nearest first; once the cone is final, c = max c_j does not depend on order and is
//   found by branch and bound. Where the walk meets a long staircase (gently rising ground: a
//   record every ring) it hands over to a bisection on s: the loop ends on the first record s
//   with no point within coneHeight / s steeper than s, a condition monotone in s (proof and
//   search in qdm_map.cpp, QdmSearch::bisectCone), whose first probes come from the previous
//   (neighbouring) texel's slope: a tight bracket, the same answer.
#include <relief/io/map_file.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <vector>

namespace relief {

struct QdmTexel {
    float a = 0, b = 0, c = 0, h = 0;
};

// A point (distance, height above the apex) of a texel's radial function.
struct QdmPoint {
    float r, v;
};
// Andrew's monotone chain, upper half, over points sorted by r (§4.1).
std::vector<QdmPoint> upperConvexBound(std::span<const QdmPoint> points);

struct QdmBuildParams {
    float heightRatio = 0.2f;
    float maxDistance = 0.0f;  // 0 = unlimited
    bool convexBound = true;
    // Pops of the nearest-first walk per texel before the cone is found by bisection instead
    // (same result; tests force each path with 0 and a huge budget).
    int64_t staircaseBudget = 256;
    // Start the bisection from the previous (neighbouring) texel's cone slope: fewer queries,
    // the same map (tests compare on/off bit for bit).
    bool warmStart = true;
    // variant=1: the paper's own map (qdm_paper.h), built by buildQdmPaper.
    bool paper = false;
    // variant=1: find the cone from its last record and check it instead of ring by ring (the
    // same map; tests compare on/off bit for bit), after a ring walk of this many pops (-1: as
    // the neighbour suggests; 0: never walk first, so tests reach the check on small maps).
    bool skipRings = true;
    int64_t ringWalkBudget = -1;
    static QdmBuildParams from(const ParamValues& params);
};

// The profile f(x) of a texel (nondecreasing; the parabola's top beyond c).
inline float qdmProfile(const QdmTexel& q, float x) {
    if (x <= q.a) return q.a > 0.0f ? q.b * x / q.a : 0.0f;
    const float u = std::min(x, q.c) - q.a;
    return q.b + u * (2.0f * (q.c - q.a) - u);
}

// Algorithm 2, solved from the junction (x = a) on: with u = x − a and τ = t − a/|d.xy|, the ray
// is `above` = h0 + dz·a/|d.xy| − b over the profile there (the line part found no crossing
// before it) and meets P(u) = b + u(2(c − a) − u) where A τ² + 2·halfB τ + above = 0,
// A = |d.xy|², halfB = dz/2 − (c − a)|d.xy|; the smaller root τ = above / (−halfB + √disc)
// ≥ 0, kInfinity where there is none (halfB ≥ 0 or disc < 0: the ray stays above P). Why not
// the paper's form (C = h0 − b − a² + 2ac about x = 0): next to a cliff c is huge (1e6 texels
// on terraces), 2ac swamps h0 − b in float, and the root rounded to just before the junction
// read as "no root", so a rising ray stepped through the cliff (found by the contract harness
// on more seeds). Here every term stays at the scale of the ray's height over the profile.
inline float parabolaStep(const QdmTexel& q, float h0, float horizontal, float dz) {
    if (!(horizontal > 0.0f)) return kInfinity;  // vertical: the line part (x = 0) decides
    const float tJunction = q.a / horizontal;
    const float above = h0 + dz * tJunction - q.b;
    if (!(above > 0.0f)) return tJunction;  // rounding put the ray on the profile there
    const float halfB = 0.5f * dz - (q.c - q.a) * horizontal;
    if (halfB >= 0.0f) return kInfinity;
    const float A = horizontal * horizontal;
    const float disc = halfB * halfB - A * above;
    if (disc < 0.0f) return kInfinity;
    return tJunction + above / (-halfB + std::sqrt(disc));
}

class QdmMap {
public:
    QdmMap(const Surface& s, std::vector<QdmTexel> texels, float maxDistance);

    int width() const { return m_width; }
    int height() const { return m_height; }
    const QdmTexel& at(float x, float y) const {
        return m_texels[size_t(texelIndex(int(std::floor(y)), m_height, m_edge)) * size_t(m_width) +
                        size_t(texelIndex(int(std::floor(x)), m_width, m_edge))];
    }
    // The horizontal distance the profile bounds S for: unlimited when it clears the highest
    // point of S at max-distance (it is nondecreasing), else max-distance.
    float reach(const QdmTexel& q) const {
        if (m_maxDistance == kInfinity || qdmProfile(q, m_maxDistance) >= m_maxZ - q.h)
            return kInfinity;
        return m_maxDistance;
    }
    const std::vector<QdmTexel>& texels() const { return m_texels; }

private:
    int m_width, m_height;
    EdgeMode m_edge;
    float m_maxZ, m_maxDistance;
    std::vector<QdmTexel> m_texels;
};

// Fast builder (pyramid staircase), parallel over rows.
std::vector<QdmTexel> buildQdm(const Surface& surface, const QdmBuildParams& params);
// The paper's Θ(N⁴) builder: every cell of the map for every texel (test oracle, small maps).
std::vector<QdmTexel> buildQdmBruteForce(const Surface& surface, const QdmBuildParams& params);

// The map of the variant params selects (buildQdmPaper for variant 1, qdm_paper.h).
std::vector<QdmTexel> buildQdmVariant(const Surface& surface, const QdmBuildParams& params);

MapArray encodeQdm(const Surface& surface, const std::vector<QdmTexel>& texels);
std::map<std::string, std::string> qdmMapParameters(const QdmBuildParams& params);
// Built now, or taken from input.maps after checking size, channels and build parameters.
Result<std::shared_ptr<const QdmMap>> qdmMapFor(const TechniqueInput& input);

}  // namespace relief
