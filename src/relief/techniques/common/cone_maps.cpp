#include <relief/techniques/common/cone_maps.h>

#include <relief/core/parallel.h>
#include <relief/surface/cell_cursor.h>
#include <relief/techniques/common/max_pyramid.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
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

// The cells a relaxed walk can visit, as one row-major grid: clamp, cells -1..W-1 (the box's
// half-texel border strips included); repeat, cells 0..W-1, any other index wrapped.
struct CellGrid {
    bool repeat;
    int first, columns, rows;

    explicit CellGrid(const Surface& s)
        : repeat(s.edge() == EdgeMode::Repeat),
          first(repeat ? 0 : -1),
          columns(repeat ? s.width() : s.width() + 1),
          rows(repeat ? s.height() : s.height() + 1) {}

    size_t size() const { return size_t(columns) * size_t(rows); }
    int wrapOrClamp(int k, int n) const {
        if (!repeat) return std::clamp(k, 0, n - 1);
        const int r = k % n;
        return r < 0 ? r + n : r;
    }
    int column(int ci) const { return wrapOrClamp(ci - first, columns); }
    int row(int cj) const { return wrapOrClamp(cj - first, rows); }
    size_t index(int ci, int cj) const {
        return size_t(row(cj)) * size_t(columns) + size_t(column(ci));
    }
    // Clamp: whether the cell is one of the grid's (a walk inside the box visits no other).
    bool holds(int ci, int cj) const {
        return repeat || (ci >= first && cj >= first && ci < first + columns && cj < first + rows);
    }
};

// The steepest plane of the cells within r cells (Chebyshev) of a cell, for r = 1, 2, 4, …, 32:
// the relaxed search's cheap reject. S is continuous and piecewise planar, so along a ray that
// starts on S and descends faster than every plane it can meet, S stays above the ray: no exit.
class SlopeWindows {
public:
    static constexpr int kLevels = 6;

    explicit SlopeWindows(const Surface& s) : m_grid(s) {
        std::vector<float> slope(m_grid.size());
        parallelRanges(m_grid.rows, 16, [&](int64_t begin, int64_t end) {
            for (int64_t row = begin; row < end; ++row)
                for (int column = 0; column < m_grid.columns; ++column) {
                    const CellPlanes p =
                        s.cellPlanes(column + m_grid.first, int(row) + m_grid.first);
                    slope[size_t(row) * size_t(m_grid.columns) + size_t(column)] =
                        std::max(planeSlope(p.first), planeSlope(p.second));
                }
        });
        // Radius 1 from the slopes, then radius 2r from radius r: the max of three r-windows
        // at −r, 0, +r along each axis covers the 2r-window (wrapped or clamped as it is), so
        // the windows are the direct filter's, at 6 reads a cell per level instead of 4r + 2.
        m_windows[0] = grow(slope, 1);
        for (int level = 1; level < kLevels; ++level)
            m_windows[size_t(level)] = grow(m_windows[size_t(level - 1)], 1 << (level - 1));
    }

    // Steepest slope within `radius` cells of cell (ci, cj); kInfinity past the widest window.
    float maxSlope(int ci, int cj, int radius) const {
        int level = 0;
        while (level < kLevels && (1 << level) < radius) ++level;
        if (level == kLevels) return kInfinity;
        return m_windows[size_t(level)][m_grid.index(ci, cj)];
    }

private:
    // Max of the values at offsets −r, 0, +r along rows, then along columns, wrapped or clamped.
    // Both passes go along rows (the second takes three whole rows), contiguous in memory.
    std::vector<float> grow(const std::vector<float>& in, int r) const {
        const int columns = m_grid.columns, rows = m_grid.rows;
        auto row = [&](const std::vector<float>& v, int j) {
            return &v[size_t(j) * size_t(columns)];
        };
        std::vector<float> across(in.size()), out(in.size());
        parallelRanges(rows, 16, [&](int64_t begin, int64_t end) {
            for (int j = int(begin); j < int(end); ++j) {
                const float* from = row(in, j);
                float* to = &across[size_t(j) * size_t(columns)];
                auto edge = [&](int k) {
                    return std::max(std::max(from[m_grid.wrapOrClamp(k - r, columns)], from[k]),
                                    from[m_grid.wrapOrClamp(k + r, columns)]);
                };
                const int inner0 = std::min(r, columns), inner1 = std::max(inner0, columns - r);
                for (int k = 0; k < inner0; ++k) to[k] = edge(k);
                for (int k = inner0; k < inner1; ++k)
                    to[k] = std::max(std::max(from[k - r], from[k]), from[k + r]);
                for (int k = inner1; k < columns; ++k) to[k] = edge(k);
            }
        });
        parallelRanges(rows, 16, [&](int64_t begin, int64_t end) {
            for (int j = int(begin); j < int(end); ++j) {
                const float* below = row(across, m_grid.wrapOrClamp(j - r, rows));
                const float* here = row(across, j);
                const float* above = row(across, m_grid.wrapOrClamp(j + r, rows));
                float* to = &out[size_t(j) * size_t(columns)];
                for (int k = 0; k < columns; ++k)
                    to[k] = std::max(std::max(below[k], here[k]), above[k]);
            }
        });
        return out;
    }

