#include <relief/techniques/qdm/qdm_paper.h>

#include <relief/core/parallel.h>

#include <algorithm>
#include <cmath>

namespace relief {

namespace {

// A node whose samples are all this fraction below the running cone slope can never raise b:
// the slope the loop keeps, b/a, only shrinks by float rounding (two roundings a ring, well
// under 1e-3 over the rings of a 4096² map).
constexpr float kSlopeMargin = 0.995f;

// floor(sqrt(d2)), exactly: the unit ring of a squared centre-to-centre distance.
int ringOf(int64_t d2) {
    auto r = int64_t(std::sqrt(double(d2)));
    while (r * r > d2) --r;
    while ((r + 1) * (r + 1) <= d2) ++r;
    return int(r);
}

// Whether an offset is the one to the nearest copy on a torus of period n: (−n/2, n/2].
bool nearestCopy(int64_t offset, int n) { return 2 * offset > -n && 2 * offset <= n; }

int64_t wrapOffset(int64_t offset, int n) {
    offset %= n;
    if (2 * offset > n) offset -= n;
    if (2 * offset <= -n) offset += n;
    return offset;
}

// The last ring the search reaches from sample (u, v).
int lastRing(const Surface& s, int u, int v, const QdmBuildParams& params) {
    const bool repeat = s.edge() == EdgeMode::Repeat;
    const int64_t dx = repeat ? s.width() / 2 : std::max(u, s.width() - 1 - u);
    const int64_t dy = repeat ? s.height() / 2 : std::max(v, s.height() - 1 - v);
    const int ring = ringOf(dx * dx + dy * dy);
    return params.maxDistance > 0.0f ? std::min(ring, int(params.maxDistance)) : ring;
}

float coneHeightOf(const Surface& s, const QdmBuildParams& params) {
    return params.heightRatio * s.maxZ();
}

// §3.1's cone loop; ring(i, along) returns m(i) where m(i) > along, else any value ≤ along.
template <class Ring>
std::pair<float, float> paperCone(float coneHeight, int last, Ring&& ring) {
    float a = 0.0f, b = 0.0f;
    for (int i = 1; i <= last; ++i) {
        const float along = a > 0.0f ? float(i) * (b / a) : 0.0f;
        b = std::max(along, ring(i, along));
        a = float(i);
        if (b > coneHeight) break;
    }
    return {a, b};
}

// c_j: the parabola from (a, b) through (j, v).
float paperC(float a, float b, int j, float v) {
    return 0.5f * (a + float(j)) + (v - b) / (2.0f * (float(j) - a));
}

// The max pyramid of the samples (level 0 = the W×H samples; node x of level L covers samples
// [x·2^L, min((x+1)·2^L, W))).
class SamplePyramid {
public:
    explicit SamplePyramid(const Surface& s) {
        m_widths.push_back(s.width());
        m_heights.push_back(s.height());
        m_levels.emplace_back(size_t(s.width()) * size_t(s.height()));
        for (int y = 0; y < s.height(); ++y)
            for (int x = 0; x < s.width(); ++x)
                m_levels[0][size_t(y) * size_t(s.width()) + size_t(x)] = s.sampleZ(x, y);
        while (m_widths.back() > 1 || m_heights.back() > 1) {
            const int w = m_widths.back(), h = m_heights.back();
            const int nw = (w + 1) / 2, nh = (h + 1) / 2;
            std::vector<float> next(size_t(nw) * size_t(nh), -kInfinity);
            const std::vector<float>& below = m_levels.back();
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    float& n = next[size_t(y / 2) * size_t(nw) + size_t(x / 2)];
                    n = std::max(n, below[size_t(y) * size_t(w) + size_t(x)]);
                }
            m_widths.push_back(nw);
            m_heights.push_back(nh);
            m_levels.push_back(std::move(next));
        }
    }
    int top() const { return int(m_levels.size()) - 1; }
    int widthAt(int level) const { return m_widths[size_t(level)]; }
    int heightAt(int level) const { return m_heights[size_t(level)]; }
    float at(int level, int x, int y) const {
        return m_levels[size_t(level)][size_t(y) * size_t(m_widths[size_t(level)]) + size_t(x)];
    }

private:
    std::vector<int> m_widths, m_heights;
    std::vector<std::vector<float>> m_levels;
};

// A pyramid node in one copy of the map (repeat: 3×3 copies), as offsets from the texel.
struct Node {
    float key = 0.0f;     // branch and bound: the bound on c_j
    int64_t nearest = 0;  // squared distance of its nearest sample position (cone walk order)
    int level, x, y, tx, ty;
    int64_t dx0, dx1, dy0, dy1;  // offsets of its first and last sample columns and rows
};

int64_t nearestOffset(int64_t lo, int64_t hi) { return std::max<int64_t>({0, lo, -hi}); }
int64_t farthestOffset(int64_t lo, int64_t hi) { return std::max(std::abs(lo), std::abs(hi)); }

class PaperSearch {
public:
    PaperSearch(const Surface& s, const QdmBuildParams& params)
        : m_s(s), m_params(params), m_pyramid(s), m_coneHeight(coneHeightOf(s, params)),
          m_repeat(s.edge() == EdgeMode::Repeat) {}

