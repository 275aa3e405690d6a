#include <relief/techniques/qdm/qdm_map.h>

#include <relief/core/parallel.h>
#include <relief/techniques/cone/cone_common.h>
#include <relief/techniques/quadtree/max_pyramid.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace relief {

namespace {

constexpr float kRoundUp = 1.0f + 1e-6f;  // float rounding of the fit, towards the safe side

struct Box {
    float x0, y0, x1, y1;
};

float boxDistance(const Box& a, const Box& b) {
    const float dx = std::max({0.0f, b.x0 - a.x1, a.x0 - b.x1});
    const float dy = std::max({0.0f, b.y0 - a.y1, a.y0 - b.y1});
    return std::sqrt(dx * dx + dy * dy);
}

struct Point {
    float r, v;
};

// What the fit reads: the points and the overlapping cells' slope constraint.
struct Radial {
    std::vector<Point> points;
    float slope = 0.0f;
};

float steeperSlope(const CellPlanes& p) {
    auto g = [](const CellPlane& q) { return std::sqrt(q.sx * q.sx + q.sy * q.sy); };
    return std::max(g(p.first), g(p.second));
}

// Adds cell (ci, cj)'s point; returns v (≤ 0 when the cell is nowhere above the apex).
float addCell(const Surface& s, const Box& foot, float h, int ci, int cj, Radial& radial) {
    const CellCorners k = s.cellCorners(ci, cj);
    const float v = std::max({k.z00, k.z10, k.z01, k.z11}) - h;
    if (v <= 0.0f) return v;
    const Box cell{float(ci) + 0.5f, float(cj) + 0.5f, float(ci) + 1.5f, float(cj) + 1.5f};
    const float r = boxDistance(foot, cell);
    if (r > 0.0f) {
        radial.points.push_back({r, v});
        return v;
    }
    const float g = steeperSlope(planesFromCorners(k));
    radial.slope = std::max(radial.slope, g);
    if (g > 0.0f) radial.points.push_back({v / g, v});
    return 0.0f;  // its point lies at v / g, not at r = 0: it bounds no farther node
}

// Smallest c whose nondecreasing parabola from (a, b) reaches v at r (> a).
float parabolaC(float a, float b, Point p) {
    const float e = p.v - b, w = p.r - a;
    if (e <= 0.0f) return a;
    return e >= w * w ? 0.5f * (a + p.r) + e / (2.0f * w) : a + std::sqrt(e);
}

// Andrew's monotone chain, upper half, over points sorted by r.
std::vector<Point> upperConvexBound(std::span<const Point> points) {
    std::vector<Point> hull;
    for (const Point& p : points) {
        while (!hull.empty() && hull.back().r == p.r && hull.back().v <= p.v) hull.pop_back();
        if (!hull.empty() && hull.back().r == p.r) continue;
        while (hull.size() >= 2) {
            const Point &o = hull[hull.size() - 2], &m = hull.back();
            if ((m.r - o.r) * (p.v - o.v) - (m.v - o.v) * (p.r - o.r) < 0.0f) break;
            hull.pop_back();
        }
        hull.push_back(p);
    }
    return hull;
}

// The paper's search (§3.1, §4.1) over the points sorted by r (the highest first among equal
// r, so that the cone search depends on the staircase only).
QdmTexel fit(Radial& radial, float h, float coneHeight, bool convex) {
    std::sort(radial.points.begin(), radial.points.end(), [](const Point& p, const Point& q) {
        return p.r < q.r || (p.r == q.r && p.v > q.v);
    });
    const std::vector<Point>& pts = radial.points;
    float s = radial.slope * kRoundUp;
    float a = s > 0.0f ? coneHeight / s : kInfinity;
    for (const Point& p : pts) {
        if (p.r > a) break;
        s = std::max(s, p.v / p.r * kRoundUp);
        a = coneHeight / s;
    }
    if (!(s > 0.0f)) return {0.0f, 0.0f, 0.0f, h};  // nothing above the apex
    const float b = s * a;
    const auto beyond = std::upper_bound(pts.begin(), pts.end(), a,
                                         [](float x, const Point& p) { return x < p.r; });
    std::span<const Point> rest(beyond, pts.end());
    const std::vector<Point> hull = convex ? upperConvexBound(rest) : std::vector<Point>();
    float c = a;
    for (const Point& p : convex ? std::span<const Point>(hull) : rest)
        c = std::max(c, parabolaC(a, b, p));
    return {a, b, c * kRoundUp + 1e-6f, h};
}

// A lower bound of the final profile while points arrive in order of r: the cone (s, a) until
// the walk passes a (then it is final), after that the parabola of the largest c so far.
class RunningFit {
public:
    explicit RunningFit(float coneHeight) : m_coneHeight(coneHeight) {}