    CellGrid m_grid;
    std::array<std::vector<float>, kLevels> m_windows;
};

// Which of a cell's planes (planesFromCorners) pass through its corner (u, v) ∈ {0, 1}²: with
// the 00–11 diagonal, first = triangle 00 10 11 and second = 00 01 11; otherwise first = 00 10 01
// and second = 10 01 11. The diagonal's corners are on both.
struct CornerPlanes {
    bool first, second;
};
CornerPlanes planesThroughCorner(const CellCorners& k, bool u, bool v) {
    const bool diagonal00 = k.z00 + k.z11 <= k.z10 + k.z01;
    if (diagonal00 ? u == v : u != v) return {true, true};
    const bool first = diagonal00 ? u : !u;  // 10 (00–11 diagonal) or 00 (10–01 diagonal)
    return {first, !first};
}

// The relaxed search's directional reject (fbm 1024²: 82 % of the walks SlopeWindows leaves).
// A candidate ray leaves its sample q horizontally along u, descending k per texel, and its walk
// only meets cells of the quadrant of u (signs of u.x, u.y, zero counted positive: the cell
// cursor then stays on that side). Over the quadrant's first cell, the one with q as a corner,
// S is the max of two planes and at least one P passes through q, so S(q + v) ≥ q.z + ∇P·v: the
// ray stays below S there when ∇P·u ≥ −k (belowFirstCell, exact directions). Over any other
// cell B of the quadrant, S ≥ the lowest corner of B, so the ray stays below S when
// k ≥ (q.z − min B) / dist(q, B); the max of that over the quadrant's cells within L of q is
// stored per sample, quadrant and L, rounded up to 16 bits (bfloat16's grid): 40 bytes a sample.
// For whole level-1 pyramid nodes (relaxedNodeProvenEmpty), the max over the node's samples of
// that and of the first cell's bound over every direction of the quadrant (min over the quarter
// circle of ∇P·u: at an axis, or −|∇P| when −∇P points into it): 10 bytes a sample more.
class SampleDrops {
public:
    static constexpr std::array<int, 5> kReach{2, 3, 4, 6, 8};  // L, texels

