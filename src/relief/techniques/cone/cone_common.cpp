#include <relief/techniques/cone/cone_common.h>

#include <relief/core/parallel.h>
#include <relief/techniques/quadtree/max_pyramid.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdlib>

namespace relief {

namespace {

struct Rect {
    float x0, y0, x1, y1;
};

float rectDistance(const Rect& a, const Rect& b) {
    const float dx = std::max({0.0f, b.x0 - a.x1, a.x0 - b.x1});
    const float dy = std::max({0.0f, b.y0 - a.y1, a.y0 - b.y1});
    return std::sqrt(dx * dx + dy * dy);
}

// Where a texel's cone starts: its footprint (a point for the published apex) and height.
struct Apex {
    Rect foot;
    float a;
};

Apex apexOf(const Surface& s, ConeKind kind, int i, int j) {
    const float x = float(i), y = float(j);
    if (kind != ConeKind::SafeStrict) {
        const float cx = x + 0.5f, cy = y + 0.5f;
        return {{cx, cy, cx, cy}, s.sampleZ(i, j)};
    }
    float a = 0.0f;
    for (float u : {0.0f, 0.5f, 1.0f})
        for (float v : {0.0f, 0.5f, 1.0f}) a = std::max(a, s.heightAt(x + u, y + v));
    return {{x, y, x + 1.0f, y + 1.0f}, a};
}

Rect cellRect(int ci, int cj) {
    return {float(ci) + 0.5f, float(cj) + 0.5f, float(ci) + 1.5f, float(cj) + 1.5f};
}

float maxCorner(const CellCorners& k) { return std::max({k.z00, k.z10, k.z01, k.z11}); }

float planeSlope(const CellPlane& p) { return std::sqrt(p.sx * p.sx + p.sy * p.sy); }

// Smallest t in [ta, tb] where the ray is strictly above both planes of the cell, or kInfinity.
float firstAboveInCell(const CellPlanes& planes, const Ray& ray, int ci, int cj, float ta,
                       float tb, float margin) {
    float lo = ta, hi = tb;
    for (const CellPlane* p : {&planes.first, &planes.second}) {
        auto above = [&](float t) {
            const vec3 q = ray.at(t);
            return q.z - p->at(q.x - (float(ci) + 0.5f), q.y - (float(cj) + 0.5f)) - margin;
        };
        const float fa = above(ta), fb = above(tb);
        if (fa <= 0.0f && fb <= 0.0f) return kInfinity;
        if (fa > 0.0f && fb > 0.0f) continue;
        const float tc = ta + (tb - ta) * (fa / (fa - fb));
        if (fa > 0.0f) hi = std::min(hi, tc); else lo = std::max(lo, tc);
    }
    return lo <= hi ? lo : kInfinity;
}

// First t in [t0, t1] where the ray is above S (out of the solid); t1 when there is none.
float firstExit(const Surface& s, const Ray& ray, float t0, float t1) {
    const float margin = 1e-5f * (1.0f + s.depth());
    for (float t = t0; t < t1;) {
        const CellSpan c = cellAt(s, ray, t, t1);
        const float e = firstAboveInCell(s.cellPlanes(c.ci, c.cj), ray, c.ci, c.cj, t, c.tb,
                                         margin);
        if (e <= c.tb) return e;
        if (c.tb >= t1) break;
        t = c.tb;
    }
    return t1;
}

// Policarpo & Oliveira: the ray from the box top above the apex through sample q, followed past
// q until it leaves the solid at C, gives |C − apex| / (z_C − a). Along the ray that ratio only
// grows, so the walk stops where it reaches `c` (the ratio found so far): C beyond cannot lower it.
float relaxedRatio(const Surface& s, const Apex& apex, vec3 q, float c) {
    const vec3 top(apex.foot.x0, apex.foot.y0, s.depth());
    if (q.x == top.x && q.y == top.y) return kInfinity;
    const Ray ray{q, glm::normalize(q - top), kInfinity};
    const RayInterval span = s.clip(ray);
    if (span.empty()) return kInfinity;
    const float reach = glm::length(vec2(q.x - top.x, q.y - top.y));
    const float vh = std::sqrt(ray.direction.x * ray.direction.x +
                               ray.direction.y * ray.direction.y);
    const float tStop = std::isfinite(c)
                            ? (c * (q.z - apex.a) - reach) / (vh - c * ray.direction.z)
                            : kInfinity;
    const float tEnd = std::min(span.tExit, std::max(0.0f, tStop));
    const float tc = firstExit(s, ray, 0.0f, tEnd);
    if (tc >= tEnd && tEnd < span.tExit) return kInfinity;
    const vec3 exit = ray.at(tc);
    if (exit.z <= apex.a) return kInfinity;
    return glm::length(vec2(exit.x - top.x, exit.y - top.y)) / (exit.z - apex.a);
}

// The bound cell (ci, cj) puts on the ratio of `apex` (kInfinity when none); `c` is the ratio
// found so far (the relaxed search skips rays that cannot lower it).
float leafRatio(const Surface& s, ConeKind kind, const Apex& apex, int ci, int cj, float c) {
    const CellCorners k = s.cellCorners(ci, cj);
    if (maxCorner(k) <= apex.a) return kInfinity;
    if (kind == ConeKind::SafeStrict) {
        const float d = rectDistance(apex.foot, cellRect(ci, cj));
        if (d > 0.0f) return d / (maxCorner(k) - apex.a);
        const CellPlanes p = planesFromCorners(k);
        const float g = std::max(planeSlope(p.first), planeSlope(p.second));
        return g > 0.0f ? 1.0f / g : kInfinity;
    }
    // Published maps: the sample at the cell's 00 corner (each sample is one cell's 00 corner).
    if (k.z00 <= apex.a) return kInfinity;
    const vec3 q(float(ci) + 0.5f, float(cj) + 0.5f, k.z00);
    const float strict =
        glm::length(vec2(q.x - apex.foot.x0, q.y - apex.foot.y0)) / (q.z - apex.a);
    if (kind == ConeKind::FaithfulStrict || strict >= c) return strict;
    return std::min(c, relaxedRatio(s, apex, q, c));
}

// Tile copies (repeat) the widest cone can reach, nearest (0, 0) first.
std::vector<ivec2> tileShifts(const Surface& s, float cMax) {
    if (s.edge() == EdgeMode::Clamp) return {ivec2(0)};
    const float reach = cMax * s.maxZ() + 2.0f;
    const int nx = int(std::ceil(reach / float(s.width())));
    const int ny = int(std::ceil(reach / float(s.height())));
    std::vector<ivec2> shifts;
    for (int ty = -ny; ty <= ny; ++ty)
        for (int tx = -nx; tx <= nx; ++tx) shifts.push_back({tx, ty});
    std::stable_sort(shifts.begin(), shifts.end(), [](ivec2 a, ivec2 b) {
        return std::abs(a.x) + std::abs(a.y) < std::abs(b.x) + std::abs(b.y);
    });
    return shifts;
}

class ConeSearch {
public:
    ConeSearch(const Surface& s, ConeKind kind)
        : m_s(s), m_kind(kind), m_pyramid(s), m_layout(m_pyramid.layout()),
          m_cMax(coneRatioMax(s)), m_shifts(tileShifts(s, m_cMax)) {}

