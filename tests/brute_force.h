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
        m_scale = std::max({double(surface.width()), double(surface.height()),
                            double(surface.depth())});
    }

    size_t triangleCount() const { return m_triangles.size(); }

    BruteHit trace(const Ray& ray) const {
        return trace(dvec3(ray.origin), dvec3(ray.direction), double(ray.tMax));
    }

    BruteHit trace(const dvec3& o, const dvec3& d, double tMax) const {
        BruteHit best;
        // Barycentric slack: triangles are closed sets and a ray through a shared edge or vertex
        // must not leak between them because of double rounding.
        const double slack = 1e-12;
        for (const Tri& tri : m_triangles) {
            const dvec3 p = glm::cross(d, tri.e2);
            const double det = glm::dot(tri.e1, p);
            // Degenerate triangles (walls of zero height) and rays in a triangle's plane have no
            // transversal hit; a ray in the plane of S always meets a neighbouring facet too.
            if (std::abs(det) < 1e-300) continue;
            const double inv = 1.0 / det;
            const dvec3 s = o - tri.a;
            const double u = glm::dot(s, p) * inv;
            if (u < -slack || u > 1.0 + slack) continue;
            const dvec3 q = glm::cross(s, tri.e1);
            const double v = glm::dot(d, q) * inv;
            if (v < -slack || u + v > 1.0 + slack) continue;
            const double t = glm::dot(tri.e2, q) * inv;
            if (t >= 0.0 && t <= tMax && t < best.t) best = {true, t};
        }
        return best;
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
        double tLo = std::numeric_limits<double>::infinity(), tHi = -tLo;
        bool anyHit = false, anyMiss = false;
        for (double delta : {ulps * double(FLT_EPSILON) * scale, ulps * double(FLT_EPSILON) * scale / 16}) {
            for (int k = 0; k < 27; ++k) {
                const dvec3 moved = o + delta * dvec3(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1);
                const BruteHit h = trace(moved, d, double(ray.tMax));
                if (!h.hit) {
                    anyMiss = true;
                    continue;
                }
                anyHit = true;
                tLo = std::min(tLo, h.t);
                tHi = std::max(tHi, h.t);
            }
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

}  // namespace relief