    void add(const Point& p, float slope) {
        if (!m_coneDone) {
            m_s = std::max(m_s, slope * kRoundUp);
            if (p.r <= cone() || p.r == m_lastR) {  // ties at r: as fit, whatever their order
                m_s = std::max(m_s, p.v / p.r * kRoundUp);
                m_lastR = p.r;
            }
        } else if (p.r > m_a) {
            m_c = std::max(m_c, parabolaC(m_a, m_b, p));
        }
    }
    // Profile value no fit of the final points can go below at distance d (d ≥ every r so far).
    // Called for nodes in the order they leave the heap: passing a (and every tie) ends the cone.
    float lowerBound(float d, const Radial& radial) {
        if (!m_coneDone && d > cone() && d > m_lastR && m_s > 0.0f) finishCone(radial);
        return bound(d);
    }
    // The same without ending the cone (for nodes not yet in order).
    float bound(float d) const {
        if (!m_coneDone) return std::min(m_s * d, m_coneHeight);
        const float u = std::min(d, m_c) - m_a;
        return d <= m_a ? m_s * d : m_b + u * (2.0f * (m_c - m_a) - u);
    }

    bool coneDone() const { return m_coneDone; }
    float c() const { return m_c; }
    // The largest c_j a cell at distance ≥ d (> a) and height ≤ v can need (c_j is
    // nonincreasing in r and nondecreasing in v).
    float cBound(float d, float v) const { return parabolaC(m_a, m_b, {d, v}); }

private:
    float cone() const { return m_s > 0.0f ? m_coneHeight / m_s : kInfinity; }
    void finishCone(const Radial& radial) {
        m_coneDone = true;
        m_a = cone();
        m_b = m_s * m_a;
        m_c = m_a;
        for (const Point& p : radial.points)
            if (p.r > m_a) m_c = std::max(m_c, parabolaC(m_a, m_b, p));
    }
    float m_coneHeight, m_s = 0.0f, m_a = 0.0f, m_b = 0.0f, m_c = 0.0f, m_lastR = -1.0f;
    bool m_coneDone = false;
};

// Tile copies a search visits: one (clamp) or the 3×3 around the texel's own (repeat), which
// hold the nearest copy of every cell.
std::vector<ivec2> shiftsOf(const Surface& s) {
    if (s.edge() == EdgeMode::Clamp) return {ivec2(0)};
    std::vector<ivec2> shifts;
    for (int ty = -1; ty <= 1; ++ty)
        for (int tx = -1; tx <= 1; ++tx) shifts.push_back({tx, ty});
    return shifts;
}

class QdmSearch {
public:
    QdmSearch(const Surface& s, const QdmBuildParams& params)
        : m_s(s), m_params(params), m_pyramid(s), m_layout(m_pyramid.layout()),
          m_shifts(shiftsOf(s)),
          m_reach(params.maxDistance > 0.0f ? params.maxDistance : kInfinity) {}

    QdmTexel texel(int i, int j) const {
        const float h = safeApexHeight(m_s, i, j);
        const Box foot{float(i), float(j), float(i + 1), float(j + 1)};
        Radial radial;
        staircase(foot, h, radial);
        return fit(radial, h, coneHeight(), m_params.convexBound);
    }

    QdmTexel texelBruteForce(int i, int j) const {
        const float h = safeApexHeight(m_s, i, j);
        const Box foot{float(i), float(j), float(i + 1), float(j + 1)};
        Radial radial;
        for (ivec2 shift : m_shifts)
            for (int l = 0; l < m_layout.cellsY; ++l)
                for (int k = 0; k < m_layout.cellsX; ++k) {
                    const ivec2 cell = globalCell(k, l, shift);
                    const Box box{float(cell.x) + 0.5f, float(cell.y) + 0.5f,
                                  float(cell.x) + 1.5f, float(cell.y) + 1.5f};
                    if (boxDistance(foot, box) <= m_reach)
                        addCell(m_s, foot, h, cell.x, cell.y, radial);
                }
        return fit(radial, h, coneHeight(), false);
    }

private:
    struct Node {
        float distance;
        int level, x, y, shift;
        bool operator<(const Node& o) const { return distance > o.distance; }  // min-heap
    };

