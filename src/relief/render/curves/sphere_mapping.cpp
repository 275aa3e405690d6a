#include <relief/render/curves/sphere_mapping.h>

#include <cmath>

namespace relief::curves {

SphereMapping::SphereMapping(const ViewFrame& view, const dvec3& centre, double radius)
    : m_view(view), m_centre(centre), m_radius(radius) {
    const dvec3 c = centre - view.eye;
    const double cx = glm::dot(c, view.right), cy = glm::dot(c, view.up);
    const double cz = glm::dot(c, view.forward);
    m_rho = glm::length(c);
    m_psi = std::atan2(std::hypot(cx, cy), cz);
    m_gamma = std::atan2(cy, cx);
    m_zv = view.focalPixels();
    m_copView = view.project(centre);
}

dvec2 SphereMapping::paperFromPixel(const dvec2& pixel) const {
    const double uc = pixel.x - 0.5 * double(m_view.width);
    const double vc = 0.5 * double(m_view.height) - pixel.y;
    const double cg = std::cos(m_gamma), sg = std::sin(m_gamma);
    return {cg * uc + sg * vc, -sg * uc + cg * vc};
}

dvec2 SphereMapping::pixelFromPaper(const dvec2& uv) const {
    const double cg = std::cos(m_gamma), sg = std::sin(m_gamma);
    const double uc = cg * uv.x - sg * uv.y, vc = sg * uv.x + cg * uv.y;
    return {uc + 0.5 * double(m_view.width), 0.5 * double(m_view.height) - vc};
}

dvec2 SphereMapping::toView(const SpherePoint& p, double radius) const {
    const double b = (radius > 0.0 ? radius : m_radius) / m_rho;
    const double sp = std::sin(m_psi), cp = std::cos(m_psi);
    const double a = 1.0 - b * std::cos(p.theta), st = b * std::sin(p.theta);
    const double den = cp * a - st * std::cos(p.phi) * sp;  // −z_p/ρ
    return pixelFromPaper({m_zv * (sp * a + st * std::cos(p.phi) * cp) / den,
                           m_zv * st * std::sin(p.phi) / den});
}

std::optional<double> SphereMapping::thetaFromB(double b, double beta, bool front) {
    const double disc = beta * beta * (b + 1.0) - b;
    if (disc < 0.0) return std::nullopt;
    const double c = (b + (front ? 1.0 : -1.0) * std::sqrt(disc)) / (beta * (b + 1.0));
    return std::acos(std::clamp(c, -1.0, 1.0));
}

std::optional<SpherePoint> SphereMapping::toSphere(const dvec2& pixel, bool front,
                                                   double radius) const {
    const dvec2 uv = paperFromPixel(pixel);
    const double sp = std::sin(m_psi), cp = std::cos(m_psi);
    const double along = uv.x * sp + m_zv * cp;  // d·ĉ
    const double d1 = uv.x * cp - m_zv * sp, d2 = uv.y;
    if (along <= 0.0) return std::nullopt;
    const double b = (d1 * d1 + d2 * d2) / (along * along);
    const auto theta = thetaFromB(b, (radius > 0.0 ? radius : m_radius) / m_rho, front);
    if (!theta) return std::nullopt;
    return SpherePoint{*theta, std::atan2(d2, d1)};
}

double SphereMapping::longitudeOf(const dvec2& pixel) const {
    const dvec2 uv = paperFromPixel(pixel);
    return std::atan2(uv.y, uv.x * std::cos(m_psi) - m_zv * std::sin(m_psi));
}

dvec3 SphereMapping::worldPoint(const SpherePoint& p, double radius) const {
    const double r = radius > 0.0 ? radius : m_radius;
    const dvec3 toEye = glm::normalize(m_view.eye - m_centre);
    // e1, e2 span the plane perpendicular to the axis; e1 lies in the paper's xz-plane (the plane
    // of the camera axis and the centre), pointing away from the image point of the axis.
    const double cg = std::cos(m_gamma), sg = std::sin(m_gamma);
    const dvec3 paperX = cg * m_view.right + sg * m_view.up;
    const dvec3 paperY = -sg * m_view.right + cg * m_view.up;
    const dvec3 paperZ = -m_view.forward;
    const double sp = std::sin(m_psi), cp = std::cos(m_psi);
    const dvec3 e1 = cp * paperX + sp * paperZ;
    const dvec3 e2 = paperY;
    return m_centre + r * (std::cos(p.theta) * toEye +
                           std::sin(p.theta) * (std::cos(p.phi) * e1 + std::sin(p.phi) * e2));
}

}  // namespace relief::curves
