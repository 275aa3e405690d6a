#pragma once
// qdm variant 1 `paper`: the quadratic displacement map and Algorithm 1 exactly as published
// (Kiglics et al. 2023 §3), beside the conservative variant 0 of qdm.h.
// Map (§3.1), per texel (u, v) with apex h = h(u, v), the sample height: m(d) = max of
//   h(x, y) − h over the samples (x, y) of the map whose centre-to-centre distance lies in
//   [d, d + 1) (unit rings; repeat mode: each sample at its nearest copy, the map being a torus).
//   Cone: for i = 1, 2, …: b ← max(i·b/a, m(i)), a ← i, until b exceeds the cone height
//   height-ratio · max(S) or i reaches the last ring (or `max-distance`). Parabola
//   y = −(x − c)² + b + (c − a)², used on both sides of its top: c = max c_j over the rings
//   j > a, c_j solving m(j) = −(j − c_j)² + b + (c_j − a)², i.e.
//   c_j = (a + j)/2 + (m(j) − b) / (2(j − a)); c = a when no ring lies beyond a.
//   `convex-bound` 1 takes the max over the vertices of the upper convex bound of the points
//   (j, m(j)) (§4.1): the same c in exact arithmetic (the parabola is concave), so the fast
//   builder computes the plain max and the brute force checks both.
// Guarantee: none (approximate). The apex at the sample and distances between sample centres
//   leave S between samples and off-centre positions unbounded, the descending half of the
//   parabola bounds nothing, and the tracer stops where the ray is not above the texel's h.
// Tracer (Algorithm 1 with Algorithm 2): from the box entry, while steps < max-steps, the last
//   step > kQdmPaperEpsilon and p.z > h of the texel under p: the line to (a, b) if the ray
//   meets it with α ≤ 1, else the smaller root of the parabola (∞ when there is none). The hit
//   is the position where the loop ends; leaving the box is a miss (or the floor). No exact
//   finish.
// Build: buildQdmPaper finds the cone from its last record: the break ring by bisection, each
//   probe a branch and bound for the steepest sample (v / ring) of a max pyramid of the samples,
//   then proves that the float loop takes that path (rounding bound, one pruned search for a
//   missed record; qdm_paper_map.cpp), else walks the rings nearest first as before (nodes that
//   cannot beat the running slope dropped). Rough ground ends the walk within a few rings, so
//   the walk runs first under a budget of pops. Then branch and bound on c (nodes by the largest
//   c_j their samples could give). Equal to the paper's Θ(N⁴) builder
//   (buildQdmPaperBruteForce: every sample for every texel) and to the ring walk to the bit
//   (qdm_paper_test.cpp). Cost: a few probes per texel instead of Θ(a²) samples on gently
//   rising ground (peaks6 1024², 2 threads: 46 CPU-s, was > 224; rough maps unchanged;
//   docs/benchmarks-bakes.md). Memory: the sample pyramid (≈ 4/3 floats) + 16 bytes per texel.
// Departures: rising rays (shadow rays; the paper traces view rays only) take the reference
//   walk; a step never moves the ray back before its box entry; rays enter through any face.
#include <relief/surface/cell_cursor.h>
#include <relief/surface/cell_walk.h>
#include <relief/techniques/qdm/qdm_map.h>

namespace relief {

// Algorithm 1's "t > ε": a step shorter than this ends the loop (texel units).
inline constexpr float kQdmPaperEpsilon = 1e-3f;
// What qdm.glsl reads from here (the qdm row's glslConstants).
inline constexpr GlslConstant kQdmGlslConstants[] = {{"kQdmPaperEpsilon", kQdmPaperEpsilon, false}};

std::vector<QdmTexel> buildQdmPaper(const Surface& surface, const QdmBuildParams& params);
std::vector<QdmTexel> buildQdmPaperBruteForce(const Surface& surface,
                                              const QdmBuildParams& params);

// One step of Algorithm 1 from h0 = p.z − h above the apex (horizontal = |d.xy|, dz = d.z < 0).
inline float paperStep(const QdmTexel& q, float h0, float horizontal, float dz) {
    if (q.a > 0.0f) {  // the line to (a, b): alpha = x / a
        const float t = h0 / (q.b / q.a * horizontal - dz);
        if (t * horizontal / q.a <= 1.0f) return t;
    }
    // A t² + B t + C = 0 by Algorithm 2: B halved, x = C / (−B + sqrt(B² − AC)), ∞ if not
    // real.
    const float A = horizontal * horizontal;
    const float halfB = 0.5f * (dz - 2.0f * q.c * horizontal);
    const float C = h0 - q.b - q.a * q.a + 2.0f * q.a * q.c;
    const float disc = halfB * halfB - A * C;
    if (disc < 0.0f) return kInfinity;
    const float x = C / (-halfB + std::sqrt(disc));
    return std::isfinite(x) ? x : kInfinity;
}

class QdmPaperTracer {
public:
    QdmPaperTracer(std::shared_ptr<const Surface> surface, std::shared_ptr<const QdmMap> map,
                   int maxSteps)
        : m_surface(std::move(surface)), m_map(std::move(map)), m_maxSteps(maxSteps) {}

    Hit trace(const Ray& ray) const {
        const Surface& s = *m_surface;
        Hit hit;
        const RayInterval span = s.clip(ray);
        if (span.empty()) return hit;
        const vec3& d = ray.direction;
        if (d.z >= 0.0f) {  // the reference walk (ExactTracer::trace)
            cellsHit(s, ray, span.tEnter, span.tExit, true, hit);
            return hit;
        }
        const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
        float t = span.tEnter, dt = kInfinity;
        while (hit.steps < m_maxSteps && dt > kQdmPaperEpsilon) {
            const vec3 p = ray.at(t);
            const QdmTexel q = m_map->at(p.x, p.y);
            ++hit.fetches;
            if (!(p.z > q.h)) break;  // p is not above the heightfield
            dt = paperStep(q, p.z - q.h, horizontal, d.z);
            ++hit.steps;
            t = std::max(t + dt, span.tEnter);
            if (!(t < span.tExit)) break;
        }
        if (!(t < span.tExit))
            return exitsThroughFloor(s, ray, span.tExit) ? hitAt(ray, span.tExit, hit) : hit;
        return hitAt(ray, t, hit);
    }

private:
    std::shared_ptr<const Surface> m_surface;
    std::shared_ptr<const QdmMap> m_map;
    int m_maxSteps;
};

}  // namespace relief
