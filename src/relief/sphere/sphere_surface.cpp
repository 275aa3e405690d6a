#include <relief/sphere/sphere_surface.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace relief {

namespace {
constexpr double kPi = std::numbers::pi;
}

SphereSurface::SphereSurface(std::shared_ptr<const Heightfield> heightfield, double radius,
                             double depth)
    : m_radius(radius),
      m_grid(std::make_shared<const Surface>(std::move(heightfield), float(depth),
                                             EdgeMode::Repeat)) {
    RELIEF_CHECK(radius > 0.0);
}

dvec2 SphereSurface::texelOf(const dvec3& n) const {
    const double longitude = std::atan2(n.y, n.x);
    const double colatitude = std::acos(std::clamp(n.z, -1.0, 1.0));
    return {double(m_grid->width()) * (longitude + kPi) / (2.0 * kPi),
            double(m_grid->height()) * (kPi - colatitude) / kPi};
}

dvec2 SphereSurface::gridPoint(const dvec3& n, bool* clampedY) const {
    dvec2 p = texelOf(n);
    const double w = double(m_grid->width()), top = double(m_grid->height()) - 0.5;
    if (p.x >= w) p.x -= w;  // longitude = π exactly
    const double y = std::clamp(p.y, 0.5, std::max(0.5, top));
    if (clampedY) *clampedY = y != p.y;
    return {p.x, y};
}

double SphereSurface::heightAt(const dvec3& n) const {
    const dvec2 p = gridPoint(n);
    return double(m_grid->heightAt(float(p.x), float(p.y)));
}

vec3 SphereSurface::texelPoint(const dvec3& n) const {
    const dvec2 p = gridPoint(n);
    return {float(p.x), float(p.y), m_grid->heightAt(float(p.x), float(p.y))};
}

SphereSurface::Frame SphereSurface::frameAt(const dvec3& n) const {
    bool clampedY = false;
    const dvec2 p = gridPoint(n, &clampedY);
    const Surface& g = *m_grid;
    const int ci = g.cellOfX(float(p.x)), cj = g.cellOfY(float(p.y));
    const float u = float(p.x) - (float(ci) + 0.5f), v = float(p.y) - (float(cj) + 0.5f);
    const CellPlanes planes = g.cellPlanes(ci, cj);
    const CellPlane& top = planes.first.at(u, v) >= planes.second.at(u, v) ? planes.first
                                                                           : planes.second;
    const double r = m_radius + double(top.at(u, v));
    // Height slopes per radian of longitude and of northward latitude.
    const double dLongitude = double(top.sx) * double(g.width()) / (2.0 * kPi);
    const double dNorth = clampedY ? 0.0 : double(top.sy) * double(g.height()) / kPi;
    const double sinColat = std::max(1e-9, std::sqrt(n.x * n.x + n.y * n.y));
    const dvec3 east = sinColat > 1e-9 ? dvec3(-n.y, n.x, 0.0) / sinColat : dvec3(0, 1, 0);
    const dvec3 north = glm::cross(n, east);
    Frame f;
    f.tangentToWorld = dmat3(east, north, n);
    f.tangentNormal = glm::normalize(dvec3(-dLongitude / (r * sinColat), -dNorth / r, 1.0));
    f.normal = glm::normalize(f.tangentToWorld * f.tangentNormal);
    return f;
}

}  // namespace relief