    vec2 texel(int i, int j) const {
        const Apex apex = apexOf(m_s, m_kind, i, j);
        float c = m_cMax;
        for (ivec2 shift : m_shifts) visitTile(apex, shift, c);
        return {apex.a, c};
    }

    vec2 texelBruteForce(int i, int j) const {
        const Apex apex = apexOf(m_s, m_kind, i, j);
        float c = m_cMax;
        for (ivec2 shift : m_shifts)
            for (int l = 0; l < m_layout.cellsY; ++l)
                for (int k = 0; k < m_layout.cellsX; ++k) {
                    const ivec2 cell = globalCell(k, l, shift);
                    c = std::min(c, leafRatio(m_s, m_kind, apex, cell.x, cell.y, kInfinity));
                }
        return {apex.a, c};
    }

private:
    struct Node {
        int level, x, y;
    };

    ivec2 globalCell(int k, int l, ivec2 shift) const {
        return {m_layout.firstCell + k + shift.x * m_s.width(),
                m_layout.firstCell + l + shift.y * m_s.height()};
    }
    Rect nodeRect(const Node& n, ivec2 shift) const {
        const int size = 1 << n.level;
        const ivec2 lo = globalCell(n.x * size, n.y * size, shift);
        const ivec2 hi = globalCell(std::min((n.x + 1) * size, m_layout.cellsX),
                                    std::min((n.y + 1) * size, m_layout.cellsY), shift);
        return {float(lo.x) + 0.5f, float(lo.y) + 0.5f, float(hi.x) + 0.5f, float(hi.y) + 0.5f};
    }

