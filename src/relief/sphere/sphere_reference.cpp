#include <relief/sphere/sphere_reference.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace relief {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Band b of texel y: 0 = the south polar strip [0, 0.5], b in [1, H−1] = cell row b−1 covering
// [b−0.5, b+0.5], H = the north polar strip [H−0.5, H].
int bandOf(double y, int height) { return std::clamp(int(std::floor(y + 0.5)), 0, height); }

// Largest angular slope of D·h over band b.
double bandSlope(const Surface& g, int b) {
    const int w = g.width(), h = g.height();
    const bool pole = b == 0 || b == h || h < 2;
    const int cj = std::clamp(b - 1, 0, std::max(0, h - 2));
    const double y0 = std::max(0.0, double(b) - 0.5), y1 = std::min(double(h), double(b) + 0.5);
    const double sinMin = std::min(std::sin(kPi * y0 / h), std::sin(kPi * y1 / h));
    double best = 0.0;
    for (int ci = -1; ci < w; ++ci) {
        const CellPlanes p = g.cellPlanes(ci, cj);
        for (const CellPlane& q : {p.first, p.second}) {
            const double lon = double(q.sx) * w / (2.0 * kPi);
            const double lat = pole ? 0.0 : double(q.sy) * h / kPi;  // polar strips: constant in y
            if (lon != 0.0 && sinMin <= 0.0) return kInf;
            const double e = lon == 0.0 ? 0.0 : lon / sinMin;
            best = std::max(best, std::sqrt(e * e + lat * lat));
        }
    }
    return best;
}

}  // namespace

SphereReference::SphereReference(std::shared_ptr<const SphereSurface> sphere)
    : m_sphere(std::move(sphere)) {
    const Surface& g = m_sphere->grid();
    m_bands = g.height() + 1;
    std::vector<double> level(static_cast<size_t>(m_bands));
    for (int b = 0; b < m_bands; ++b) level[size_t(b)] = bandSlope(g, b);
    m_rangeMax.push_back(std::move(level));
    for (int span = 2; span <= m_bands; span *= 2) {
        const std::vector<double>& prev = m_rangeMax.back();
        std::vector<double> next(static_cast<size_t>(m_bands - span + 1));
        for (size_t i = 0; i < next.size(); ++i)
            next[i] = std::max(prev[i], prev[i + size_t(span / 2)]);
        m_rangeMax.push_back(std::move(next));
    }
}

double SphereReference::slopeBound(double colat0, double colat1) const {
    const int h = m_sphere->grid().height();
    // texel y = H·(π − colat)/π: larger colatitude, smaller y.
    const double ya = h * (kPi - std::clamp(colat1, 0.0, kPi)) / kPi;
    const double yb = h * (kPi - std::clamp(colat0, 0.0, kPi)) / kPi;
    const int b0 = bandOf(ya, h), b1 = bandOf(yb, h);
    const int len = b1 - b0 + 1;
    int k = 0;
    while ((2 << k) <= len) ++k;
    return std::max(m_rangeMax[size_t(k)][size_t(b0)], m_rangeMax[size_t(k)][size_t(b1 - (1 << k) + 1)]);
}

double SphereReference::field(const dvec3& p) const {
    const double r = glm::length(p);
    return r - m_sphere->radius() - m_sphere->heightAt(p / r);
}

double SphereReference::safeStep(const dvec3& p, double f) const {
    const double r0 = m_sphere->radius();
    const double colat = std::acos(std::clamp(p.z / glm::length(p), -1.0, 1.0));
    double delta = f;
    for (int k = 0; k < 60; ++k) {
        const double reach = delta / r0;
        const double g = slopeBound(colat - reach, colat + reach);
        const double allowed = f / std::sqrt(1.0 + (g / r0) * (g / r0));
        if (delta <= allowed) return delta;
        delta = std::isfinite(allowed) && allowed > 0.0 ? allowed : 0.5 * delta;
        if (delta < kMinStep) return kMinStep;
    }
    return kMinStep;
}

Hit SphereReference::trace(const Ray& ray) const {
    Hit hit;
    const dvec3 o(ray.origin), d = glm::normalize(dvec3(ray.direction));
    // The enclosing sphere R + D·max h bounds the march.
    const double outer = m_sphere->maxRadius() + 1e-9;
    const double b = glm::dot(o, d), c = glm::dot(o, o) - outer * outer;
    const double disc = b * b - c;
    if (disc < 0.0) return hit;
    double t = std::max(0.0, -b - std::sqrt(disc));
    const double tExit = std::min(double(ray.tMax), -b + std::sqrt(disc));
    if (t > tExit) return hit;
    double f = field(o + t * d);
    double tPrev = t;
    ++hit.steps;
    while (f > 0.0) {
        tPrev = t;
        t += safeStep(o + t * d, f);
        if (t > tExit) return hit;
        f = field(o + t * d);
        ++hit.steps;
    }
    double lo = tPrev, hi = t;
    for (int k = 0; k < 60 && hi - lo > 1e-9 * std::max(1.0, hi); ++k) {
        const double mid = 0.5 * (lo + hi);
        (field(o + mid * d) > 0.0 ? lo : hi) = mid;
        ++hit.steps;
    }
    hit.hit = true;
    hit.t = float(hi);
    hit.position = ray.at(hit.t);
    hit.fetches = 4 * hit.steps;
    return hit;
}

}  // namespace relief
