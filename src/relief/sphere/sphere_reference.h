#pragma once
// The exact reference on the sphere (DESIGN §6): Lipschitz-safe marching of the displaced sphere
// F(p) = |p| − R − D·h(p/|p|) plus bisection.
//
// Safety: from a point where F > 0, a step δ is safe when δ ≤ F/L with L an upper bound of |∇F|
// over the ball of radius δ. Outside radius R, |∇F|² ≤ 1 + (G/R)², G being the largest angular
// slope of D·h (world units per radian: √((∂/∂lon / sin colat)² + (∂/∂colat)²)) over the
// colatitudes the ball can reach (within δ/R). G is tabulated per row of cells (both triangles
// of every cell; sin colat at the row's end nearest a pole) in a range-max table, and the step
// is the largest δ ≤ F that satisfies δ ≤ F/L(δ): a per-latitude "maximum slope of the displaced
// surface", because the global one is infinite where rows converge at the poles.
// Where no such δ exceeds kMinStep (a ball that reaches a pole whose row is not constant: the
// surface fans out there, sphere_surface.h), the march takes kMinStep and is exact only up to
// features thinner than that. The crossing is then bisected to double precision.
// The `exact` row traces the sphere with it (TechniqueInfo::createSphere).
#include <relief/core/math.h>
#include <relief/sphere/sphere_surface.h>

#include <vector>

namespace relief {

class SphereReference {
public:
    static constexpr double kMinStep = 1e-3;  // world units (texels)

    explicit SphereReference(std::shared_ptr<const SphereSurface> sphere);

    Hit trace(const Ray& ray) const;
    // The bound G over colatitude range [c0, c1] (radians), for tests.
    double slopeBound(double colat0, double colat1) const;

private:
    double field(const dvec3& p) const;
    double safeStep(const dvec3& p, double f) const;

    std::shared_ptr<const SphereSurface> m_sphere;
    int m_bands = 0;
    std::vector<std::vector<double>> m_rangeMax;  // sparse table over bands of texel y
};

}  // namespace relief
