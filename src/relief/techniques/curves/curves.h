#pragma once
// curves — visibility-curve stepping, as a per-ray technique (contract approximate).
// Paper: Fourquet, Cowan & Mann, "Geometric Displacement on Plane and Sphere" (GI 2008), §4.
//   The method is not per-ray: each eye ray of a visibility curve starts from the previous
//   one's solution. The paper's renderer, which draws whole images that way on the plane and the
//   sphere, is render/curves/curves_renderer.h (TechniqueInfo::image = VisibilityCurves).
//   To answer a single ray, this tracer walks that ray's own curve: the eye rays of its vertical
//   cutting plane from the one through the leading edge (or straight down when the origin is
//   above the region: CoP_s) to the ray itself, `angle-step` radians apart, each solved by
//   curve_stepper.h with threshold ε·Δs. Slow (hundreds of eye rays per ray); it is there so that
//   `curves` runs everywhere the registry does (contract test, bench, trace).
// Map: none; no build cost. Can overshoot: yes (a step passes over features thinner than the
//   gap between two eye rays). Rays that do not descend end the curve: they miss.
// Departures: the leading edge is a wall of the solid (curve_stepper.h); repeat mode: every curve
//   starts at CoP_s and ends after Surface::kRepeatTravelFactor·max(W, H) texels.
// Steps = evaluations (step pairs and binary cuts) over the whole walk; fetches = 4 per one.
#include <relief/techniques/common/curve_stepper.h>
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
    {"angle-step", 2e-3, 1e-5, 0.1, false, "radians between the eye rays walked to reach a ray",
     ParamRole::RayWalk},
    {"samples", 2, 0.25, 256, false, "samples per pixel of the image renderer",
     ParamRole::ImageSampling},
};
Result<std::unique_ptr<Tracer>> createCurves(const TechniqueInput& input);
}  // namespace relief