    QdmTexel texel(int u, int v) const {
        const float h = m_s.sampleZ(u, v);
        const int last = lastRing(m_s, u, v, m_params);
        const auto [a, b] = coneOf(u, v, h, last);
        return {a, b, maximizeC(u, v, h, last, a, b), h};
    }

private:
    // The node's offsets from (u, v) in the copy (tx, ty) of the map.
    Node node(int u, int v, int level, int x, int y, int tx, int ty) const {
        const int64_t w = m_s.width(), hgt = m_s.height();
        const int64_t x0 = int64_t(x) << level, y0 = int64_t(y) << level;
        const int64_t x1 = std::min((int64_t(x) + 1) << level, w) - 1;
        const int64_t y1 = std::min((int64_t(y) + 1) << level, hgt) - 1;
        Node n{.level = level, .x = x, .y = y, .tx = tx, .ty = ty, .dx0 = x0 + tx * w - u,
               .dx1 = x1 + tx * w - u, .dy0 = y0 + ty * hgt - v, .dy1 = y1 + ty * hgt - v};
        n.nearest = nearestSquared(n);
        return n;
    }
    // Whether some sample of the node lies at its nearest copy (always, in clamp mode).
    bool holdsNearest(const Node& n) const {
        if (!m_repeat) return true;
        const int w = m_s.width(), hgt = m_s.height();
        return 2 * n.dx1 > -w && 2 * n.dx0 <= w && 2 * n.dy1 > -hgt && 2 * n.dy0 <= hgt;
    }
    static int64_t nearestSquared(const Node& n) {
        const int64_t dx = nearestOffset(n.dx0, n.dx1), dy = nearestOffset(n.dy0, n.dy1);
        return dx * dx + dy * dy;
    }
    static int64_t farthestSquared(const Node& n) {
        const int64_t dx = farthestOffset(n.dx0, n.dx1), dy = farthestOffset(n.dy0, n.dy1);
        return dx * dx + dy * dy;
    }
    template <class Push>
    void pushRoots(int u, int v, Push&& push) const {
        const int k = m_repeat ? 1 : 0;
        for (int ty = -k; ty <= k; ++ty)
            for (int tx = -k; tx <= k; ++tx) push(node(u, v, m_pyramid.top(), 0, 0, tx, ty));
    }
    template <class Push>
    void pushChildren(int u, int v, const Node& n, Push&& push) const {
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const int x = 2 * n.x + dx, y = 2 * n.y + dy;
                if (x < m_pyramid.widthAt(n.level - 1) && y < m_pyramid.heightAt(n.level - 1))
                    push(node(u, v, n.level - 1, x, y, n.tx, n.ty));
            }
    }

    // The cone: nodes nearest first; a ring's samples are all out of the heap before the loop
    // asks for the next ring. Nodes at or below the apex, or below the running slope at their
    // nearest ring, cannot raise b on any later ring and are dropped.
    std::pair<float, float> coneOf(int u, int v, float h, int last) const {
        thread_local std::vector<Node> heap;
        heap.clear();
        auto nearer = [](const Node& p, const Node& q) { return p.nearest > q.nearest; };
        auto push = [&](const Node& n) {
            if (!holdsNearest(n) || !(m_pyramid.at(n.level, n.x, n.y) - h > 0.0f)) return;
            heap.push_back(n);
            std::push_heap(heap.begin(), heap.end(), nearer);
        };
        pushRoots(u, v, push);
        auto ring = [&](int i, float along) {
            const float slope = along / float(i);
            float best = -kInfinity;
            const int64_t limit = int64_t(i + 1) * (i + 1);
            while (!heap.empty() && heap.front().nearest < limit) {
                std::pop_heap(heap.begin(), heap.end(), nearer);
                const Node n = heap.back();
                heap.pop_back();
                const float top = m_pyramid.at(n.level, n.x, n.y) - h;
                const int nearest = ringOf(n.nearest);
                if (!(top > kSlopeMargin * slope * float(nearest))) continue;
                if (n.level > 0) {
                    pushChildren(u, v, n, push);
                } else if (nearest == i && (!m_repeat || (nearestCopy(n.dx0, m_s.width()) &&
                                                          nearestCopy(n.dy0, m_s.height())))) {
                    best = std::max(best, top);
                }
            }
            return best;
        };
        return paperCone(m_coneHeight, last, ring);
    }

