#include <relief/techniques/common/cone_maps.h>

#include <relief/core/parallel.h>
#include <relief/surface/cell_cursor.h>
#include <relief/techniques/common/max_pyramid.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>

namespace relief {

Status checkConeParams(const ParamValues& params, std::string_view technique) {
    const int bits = params.getInt("bits");
    if (bits != 8 && bits != 16 && bits != 32)
        return makeError(ErrorKind::BadArgument, "{}: bits must be 8, 16 or 32 (got {})",
                         technique, bits);
    return {};
}

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

// First t ≥ t0 where the ray is above S (out of the solid): tExit when it stays in the solid up
// to tExit, kInfinity when it does up to the cell where `tStop` falls (the walk goes no further).
// Each cell is tested over its whole span below tExit, whatever tStop is: an exit point is an
// ill-conditioned interpolation where the ray grazes a plane, and computing it on the same
// interval makes it the same float for every tStop (search and brute force agree to the bit).
float firstExit(const Surface& s, const Ray& ray, float t0, float tStop, float tExit) {
    const float margin = 1e-5f * (1.0f + s.depth());
    for (float t = t0; t < tExit;) {
        const CellSpan c = cellAt(s, ray, t, tExit);
        const float e = firstAboveInCell(s.cellPlanes(c.ci, c.cj), ray, c.ci, c.cj, t, c.tb,
                                         margin);
        if (e <= c.tb) return e;
        if (c.tb >= tStop && c.tb < tExit) return kInfinity;
        if (c.tb >= tExit) break;
        t = c.tb;
    }
    return tExit;
}

// The steepest plane of the cells within r cells (Chebyshev) of a cell, for r = 1, 2, 4, …, 32:
// the relaxed search's cheap reject. S is continuous and piecewise planar, so along a ray that
// starts on S and descends faster than every plane it can meet, S stays above the ray: no exit.
class SlopeWindows {
public:
    static constexpr int kLevels = 6;

    explicit SlopeWindows(const Surface& s)
        : m_repeat(s.edge() == EdgeMode::Repeat),
          m_first(m_repeat ? 0 : -1),
          m_columns(m_repeat ? s.width() : s.width() + 1),
          m_rows(m_repeat ? s.height() : s.height() + 1) {
        std::vector<float> slope(size_t(m_columns) * size_t(m_rows));
        parallelRanges(m_rows, 16, [&](int64_t begin, int64_t end) {
            for (int64_t row = begin; row < end; ++row)
                for (int column = 0; column < m_columns; ++column) {
                    const CellPlanes p = s.cellPlanes(column + m_first, int(row) + m_first);
                    slope[size_t(row) * size_t(m_columns) + size_t(column)] =
                        std::max(planeSlope(p.first), planeSlope(p.second));
                }
        });
        for (int level = 0; level < kLevels; ++level)
            m_windows[size_t(level)] = maxFilter(slope, 1 << level);
    }

    // Steepest slope within `radius` cells of cell (ci, cj); kInfinity past the widest window.
    float maxSlope(int ci, int cj, int radius) const {
        int level = 0;
        while (level < kLevels && (1 << level) < radius) ++level;
        if (level == kLevels) return kInfinity;
        return m_windows[size_t(level)][size_t(row(cj)) * size_t(m_columns) + size_t(column(ci))];
    }

private:
    int column(int ci) const { return wrapOrClamp(ci - m_first, m_columns); }
    int row(int cj) const { return wrapOrClamp(cj - m_first, m_rows); }
    int wrapOrClamp(int k, int n) const {
        if (!m_repeat) return std::clamp(k, 0, n - 1);
        const int r = k % n;
        return r < 0 ? r + n : r;
    }