    float coneHeight() const { return m_params.heightRatio * m_s.maxZ(); }

    ivec2 globalCell(int k, int l, ivec2 shift) const {
        return {m_layout.firstCell + k + shift.x * m_s.width(),
                m_layout.firstCell + l + shift.y * m_s.height()};
    }
    Box nodeBox(int level, int x, int y, ivec2 shift) const {
        const int size = 1 << level;
        const ivec2 lo = globalCell(x * size, y * size, shift);
        const ivec2 hi = globalCell(std::min((x + 1) * size, m_layout.cellsX),
                                    std::min((y + 1) * size, m_layout.cellsY), shift);
        return {float(lo.x) + 0.5f, float(lo.y) + 0.5f, float(hi.x) + 0.5f, float(hi.y) + 0.5f};
    }
    Node node(const Box& foot, int level, int x, int y, int shift) const {
        return {boxDistance(foot, nodeBox(level, x, y, m_shifts[size_t(shift)])), level, x, y,
                shift};
    }

    // Best-first by distance. A node is skipped when no cell in it can change the fit: no higher
    // than the best point found nearer (staircase), or under the profile the fit has reached so
    // far at the node's distance (it only grows: s and c only increase, b = cone height).
    void staircase(const Box& foot, float h, Radial& radial) const {
        thread_local std::vector<Node> heap;
        heap.clear();
        for (int k = 0; k < int(m_shifts.size()); ++k)
            heap.push_back(node(foot, m_layout.topLevel(), 0, 0, k));
        std::make_heap(heap.begin(), heap.end());
        RunningFit running(coneHeight());
        float best = 0.0f;
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end());
            const Node n = heap.back();
            heap.pop_back();
            if (n.distance > m_reach) break;
            const float v = m_pyramid.at(n.level, n.x, n.y) - h;
            if (v <= best || v <= running.lowerBound(n.distance, radial)) continue;
            if (running.coneDone()) {  // the cone is final: the rest only raises c, in any order
                heap.push_back(n);
                maximizeC(foot, h, heap, running, radial);
                return;
            }
            if (n.level == 0) {
                const ivec2 cell = globalCell(n.x, n.y, m_shifts[size_t(n.shift)]);
                const size_t before = radial.points.size();
                best = std::max(best, addCell(m_s, foot, h, cell.x, cell.y, radial));
                for (size_t k = before; k < radial.points.size(); ++k)
                    running.add(radial.points[k], radial.slope);
                continue;
            }
            const int level = n.level - 1;
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const int x = 2 * n.x + dx, y = 2 * n.y + dy;
                    if (x >= m_layout.widthAt(level) || y >= m_layout.heightAt(level)) continue;
                    const Node kid = node(foot, level, x, y, n.shift);
                    const float kv = m_pyramid.at(level, x, y) - h;
                    if (kv <= best || kv <= running.bound(kid.distance)) continue;
                    heap.push_back(kid);
                    std::push_heap(heap.begin(), heap.end());
                }
        }
    }

    // Branch and bound for c = max c_j: nodes by the largest c_j a cell in them could need.
    void maximizeC(const Box& foot, float h, const std::vector<Node>& nodes, RunningFit& running,
                   Radial& radial) const {
        thread_local std::vector<std::pair<float, Node>> heap;
        heap.clear();
        auto push = [&](const Node& n) {
            if (n.distance > m_reach) return;
            const float bound = running.cBound(n.distance, m_pyramid.at(n.level, n.x, n.y) - h);
            if (bound <= running.c()) return;
            heap.push_back({bound, n});
            std::push_heap(heap.begin(), heap.end(), byBound);
        };
        for (const Node& n : nodes) push(n);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), byBound);
            const auto [bound, n] = heap.back();
            heap.pop_back();
            if (bound <= running.c()) break;
            if (n.level == 0) {
                const ivec2 cell = globalCell(n.x, n.y, m_shifts[size_t(n.shift)]);
                const size_t before = radial.points.size();
                addCell(m_s, foot, h, cell.x, cell.y, radial);
                for (size_t k = before; k < radial.points.size(); ++k)
                    running.add(radial.points[k], radial.slope);
                continue;
            }
            const int level = n.level - 1;
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const int x = 2 * n.x + dx, y = 2 * n.y + dy;
                    if (x < m_layout.widthAt(level) && y < m_layout.heightAt(level))
                        push(node(foot, level, x, y, n.shift));
                }
        }
    }
    static bool byBound(const std::pair<float, Node>& p, const std::pair<float, Node>& q) {
        return p.first < q.first;
    }

    const Surface& m_s;
    QdmBuildParams m_params;
    MaxPyramid m_pyramid;
    PyramidLayout m_layout;
    std::vector<ivec2> m_shifts;
    float m_reach;
};

