#pragma once
// linear — relief mapping's linear search with binary refinement.
// Paper: Policarpo, Oliveira & Comba, "Real-time relief mapping on arbitrary polygonal surfaces"
//   (I3D 2005), the LS baseline of the safety-shapes and quadratic-map papers.
// Guarantee: none (approximate): a linear step can jump over thin features, and the height
//   lookup is a bilinear fetch, which equals S only on centerlines.
// Map: none (bilinear fetches of the heightfield, as a GPU texture unit gives them).
// Cost per ray: N + M fetches (`max-steps` = N linear steps, `binary-steps` = M).
// Departure: the N steps divide the ray's interval inside the box (entry through any face)
//   rather than the top-to-bottom depth range, so side views work; a ray that is still above the
//   surface after N steps is a miss (that is how silhouettes appear).
#include <relief/techniques/technique.h>

namespace relief {

class LinearTracer {
public:
    LinearTracer(std::shared_ptr<const Surface> surface, int linearSteps, int binarySteps)
        : m_surface(std::move(surface)), m_linearSteps(linearSteps), m_binarySteps(binarySteps) {}

    Hit trace(const Ray& ray) const;

private:
    bool below(const Ray& ray, float t, Hit& hit) const {
        const vec3 p = ray.at(t);
        ++hit.fetches;
        return p.z <= m_surface->bilinearZ(p.x, p.y);
    }

    std::shared_ptr<const Surface> m_surface;
    int m_linearSteps;
    int m_binarySteps;
};

inline Hit LinearTracer::trace(const Ray& ray) const {
    Hit hit;
    const RayInterval span = m_surface->clip(ray);
    if (span.empty()) return hit;
    const float dt = (span.tExit - span.tEnter) / float(m_linearSteps);
    float tAbove = span.tEnter, tBelow = kInfinity;
    if (below(ray, span.tEnter, hit)) {
        tBelow = span.tEnter;
    } else {
        for (int k = 1; k <= m_linearSteps; ++k) {
            ++hit.steps;
            const float t = k == m_linearSteps ? span.tExit : span.tEnter + float(k) * dt;
            if (below(ray, t, hit)) {
                tBelow = t;
                break;
            }
            tAbove = t;
        }
        if (tBelow == kInfinity) return hit;
        for (int k = 0; k < m_binarySteps; ++k) {
            ++hit.steps;
            const float mid = 0.5f * (tAbove + tBelow);
            (below(ray, mid, hit) ? tBelow : tAbove) = mid;
        }
    }
    hit.hit = true;
    hit.t = tBelow == span.tEnter ? tBelow : 0.5f * (tAbove + tBelow);
    hit.position = ray.at(hit.t);
    return hit;
}

}  // namespace relief

namespace relief {
inline constexpr ParamSpec kLinearParams[] = {
    {"max-steps", 32, 1, 65536, true, "linear search steps N", ParamRole::IterationCap},
    {"binary-steps", 8, 0, 64, true, "binary refinement steps M"},
};
Result<std::unique_ptr<Tracer>> createLinear(const TechniqueInput& input);
}  // namespace relief
