#pragma once
// curves as a per-ray technique (registry row `curves`, contract approximate).
// Paper: Fourquet, Cowan & Mann 2008 (curves_renderer.h is the renderer the paper describes).
// The method is not per-ray: each solution starts from the previous eye ray's. To answer a single
// ray honestly, this tracer walks that ray's own visibility curve: the eye rays of the ray's
// vertical cutting plane, from the one through the leading edge (or straight down when the origin
// is above the region: CoP_s) to the ray itself, `angle-step` radians apart, each solved by the
// stepping of stepper.h with threshold ε·Δs. It is slow (hundreds of eye rays per ray) and is
// there so that `curves` runs everywhere the registry does (contract test, bench, trace).
// Map: none. Can overshoot: yes (a step passes over features thinner than the gap between two
// eye rays). Rays that do not descend cannot be stepped forward and end the curve: they miss.
// Repeat mode: the region is infinite, so every curve starts at CoP_s and ends after
// Surface::kRepeatTravelFactor·max(W, H) texels.
// Steps = evaluations (horizontal + vertical step pairs and binary cuts) over the whole walk;
// fetches = 4 per evaluation.
#include <relief/curves/stepper.h>
#include <relief/techniques/technique.h>

namespace relief::curves {

class CurvesTracer {
public:
    CurvesTracer(std::shared_ptr<const Surface> surface, double angleStep, StepParams params)
        : m_surface(std::move(surface)), m_angleStep(angleStep), m_params(params) {}

    Hit trace(const Ray& ray) const;

private:
    std::shared_ptr<const Surface> m_surface;
    double m_angleStep;
    StepParams m_params;
};

}  // namespace relief::curves

namespace relief {
inline constexpr ParamSpec kCurvesParams[] = {
    {"max-steps", 200, 1, 1e6, true, "evaluations per eye ray", ParamRole::IterationCap},
    {"epsilon", 0.05, 1e-6, 10, false, "convergence threshold, a fraction of the eye-ray spacing"},
    {"angle-step", 2e-3, 1e-5, 0.1, false, "radians between the eye rays walked to reach a ray"},
};
Result<std::unique_ptr<Tracer>> createCurves(const TechniqueInput& input);
}  // namespace relief
