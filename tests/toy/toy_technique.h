#pragma once
// A toy technique, written the way docs/architecture.md tells a newcomer to add one: a tracer on
// the public surface API, a parameter table with roles, and one registry row. The test that
// registers it gets the CLI, the contract harness and the bench without touching them.
// Method: march the ray in fixed steps on S (heightAt), then bisect the last step. Contract:
// approximate (a step can pass over a peak thinner than the step).
#include <relief/techniques/technique.h>

namespace relief::toy {

class MarchTracer {
public:
    MarchTracer(std::shared_ptr<const Surface> surface, int maxSteps, float step)
        : m_surface(std::move(surface)), m_maxSteps(maxSteps), m_step(step) {}

    Hit trace(const Ray& ray) const {
        Hit hit;
        const RayInterval span = m_surface->clip(ray);
        if (span.empty()) return hit;
        float t = span.tEnter;
        for (; hit.steps < m_maxSteps && t <= span.tExit; ++hit.steps, t += m_step) {
            const vec3 p = ray.at(t);
            ++hit.fetches;
            if (p.z > m_surface->heightAt(p.x, p.y)) continue;
            float above = std::max(span.tEnter, t - m_step), below = t;
            for (int k = 0; k < 24; ++k) {
                const float mid = 0.5f * (above + below);
                const vec3 q = ray.at(mid);
                ++hit.fetches;
                (q.z > m_surface->heightAt(q.x, q.y) ? above : below) = mid;
            }
            hit.hit = true;
            hit.t = below;
            hit.position = ray.at(below);
            return hit;
        }
        return hit;
    }

private:
    std::shared_ptr<const Surface> m_surface;
    int m_maxSteps;
    float m_step;
};

inline constexpr ParamSpec kMarchParams[] = {
    {"max-steps", 4096, 1, 1e6, true, "march steps", ParamRole::IterationCap},
    {"step", 0.25, 0.01, 4, false, "step length in texels"},
};

inline Result<std::unique_ptr<Tracer>> createMarch(const TechniqueInput& input) {
    return makeBatchTracer(MarchTracer(input.surface, input.params.getInt("max-steps"),
                                       float(input.params.get("step"))));
}

inline const TechniqueInfo kMarchRow = {
    .name = "toy-march", .paper = "none (a test's toy)",
    .summary = "fixed steps on S, then bisection", .contract = Contract::Approximate,
    .params = kMarchParams, .create = createMarch};

}  // namespace relief::toy