    explicit SampleDrops(const Surface& s)
        : m_grid(s),
          m_nodeColumns((m_grid.columns + 1) / 2),
          m_drops(m_grid.size() * kPerSample),
          m_nodeDrops(size_t(m_nodeColumns) * size_t((m_grid.rows + 1) / 2) * kPerSample) {
        std::vector<float> lowest(m_grid.size()), height(m_grid.size());
        parallelRanges(m_grid.rows, 16, [&](int64_t begin, int64_t end) {
            for (int64_t row = begin; row < end; ++row)
                for (int column = 0; column < m_grid.columns; ++column) {
                    const int ci = column + m_grid.first, cj = int(row) + m_grid.first;
                    const CellCorners k = s.cellCorners(ci, cj);
                    const size_t at = size_t(row) * size_t(m_grid.columns) + size_t(column);
                    lowest[at] = std::min({k.z00, k.z10, k.z01, k.z11});
                    height[at] = s.sampleZ(ci, cj);
                }
        });
        const std::vector<Offset> offsets = quadrantOffsets();
        // Row by row, one offset at a time over the whole row (vectorizable); in clamp mode the
        // cells off the grid are left out (a walk inside the box never meets them).
        parallelRanges(m_grid.rows, 4, [&](int64_t begin, int64_t end) {
            const int columns = m_grid.columns;
            std::vector<float> drop(static_cast<size_t>(columns));
            for (int row = int(begin); row < int(end); ++row) {
                const float* z = &height[size_t(row) * size_t(columns)];
                for (int quadrant = 0; quadrant < 4; ++quadrant) {
                    const bool negativeX = quadrant & 1, negativeY = quadrant & 2;
                    std::fill(drop.begin(), drop.end(), 0.0f);
                    size_t o = 0;
                    for (int level = 0; level < kLevels; ++level) {
                        for (; o < offsets.size() && offsets[o].level == level; ++o) {
                            const int di = negativeX ? -offsets[o].a - 1 : offsets[o].a;
                            const int dj = negativeY ? -offsets[o].b - 1 : offsets[o].b;
                            const float inverse = 1.0f / offsets[o].distance;
                            const int other = row + dj;
                            if (!m_grid.repeat && (other < 0 || other >= m_grid.rows)) continue;
                            const float* low =
                                &lowest[size_t(m_grid.wrapOrClamp(other, m_grid.rows)) *
                                        size_t(columns)];
                            const int c0 = m_grid.repeat ? 0 : std::max(0, -di);
                            const int c1 =
                                m_grid.repeat ? columns : std::min(columns, columns - di);
                            if (m_grid.repeat)
                                for (int c = 0; c < columns; ++c)
                                    drop[size_t(c)] =
                                        std::max(drop[size_t(c)],
                                                 (z[c] - low[m_grid.wrapOrClamp(c + di, columns)]) *
                                                     inverse);
                            else
                                for (int c = c0; c < c1; ++c)
                                    drop[size_t(c)] =
                                        std::max(drop[size_t(c)], (z[c] - low[c + di]) * inverse);
                        }
                        for (int c = 0; c < columns; ++c)
                            m_drops[slot(size_t(row) * size_t(columns) + size_t(c), quadrant,
                                         level)] = roundUp(drop[size_t(c)]);
                    }
                }
            }
        });
        // Level-1 nodes: their ≤ 2×2 samples, each with its first cell's bound.
        const int nodeRows = (m_grid.rows + 1) / 2;
        parallelRanges(nodeRows, 8, [&](int64_t begin, int64_t end) {
            for (int ny = int(begin); ny < int(end); ++ny)
                for (int nx = 0; nx < m_nodeColumns; ++nx)
                    for (int quadrant = 0; quadrant < 4; ++quadrant) {
                        std::array<uint16_t, kLevels> v{};
                        for (int row = 2 * ny; row < std::min(2 * ny + 2, m_grid.rows); ++row)
                            for (int c = 2 * nx; c < std::min(2 * nx + 2, m_grid.columns); ++c) {
                                const uint16_t first = roundUp(firstCellDrop(
                                    s, c + m_grid.first, row + m_grid.first, quadrant & 1,
                                    quadrant & 2));
                                const size_t sample =
                                    size_t(row) * size_t(m_grid.columns) + size_t(c);
                                for (int level = 0; level < kLevels; ++level)
                                    v[size_t(level)] =
                                        std::max({v[size_t(level)], first,
                                                  m_drops[slot(sample, quadrant, level)]});
                            }
                        const size_t node = size_t(ny) * size_t(m_nodeColumns) + size_t(nx);
                        for (int level = 0; level < kLevels; ++level)
                            m_nodeDrops[slot(node, quadrant, level)] = v[size_t(level)];
                    }
        });
    }

    // The least descent per texel that keeps a ray from sample (ci, cj) below S over the cells of
    // its quadrant other than the first, out to `length` texels; kInfinity past the widest L.
    float drop(int ci, int cj, bool negativeX, bool negativeY, float length) const {
        const int level = levelOf(length);
        if (level == kLevels) return kInfinity;
        return decode(m_drops[slot(m_grid.index(ci, cj), quadrant(negativeX, negativeY), level)]);
    }
    // The same for every sample of level-1 pyramid node (nx, ny), first cells included.
    float nodeDrop(int nx, int ny, bool negativeX, bool negativeY, float length) const {
        const int level = levelOf(length);
        if (level == kLevels) return kInfinity;
        const size_t node = size_t(ny) * size_t(m_nodeColumns) + size_t(nx);
        return decode(m_nodeDrops[slot(node, quadrant(negativeX, negativeY), level)]);
    }

private:
    static constexpr int kLevels = int(kReach.size());
    static constexpr size_t kPerSample = 4 * kLevels;