    void visitTile(const Apex& apex, ivec2 shift, float& c) const {
        std::array<Node, 4 * PyramidLayout::kMaxLevels + 4> stack;
        int top = 0;
        stack[top++] = {m_layout.topLevel(), 0, 0};
        while (top > 0) {
            const Node n = stack[--top];
            const float m = m_pyramid.at(n.level, n.x, n.y);
            if (m <= apex.a) continue;
            const float d = rectDistance(apex.foot, nodeRect(n, shift));
            if (d >= c * (m - apex.a)) continue;
            if (n.level == 0) {
                const ivec2 cell = globalCell(n.x, n.y, shift);
                c = std::min(c, leafRatio(m_s, m_kind, apex, cell.x, cell.y, c));
                continue;
            }
            pushChildren(apex, shift, n, stack.data(), top);
        }
    }

    // Children that exist, farthest pushed first so that the nearest is visited first.
    template <class Stack>
    void pushChildren(const Apex& apex, ivec2 shift, const Node& n, Stack* stack, int& top) const {
        std::array<std::pair<float, Node>, 4> kids;
        int count = 0;
        const int level = n.level - 1;
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const Node kid{level, 2 * n.x + dx, 2 * n.y + dy};
                if (kid.x >= m_layout.widthAt(level) || kid.y >= m_layout.heightAt(level)) continue;
                kids[size_t(count++)] = {rectDistance(apex.foot, nodeRect(kid, shift)), kid};
            }
        std::sort(kids.begin(), kids.begin() + count,
                  [](const auto& p, const auto& q) { return p.first > q.first; });
        for (int k = 0; k < count; ++k) stack[top++] = kids[size_t(k)].second;
    }

    const Surface& m_s;
    ConeKind m_kind;
    MaxPyramid m_pyramid;
    PyramidLayout m_layout;
    float m_cMax;
    std::vector<ivec2> m_shifts;
};

template <class PerTexel>
std::vector<vec2> buildRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<vec2> cones(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        for (int j = int(begin); j < int(end); ++j)
            for (int i = 0; i < s.width(); ++i)
                cones[size_t(j) * size_t(s.width()) + size_t(i)] = perTexel(i, j);
    });
    return cones;
}

constexpr float kDecodeMargin = kConeDecodeMargin;

}  // namespace

float coneRatioMax(const Surface& s) {
    const float extent = s.edge() == EdgeMode::Clamp ? float(std::max(s.width(), s.height()))
                                                     : float(std::min(s.width(), s.height()));
    return extent / std::max(s.maxZ(), 1e-6f);
}

std::vector<vec2> buildCones(const Surface& surface, ConeKind kind) {
    const ConeSearch search(surface, kind);
    return buildRows(surface, [&](int i, int j) { return search.texel(i, j); });
}

float safeApexHeight(const Surface& surface, int i, int j) {
    return apexOf(surface, ConeKind::SafeStrict, i, j).a;
}

std::vector<vec2> buildConesBruteForce(const Surface& surface, ConeKind kind) {
    const ConeSearch search(surface, kind);
    return buildRows(surface, [&](int i, int j) { return search.texelBruteForce(i, j); });
}

