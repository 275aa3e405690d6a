#pragma once
// Brute-force oracle for S in clamp mode (DESIGN §2): the ray against every triangle of the closed
// solid (`buildSolidMesh`, the same triangles Embree gets), Möller–Trumbore in double precision,
// smallest t ≥ 0. Slow on purpose: no acceleration structure, no shared code with the tracers, so
// it can judge them. Float rays and float vertices convert to double exactly, so its only error is
// double rounding, ~1e-9 of float's.
//
// Float tracers cannot be asked for more than backward stability: their answer must be the exact
// answer for some ray within float rounding of the given one. `agreesWithinRounding` checks that
// when a ray is ill-conditioned (grazing an edge, or nearly parallel to the plane it hits).
#include <relief/embree/embree_scene.h>
#include <relief/surface/surface.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

namespace relief {

struct BruteHit {
    bool hit = false;
    double t = std::numeric_limits<double>::infinity();
};

// Same hit/miss and, for hits, |Δt| ≤ tolerance (DESIGN §3: 1e-3 texel).
inline bool sameAnswer(bool hitA, double tA, bool hitB, double tB, double tolerance = 1e-3) {
    if (hitA != hitB) return false;
    return !hitA || std::abs(tA - tB) <= tolerance;
}

class BruteForceTracer {
public:
    explicit BruteForceTracer(const Surface& surface) {
        RELIEF_CHECK(surface.edge() == EdgeMode::Clamp);
        const TriangleMesh mesh = buildSolidMesh(surface);
        m_triangles.reserve(mesh.triangles.size());
        for (const glm::uvec3& tri : mesh.triangles) {
            const dvec3 a(mesh.vertices[tri.x]), b(mesh.vertices[tri.y]), c(mesh.vertices[tri.z]);
            m_triangles.push_back({a, b - a, c - a});
        }
        m_scale =
            std::max({double(surface.width()), double(surface.height()), double(surface.depth())});
    }

    size_t triangleCount() const { return m_triangles.size(); }

    BruteHit trace(const Ray& ray) const {
        return trace(dvec3(ray.origin), dvec3(ray.direction), double(ray.tMax));
    }

    BruteHit trace(const dvec3& o, const dvec3& d, double tMax) const {
        BruteHit best;
        traceParallelRays(std::span(&o, 1), d, tMax, std::span(&best, 1));
        return best;
    }

    // Rays from several origins with one direction, in one pass over the triangles (the
    // direction's cross products are shared, and big meshes are read once).
    void traceParallelRays(std::span<const dvec3> origins, const dvec3& d, double tMax,
                           std::span<BruteHit> best) const {
        std::fill(best.begin(), best.end(), BruteHit{});
        // Barycentric slack: triangles are closed sets and a ray through a shared edge or vertex
        // must not leak between them because of double rounding.
        const double slack = 1e-12;
        for (const Tri& tri : m_triangles) {
            const dvec3 p = glm::cross(d, tri.e2);
            const double det = glm::dot(tri.e1, p);
            // Degenerate triangles (walls of zero height where a border sample is 0) and rays in
            // a triangle's plane are skipped: the tests aim no ray along a facet.
            if (std::abs(det) < 1e-300) continue;
            const double inv = 1.0 / det;
            for (size_t k = 0; k < origins.size(); ++k) {
                const dvec3 s = origins[k] - tri.a;
                const double u = glm::dot(s, p) * inv;
                if (u < -slack || u > 1.0 + slack) continue;
                const dvec3 q = glm::cross(s, tri.e1);
                const double v = glm::dot(d, q) * inv;
                if (v < -slack || u + v > 1.0 + slack) continue;
                const double t = glm::dot(tri.e2, q) * inv;
                if (t >= 0.0 && t <= tMax && t < best[k].t) best[k] = {true, t};
            }
        }
    }

    // Whether (hit, t) is the oracle's answer for the ray or for some ray whose origin is moved
    // by up to `ulps` float ulps of the scene's scale: the most a float tracer can be held to.
    // The origin moves to the 26 neighbours of a cube (edges and corners of the box are 2- and
    // 3-dimensional knife edges) at two scales (at a tangent touch t jumps as soon as the ray
    // dips below S). Hits are compared with `tolerance`, widened to the spread of the moved rays'
    // t (t itself is ill-conditioned when the ray is nearly parallel to the facet it hits).
    bool agreesWithinRounding(const Ray& ray, bool hit, double t, double ulps = 8.0,
                              double tolerance = 1e-3) const {
        const dvec3 o(ray.origin), d(ray.direction);
        const double scale = std::max({m_scale, std::abs(o.x), std::abs(o.y), std::abs(o.z)});
        const double coarse = ulps * double(FLT_EPSILON) * scale;
        std::vector<dvec3> moved;
        for (double delta : {coarse, coarse / 16.0})
            for (int k = 0; k < 27; ++k)
                moved.push_back(o + delta * dvec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1));
        std::vector<BruteHit> hits(moved.size());
        traceParallelRays(moved, d, double(ray.tMax), hits);
        double tLo = std::numeric_limits<double>::infinity(), tHi = -tLo;
        bool anyHit = false, anyMiss = false;
        for (const BruteHit& h : hits) {
            if (!h.hit) {
                anyMiss = true;
                continue;
            }
            anyHit = true;
            tLo = std::min(tLo, h.t);
            tHi = std::max(tHi, h.t);
        }
        if (!hit) return anyMiss;
        return anyHit && t >= tLo - tolerance && t <= tHi + tolerance;
    }

private:
    struct Tri {
        dvec3 a, e1, e2;
    };
    std::vector<Tri> m_triangles;
    double m_scale = 1.0;
};

// Who is right when `exact` and a peer (Embree, another tracer) disagree on a ray, judged by the
// oracle. Names of the kinds are the ones printed by the tests and the bench.
enum class Disagreement {
    IllConditioned,  // the oracle sides with exact, and the peer is right within rounding too
    PeerWrong,       // the oracle sides with exact and rejects the peer even within rounding
    ExactRounding,   // the oracle differs from exact, but exact is right within rounding
    Unexplained,     // exact is wrong
};

inline const char* toString(Disagreement kind) {
    switch (kind) {
        case Disagreement::IllConditioned:
            return "ill-conditioned";
        case Disagreement::PeerWrong:
            return "peer wrong";
        case Disagreement::ExactRounding:
            return "exact decided by rounding";
        default:
            return "unexplained";
    }
}

inline Disagreement classifyDisagreement(const BruteForceTracer& oracle, const Ray& ray,
                                         bool exactHit, double exactT, bool peerHit, double peerT,
                                         BruteHit* oracleHit = nullptr, double tolerance = 1e-3) {
    const BruteHit b = oracle.trace(ray);
    if (oracleHit) *oracleHit = b;
    if (sameAnswer(exactHit, exactT, b.hit, b.t, tolerance))
        return oracle.agreesWithinRounding(ray, peerHit, peerT, 8.0, tolerance)
                   ? Disagreement::IllConditioned
                   : Disagreement::PeerWrong;
    if (oracle.agreesWithinRounding(ray, exactHit, exactT, 8.0, tolerance))
        return Disagreement::ExactRounding;
    return Disagreement::Unexplained;
}

}  // namespace relief