    // The cells of the quadrant (+, +) as gaps (a, b) ≥ 0 from q with their distance, by level
    // (the smallest L that reaches them); the first cell (0, 0) is left out. The other
    // quadrants are mirror images: gap a is the cell offset a on the + side, −a − 1 on the − side.
    struct Offset {
        int a, b, level;
        float distance;
    };
    static std::vector<Offset> quadrantOffsets() {
        std::vector<Offset> offsets;
        for (int b = 0; b <= kReach.back(); ++b)
            for (int a = 0; a <= kReach.back(); ++a) {
                if (a == 0 && b == 0) continue;
                const float distance = std::sqrt(float(a * a + b * b));
                const int level = levelOf(distance);
                if (level < kLevels) offsets.push_back({a, b, level, distance});
            }
        std::stable_sort(offsets.begin(), offsets.end(),
                         [](const Offset& x, const Offset& y) { return x.level < y.level; });
        return offsets;
    }

    // The first cell's bound for every direction of the quadrant (kInfinity off the grid).
    float firstCellDrop(const Surface& s, int ci, int cj, bool negativeX, bool negativeY) const {
        const int fi = ci - (negativeX ? 1 : 0), fj = cj - (negativeY ? 1 : 0);
        if (!m_grid.holds(fi, fj)) return kInfinity;
        const CellCorners k = s.cellCorners(fi, fj);
        const CellPlanes p = planesFromCorners(k);
        const CornerPlanes through = planesThroughCorner(k, negativeX, negativeY);
        float rise = -kInfinity;  // max over the planes through q of min over u of ∇P·u
        for (const auto& [plane, on] : {std::pair{&p.first, through.first},
                                        std::pair{&p.second, through.second}}) {
            if (!on) continue;
            const float gx = negativeX ? -plane->sx : plane->sx;
            const float gy = negativeY ? -plane->sy : plane->sy;
            rise = std::max(rise, gx < 0.0f && gy < 0.0f ? -std::sqrt(gx * gx + gy * gy)
                                                         : std::min(gx, gy));
        }
        return std::max(0.0f, -rise);
    }

    static int levelOf(float length) {
        int level = 0;
        while (level < kLevels && float(kReach[size_t(level)]) < length) ++level;
        return level;
    }
    static int quadrant(bool negativeX, bool negativeY) {
        return (negativeX ? 1 : 0) + (negativeY ? 2 : 0);
    }
    static size_t slot(size_t entry, int quadrant, int level) {
        return entry * kPerSample + size_t(quadrant * kLevels + level);
    }

    // The upper 16 bits of a float ≥ 0, rounded up (with a margin against the rounding of the
    // bound's own arithmetic), and back.
    static uint16_t roundUp(float v) {
        if (!(v < kInfinity)) return 0x7f80u;  // +∞
        const uint32_t bits = std::bit_cast<uint32_t>(v * (1.0f + 1e-5f));
        const uint32_t high = bits >> 16;
        return uint16_t((bits & 0xffffu) != 0 ? high + 1 : high);
    }
    static float decode(uint16_t v) { return std::bit_cast<float>(uint32_t(v) << 16); }

    CellGrid m_grid;
    int m_nodeColumns;
    std::vector<uint16_t> m_drops, m_nodeDrops;
};

// What relaxedRatio's rejects read (FaithfulRelaxed with skipProvenWalks).
struct WalkBounds {
    SlopeWindows slopes;
    SampleDrops drops;
    explicit WalkBounds(const Surface& s) : slopes(s), drops(s) {}
};

// Whether a ray from sample q = the 00 corner of `cell`, along d, stays below S over the first
// cell of its quadrant: some plane of that cell through q descends no faster along d than the ray
// (SampleDrops).
bool belowFirstCell(const Surface& s, ivec2 cell, const vec3& d) {
    const bool right = d.x >= 0.0f, up = d.y >= 0.0f;
    const CellCorners k = s.cellCorners(cell.x - (right ? 0 : 1), cell.y - (up ? 0 : 1));
    const CellPlanes p = planesFromCorners(k);
    const CornerPlanes through = planesThroughCorner(k, !right, !up);
    auto descends = [&](const CellPlane& plane) { return plane.sx * d.x + plane.sy * d.y >= d.z; };
    return (through.first && descends(p.first)) || (through.second && descends(p.second));
}

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

// Whether the ray from q inside the box along d (horizontal length `reach`) meets no box face
// within `length` texels of horizontal travel: the clamp sides are at least as far along the ray
// as across (|d.x|, |d.y| ≤ reach), the floor z = 0 is q.z·reach / −d.z away. A cheaper
// sufficient form of reach · boxExitFromInside > length, for the walk rejects.
bool boxFartherThan(const Surface& s, const vec3& q, const vec3& d, float reach, float length) {
    if (d.z < 0.0f && !(q.z * reach > -d.z * length)) return false;
    if (s.edge() == EdgeMode::Repeat)
        return length < Surface::kRepeatTravelFactor * float(std::max(s.width(), s.height()));
    return std::min({q.x, float(s.width()) - q.x, q.y, float(s.height()) - q.y}) > length;
}

