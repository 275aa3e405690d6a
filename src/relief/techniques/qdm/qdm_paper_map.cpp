#include <relief/techniques/qdm/qdm_paper.h>

#include <relief/core/parallel.h>

#include <algorithm>
#include <cmath>
#include <limits>

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
    float key = 0.0f;     // branch and bound: the bound on c_j (or on v / ring)
    int64_t nearest = 0;  // squared distance of its nearest sample position (cone walk order)
    int level, x, y, tx, ty;
    int64_t dx0, dx1, dy0, dy1;  // offsets of its first and last sample columns and rows
};

int64_t nearestOffset(int64_t lo, int64_t hi) { return std::max<int64_t>({0, lo, -hi}); }
int64_t farthestOffset(int64_t lo, int64_t hi) { return std::max(std::abs(lo), std::abs(hi)); }

// Pops of the ring walk before the cone is sought from its last record instead (the same
// result): long after a neighbour the walk served, short after one it did not (rough ground
// ends within a few rings, gently rising ground never soon). At 256² fixed budgets of 64–512
// each lost on fbm, peaks6 or Colorado; this pair kept the walk's time on fbm and Colorado and
// the probes' on peaks6.
constexpr int64_t kWalkBudgetAfterWalk = 1024, kWalkBudgetAfterProbes = 32;
constexpr int64_t kUnlimited = std::numeric_limits<int64_t>::max();

// What a texel hands to the next one (PaperSearch::texel).
struct PaperGuess {
    int ring = 0;        // where its cone loop broke
    bool walked = true;  // its cone came from the ring walk within budget
    int x = -1, y = -1;  // its steepest sample up to there
};

class PaperSearch {
public:
    PaperSearch(const Surface& s, const QdmBuildParams& params)
        : m_s(s), m_params(params), m_pyramid(s), m_coneHeight(coneHeightOf(s, params)),
          m_repeat(s.edge() == EdgeMode::Repeat) {}