    // Max over the (2·radius + 1)² window, separably (along rows, then along columns).
    std::vector<float> maxFilter(const std::vector<float>& in, int radius) const {
        std::vector<float> across(in.size()), out(in.size());
        auto pass = [&](const std::vector<float>& from, std::vector<float>& to, bool alongRows) {
            const int lines = alongRows ? m_rows : m_columns;
            const int length = alongRows ? m_columns : m_rows;
            auto index = [&](int64_t line, int k) {
                return alongRows ? size_t(line) * size_t(m_columns) + size_t(k)
                                 : size_t(k) * size_t(m_columns) + size_t(line);
            };
            parallelRanges(lines, 16, [&](int64_t begin, int64_t end) {
                for (int64_t line = begin; line < end; ++line)
                    for (int k = 0; k < length; ++k) {
                        float m = 0.0f;
                        for (int o = -radius; o <= radius; ++o)
                            m = std::max(m, from[index(line, wrapOrClamp(k + o, length))]);
                        to[index(line, k)] = m;
                    }
            });
        };
        pass(in, across, true);
        pass(across, out, false);
        return out;
    }

    bool m_repeat;
    int m_first, m_columns, m_rows;
    std::array<std::vector<float>, kLevels> m_windows;
};

// Where a ray starting at q inside the box leaves it (Surface::clip for an inside origin, without
// its entry slabs: this runs once per candidate of the relaxed search).
float boxExitFromInside(const Surface& s, const Ray& ray) {
    const vec3& q = ray.origin;
    const vec3& d = ray.direction;
    float t = d.z < 0.0f ? -q.z / d.z : kInfinity;
    if (s.edge() == EdgeMode::Repeat) {
        const float travel = Surface::kRepeatTravelFactor * float(std::max(s.width(), s.height()));
        return std::min(t, travel / std::sqrt(d.x * d.x + d.y * d.y));
    }
    if (d.x != 0.0f) t = std::min(t, ((d.x > 0.0f ? float(s.width()) : 0.0f) - q.x) / d.x);
    if (d.y != 0.0f) t = std::min(t, ((d.y > 0.0f ? float(s.height()) : 0.0f) - q.y) / d.y);
    return std::max(t, 0.0f);
}

// Policarpo & Oliveira: the ray from the box top above the apex through sample q, followed past
// q until it leaves the solid at C, gives |C − apex| / (z_C − a). Along the ray that ratio only
// grows, so the walk stops where it reaches `c` (the ratio found so far): C beyond cannot lower it.
// The ray runs from q along q − top, unnormalized: at t its horizontal distance from the apex is
// reach·(1 + t), so neither a normalization nor a distance needs a square root.
// Candidates whose ray stays in the solid up to tStop are the vast majority (94 % on fbm 512²):
// when the ray descends faster than the steepest plane of every cell the walk would test (those
// up to the one holding tStop, within travel + √2 of q), the walk cannot find an exit there and
// is skipped; the result is the walk's, to the bit.
float relaxedRatio(const Surface& s, const SlopeWindows* slopes, const Apex& apex, ivec2 cell,
                   vec3 q, float c) {
    const vec3 d(q.x - apex.foot.x0, q.y - apex.foot.y0, q.z - s.depth());
    if (d.x == 0.0f && d.y == 0.0f) return kInfinity;
    const Ray ray{q, d, kInfinity};
    const float reach = std::sqrt(d.x * d.x + d.y * d.y);
    const float tExit = boxExitFromInside(s, ray);
    const float tStop =
        std::isfinite(c) ? (c * (q.z - apex.a) - reach) / (reach - c * d.z) : kInfinity;
    const float travel = reach * std::max(0.0f, tStop);
    if (slopes && reach * tExit > travel + 2.0f &&
        -d.z >= reach * slopes->maxSlope(cell.x, cell.y, int(std::ceil(travel + 1.5f)) + 1))
        return kInfinity;
    const float tc = firstExit(s, ray, 0.0f, std::max(0.0f, tStop), tExit);
    if (!(tc <= tExit)) return kInfinity;
    const float exitZ = q.z + tc * d.z;
    if (exitZ <= apex.a) return kInfinity;
    return reach * (1.0f + tc) / (exitZ - apex.a);
}

// The bound cell (ci, cj) puts on the ratio of `apex` (kInfinity when none); `c` is the ratio
// found so far (the relaxed search skips rays that cannot lower it).
float leafRatio(const Surface& s, const SlopeWindows* slopes, ConeKind kind, const Apex& apex,
                int ci, int cj, float c) {
    if (kind == ConeKind::SafeStrict) {
        const CellCorners k = s.cellCorners(ci, cj);
        if (maxCorner(k) <= apex.a) return kInfinity;
        const float d = rectDistance(apex.foot, cellRect(ci, cj));
        if (d > 0.0f) return d / (maxCorner(k) - apex.a);
        const CellPlanes p = planesFromCorners(k);
        const float g = std::max(planeSlope(p.first), planeSlope(p.second));
        return g > 0.0f ? 1.0f / g : kInfinity;
    }
    // Published maps: the sample at the cell's 00 corner (each sample is one cell's 00 corner).
    const float z00 = s.sampleZ(ci, cj);
    if (z00 <= apex.a) return kInfinity;
    const vec3 q(float(ci) + 0.5f, float(cj) + 0.5f, z00);
    const vec2 toQ(q.x - apex.foot.x0, q.y - apex.foot.y0);
    const float rise = q.z - apex.a;
    // Squared, with a rounding margin, before the square root and the division: most cells the
    // search reaches cannot lower c (the brute force, c = ∞, never takes this exit).
    constexpr float kRoundingMargin = 1.0f + 1e-5f;
    if (glm::dot(toQ, toQ) > c * c * rise * rise * kRoundingMargin) return kInfinity;
    const float strict = glm::length(toQ) / rise;
    if (kind == ConeKind::FaithfulStrict || strict >= c) return strict;
    return std::min(c, relaxedRatio(s, slopes, apex, {ci, cj}, q, c));
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

// The narrowest cone found so far for one apex and the cell that set it (kNoCell while c is
// still the cap): that cell is the next texel's first guess.
constexpr ivec2 kNoCell{std::numeric_limits<int>::min()};
struct Best {
    float c;
    ivec2 cell = kNoCell;
    void offer(float ratio, ivec2 at) {
        if (ratio < c) c = ratio, cell = at;
    }
};

// What a run of rows carries from texel to texel: the cell that set the last c (the next
// texel's first guess) and, per pyramid level, how often relaxedNodeProvenEmpty succeeded. That
// test only skips nodes that cannot lower c, so trying it or not changes no result, only the
// time; on rough ground it rarely succeeds (fbm 512²: 20 % at level 1, 8 % at 2, none above)
// and its square roots and window read cost more than the walks it saves (14 % more CPU with it
// than without), on smooth ground it saves more than it costs (peaks6 1024²: 21 % less). So a
// level is tried while at least half of its recent tries succeed, and otherwise one node in 16,
// to notice when the ground changes (fbm 512² 8.2 CPU-s as with no tries, peaks6 1024² 8.5
// against 10.3 always trying and 13.0 never).
struct SearchHints {
    ivec2 guess = kNoCell;
    std::array<uint16_t, PyramidLayout::kMaxLevels> tries{}, wins{}, skipped{};

    bool worthProving(int level) {
        if (tries[size_t(level)] < 32 || 2 * wins[size_t(level)] >= tries[size_t(level)])
            return true;
        return (++skipped[size_t(level)] & 15) == 0;
    }
    void recordProof(int level, bool proven) {
        uint16_t& t = tries[size_t(level)];
        uint16_t& w = wins[size_t(level)];
        if (++t == 1024) t /= 2, w /= 2;  // recent tries weigh more
        w += proven;
    }
};

// A node can hold a cell that lowers c only if dist(F, node) < c·(max − a) (every ratio in it is
// at least dist / (max − a)); compared squared, dist² is exact (half-texel coordinates). The
// margin keeps float rounding from ever dropping the cell that sets c, so the search returns
// exactly the brute force's minimum.
inline bool mayLower(float distance2, float max, float a, float c) {
    constexpr float kRoundingMargin = 1.0f + 1e-5f;
    const float reach = c * (max - a) * kRoundingMargin;
    return distance2 < reach * reach;
}

class ConeSearch {
public:
    ConeSearch(const Surface& s, ConeKind kind, bool skipProvenWalks = false)
        : m_s(s),
          m_kind(kind),
          m_pyramid(kind == ConeKind::SafeStrict ? MaxPyramid(s) : MaxPyramid::overCellOrigins(s)),
          m_layout(m_pyramid.layout()),
          m_sampleInset(kind == ConeKind::SafeStrict ? 0.0f : 1.0f),
          m_cMax(coneRatioMax(s)), m_shifts(tileShifts(s, m_cMax)),
          m_slopes(kind == ConeKind::FaithfulRelaxed && skipProvenWalks
                       ? std::make_unique<SlopeWindows>(s)
                       : nullptr) {}

    // `guess`: a cell that bounded a neighbouring texel (or kNoCell). Any cell's ratio is one of
    // the values the minimum is taken over, so starting from it changes only how much of the
    // pyramid is pruned, never the result. On return it holds the cell that set this texel's c.
    vec2 texel(int i, int j, SearchHints& hints) const {
        ivec2& guess = hints.guess;
        const Apex apex = apexOf(m_s, m_kind, i, j);
        Best best{m_cMax};
        if (guess != kNoCell)
            best.offer(ratioOf(apex, guess, best.c), guess);
        for (ivec2 shift : m_shifts) visitTile(apex, shift, best, hints);
        if (best.cell != kNoCell) guess = best.cell;
        return {apex.a, best.c};
    }

    vec2 texelBruteForce(int i, int j) const {
        const Apex apex = apexOf(m_s, m_kind, i, j);
        float c = m_cMax;
        for (ivec2 shift : m_shifts)
            for (int l = 0; l < m_layout.cellsY; ++l)
                for (int k = 0; k < m_layout.cellsX; ++k) {
                    const ivec2 cell = tileCell(shift) + ivec2(k, l);
                    c = std::min(c, ratioOf(apex, cell, kInfinity));
                }
        return {apex.a, c};
    }

private:
    struct Node {
        int level, x, y;
        float distance2;  // from the apex footprint
        float max;        // of S over the node
        // The lowest ratio a cell of the node can give, squared: distance² / (max − a)² (+∞
        // when max ≤ a). Nodes are visited lowest bound first, so that c falls early and
        // fewer candidates reach the relaxed search's walk; c is a minimum over all of them, so
        // the order changes no result.
        float order;
    };
    static Node makeNode(int level, int x, int y, float distance2, float max, float a) {
        const float rise = max - a;
        return {level, x, y, distance2, max, rise > 0.0f ? distance2 / (rise * rise) : kInfinity};
    }

    float ratioOf(const Apex& apex, ivec2 cell, float c) const {
        return leafRatio(m_s, m_slopes.get(), m_kind, apex, cell.x, cell.y, c);
    }

    // The global cell of pyramid index (0, 0) in the tile copy `shift`.
    ivec2 tileCell(ivec2 shift) const {
        return ivec2(m_layout.firstCell) + shift * ivec2(m_s.width(), m_s.height());
    }

    // Squared distance from F to the cells of node (level, x, y) (published maps: to its cells'
    // 00 corners, the samples they stand for); `origin`: the lower corner of the tile copy's
    // first cell.
    float distance2(const Rect& foot, vec2 origin, int level, int x, int y) const {
        auto gap = [&](int node, int cells, float base, float lo, float hi) {
            const float nodeLo = base + float(node << level);
            const float nodeHi =
                base + float(std::min((node + 1) << level, cells)) - m_sampleInset;
            return std::max({0.0f, nodeLo - hi, lo - nodeHi});
        };
        const float dx = gap(x, m_layout.cellsX, origin.x, foot.x0, foot.x1);
        const float dy = gap(y, m_layout.cellsY, origin.y, foot.y0, foot.y1);
        return dx * dx + dy * dy;
    }

    void visitTile(const Apex& apex, ivec2 shift, Best& best, SearchHints& hints) const {
        const ivec2 first = tileCell(shift);
        const vec2 origin = vec2(first) + 0.5f;
        std::array<Node, 4 * PyramidLayout::kMaxLevels + 16> stack;
        int top = pushStart(apex, origin, best.c, stack.data());
        while (top > 0) {
            const Node n = stack[--top];
            if (!mayLower(n.distance2, n.max, apex.a, best.c)) continue;  // c fell since the push
            if (m_slopes && n.level > 0 && hints.worthProving(n.level)) {
                const bool proven = relaxedNodeProvenEmpty(apex, first, n, best.c);
                hints.recordProof(n.level, proven);
                if (proven) continue;
            }
            if (n.level == 0) {  // a start node that is already a cell (short reach, tiny map)
                const ivec2 at = first + ivec2(n.x, n.y);
                best.offer(ratioOf(apex, at, best.c), at);
                continue;
            }
            if (n.level > 1) {
                pushChildren(apex, origin, n, best.c, stack.data(), top);
                continue;
            }
            forEachChild(apex, origin, n, best.c, [&](const Node& cell) {
                const ivec2 at = first + ivec2(cell.x, cell.y);
                best.offer(ratioOf(apex, at, best.c), at);
            });
        }
    }

    // FaithfulRelaxed: relaxedRatio's walk skip, bounded over a whole node. Every candidate ray
    // through a sample of n descends at least (D − max n) / (farthest sample distance) per texel
    // and needs to travel at most c(D − a) / (1 + c·that) − (nearest distance) past its sample
    // before its ratio reaches c; when that slope beats the steepest plane within the node grown
    // by that travel, and no box face is that close, no walk in n can find an exit below c.
    // Needs m_slopes (the caller tries it only then).
    bool relaxedNodeProvenEmpty(const Apex& apex, ivec2 first, const Node& n, float c) const {
        const int x0 = n.x << n.level, x1 = std::min((n.x + 1) << n.level, m_layout.cellsX);
        const int y0 = n.y << n.level, y1 = std::min((n.y + 1) << n.level, m_layout.cellsY);
        // The node's samples (each cell's 00 corner), relative to the apex.
        const float lx = float(first.x + x0) + 0.5f - apex.foot.x0;
        const float hx = float(first.x + x1 - 1) + 0.5f - apex.foot.x0;
        const float ly = float(first.y + y0) + 0.5f - apex.foot.y0;
        const float hy = float(first.y + y1 - 1) + 0.5f - apex.foot.y0;
        const float farX = std::max(std::abs(lx), std::abs(hx));
        const float farY = std::max(std::abs(ly), std::abs(hy));
        const float nearX = std::max({0.0f, lx, -hx}), nearY = std::max({0.0f, ly, -hy});
        const float rNear = std::sqrt(nearX * nearX + nearY * nearY);
        const float depth = m_s.depth();
        if (!(n.max < depth) || !(apex.a < depth) || !(rNear > 0.0f)) return false;
        const float kMin = (depth - n.max) / std::sqrt(farX * farX + farY * farY);
        const float travel = c * (depth - apex.a) / (1.0f + c * kMin) - rNear + 0.5f;
        const float toFloor = apex.a * rNear / (depth - apex.a);
        if (!(travel > 0.0f) || !(toFloor > travel + 2.0f)) return false;
        if (m_s.edge() == EdgeMode::Clamp) {
            const float margin = travel + 2.0f;
            const vec2 lo = vec2(first + ivec2(x0, y0)) + 0.5f - margin;
            const vec2 hi = vec2(first + ivec2(x1 - 1, y1 - 1)) + 0.5f + margin;
            if (lo.x <= 0.0f || lo.y <= 0.0f || hi.x >= float(m_s.width()) ||
                hi.y >= float(m_s.height()))
                return false;
        }
        const int grow = int(std::ceil(travel + 1.5f)) + 2;
        const int radius = std::max(x1 - x0, y1 - y0) / 2 + grow;
        const ivec2 centre = first + ivec2((x0 + x1 - 1) / 2, (y0 + y1 - 1) / 2);
        constexpr float kRoundingMargin = 1.0f + 1e-4f;
        return kMin >= m_slopes->maxSlope(centre.x, centre.y, radius) * kRoundingMargin;
    }

    // Calls visit(child) for the children of n that may lower c (their max tested before they
    // are pushed, so that hopeless nodes are neither stored nor sorted).
    template <class Visit>
    void forEachChild(const Apex& apex, vec2 origin, const Node& n, const float& c,
                      Visit&& visit) const {
        const int level = n.level - 1;
        const int x1 = std::min(2 * n.x + 2, m_layout.widthAt(level));
        const int y1 = std::min(2 * n.y + 2, m_layout.heightAt(level));
        for (int y = 2 * n.y; y < y1; ++y)
            for (int x = 2 * n.x; x < x1; ++x) {
                const float m = m_pyramid.at(level, x, y);
                if (m <= apex.a) continue;
                const Node kid = makeNode(level, x, y, distance2(apex.foot, origin, level, x, y),
                                          m, apex.a);
                if (mayLower(kid.distance2, m, apex.a, c)) visit(kid);
            }
    }

    // The children that may lower c, highest bound pushed first (the lowest is visited first).
    void pushChildren(const Apex& apex, vec2 origin, const Node& n, float c, Node* stack,
                      int& top) const {
        Node* kids = stack + top;
        int count = 0;
        forEachChild(apex, origin, n, c,
                     [&](const Node& kid) { insertByBound(kid, kids, count); });
        top += count;
    }

    // Where the descent starts: no cell farther than R = c·(max S − a) from F can lower c, so
    // instead of the root, the (at most 4×4) nodes of the finest level with 2^level ≥ R that
    // meet F grown by R, highest bound pushed first (R taken with a generous margin against
    // rounding). Returns the stack size.
    int pushStart(const Apex& apex, vec2 origin, float c, Node* stack) const {
        const float maxS = m_pyramid.at(m_layout.topLevel(), 0, 0);
        float reach = c * (maxS - apex.a) * 1.001f + 1.0f;
        int level = 0;
        while (level < m_layout.topLevel() && float(1 << level) < reach) ++level;
        if (level == m_layout.topLevel()) reach = kInfinity;
        auto nodeRange = [&](float lo, float hi, float base, int nodes) {
            const float size = float(1 << level);
            const float first = std::floor((lo - reach - base) / size);
            const float last = std::floor((hi + reach - base) / size);
            return ivec2(int(std::max(first, 0.0f)), int(std::min(last, float(nodes - 1))));
        };
        const ivec2 xs = nodeRange(apex.foot.x0, apex.foot.x1, origin.x, m_layout.widthAt(level));
        const ivec2 ys = nodeRange(apex.foot.y0, apex.foot.y1, origin.y, m_layout.heightAt(level));
        int top = 0;
        for (int y = ys.x; y <= ys.y; ++y)
            for (int x = xs.x; x <= xs.y; ++x)
                insertByBound(makeNode(level, x, y, distance2(apex.foot, origin, level, x, y),
                                       m_pyramid.at(level, x, y), apex.a),
                              stack, top);
        return top;
    }

    // Inserts n into stack[0, top) kept highest bound first (the lowest is popped first; ties:
    // the one inserted first).
    static void insertByBound(const Node& n, Node* stack, int& top) {
        int k = top++;
        for (; k > 0 && stack[k - 1].order < n.order; --k) stack[k] = stack[k - 1];
        stack[k] = n;
    }

    const Surface& m_s;
    ConeKind m_kind;
    // Safe maps: over the cells (a cell bounds the cone by its highest corner); published maps:
    // over the cells' 00 corners (their candidates are samples), a node's sample box 1 narrower.
    MaxPyramid m_pyramid;
    PyramidLayout m_layout;
    float m_sampleInset;
    float m_cMax;
    std::vector<ivec2> m_shifts;
    std::unique_ptr<const SlopeWindows> m_slopes;  // FaithfulRelaxed with skipProvenWalks only
};

// Rows in parallel; inside a run of rows texels go boustrophedon (left to right, then right to
// left) so that each texel's neighbour, the previous one, hands over its guess (SearchHints).
template <class PerTexel>
std::vector<vec2> buildRows(const Surface& s, PerTexel&& perTexel) {
    std::vector<vec2> cones(size_t(s.width()) * size_t(s.height()));
    parallelRanges(s.height(), 1, [&](int64_t begin, int64_t end) {
        SearchHints hints;
        for (int j = int(begin); j < int(end); ++j)
            for (int k = 0; k < s.width(); ++k) {
                const int i = (j - int(begin)) % 2 == 0 ? k : s.width() - 1 - k;
                cones[size_t(j) * size_t(s.width()) + size_t(i)] = perTexel(i, j, hints);
            }
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

std::vector<vec2> buildCones(const Surface& surface, ConeKind kind, bool skipProvenWalks) {
    const ConeSearch search(surface, kind, skipProvenWalks);
    return buildRows(surface,
                     [&](int i, int j, SearchHints& hints) { return search.texel(i, j, hints); });
}

float safeApexHeight(const Surface& surface, int i, int j) {
    return apexOf(surface, ConeKind::SafeStrict, i, j).a;
}

std::vector<vec2> buildConesBruteForce(const Surface& surface, ConeKind kind) {
    const ConeSearch search(surface, kind);
    return buildRows(surface, [&](int i, int j, SearchHints&) { return search.texelBruteForce(i, j); });
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

// Spot check of a decoded baked map (maps are checksummed, so this catches values edited by hand
// or written by a faulty builder): at up to 4096 texels spread over the map, the apex is finite,
// not below the texel's sample and not above the box top, the ratio lies in [0, cMax], and for
// the strict kinds no sample within 2 texels lies inside the cone (c·(h_q − a) ≤ dist, with the
// footprint for SafeStrict and the texel centre for FaithfulStrict; relaxed cones may contain
// samples by design). Quantization only narrows cones and raises apexes, so it passes too.
Status spotCheckCones(const Surface& s, const ConeMap& map, ConeKind kind,
                      std::string_view technique) {
    const float tolerance = 1e-4f * std::max(1.0f, s.depth());
    const float cMax = coneRatioMax(s) * (1.0f + 1e-5f);
    const size_t count = size_t(map.width()) * size_t(map.height());
    const size_t stride = std::max<size_t>(1, count / 4096);
    auto refuse = [&](int i, int j, const std::string& what) {
        return makeError(ErrorKind::InvalidInput,
                         "{}: baked 'cones' texel ({}, {}) {}; the maps were "
                         "edited or built wrongly, bake them again",
                         technique, i, j, what);
    };
    for (size_t k = stride / 2; k < count; k += stride) {
        const int i = int(k % size_t(map.width())), j = int(k / size_t(map.width()));
        const vec2 t = map.texels()[k];
        const float a = t.x, c = t.y;
        if (!(a >= s.sampleZ(i, j) - tolerance && a <= s.depth() * (1.0f + 1e-5f) + tolerance))
            return refuse(i, j,
                          fmt::format("has apex {} outside [sample {}, depth {}]", a,
                                      s.sampleZ(i, j), s.depth()));
        if (!(c >= 0.0f && c <= cMax))
            return refuse(i, j, fmt::format("has ratio {} outside [0, {}]", c, cMax));
        if (kind == ConeKind::FaithfulRelaxed) continue;
        for (int qj = j - 2; qj <= j + 2; ++qj)
            for (int qi = i - 2; qi <= i + 2; ++qi) {
                if (s.edge() == EdgeMode::Clamp &&
                    (qi < 0 || qj < 0 || qi >= s.width() || qj >= s.height()))
                    continue;
                const float rise = s.sampleZ(qi, qj) - a;
                if (rise <= 0.0f) continue;
                // Distance from the footprint [i, i+1]×[j, j+1] (or its centre) to the sample.
                const float cx = float(qi) + 0.5f, cy = float(qj) + 0.5f;
                const float dx = kind == ConeKind::SafeStrict
                                     ? std::max({float(i) - cx, 0.0f, cx - float(i + 1)})
                                     : cx - (float(i) + 0.5f);
                const float dy = kind == ConeKind::SafeStrict
                                     ? std::max({float(j) - cy, 0.0f, cy - float(j + 1)})
                                     : cy - (float(j) + 0.5f);
                if (c * rise > std::sqrt(dx * dx + dy * dy) * (1.0f + 1e-4f) + tolerance)
                    return refuse(i, j,
                                  fmt::format("has ratio {}, wider than the sample at ({}, {}) "
                                              "allows ({} over {})",
                                              c, qi, qj, std::sqrt(dx * dx + dy * dy), rise));
            }
    }
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
        auto map =
            std::make_shared<const ConeMap>(decodeCones(s, *input.maps->find("cones"), encoding));
        if (Status status = spotCheckCones(s, *map, kind, technique); !status.ok())
            return status.error();
        return map;
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
