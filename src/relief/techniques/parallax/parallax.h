#pragma once
// parallax — parallax mapping with offset limiting.
// Paper: Kaneko et al. 2001; offset limiting after Welsh, "Parallax mapping with offset limiting"
//   (2004): the texture offset is h·V.xy without the division by V.z, which bounds the error at
//   grazing angles.
// Guarantee: none (approximate); one height fetch per ray, no search.
// Map: none. Cost: 1 step, 1 fetch.
// Geometry here: the ray enters the box at p0; the fetched height below p0 gives the depth
//   δ = p0.z − S_bilinear(p0.xy); offset limiting moves the lookup δ·|d.xy| sideways, which is the
//   point of the ray at t = t0 + δ. A ray whose parallax point lies past the box exit misses.
#include <relief/techniques/technique.h>

namespace relief {

class ParallaxTracer {
public:
    explicit ParallaxTracer(std::shared_ptr<const Surface> surface)
        : m_surface(std::move(surface)) {}

    Hit trace(const Ray& ray) const {
        Hit hit;
        const RayInterval span = m_surface->clip(ray);
        if (span.empty()) return hit;
        const vec3 entry = ray.at(span.tEnter);
        hit.steps = 1;
        hit.fetches = 1;
        const float depthBelowEntry =
            std::max(0.0f, entry.z - m_surface->bilinearZ(entry.x, entry.y));
        const float t = span.tEnter + depthBelowEntry;
        if (t > span.tExit) return hit;
        hit.hit = true;
        hit.t = t;
        hit.position = ray.at(t);
        return hit;
    }

private:
    std::shared_ptr<const Surface> m_surface;
};

}  // namespace relief

namespace relief {
Result<std::unique_ptr<Tracer>> createParallax(const TechniqueInput& input);
}  // namespace relief
