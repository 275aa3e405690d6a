#include <relief/core/huge_pages.h>
#include <relief/surface/surface.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief {

std::string_view toString(EdgeMode mode) { return mode == EdgeMode::Clamp ? "clamp" : "repeat"; }

Surface::Surface(std::shared_ptr<const Heightfield> heightfield, float depth, EdgeMode edge)
    : m_heightfield(std::move(heightfield)),
      m_width(m_heightfield->width),
      m_height(m_heightfield->height),
      m_depth(depth),
      m_edge(edge) {
    RELIEF_CHECK(m_width > 0 && m_height > 0 && depth >= 0.0f);
    const Heightfield& hf = *m_heightfield;
    m_padded.resize(size_t(m_width + 2) * size_t(m_height + 2));
    for (int j = -1; j <= m_height; ++j) {
        for (int i = -1; i <= m_width; ++i) {
            int si = wrapColumn(i), sj = wrapRow(j);
            si = std::clamp(si, 0, m_width - 1);  // clamp mode: border = outermost sample
            sj = std::clamp(sj, 0, m_height - 1);
            const float z = m_depth * hf.at(si, sj);
            m_padded[size_t(j + 1) * size_t(m_width + 2) + size_t(i + 1)] = z;
            m_maxZ = std::max(m_maxZ, z);
        }
    }
    adviseHugePages(m_padded.data(), m_padded.size() * sizeof(float));
}

float Surface::heightAt(float x, float y) const {
    const int ci = cellOfX(x), cj = cellOfY(y);
    return cellPlanes(ci, cj).at(x - (float(ci) + 0.5f), y - (float(cj) + 0.5f));
}

float Surface::bilinearZ(float x, float y) const {
    const int ci = cellOfX(x), cj = cellOfY(y);
    const float u = std::clamp(x - (float(ci) + 0.5f), 0.0f, 1.0f);
    const float v = std::clamp(y - (float(cj) + 0.5f), 0.0f, 1.0f);
    const CellCorners c = cellCorners(ci, cj);
    return (1 - v) * ((1 - u) * c.z00 + u * c.z10) + v * ((1 - u) * c.z01 + u * c.z11);
}

vec3 Surface::normalAt(const vec3& p) const {
    const int ci = cellOfX(p.x), cj = cellOfY(p.y);
    const float u = p.x - (float(ci) + 0.5f), v = p.y - (float(cj) + 0.5f);
    const CellPlanes planes = cellPlanes(ci, cj);
    if (m_edge == EdgeMode::Clamp) {
        const float below = planes.at(u, v) - p.z;
        const float wallTolerance = 1e-3f;
        if (below > wallTolerance) {  // on a side or bottom face of the solid
            const float eps = 1e-3f;
            if (p.x <= eps) return {-1, 0, 0};
            if (p.x >= float(m_width) - eps) return {1, 0, 0};
            if (p.y <= eps) return {0, -1, 0};
            if (p.y >= float(m_height) - eps) return {0, 1, 0};
            return {0, 0, -1};
        }
    }
    const CellPlane& top = planes.first.at(u, v) >= planes.second.at(u, v) ? planes.first
                                                                           : planes.second;
    return glm::normalize(vec3(-top.sx, -top.sy, 1.0f));
}

namespace {
// Intersects [lo, hi] with the slab [a, b] along one axis.
bool clipSlab(float origin, float direction, float a, float b, float& lo, float& hi) {
    if (direction == 0.0f) return origin >= a && origin <= b;
    const float inv = 1.0f / direction;
    float t0 = (a - origin) * inv, t1 = (b - origin) * inv;
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
    return lo <= hi;
}
}  // namespace

RayInterval Surface::clip(const Ray& ray) const {
    RayInterval r{0.0f, ray.tMax};
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    // The readers refuse such rays; one built in code must miss rather than walk garbage (a NaN
    // compares false everywhere, an infinite origin puts every t at ±inf).
    const bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) &&
                        std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    if (!finite || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) || !(ray.tMax > 0.0f)) return RayInterval{};
    if (std::max({std::abs(o.x), std::abs(o.y), std::abs(o.z)}) > kMaxOriginCoordinate)
        return RayInterval{};
    bool inside = clipSlab(o.z, d.z, 0.0f, m_depth, r.tEnter, r.tExit);
    if (m_edge == EdgeMode::Clamp) {
        inside = inside && clipSlab(o.x, d.x, 0.0f, float(m_width), r.tEnter, r.tExit) &&
                 clipSlab(o.y, d.y, 0.0f, float(m_height), r.tEnter, r.tExit);
    } else {
        const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
        const float travel = kRepeatTravelFactor * float(std::max(m_width, m_height));
        if (horizontal > 0.0f) r.tExit = std::min(r.tExit, travel / horizontal);
    }
    // Above the highest sample and rising: nothing can be hit.
    if (d.z > 0.0f) r.tExit = std::min(r.tExit, std::max(r.tEnter, (m_maxZ - o.z) / d.z));
    if (!inside) return RayInterval{};
    return r;
}

Ray Surface::nearBox(const Ray& ray, double& offset) const {
    offset = 0.0;
    const dvec3 o(ray.origin), d(ray.direction);
    const double lo[3] = {0.0, 0.0, 0.0};
    const double hi[3] = {double(m_width), double(m_height), double(m_depth)};
    const double size = std::max({hi[0], hi[1], hi[2], 1.0});
    const bool repeat = m_edge == EdgeMode::Repeat;
    double outside = 0.0;
    for (int a = 0; a < 3; ++a) outside = std::max({outside, lo[a] - o[a], o[a] - hi[a]});
    if (!(outside > kNearBoxFactor * size)) return ray;  // near, or not a number: clip decides
    double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
    for (int a = repeat ? 2 : 0; a < 3; ++a) {
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) t1 = -1.0;
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
    }
    Ray moved = ray;
    if (!(t0 <= t1) || !(t0 < double(ray.tMax))) {
        moved.tMax = 0.0f;
        return moved;
    }
    // Stop a box size short of the entry: clip() then finds the entry itself, in float.
    const double start = std::max(0.0, t0 - size);
    dvec3 p = o + start * d;
    if (repeat)
        for (int a = 0; a < 2; ++a) p[a] -= std::floor(p[a] / hi[a]) * hi[a];
    moved.origin = vec3(p);
    moved.tMax = float(double(ray.tMax) - start);
    offset = start;
    return moved;
}

}  // namespace relief
