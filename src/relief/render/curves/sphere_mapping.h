#pragma once
// Sphere ↔ view plane (Fourquet et al. 2008, §5.2). The paper's frame: eye at the origin, view
// plane z = −z_v (z_v = focal distance in pixels), sphere centre at (ρ sin ψ, 0, −ρ cos ψ); the
// sphere's own pole (θ = 0) faces the eye and longitude φ = 0 lies in the xz-plane, so the
// visibility curves (constant φ) are lines through CoP_v, the image of the centre. Our camera's
// image is rotated about its axis (angle γ) to put the centre on the paper's u axis.
//
// Departure: the paper's printed inverse uses (u sin ψ − z_v cos ψ) and (z_v sin ψ + u cos ψ),
// i.e. the centre at z = +ρ cos ψ, inconsistent with its forward mapping (whose denominator also
// has the opposite sign of z_p). We use the forward mapping derived from the paper's x_p, y_p,
// z_p and the inverse consistent with it:
//   tan²δ = B = ((u cos ψ − z_v sin ψ)² + v²)/(u sin ψ + z_v cos ψ)²,  φ = atan2(v, u cos ψ −
//   z_v sin ψ),  cos θ = (B ± √(β²(B+1) − B))/(β(B+1)) with β = R/ρ (+ front, − back facing),
// which is the paper's θ formula. Tests check the round trips and a direct 3D projection.
#include <relief/render/curves/view_frame.h>

#include <optional>

namespace relief::curves {

struct SpherePoint {
    double theta, phi;  // colatitude from the eye-facing pole, longitude about it
};

class SphereMapping {
public:
    SphereMapping(const ViewFrame& view, const dvec3& centre, double radius);

    double rho() const { return m_rho; }
    double psi() const { return m_psi; }
    double beta() const { return m_radius / m_rho; }
    dvec2 copView() const { return m_copView; }

    // Image point (pixels) of (θ, φ) on the sphere of radius `radius` (default: the base).
    dvec2 toView(const SpherePoint& p, double radius = 0.0) const;
    // (θ, φ) where the eye ray through `pixel` meets the sphere of radius `radius`; none where
    // it misses. front = the nearer intersection.
    std::optional<SpherePoint> toSphere(const dvec2& pixel, bool front = true,
                                        double radius = 0.0) const;
    // φ of the visibility line through `pixel` (defined wherever the pixel looks towards the
    // centre's side of the view, hit or miss).
    double longitudeOf(const dvec2& pixel) const;
    // World position of (θ, φ) at radius r, for tests and shading.
    dvec3 worldPoint(const SpherePoint& p, double radius = 0.0) const;

    // The paper's θ formula from B = tan²δ and β.
    static std::optional<double> thetaFromB(double b, double beta, bool front);

private:
    dvec2 paperFromPixel(const dvec2& pixel) const;
    dvec2 pixelFromPaper(const dvec2& uv) const;

    ViewFrame m_view;
    dvec3 m_centre;
    double m_radius, m_rho, m_psi, m_gamma, m_zv;
    dvec2 m_copView;
};

}  // namespace relief::curves