    // c = max c_j over the samples beyond ring a: branch and bound, nodes by the largest c_j
    // their samples could give.
    float maximizeC(int u, int v, float h, int last, float a, float b) const {
        thread_local std::vector<Node> heap;
        heap.clear();
        auto lower = [](const Node& p, const Node& q) { return p.key < q.key; };
        float best = -kInfinity;
        auto push = [&](Node n) {
            if (!holdsNearest(n)) return;
            const int far = std::min(ringOf(farthestSquared(n)), last);
            const int near = std::max(ringOf(n.nearest), int(a) + 1);
            if (far < near) return;
            // c_j grows with v, and at v = top it is convex in j: the larger end bounds it.
            const float top = m_pyramid.at(n.level, n.x, n.y) - h;
            const float bound = std::max(paperC(a, b, near, top), paperC(a, b, far, top));
            n.key = bound + 1e-5f * (std::abs(bound) + 1.0f);  // float rounding of the leaves
            if (!(n.key > best)) return;
            heap.push_back(n);
            std::push_heap(heap.begin(), heap.end(), lower);
        };
        pushRoots(u, v, push);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), lower);
            const Node n = heap.back();
            heap.pop_back();
            if (!(n.key > best)) break;
            if (n.level > 0) {
                pushChildren(u, v, n, push);
            } else if (!m_repeat ||
                       (nearestCopy(n.dx0, m_s.width()) && nearestCopy(n.dy0, m_s.height()))) {
                const int j = ringOf(n.nearest);
                if (float(j) > a && j <= last)
                    best = std::max(best, paperC(a, b, j, m_pyramid.at(0, n.x, n.y) - h));
            }
        }
        return best > -kInfinity ? best : a;
    }

    const Surface& m_s;
    QdmBuildParams m_params;
    SamplePyramid m_pyramid;
    float m_coneHeight;
    bool m_repeat;
};

template <class PerTexel>
std::vector<QdmTexel> buildPaperRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<QdmTexel> texels(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        for (int v = int(begin); v < int(end); ++v)
            for (int u = 0; u < s.width(); ++u)
                texels[size_t(v) * size_t(s.width()) + size_t(u)] = perTexel(u, v);
    });
    return texels;
}

}  // namespace

std::vector<QdmTexel> buildQdmPaper(const Surface& surface, const QdmBuildParams& params) {
    const PaperSearch search(surface, params);
    return buildPaperRows(surface, [&](int u, int v) { return search.texel(u, v); });
}

// §3.1 as written: m(d) from every sample of the map, the cone loop, then c over the rings (or
// their upper convex bound's vertices).
std::vector<QdmTexel> buildQdmPaperBruteForce(const Surface& s, const QdmBuildParams& params) {
    const float coneHeight = coneHeightOf(s, params);
    const bool repeat = s.edge() == EdgeMode::Repeat;
    return buildPaperRows(s, [&](int u, int v) {
        const float h = s.sampleZ(u, v);
        const int last = lastRing(s, u, v, params);
        std::vector<float> m(size_t(last) + 1, -kInfinity);
        for (int y = 0; y < s.height(); ++y)
            for (int x = 0; x < s.width(); ++x) {
                const int64_t dx = repeat ? wrapOffset(x - u, s.width()) : x - u;
                const int64_t dy = repeat ? wrapOffset(y - v, s.height()) : y - v;
                const int k = ringOf(dx * dx + dy * dy);
                if (k <= last) m[size_t(k)] = std::max(m[size_t(k)], s.sampleZ(x, y) - h);
            }
        const auto [a, b] = paperCone(coneHeight, last, [&](int i, float) { return m[size_t(i)]; });
        std::vector<QdmPoint> beyond;
        for (int j = int(a) + 1; j <= last; ++j)
            if (m[size_t(j)] > -kInfinity) beyond.push_back({float(j), m[size_t(j)]});
        if (params.convexBound) beyond = upperConvexBound(beyond);
        float c = -kInfinity;
        for (const QdmPoint& p : beyond) c = std::max(c, paperC(a, b, int(p.r), p.v));
        return QdmTexel{a, b, c > -kInfinity ? c : a, h};
    });
}

}  // namespace relief