    // `guess`: the previous (neighbouring) texel's break ring and steepest sample; they only
    // pick where the search for the last record probes first and prune it. On return: this
    // texel's.
    QdmTexel texel(int u, int v, PaperGuess& guess) const {
        const float h = m_s.sampleZ(u, v);
        const int last = lastRing(m_s, u, v, m_params);
        // Rough ground: the walk ends within a few rings, cheaper than the probes.
        const int64_t budget = !m_params.skipRings            ? kUnlimited
                               : m_params.ringWalkBudget >= 0 ? m_params.ringWalkBudget
                               : guess.walked                 ? kWalkBudgetAfterWalk
                                                              : kWalkBudgetAfterProbes;
        bool over = false;
        std::pair<float, float> cone = coneOf(u, v, h, last, budget, over);
        guess.walked = !over;
        if (over && !coneFromLastRecord(u, v, h, last, guess, cone))
            cone = coneOf(u, v, h, last, kUnlimited, over);
        const auto [a, b] = cone;
        guess.ring = int(a);
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
    // `budget`: pops before it gives up (sets `over`; the pair is then meaningless).
    std::pair<float, float> coneOf(int u, int v, float h, int last, int64_t budget,
                                   bool& over) const {
        int64_t pops = 0;
        over = false;
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
                if (++pops > budget) {
                    over = true;
                    return kInfinity;  // ends the loop
                }
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

    // ---- The cone from its last record ---------------------------------------------------
    // The loop (paperCone) keeps b_i = max(A_i, m(i)) with A_i = fl(i·fl(b_{i−1}/(i−1))), so a
    // ring with m(i) > A_i (a record) sets b to m(i) exactly and the state after it depends on
    // nothing before. The result is therefore the chain from the last record ℓ before the
    // break, and ring by ring costs Θ(a²) samples on gently rising ground (a record every ring).
    // Instead: in exact arithmetic b_i = i·G_i with G_i = max over rings k ≤ i of m(k)/k, the
    // break is the first i with i·G_i > H (found by bisection on i, each probe a branch and
    // bound for G_i, the first probe at the neighbour's ring), and ℓ is the ring of the
    // steepest sample up to there. The float loop is then proved to take that path, or the
    // rings are walked as before:
    //   (1) ℓ is a float record: by induction b_k ≤ k·G_k·(1 + δ_k), δ_k = (1 + 2^−24)^{2k+2} − 1
    //       (two roundings a ring), so m(ℓ) > ℓ·G_{ℓ−1}·(1 + δ_ℓ) beats A_ℓ;
    //   (2) no break before ℓ: (ℓ − 1)·G_{ℓ−1}·(1 + δ_{ℓ−1}) ≤ H (k·G_k only grows);
    //   (3) the chain from b_ℓ = m(ℓ) is run as the loop runs it (paperCone itself), to its
    //       break T, and (4) no sample at a ring k in (ℓ, T] lies above A_k (one pruned search).
    // The same (a, b) to the bit as the ring walk (test QdmPaperMap.SkippingRingsChangesNothing).
    struct Steepest {
        double slope = 0.0;  // max of v / ring over the samples with v > 0 (0: none)
        int ring = 0;        // its ring, the nearest among equal slopes
        float v = 0.0f;      // its height above the apex: m(ring)
        int x = -1, y = -1;  // the sample
    };

    // Sample (x, y) from apex (u, v) at height h, as a leaf of the search sees it (its nearest
    // copy); slope 0 when it is no candidate within maxRing.
    Steepest sampleSlope(int u, int v, float h, int x, int y, int maxRing) const {
        int64_t dx = int64_t(x) - u, dy = int64_t(y) - v;
        if (m_repeat) dx = wrapOffset(dx, m_s.width()), dy = wrapOffset(dy, m_s.height());
        const int ring = ringOf(dx * dx + dy * dy);
        const float top = m_pyramid.at(0, x, y) - h;
        if (ring < 1 || ring > maxRing || !(top > 0.0f)) return {};
        return {double(top) / double(ring), ring, top, x, y};
    }

    // Rings 1 … maxRing: branch and bound, nodes by top / (their nearest ring). `start`: a
    // candidate already known (it only prunes: ties still go to the nearer ring).
    Steepest steepest(int u, int v, float h, int maxRing, Steepest start) const {
        thread_local std::vector<Node> heap;
        heap.clear();
        auto lower = [](const Node& p, const Node& q) { return p.key < q.key; };
        Steepest best = start;
        auto push = [&](Node n) {
            if (!holdsNearest(n)) return;
            const float top = m_pyramid.at(n.level, n.x, n.y) - h;
            const int near = ringOf(n.nearest);
            if (!(top > 0.0f) || near > maxRing) return;
            // Rounded up: the bound must not drop the steepest sample (G bounds the loop).
            n.key = near == 0 ? kInfinity : float(double(top) / double(near) * (1.0 + 1e-6));
            if (double(n.key) < best.slope) return;
            heap.push_back(n);
            std::push_heap(heap.begin(), heap.end(), lower);
        };
        pushRoots(u, v, push);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), lower);
            const Node n = heap.back();
            heap.pop_back();
            if (double(n.key) < best.slope) break;
            if (n.level > 0) {
                pushChildren(u, v, n, push);
                continue;
            }
            const int ring = ringOf(n.nearest);
            if (ring < 1 || (m_repeat && !(nearestCopy(n.dx0, m_s.width()) &&
                                           nearestCopy(n.dy0, m_s.height()))))
                continue;
            const float top = m_pyramid.at(0, n.x, n.y) - h;
            const double slope = double(top) / double(ring);
            if (slope > best.slope || (slope == best.slope && ring < best.ring))
                best = {slope, ring, top, n.x, n.y};
        }
        return best;
    }

    // Whether a sample at a ring k in (first, lastK] lies above along[k] (a record the chain
    // from `first` does not have); minFrom[k] = min of along over [k, lastK] bounds a node.
    bool recordAfter(int u, int v, float h, int first, int lastK, const std::vector<float>& along,
                     const std::vector<float>& minFrom) const {
        thread_local std::vector<Node> stack;
        stack.clear();
        bool found = false;
        auto push = [&](const Node& n) {
            if (found || !holdsNearest(n)) return;
            const int near = std::max(ringOf(n.nearest), first + 1);
            const int far = std::min(ringOf(farthestSquared(n)), lastK);
            if (near > far) return;
            const float top = m_pyramid.at(n.level, n.x, n.y) - h;
            if (!(top > minFrom[size_t(near)])) return;
            if (n.level > 0) {
                stack.push_back(n);
                return;
            }
            if (!m_repeat ||
                (nearestCopy(n.dx0, m_s.width()) && nearestCopy(n.dy0, m_s.height())))
                found = top > along[size_t(ringOf(n.nearest))];
        };
        pushRoots(u, v, push);
        while (!stack.empty() && !found) {
            const Node n = stack.back();
            stack.pop_back();
            pushChildren(u, v, n, push);
        }
        return found;
    }

    // The cone by (1)–(4) above; false when a condition fails (then the rings are walked).
    bool coneFromLastRecord(int u, int v, float h, int last, PaperGuess& guess,
                            std::pair<float, float>& cone) const {
        if (last < 1) return false;
        const double H = double(m_coneHeight);
        // The neighbour's steepest sample, and each probe's, start the probes they fit.
        const Steepest near = guess.x >= 0 ? sampleSlope(u, v, h, guess.x, guess.y, last)
                                           : Steepest{};
        std::vector<std::pair<int, Steepest>> probes;  // a handful per texel
        auto G = [&](int i) {
            Steepest start = near.ring <= i ? near : Steepest{};
            for (const auto& [ring, s] : probes) {
                if (ring == i) return s;
                if (s.ring <= i && s.slope > start.slope) start = s;
            }
            probes.push_back({i, steepest(u, v, h, i, start)});
            return probes.back().second;
        };
        auto breaks = [&](int i) { return G(i).slope * double(i) > H; };
        // The first i ≤ last with i·G_i > H (last when none): lo fails, hi holds or is last.
        int lo = 0, hi = last;
        if (const int g = guess.ring; g >= 1 && g < last) {
            if (breaks(g)) {
                hi = g;
                if (g > 1 && !breaks(g - 1)) lo = g - 1;
            } else {
                lo = g;
                if (breaks(g + 1)) hi = g + 1;
            }
        }
        while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            (breaks(mid) ? hi : lo) = mid;
        }
        const Steepest record = G(hi);
        guess.x = record.x, guess.y = record.y;
        const int l = record.slope > 0.0 ? record.ring : 0;
        const double before = l >= 2 ? G(l - 1).slope : 0.0;
        auto delta = [](int k) {
            return std::expm1(double(2 * k + 2) * std::log1p(0x1p-24)) * (1.0 + 1e-6) + 1e-12;
        };
        if (l >= 1 && !(double(record.v) > double(l) * before * (1.0 + delta(l)))) return false;
        if (l >= 2 && !(double(l - 1) * before * (1.0 + delta(l - 1)) <= H)) return false;
        // (3): the loop itself, told that ℓ is the only record; it notes the A_k it meets.
        thread_local std::vector<float> along, minFrom;
        along.assign(size_t(last) + 2, 0.0f);
        cone = paperCone(m_coneHeight, last, [&](int i, float a) {
            if (i > l) along[size_t(i)] = a;
            return i == l ? record.v : -kInfinity;
        });
        const int T = int(cone.first);
        if (T <= l) return true;
        minFrom.assign(size_t(T) + 2, kInfinity);
        for (int k = T; k > l; --k) minFrom[size_t(k)] = std::min(minFrom[size_t(k) + 1], along[size_t(k)]);
        return !recordAfter(u, v, h, l, T, along, minFrom);
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