// Policarpo & Oliveira: the ray from the box top above the apex through sample q, followed past
// q until it leaves the solid at C, gives |C − apex| / (z_C − a). Along the ray that ratio only
// grows, so the walk stops where it reaches `c` (the ratio found so far): C beyond cannot lower it.
// The ray runs from q along q − top, unnormalized: at t its horizontal distance from the apex is
// reach·(1 + t) (`reach` = |q − apex| horizontally, the caller's), so neither a normalization nor
// a distance needs a square root here.
// Candidates whose ray stays in the solid up to tStop are the vast majority (98 % on fbm 1024²):
// the walks that the bounds (SampleDrops, then SlopeWindows) prove find no exit in the cells up
// to the one holding tStop, within travel + √2 of q, are skipped; the result is the walk's, to
// the bit.
float relaxedRatio(const Surface& s, const WalkBounds* bounds, const Apex& apex, ivec2 cell,
                   vec3 q, float reach, float c) {
    const vec3 d(q.x - apex.foot.x0, q.y - apex.foot.y0, q.z - s.depth());
    if (d.x == 0.0f && d.y == 0.0f) return kInfinity;
    const float tStop =
        std::isfinite(c) ? (c * (q.z - apex.a) - reach) / (reach - c * d.z) : kInfinity;
    const float travel = reach * std::max(0.0f, tStop);
    if (bounds && boxFartherThan(s, q, d, reach, travel + 2.0f)) {
        // The walk meets cells within travel + √2 of q (to the end of the one holding tStop).
        constexpr float kRoundingMargin = 1.0f + 1e-4f;
        const float length = travel + 1.5f;
        if (-d.z >= reach * kRoundingMargin *
                        bounds->drops.drop(cell.x, cell.y, d.x < 0.0f, d.y < 0.0f, length) &&
            belowFirstCell(s, cell, d))
            return kInfinity;
        if (-d.z >= reach * bounds->slopes.maxSlope(cell.x, cell.y, int(std::ceil(length)) + 1))
            return kInfinity;
    }
    const Ray ray{q, d, kInfinity};
    const float tExit = boxExitFromInside(s, ray);
    const float tc = firstExit(s, ray, 0.0f, std::max(0.0f, tStop), tExit);
    if (!(tc <= tExit)) return kInfinity;
    const float exitZ = q.z + tc * d.z;
    if (exitZ <= apex.a) return kInfinity;
    return reach * (1.0f + tc) / (exitZ - apex.a);
}