template <class PerTexel>
std::vector<QdmTexel> buildRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<QdmTexel> texels(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        for (int j = int(begin); j < int(end); ++j)
            for (int i = 0; i < s.width(); ++i)
                texels[size_t(j) * size_t(s.width()) + size_t(i)] = perTexel(i, j);
    });
    return texels;
}

}  // namespace

QdmBuildParams QdmBuildParams::from(const ParamValues& params) {
    return {float(params.get("height-ratio")), float(params.get("max-distance")),
            params.getInt("convex-bound") != 0};
}

QdmMap::QdmMap(const Surface& s, std::vector<QdmTexel> texels, float maxDistance)
    : m_width(s.width()), m_height(s.height()), m_edge(s.edge()), m_maxZ(s.maxZ()),
      m_maxDistance(maxDistance > 0.0f ? maxDistance : kInfinity), m_texels(std::move(texels)) {}

std::vector<QdmTexel> buildQdm(const Surface& surface, const QdmBuildParams& params) {
    const QdmSearch search(surface, params);
    return buildRows(surface, [&](int i, int j) { return search.texel(i, j); });
}

std::vector<QdmTexel> buildQdmBruteForce(const Surface& surface, const QdmBuildParams& params) {
    const QdmSearch search(surface, params);
    return buildRows(surface, [&](int i, int j) { return search.texelBruteForce(i, j); });
}

MapArray encodeQdm(const Surface& s, const std::vector<QdmTexel>& texels) {
    MapArray array{"qdm", s.width(), s.height(), 4, {}};
    array.data.reserve(texels.size() * 4);
    for (const QdmTexel& q : texels) array.data.insert(array.data.end(), {q.a, q.b, q.c, q.h});
    return array;
}

std::map<std::string, std::string> qdmMapParameters(const QdmBuildParams& params) {
    return {{"height-ratio", fmt::format("{:.9g}", params.heightRatio)},
            {"max-distance", fmt::format("{:.9g}", params.maxDistance)},
            {"convex-bound", params.convexBound ? "1" : "0"}};
}

namespace {
Result<std::vector<QdmTexel>> bakedTexels(const TechniqueMaps& maps, const Surface& s,
                                          const QdmBuildParams& params) {
    for (const auto& [key, value] : qdmMapParameters(params)) {
        auto found = maps.parameters.find(key);
        if (found == maps.parameters.end() || found->second != value)
            return makeError(ErrorKind::InvalidInput,
                             "qdm: baked maps have {}={} but the tracer asks for {}={}", key,
                             found == maps.parameters.end() ? "(none)" : found->second, key,
                             value);
    }
    const MapArray* array = maps.find("qdm");
    if (!array) return makeError(ErrorKind::InvalidInput, "qdm: baked maps lack 'qdm'");
    if (array->width != s.width() || array->height != s.height() || array->channels != 4 ||
        array->data.size() != size_t(s.width()) * size_t(s.height()) * 4)
        return makeError(ErrorKind::InvalidInput,
                         "qdm: 'qdm' is {}x{}x{} but the heightfield needs {}x{}x4", array->width,
                         array->height, array->channels, s.width(), s.height());
    std::vector<QdmTexel> texels(size_t(s.width()) * size_t(s.height()));
    for (size_t k = 0; k < texels.size(); ++k) {
        const float* d = &array->data[4 * k];
        if (!(std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2]) &&
              std::isfinite(d[3]) && d[0] >= 0.0f && d[1] >= 0.0f && d[2] >= d[0]))
            return makeError(ErrorKind::InvalidInput, "qdm: texel {} holds an invalid entry", k);
        texels[k] = {d[0], d[1], d[2], d[3]};
    }
    return texels;
}
}  // namespace

Result<std::shared_ptr<const QdmMap>> qdmMapFor(const TechniqueInput& input) {
    const Surface& s = *input.surface;
    const QdmBuildParams params = QdmBuildParams::from(input.params);
    if (!input.maps)
        return std::make_shared<const QdmMap>(s, buildQdm(s, params), params.maxDistance);
    auto texels = bakedTexels(*input.maps, s, params);
    if (!texels) return texels.error();
    return std::make_shared<const QdmMap>(s, std::move(*texels), params.maxDistance);
}

}  // namespace relief