// Rows in parallel; inside a run of rows texels go boustrophedon, so that the previous texel,
// whose cone ring is handed over as `guess`, is a neighbour.
template <class PerTexel>
std::vector<QdmTexel> buildPaperRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<QdmTexel> texels(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        PaperGuess guess;
        for (int v = int(begin); v < int(end); ++v)
            for (int k = 0; k < s.width(); ++k) {
                const int u = (v - int(begin)) % 2 == 0 ? k : s.width() - 1 - k;
                texels[size_t(v) * size_t(s.width()) + size_t(u)] = perTexel(u, v, guess);
            }
    });
    return texels;
}

}  // namespace

std::vector<QdmTexel> buildQdmPaper(const Surface& surface, const QdmBuildParams& params) {
    const PaperSearch search(surface, params);
    return buildPaperRows(surface,
                          [&](int u, int v, PaperGuess& guess) { return search.texel(u, v, guess); });
}

// §3.1 as written: m(d) from every sample of the map, the cone loop, then c over the rings (or
// their upper convex bound's vertices).
std::vector<QdmTexel> buildQdmPaperBruteForce(const Surface& s, const QdmBuildParams& params) {
    const float coneHeight = coneHeightOf(s, params);
    const bool repeat = s.edge() == EdgeMode::Repeat;
    return buildPaperRows(s, [&](int u, int v, PaperGuess&) {
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