// The bound cell (ci, cj) puts on the ratio of `apex` (kInfinity when none); `c` is the ratio
// found so far (the relaxed search skips rays that cannot lower it).
float leafRatio(const Surface& s, const WalkBounds* bounds, ConeKind kind, const Apex& apex,
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
    const float distance = glm::length(toQ);
    const float strict = distance / rise;
    if (kind == ConeKind::FaithfulStrict || strict >= c) return strict;
    return std::min(c, relaxedRatio(s, bounds, apex, {ci, cj}, q, distance, c));
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
// time; with the slope windows alone it rarely succeeded on rough ground (fbm 512²: 20 % at
// level 1, 8 % at 2, none above; with SampleDrops 76 % on fbm 1024²) and its square roots and
// window read cost more than the walks it saved (14 % more CPU with it than without), on smooth
// ground it saves more than it costs (peaks6 1024²: 21 % less). So a
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
          m_bounds(kind == ConeKind::FaithfulRelaxed && skipProvenWalks
                       ? std::make_unique<WalkBounds>(s)
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
        // the order changes no result. Set when the node is pushed (insertByBound).
        float order;
    };
    static Node makeNode(int level, int x, int y, float distance2, float max) {
        return {level, x, y, distance2, max, 0.0f};
    }

    float ratioOf(const Apex& apex, ivec2 cell, float c) const {
        return leafRatio(m_s, m_bounds.get(), m_kind, apex, cell.x, cell.y, c);
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
        // Level-1 nodes are tried before they are pushed (on fbm 1024² three in four are
        // proven: neither sorted, stored nor popped), the others when they are popped.
        auto keep = [&](const Node& kid) {
            return kid.level != 1 || !provenEmpty(apex, first, kid, best.c, hints);
        };
        int top = pushStart(apex, origin, best.c, stack.data(), keep);
        while (top > 0) {
            const Node n = stack[--top];
            if (!mayLower(n.distance2, n.max, apex.a, best.c)) continue;  // c fell since the push
            if (n.level > 1 && provenEmpty(apex, first, n, best.c, hints)) continue;
            if (n.level == 0) {  // a start node that is already a cell (short reach, tiny map)
                const ivec2 at = first + ivec2(n.x, n.y);
                best.offer(ratioOf(apex, at, best.c), at);
                continue;
            }
            if (n.level > 1) {
                pushChildren(apex, origin, n, best.c, stack.data(), top, keep);
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
    // before its ratio reaches c; when no box face is that close and that slope beats SampleDrops'
    // bound for the node (level 1, every sample in one quadrant of the apex) or the steepest
    // plane within the node grown by that travel, no walk in n can find an exit below c.
    // Needs m_bounds (the caller tries it only then).
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
        constexpr float kRoundingMargin = 1.0f + 1e-4f;
        // Level 1 with every sample on one side of the apex in x and in y: SampleDrops' bound
        // for the node (each ray's walk meets cells within travel + √2 of its sample).
        if (n.level == 1 && (lx >= 0.0f || hx < 0.0f) && (ly >= 0.0f || hy < 0.0f) &&
            kMin >= m_bounds->drops.nodeDrop(n.x, n.y, hx < 0.0f, hy < 0.0f, travel + 1.5f) *
                        kRoundingMargin)
            return true;
        const int grow = int(std::ceil(travel + 1.5f)) + 2;
        const int radius = std::max(x1 - x0, y1 - y0) / 2 + grow;
        const ivec2 centre = first + ivec2((x0 + x1 - 1) / 2, (y0 + y1 - 1) / 2);
        return kMin >= m_bounds->slopes.maxSlope(centre.x, centre.y, radius) * kRoundingMargin;
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
                const Node kid =
                    makeNode(level, x, y, distance2(apex.foot, origin, level, x, y), m);
                if (mayLower(kid.distance2, m, apex.a, c)) visit(kid);
            }
    }

    // The children that may lower c, highest bound pushed first (the lowest is visited first).
    // (Those that `keep` also accepts.)
    template <class Keep>
    void pushChildren(const Apex& apex, vec2 origin, const Node& n, float c, Node* stack,
                      int& top, Keep&& keep) const {
        Node* kids = stack + top;
        int count = 0;
        forEachChild(apex, origin, n, c, [&](const Node& kid) {
            if (keep(kid)) insertByBound(kid, apex.a, kids, count);
        });
        top += count;
    }

    // FaithfulRelaxed with the walk rejects: whether relaxedNodeProvenEmpty skips n, tried per
    // level as SearchHints rules.
    bool provenEmpty(const Apex& apex, ivec2 first, const Node& n, float c,
                     SearchHints& hints) const {
        if (!m_bounds || n.level == 0 || !hints.worthProving(n.level)) return false;
        const bool proven = relaxedNodeProvenEmpty(apex, first, n, c);
        hints.recordProof(n.level, proven);
        return proven;
    }

    // Where the descent starts: no cell farther than R = c·(max S − a) from F can lower c, so
    // instead of the root, the (at most 4×4) nodes of the finest level with 2^level ≥ R that
    // meet F grown by R, highest bound pushed first (R taken with a generous margin against
    // rounding). Returns the stack size.
    template <class Keep>
    int pushStart(const Apex& apex, vec2 origin, float c, Node* stack, Keep&& keep) const {
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
            for (int x = xs.x; x <= xs.y; ++x) {
                const Node n = makeNode(level, x, y, distance2(apex.foot, origin, level, x, y),
                                        m_pyramid.at(level, x, y));
                if (keep(n)) insertByBound(n, apex.a, stack, top);
            }
        return top;
    }

    // Inserts n, its order set for apex height a, into stack[0, top) kept highest bound first
    // (the lowest is popped first; ties: the one inserted first).
    static void insertByBound(Node n, float a, Node* stack, int& top) {
        const float rise = n.max - a;
        n.order = rise > 0.0f ? n.distance2 / (rise * rise) : kInfinity;
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
    std::unique_ptr<const WalkBounds> m_bounds;  // FaithfulRelaxed with skipProvenWalks only
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