MapArray encodeCones(const Surface& s, const std::vector<vec2>& cones,
                     const ConeEncoding& encoding) {
    MapArray array{"cones", s.width(), s.height(), 2, {}};
    array.data.reserve(cones.size() * 2);
    const float cMax = coneRatioMax(s);
    const float levels = float((1u << std::min(encoding.bits, 24)) - 1u);
    const bool quantize = encoding.bits < 32;
    for (const vec2& texel : cones) {
        float a = texel.x;
        float r = std::min(texel.y / cMax, 1.0f);
        if (encoding.sqrtRatio) r = std::sqrt(r);
        if (quantize) {
            a = s.depth() > 0.0f ? std::min(1.0f, std::ceil(a / s.depth() * levels) / levels) : 0.0f;
            r = std::floor(r * levels) / levels;
        }
        array.data.push_back(a);
        array.data.push_back(r);
    }
    return array;
}

ConeMap decodeCones(const Surface& s, const MapArray& array, const ConeEncoding& encoding) {
    std::vector<vec2> texels(size_t(array.width) * size_t(array.height));
    const float cMax = coneRatioMax(s);
    const bool quantize = encoding.bits < 32;
    for (size_t k = 0; k < texels.size(); ++k) {
        float a = array.data[2 * k], r = array.data[2 * k + 1];
        if (quantize) a = a * s.depth() * (1.0f + kDecodeMargin);
        if (encoding.sqrtRatio) r = r * r;
        texels[k] = {a, r * cMax * (1.0f - kDecodeMargin)};
    }
    return ConeMap(array.width, array.height, s.edge(), std::move(texels));
}

ConeEncoding encodingFrom(const ParamValues& params) {
    return {params.getInt("bits"), params.getInt("sqrt") != 0};
}

std::map<std::string, std::string> mapParameters(const Surface& s, int variant,
                                                 const ConeEncoding& encoding) {
    return {{"variant", std::to_string(variant)},
            {"bits", std::to_string(encoding.bits)},
            {"sqrt", encoding.sqrtRatio ? "1" : "0"},
            {"cone-max", fmt::format("{:.9g}", coneRatioMax(s))}};
}

namespace {
Status checkBaked(const TechniqueInput& input, std::string_view technique, int variant,
                  const ConeEncoding& encoding) {
    const TechniqueMaps& maps = *input.maps;
    const Surface& s = *input.surface;
    const auto wanted = mapParameters(s, variant, encoding);
    for (const auto& [key, value] : wanted) {
        auto found = maps.parameters.find(key);
        if (found == maps.parameters.end() || found->second != value)
            return makeError(ErrorKind::InvalidInput,
                             "{}: baked maps have {}={} but the tracer asks for {}={}", technique,
                             key, found == maps.parameters.end() ? "(none)" : found->second, key,
                             value);
    }
    const MapArray* cones = maps.find("cones");
    if (!cones) return makeError(ErrorKind::InvalidInput, "{}: baked maps lack 'cones'", technique);
    if (cones->width != s.width() || cones->height != s.height() || cones->channels != 2 ||
        cones->data.size() != size_t(s.width()) * size_t(s.height()) * 2)
        return makeError(ErrorKind::InvalidInput,
                         "{}: 'cones' is {}x{}x{} but the heightfield needs {}x{}x2", technique,
                         cones->width, cones->height, cones->channels, s.width(), s.height());
    return {};
}
}  // namespace

Result<std::shared_ptr<const ConeMap>> coneMapFor(const TechniqueInput& input,
                                                  std::string_view technique, ConeKind kind,
                                                  int variant) {
    const ConeEncoding encoding = encodingFrom(input.params);
    const Surface& s = *input.surface;
    if (input.maps) {
        if (Status status = checkBaked(input, technique, variant, encoding); !status.ok())
            return status.error();
        return std::make_shared<const ConeMap>(
            decodeCones(s, *input.maps->find("cones"), encoding));
    }
    return std::make_shared<const ConeMap>(
        decodeCones(s, encodeCones(s, buildCones(s, kind), encoding), encoding));
}

Result<TechniqueMaps> coneTechniqueMaps(const TechniqueInput& input, std::string_view technique,
                                        ConeKind kind, int variant) {
    const ConeEncoding encoding = encodingFrom(input.params);
    const Surface& s = *input.surface;
    TechniqueMaps maps;
    maps.technique = std::string(technique);
    maps.parameters = mapParameters(s, variant, encoding);
    maps.arrays.push_back(encodeCones(s, buildCones(s, kind), encoding));
    return maps;
}

}  // namespace relief
