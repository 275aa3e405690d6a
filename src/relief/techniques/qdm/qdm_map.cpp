#include <relief/techniques/qdm/qdm_map.h>

#include <relief/core/parallel.h>
#include <relief/techniques/qdm/qdm_paper.h>
#include <relief/techniques/common/cone_maps.h>
#include <relief/techniques/common/max_pyramid.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace relief {

namespace {

constexpr float kRoundUp = 1.0f + 1e-6f;  // float rounding of the fit, towards the safe side
// Relative half-width of the bracket the neighbour's cone slope gives the bisection.
// (0.003 … 0.03 measured on peaks6 512²: 0.005 best; a miss costs up to 4 more probes.)
constexpr float kWarmBracket = 0.005f;
// The walk's budget when a warm start is at hand (the bisection is then cheap; the walk's disc
// still saves the queries the nearest rings): 64 measured better than 0, 16, 32 and 256.
constexpr int64_t kWarmBudget = 64;

struct Box {
    float x0, y0, x1, y1;
};

// Always inlined: the searches call it for every node they meet, and GCC kept it out of line,
// where the calls were a fifth of a 1024² bake (peaks6; inlined: 9 % faster, same maps).
[[gnu::always_inline]] inline float boxDistance(const Box& a, const Box& b) {
    const float dx = std::max({0.0f, b.x0 - a.x1, a.x0 - b.x1});
    const float dy = std::max({0.0f, b.y0 - a.y1, a.y0 - b.y1});
    return std::sqrt(dx * dx + dy * dy);
}

// The largest distance from a to a point of b: no box inside b is farther from a. (Inlined as
// boxDistance is.)
[[gnu::always_inline]] inline float farthestDistance(const Box& a, const Box& b) {
    const float dx = std::max({0.0f, b.x1 - a.x1, a.x0 - b.x0});
    const float dy = std::max({0.0f, b.y1 - a.y1, a.y0 - b.y0});
    return std::sqrt(dx * dx + dy * dy);
}

using Point = QdmPoint;

// What a texel hands to the next one in the build order (QdmSearch::texel).
struct WarmStart {
    float slope = 0.0f;
    bool bisected = false;
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

// A point's cone slope as the fit computes it (rounded towards the safe side).
float ratioOf(const Point& p) { return p.v / p.r * kRoundUp; }

// The cone's reach for slope s: the fit stops at the first point beyond it.
float reachOf(float coneHeight, float s) { return s > 0.0f ? coneHeight / s : kInfinity; }

// Smallest c whose nondecreasing parabola from (a, b) reaches v at r (> a).
float parabolaC(float a, float b, Point p) {
    const float e = p.v - b, w = p.r - a;
    if (e <= 0.0f) return a;
    return e >= w * w ? 0.5f * (a + p.r) + e / (2.0f * w) : a + std::sqrt(e);
}

}  // namespace

std::vector<QdmPoint> upperConvexBound(std::span<const QdmPoint> points) {
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

namespace {

// The paper's search (§3.1, §4.1) over the points sorted by r (the highest first among equal
// r, so that the cone search depends on the staircase only).
QdmTexel fit(Radial& radial, float h, float coneHeight, bool convex) {
    std::sort(radial.points.begin(), radial.points.end(), [](const Point& p, const Point& q) {
        return p.r < q.r || (p.r == q.r && p.v > q.v);
    });
    const std::vector<Point>& pts = radial.points;
    float s = radial.slope * kRoundUp;
    float a = reachOf(coneHeight, s);
    for (const Point& p : pts) {
        if (p.r > a) break;
        s = std::max(s, ratioOf(p));
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
                m_s = std::max(m_s, ratioOf(p));
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

    // The cone found by the bisection (the fit's final slope): the parabola search follows.
    void finishConeAt(float s, const Radial& radial) {
        m_s = s;
        finishCone(radial);
    }
    bool coneDone() const { return m_coneDone; }
    float slope() const { return m_s; }
    float c() const { return m_c; }
    // The largest c_j a cell at distance ≥ d and height ≤ v can need (c_j is nonincreasing in
    // r and nondecreasing in v). A node reaching down to a can hold points just beyond a, whose
    // c_j has no bound unless they are under b (then c_j = a).
    float cBound(float d, float v) const {
        if (d > m_a) return parabolaC(m_a, m_b, {d, v});
        return v > m_b ? kInfinity : m_a;
    }

private:
    float cone() const { return reachOf(m_coneHeight, m_s); }
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

    // `guess`: the previous texel's cone slope (a neighbour in the serpentine order of buildRows)
    // and whether it needed the bisection, or {0, false}. It only picks where the bisection probes
    // first and how long the walk runs before it (see bisectCone; the budget changes nothing
    // either), never the result. On return it holds this texel's.
    QdmTexel texel(int i, int j, WarmStart& guess) const {
        const float h = safeApexHeight(m_s, i, j);
        const Box foot{float(i), float(j), float(i + 1), float(j + 1)};
        Radial radial;
        Walked walked;
        const bool warm = m_params.warmStart && guess.slope > 0.0f;
        const int64_t budget = warm && guess.bisected
                                   ? std::min(kWarmBudget, m_params.staircaseBudget)
                                   : m_params.staircaseBudget;
        const bool bisected = !staircase(foot, h, budget, radial, walked);
        if (bisected) bisectCone(i, j, foot, h, walked, warm ? guess.slope : 0.0f, radial);
        const QdmTexel q = fit(radial, h, coneHeight(), m_params.convexBound);
        guess = {q.a > 0.0f && std::isfinite(q.a) ? q.b / q.a : 0.0f, bisected};
        return q;
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
    struct Walked {  // where the walk stopped and the slope it had reached
        float distance = 0.0f, slope = 0.0f;
    };
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
    // False when the cone is not final after the budget of pops (a long staircase on gently
    // rising ground: one point per ring), for bisectCone to take over from `walked`.
    bool staircase(const Box& foot, float h, int64_t budget, Radial& radial,
                   Walked& walked) const {
        thread_local std::vector<Node> heap;
        heap.clear();
        addRoots(foot, heap);
        std::make_heap(heap.begin(), heap.end());
        RunningFit running(coneHeight());
        float best = 0.0f;
        float last = 0.0f;
        for (int64_t pops = 0; !heap.empty(); ++pops) {
            // Hand over between distances: the fit takes the highest of tied points first.
            if (pops > budget && heap.front().distance > last) {
                walked = {heap.front().distance, running.slope()};
                return false;
            }
            std::pop_heap(heap.begin(), heap.end());
            const Node n = heap.back();
            heap.pop_back();
            last = n.distance;
            if (n.distance > m_reach) break;
            const float v = m_pyramid.at(n.level, n.x, n.y) - h;
            if (v <= best || v <= running.lowerBound(n.distance, radial)) continue;
            if (running.coneDone()) {  // the cone is final: the rest only raises c, in any order
                heap.push_back(n);
                maximizeC(foot, h, heap, running, radial);
                return true;
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
        return true;
    }

    // ---- The cone by bisection ----------------------------------------------------------------
    // The fit's cone loop, restated. Call the slopes at which it raises s records (s0 = the
    // overlapping cells' slope, then every point steeper than all nearer ones). After record
    // s_k the loop goes on exactly while some point within reach(s_k) is steeper than s_k, so
    // it ends at the first record s with
    //     final(s):  no point p with r_p ≤ reach(s) has slope(p) > s,
    // reach(s) = coneHeight / s evaluated as the fit evaluates it. final is monotone in s
    // (reach shrinks as s grows), so once lo is known not to be final, the first record above
    // lo is the first point (in the fit's order) steeper than lo, and the answer is that
    // point's slope as soon as it is final. Bisecting lo between a value that is not final and
    // one that is skips the long runs of records one ring apart; each query is a pruned
    // pyramid search. The fit then meets the same loop on the points kept (the overlapping
    // cells, the final record, the parabola's points) and ends on the same slope.
    // It starts where the walk stopped: every point nearer than `walked.distance` is no steeper
    // than the walk's slope (it took it or pruned it), which is a record not yet known final,
    // every smaller record having been passed. The queries skip that disc.
    struct Probe {
        Box foot;
        float h;
        float walked;                    // no point nearer is steeper than any s tested
        std::vector<Point> overlapping;  // the cells at distance 0, as points (v / G, v)
    };

    //
    // Warm start. The loop below needs only lo: not final (and ≥ the walk's slope and the
    // overlapping cells' slope, so that every record up to lo is passed and lo is a valid
    // "mid"), and hi: final, hi ≥ lo (not necessarily ≥ the answer: a record ≥ hi is final by
    // monotonicity, so the loop stops there). Any slope t ≥ lo can be tested and classified:
    // final(t) → it may serve as hi; not final → it may serve as lo, exactly as the bisection's
    // midpoints are. The neighbour's cone slope g (the previous texel in serpentine order, which
    // on smooth ground is within a few per cent of this one's) is tested as g(1 − ε) and
    // g(1 + ε): the bracket is then tight and steepestWithin is not needed. Which values are
    // tested changes only the number of queries, never the record the loop ends on (the first
    // final record), so the map is bit for bit the same (test QdmMap.WarmStartChangesNothing).
    void bisectCone(int i, int j, const Box& foot, float h, const Walked& walked, float guess,
                    Radial& radial) const {
        Probe probe{foot, h, walked.distance, {}};
        Radial overlapping;
        for (int cj = j - 1; cj <= j; ++cj)
            for (int ci = i - 1; ci <= i; ++ci) addCell(m_s, foot, h, ci, cj, overlapping);
        probe.overlapping = overlapping.points;
        radial.slope = std::max(radial.slope, overlapping.slope);  // the walk may not be there yet
        radial.points.insert(radial.points.end(), overlapping.points.begin(),
                             overlapping.points.end());
        float lo = std::max(walked.slope, overlapping.slope * kRoundUp);
        float hi = kInfinity;  // a final slope ≥ lo once known
        bool loFinalUnknown = true;
        // Classifies a probe t > lo (see above); false when it is final.
        auto raise = [&](float t) {
            if (isFinal(probe, t)) {
                hi = std::min(hi, t);
                return false;
            }
            lo = t, loFinalUnknown = false;  // lo not final: neither is anything below it
            return true;
        };
        if (guess > lo && std::isfinite(guess)) {
            const float down = guess * (1.0f - kWarmBracket);
            if (!(down > lo) || raise(down)) {
                // Below the answer's threshold: up from g until a final probe (≤ 4 probes).
                for (float e = kWarmBracket; e < 1.0f && !(hi < kInfinity); e *= 4.0f) {
                    const float t = guess * (1.0f + e);
                    if (t > lo) raise(t);
                }
            } else {
                // down is final (hi): down from g until one that is not (≤ 3 probes).
                for (float e = 4.0f * kWarmBracket; e < 1.0f; e *= 4.0f) {
                    const float t = guess * (1.0f - e);
                    if (!(t > lo) || raise(t)) break;
                }
            }
        }
        if (!(loFinalUnknown && isFinal(probe, lo))) {
            if (!(hi < kInfinity))
                hi = std::max(lo, steepestWithin(probe, reachOf(coneHeight(), lo)));  // final
            while (true) {
                const Point first = firstSteeperThan(probe, lo);
                lo = ratioOf(first);
                if (lo >= hi || isFinal(probe, lo)) {
                    radial.points.push_back(first);
                    break;
                }
                const float mid = std::sqrt(lo) * std::sqrt(hi);
                if (mid > lo && mid < hi) (isFinal(probe, mid) ? hi : lo) = mid;
            }
        }
        RunningFit running(coneHeight());
        running.finishConeAt(lo, radial);
        maximizeC(foot, h, rootsOf(foot), running, radial);
    }

    // The point of a level-0 node (a cell) not overlapping the footprint, as addCell makes it.
    Point cellPoint(const Node& n, float h) const {
        const ivec2 cell = globalCell(n.x, n.y, m_shifts[size_t(n.shift)]);
        const CellCorners k = m_s.cellCorners(cell.x, cell.y);
        return {n.distance, std::max({k.z00, k.z10, k.z01, k.z11}) - h};
    }
    // Bounds the slope of every point in the node (0: nothing above the apex). Overlapping
    // cells are left to Probe::overlapping.
    float slopeBound(const Node& n, float h) const {
        const float v = m_pyramid.at(n.level, n.x, n.y) - h;
        if (v <= 0.0f) return 0.0f;
        if (n.distance > 0.0f) return v / n.distance * kRoundUp;
        return n.level > 0 ? kInfinity : 0.0f;
    }
    template <class Visit>
    void forChildren(const Node& n, const Box& foot, Visit&& visit) const {
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) {
                const int x = 2 * n.x + dx, y = 2 * n.y + dy;
                if (x < m_layout.widthAt(n.level - 1) && y < m_layout.heightAt(n.level - 1))
                    visit(node(foot, n.level - 1, x, y, n.shift));
            }
    }
    // The roots (one per shift), appended to `nodes`.
    void addRoots(const Box& foot, std::vector<Node>& nodes) const {
        for (int k = 0; k < int(m_shifts.size()); ++k)
            nodes.push_back(node(foot, m_layout.topLevel(), 0, 0, k));
    }
    std::vector<Node> rootsOf(const Box& foot) const {
        std::vector<Node> roots;
        addRoots(foot, roots);
        return roots;
    }

    // Whether the node holds no point the walk left (all nearer than where it stopped).
    bool walkedPast(const Node& n, const Probe& probe) const {
        return farthestDistance(probe.foot, nodeBox(n.level, n.x, n.y, m_shifts[size_t(n.shift)])) <
               probe.walked;
    }

    // final(s): no point within reach(s) steeper than s (depth first, stops at the first one).
    bool isFinal(const Probe& probe, float s) const {
        const float reach = std::min(reachOf(coneHeight(), s), m_reach);
        for (const Point& p : probe.overlapping)
            if (!(p.r > reach) && ratioOf(p) > s) return false;
        thread_local std::vector<Node> stack;
        stack.clear();  // kept from the last call: no allocation per query
        addRoots(probe.foot, stack);
        while (!stack.empty()) {
            const Node n = stack.back();
            stack.pop_back();
            if (n.distance > reach || !(slopeBound(n, probe.h) > s) || walkedPast(n, probe))
                continue;
            if (n.level == 0) {
                if (ratioOf(cellPoint(n, probe.h)) > s) return false;
                continue;
            }
            forChildren(n, probe.foot, [&](const Node& kid) { stack.push_back(kid); });
        }
        return true;
    }

    // The first point in the fit's order (nearest, then highest) steeper than lo; one exists
    // within reach(lo) because lo is not final.
    Point firstSteeperThan(const Probe& probe, float lo) const {
        const float reach = std::min(reachOf(coneHeight(), lo), m_reach);
        auto before = [](const Point& p, const Point& q) {
            return p.r < q.r || (p.r == q.r && p.v > q.v);
        };
        Point first{kInfinity, 0.0f};
        for (const Point& p : probe.overlapping)
            if (ratioOf(p) > lo && before(p, first)) first = p;
        thread_local std::vector<Node> heap;
        heap.clear();
        addRoots(probe.foot, heap);
        std::make_heap(heap.begin(), heap.end());
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end());
            const Node n = heap.back();
            heap.pop_back();
            if (n.distance > first.r || n.distance > reach) break;
            if (!(slopeBound(n, probe.h) > lo) || walkedPast(n, probe)) continue;
            if (n.level == 0) {
                const Point p = cellPoint(n, probe.h);
                if (ratioOf(p) > lo && before(p, first)) first = p;
                continue;
            }
            forChildren(n, probe.foot, [&](const Node& kid) {
                heap.push_back(kid);
                std::push_heap(heap.begin(), heap.end());
            });
        }
        RELIEF_CHECK(first.r < kInfinity);
        return first;
    }

    // The steepest slope of the points within reach (branch and bound on slopeBound).
    float steepestWithin(const Probe& probe, float reach) const {
        reach = std::min(reach, m_reach);
        float best = 0.0f;
        for (const Point& p : probe.overlapping)
            if (!(p.r > reach)) best = std::max(best, ratioOf(p));
        thread_local std::vector<std::pair<float, Node>> heap;
        heap.clear();
        auto push = [&](const Node& n) {
            const float bound = slopeBound(n, probe.h);
            if (n.distance > reach || !(bound > best) || walkedPast(n, probe)) return;
            heap.push_back({bound, n});
            std::push_heap(heap.begin(), heap.end(), byBound);
        };
        for (const Node& root : rootsOf(probe.foot)) push(root);
        while (!heap.empty()) {
            std::pop_heap(heap.begin(), heap.end(), byBound);
            const auto [bound, n] = heap.back();
            heap.pop_back();
            if (!(bound > best)) break;
            if (n.level > 0) forChildren(n, probe.foot, push);
            else best = std::max(best, ratioOf(cellPoint(n, probe.h)));
        }
        return best;
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
    // A function object, not a function: the heap operations inline it (through a function
    // pointer they called it for every comparison).
    struct ByBound {
        bool operator()(const std::pair<float, Node>& p, const std::pair<float, Node>& q) const {
            return p.first < q.first;
        }
    };
    static constexpr ByBound byBound{};

    const Surface& m_s;
    QdmBuildParams m_params;
    MaxPyramid m_pyramid;
    PyramidLayout m_layout;
    std::vector<ivec2> m_shifts;
    float m_reach;
};

// Rows in parallel; inside a run of rows texels go boustrophedon (left to right, then right to
// left) so that the previous texel, whose cone slope is handed over as `guess`, is a neighbour.
template <class PerTexel>
std::vector<QdmTexel> buildRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<QdmTexel> texels(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        WarmStart guess;
        for (int j = int(begin); j < int(end); ++j)
            for (int k = 0; k < s.width(); ++k) {
                const int i = (j - int(begin)) % 2 == 0 ? k : s.width() - 1 - k;
                texels[size_t(j) * size_t(s.width()) + size_t(i)] = perTexel(i, j, guess);
            }
    });
    return texels;
}

}  // namespace

QdmBuildParams QdmBuildParams::from(const ParamValues& params) {
    QdmBuildParams built{float(params.get("height-ratio")), float(params.get("max-distance")),
                         params.getInt("convex-bound") != 0};
    built.paper = params.getInt("variant") == 1;
    return built;
}

QdmMap::QdmMap(const Surface& s, std::vector<QdmTexel> texels, float maxDistance)
    : m_width(s.width()), m_height(s.height()), m_edge(s.edge()), m_maxZ(s.maxZ()),
      m_maxDistance(maxDistance > 0.0f ? maxDistance : kInfinity), m_texels(std::move(texels)) {}

std::vector<QdmTexel> buildQdm(const Surface& surface, const QdmBuildParams& params) {
    const QdmSearch search(surface, params);
    return buildRows(surface,
                     [&](int i, int j, WarmStart& guess) { return search.texel(i, j, guess); });
}

std::vector<QdmTexel> buildQdmBruteForce(const Surface& surface, const QdmBuildParams& params) {
    const QdmSearch search(surface, params);
    return buildRows(surface,
                     [&](int i, int j, WarmStart&) { return search.texelBruteForce(i, j); });
}

std::vector<QdmTexel> buildQdmVariant(const Surface& surface, const QdmBuildParams& params) {
    return params.paper ? buildQdmPaper(surface, params) : buildQdm(surface, params);
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
            {"convex-bound", params.convexBound ? "1" : "0"},
            {"variant", params.paper ? "1" : "0"}};
}

namespace {
Result<std::vector<QdmTexel>> bakedTexels(const TechniqueMaps& maps, const Surface& s,
                                          const QdmBuildParams& params) {
    for (const auto& [key, value] : qdmMapParameters(params)) {
        auto found = maps.parameters.find(key);
        // Maps baked before the paper variant existed are the safe variant's.
        if (found == maps.parameters.end() && key == "variant" && value == "0") continue;
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
              std::isfinite(d[3]) && d[0] >= 0.0f && d[1] >= 0.0f &&
              (params.paper || d[2] >= d[0])))  // the paper's c may lie before a
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
        return std::make_shared<const QdmMap>(s, buildQdmVariant(s, params), params.maxDistance);
    auto texels = bakedTexels(*input.maps, s, params);
    if (!texels) return texels.error();
    return std::make_shared<const QdmMap>(s, std::move(*texels), params.maxDistance);
}

}  // namespace relief
