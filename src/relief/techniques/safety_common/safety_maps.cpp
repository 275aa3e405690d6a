#include <relief/techniques/safety_common/safety_maps.h>

#include <relief/techniques/safety_common/safety_exterior.h>

#include <relief/core/parallel.h>

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>
#include <numbers>

namespace relief::safety {

double tanPhiMax(double phiMaxDeg) {
    if (phiMaxDeg >= 90.0) return std::numeric_limits<double>::infinity();
    return std::tan(phiMaxDeg * std::numbers::pi / 180.0);
}

// ---- Frames ----

void Frame::world(double a, double b, double& X, double& Y) const {
    switch (cls) {
        case kXPlus: X = a, Y = b; return;
        case kXMinus: X = -a, Y = b; return;
        case kYPlus: X = b, Y = a; return;
        default: X = b, Y = -a; return;
    }
}

void Frame::local(double X, double Y, double& a, double& b) const {
    switch (cls) {
        case kXPlus: a = X, b = Y; return;
        case kXMinus: a = -X, b = Y; return;
        case kYPlus: a = Y, b = X; return;
        default: a = -Y, b = X; return;
    }
}

void Frame::worldCell(int ac, int bc, int& ci, int& cj) const {
    switch (cls) {
        case kXPlus: ci = ac, cj = bc; return;
        case kXMinus: ci = -ac - 1, cj = bc; return;
        case kYPlus: ci = bc, cj = ac; return;
        default: ci = bc, cj = -ac - 1; return;
    }
}

void Frame::texel(int i, int j, int& a0, int& b0) const {
    switch (cls) {
        case kXPlus: a0 = i, b0 = j; return;
        case kXMinus: a0 = -i, b0 = j; return;
        case kYPlus: a0 = j, b0 = i; return;
        default: a0 = -j, b0 = i; return;
    }
}

namespace {

bool cellInBox(const Surface& s, int ci, int cj) {
    return s.edge() == EdgeMode::Repeat ||
           (ci >= -1 && ci <= s.width() - 1 && cj >= -1 && cj <= s.height() - 1);
}

LocalTriangle makeTriangle(const Frame& f, const std::array<double, 3>& X,
                           const std::array<double, 3>& Y, const std::array<double, 3>& Z) {
    LocalTriangle t;
    for (int v = 0; v < 3; ++v) {
        f.local(X[v], Y[v], t.a[v], t.b[v]);
        t.z[v] = Z[v];
    }
    const double ua = t.a[1] - t.a[0], ub = t.b[1] - t.b[0], uz = t.z[1] - t.z[0];
    const double va = t.a[2] - t.a[0], vb = t.b[2] - t.b[0], vz = t.z[2] - t.z[0];
    const double na = ub * vz - uz * vb, nb = uz * va - ua * vz, nz = ua * vb - ub * va;
    t.pa = -na / nz;
    t.pb = -nb / nz;
    t.z0 = t.z[0] - t.pa * t.a[0] - t.pb * t.b[0];
    return t;
}

// Number of local columns (offsets from a0) inside the box in clamp mode; "unbounded" in repeat.
int columnsAhead(const Surface& s, int cls, int i, int j) {
    if (s.edge() == EdgeMode::Repeat) return std::numeric_limits<int>::max() / 4;
    switch (cls) {
        case kXPlus: return s.width() - 1 - i;
        case kXMinus: return i;
        case kYPlus: return s.height() - 1 - j;
        default: return j;
    }
}

int crossCount(const Surface& s, int cls) { return cls < kYPlus ? s.height() : s.width(); }

}  // namespace

int allowedDirections(double pa, double pb, double tanPhi, double (&lo)[2], double (&hi)[2]) {
    constexpr double kQuarter = std::numbers::pi / 4.0;
    // Without a restriction (φ_max = 90°: tanPhi = ∞) or on a gentle plane every direction is
    // allowed: |pa| + |pb| bounds the gradient's length, and the margin hypot's error (< 1 ulp),
    // so the answer is the one below without its hypot (3 % of a safety bake's time).
    if (tanPhi >= (std::abs(pa) + std::abs(pb)) * (1.0 + 1e-15)) {
        lo[0] = -1.0, hi[0] = 1.0;
        return 1;
    }
    const double g = std::hypot(pa, pb);
    if (!(tanPhi < g)) {
        lo[0] = -1.0, hi[0] = 1.0;
        return 1;
    }
    if (tanPhi < -g) return 0;
    const double w = std::acos(std::clamp(tanPhi / g, -1.0, 1.0)) - 1e-12;  // conservative
    const double centre = std::atan2(pb, pa);
    double intervals[3][2] = {{-kQuarter, kQuarter}};
    int count = 1;
    for (int n = -1; n <= 1; ++n) {
        const double e0 = centre - w + 2.0 * std::numbers::pi * n;
        const double e1 = centre + w + 2.0 * std::numbers::pi * n;
        double next[3][2];
        int nextCount = 0;
        for (int k = 0; k < count; ++k) {
            const double a = intervals[k][0], b = intervals[k][1];
            if (e1 <= a || e0 >= b) {
                next[nextCount][0] = a, next[nextCount++][1] = b;
                continue;
            }
            if (a < e0) next[nextCount][0] = a, next[nextCount++][1] = e0;
            if (e1 < b) next[nextCount][0] = e1, next[nextCount++][1] = b;
        }
        count = std::min(nextCount, 2);
        for (int k = 0; k < count; ++k) intervals[k][0] = next[k][0], intervals[k][1] = next[k][1];
    }
    for (int k = 0; k < count; ++k) {
        lo[k] = std::tan(intervals[k][0]);
        hi[k] = std::tan(intervals[k][1]);
    }
    return count;
}

bool cellTriangles(const Surface& s, const Frame& f, int ci, int cj,
                   std::array<LocalTriangle, 2>& out) {
    if (!cellInBox(s, ci, cj)) return false;
    const CellCorners c = s.cellCorners(ci, cj);
    const double x0 = ci, x1 = ci + 1, y0 = cj, y1 = cj + 1;
    if (c.z00 + c.z11 <= c.z10 + c.z01) {  // same rule and arithmetic as planesFromCorners
        out[0] = makeTriangle(f, {x0, x1, x1}, {y0, y0, y1}, {c.z00, c.z10, c.z11});
        out[1] = makeTriangle(f, {x0, x1, x0}, {y0, y1, y1}, {c.z00, c.z11, c.z01});
    } else {
        out[0] = makeTriangle(f, {x0, x1, x0}, {y0, y0, y1}, {c.z00, c.z10, c.z01});
        out[1] = makeTriangle(f, {x1, x1, x0}, {y0, y1, y1}, {c.z10, c.z11, c.z01});
    }
    return true;
}

double SegmentHeights::at(double b) const {
    const double u = b - double(b0);
    return u <= 0.0 ? mid + (mid - lo) * 2.0 * u : mid + (hi - mid) * 2.0 * u;
}

SegmentHeights segmentHeights(const Surface& s, const Frame& f, int i, int j) {
    SegmentHeights seg;
    f.texel(i, j, seg.a0, seg.b0);
    auto z = [&](int b) {
        double X, Y;
        f.world(seg.a0, b, X, Y);
        return double(s.sampleZ(int(X), int(Y)));
    };
    const double below = z(seg.b0 - 1), centre = z(seg.b0), above = z(seg.b0 + 1);
    seg.lo = 0.5 * (below + centre);
    seg.mid = centre;
    seg.hi = 0.5 * (centre + above);
    return seg;
}

bool isLimiting(const SegmentHeights& seg, const LocalTriangle& t, double tanPhi) {
    double lo[2], hi[2];
    const int arcs = allowedDirections(t.pa, t.pb, tanPhi, lo, hi);
    const double eps = 1e-9 * (1.0 + std::abs(seg.mid));
    const double a0 = seg.a0, b0 = seg.b0;
    auto above = [&](double b) { return t.z0 + t.pa * a0 + t.pb * b - seg.at(b) > eps; };
    for (int k = 0; k < arcs; ++k) {
        double y0 = b0 - 0.5, y1 = b0 + 0.5;
        double reachLo = std::numeric_limits<double>::infinity(), reachHi = -reachLo;
        for (int v = 0; v < 3; ++v) {
            const double along = t.a[v] - a0;
            reachLo = std::min(reachLo, t.b[v] - hi[k] * along);
            reachHi = std::max(reachHi, t.b[v] - lo[k] * along);
        }
        y0 = std::max(y0, reachLo);
        y1 = std::min(y1, reachHi);
        if (y0 > y1) continue;
        if (above(y0) || above(y1) || (y0 < b0 && b0 < y1 && above(b0))) return true;
    }
    return false;
}

// ---- Safety distance ----

namespace {

// A bound on how high a cell's triangle planes can reach when extended back k + 1 columns and
// k + 2.5 rows: max corner height + (|s_x| + |s_y|)·(k + 2.5). Cells below s_τ by this bound
// cannot be limiting (their planes stay below S there). Kept per line across the class axis
// (cell columns for the x classes, rows for the y classes) with maxima over aligned blocks of
// 16 and 256 cells, so a whole column of the wedge is usually dismissed in a few reads: flat
// land and sea cost almost nothing.
class CellBounds {
public:
    CellBounds(const Surface& s, bool alongY) : m_alongY(alongY) {
        m_repeat = s.edge() == EdgeMode::Repeat;
        const int extra = m_repeat ? 0 : 1;  // clamp: cells -1 .. W-1
        m_lines = (alongY ? s.width() : s.height()) + extra;
        m_length = (alongY ? s.height() : s.width()) + extra;
        for (int l = 0; l < 3; ++l) m_z[l].assign(blocks(l), 0.0f), m_g[l].assign(blocks(l), 0.0f);
        parallelRanges(m_lines, 16, [&](int64_t begin, int64_t end) {
            for (int64_t line = begin; line < end; ++line)
                for (int p = 0; p < m_length; ++p) fillCell(s, int(line), p);
        });
        for (int l = 1; l < 3; ++l)
            for (int line = 0; line < m_lines; ++line)
                for (int p = 0; p < m_length; ++p) {
                    const size_t from = at(0, line, p), to = at(l, line, p);
                    m_z[l][to] = std::max(m_z[l][to], m_z[0][from]);
                    m_g[l][to] = std::max(m_g[l][to], m_g[0][from]);
                }
    }

    // True when no cell in [lo, hi] across the axis in `line` (cell indices as Surface uses
    // them) can hold a limiting triangle for a segment whose lowest point is `lowest`: their
    // planes cannot rise above it within the wedge, or (φ_max < 0) they are flatter than the
    // steepest allowed rays, so no allowed ray lies in them.
    bool dismiss(int line, int lo, int hi, int k, double lowest, double tanPhi) const {
        float g = 0.0f;
        const double z = reach(line, lo, hi, k, g);
        return z <= lowest || double(g) < -tanPhi;
    }

    // The cell's bound on |∇| (level 0).
    float cellSlope(int line, int p) const {
        line = m_repeat ? wrap(line, m_lines) : line + 1;
        p = m_repeat ? wrap(p, m_length) : p + 1;
        return m_g[0][at(0, line, p)];
    }

private:
    double reach(int line, int lo, int hi, int k, float& g) const {
        line = m_repeat ? wrap(line, m_lines) : line + 1;
        float z = -kInfinity;
        if (m_repeat) {
            if (hi - lo + 1 >= m_length) {
                lo = 0, hi = m_length - 1;
            } else {
                const int span = hi - lo;
                lo = wrap(lo, m_length);
                hi = lo + span;
            }
        } else {
            lo += 1, hi += 1;
        }
        if (hi >= m_length) {  // wrapped (repeat)
            gather(line, lo, m_length - 1, z, g);
            gather(line, 0, hi - m_length, z, g);
        } else {
            gather(line, lo, hi, z, g);
        }
        return double(z) + double(g) * (double(k) + 2.5);
    }

    static constexpr int kShift[3] = {0, 4, 8};
    size_t blocks(int l) const {
        return size_t(m_lines) * size_t(((m_length - 1) >> kShift[l]) + 1);
    }
    size_t at(int l, int line, int p) const {
        return size_t(line) * size_t(((m_length - 1) >> kShift[l]) + 1) + size_t(p >> kShift[l]);
    }
    static int wrap(int v, int n) {
        v %= n;
        return v < 0 ? v + n : v;
    }
    void fillCell(const Surface& s, int line, int p) {
        const int extra = m_repeat ? 0 : 1;
        const int ci = (m_alongY ? line : p) - extra, cj = (m_alongY ? p : line) - extra;
        const CellCorners c = s.cellCorners(ci, cj);
        // Each triangle's slopes are corner differences along x and y.
        const double sx = std::max(std::abs(double(c.z10) - c.z00), std::abs(double(c.z11) - c.z01));
        const double sy = std::max(std::abs(double(c.z01) - c.z00), std::abs(double(c.z11) - c.z10));
        m_z[0][at(0, line, p)] = std::max({c.z00, c.z10, c.z01, c.z11});
        m_g[0][at(0, line, p)] = std::nextafter(float(sx + sy), kInfinity);
    }
    void gather(int line, int lo, int hi, float& z, float& g) const {
        int p = lo;
        while (p <= hi) {
            int l = 2;
            while (l > 0 && ((p & ((1 << kShift[l]) - 1)) != 0 || p + (1 << kShift[l]) - 1 > hi)) --l;
            const size_t idx = at(l, line, p);
            z = std::max(z, m_z[l][idx]);
            g = std::max(g, m_g[l][idx]);
            p += 1 << kShift[l];
        }
    }

    bool m_alongY, m_repeat;
    int m_lines, m_length;
    std::vector<float> m_z[3], m_g[3];
};

// A per-class bound on how high a cell's triangle planes reach when extended back to the
// segment s_τ of a texel k columns behind: isLimiting needs a plane above S by its eps at one
// of b0 − ½, b0, b0 + ½. A plane z0 + pa·a + pb·b is there at V − pa·k − pb·(δ − o), V = its
// height at the cell's near edge and centre, δ = cell centre − b0, o the point's offset
// (translation invariant, so repeat-mode copies share it). Unlike
// CellBounds this sees that land rising away from a texel is harmless, which makes flat sea
// beside a coast cheap. Kept as pyramids of aligned 2^L × 2^L blocks (skipColumns) and 1 × 2^L
// column blocks (anyCell), each block's planes taken at its centre (max v there, ranges of −pa
// and −pb, rounded outwards), so a run of columns of a wide wedge is dismissed in a few reads
// where the old scan visited every cell of it.
class PlaneBounds {
public:
    PlaneBounds(const Surface& s, int cls) : m_cls(cls) {
        m_repeat = s.edge() == EdgeMode::Repeat;
        const int extra = m_repeat ? 0 : 1;  // clamp: cells -1 .. W-1
        const bool xClass = cls < kYPlus;
        m_nu = (xClass ? s.width() : s.height()) + extra;
        m_nv = (xClass ? s.height() : s.width()) + extra;
        const Frame f{cls};
        m_cells = {m_nu, m_nv, std::vector<Entry>(size_t(m_nu) * size_t(m_nv))};
        // isLimiting's rounding grows with the magnitude of the doubles it adds (z0 reaches back
        // to the origin: |pa|·|a| + |pb|·|b|), so each cell's V carries its own allowance. One
        // allowance for the whole map, from its steepest cell, outgrew the eps at 1024² with a
        // steep coast and left flat sea to the exact test, cell by cell (the scan went r²).
        const double span = 2.0 * (m_nu + m_nv) + 4.0;  // repeat copies reach a period further
        m_rounding = kUlps * (1.0 + double(s.maxZ()));
        std::vector<float> cellAmin(size_t(m_nu) * size_t(m_nv), kInfinity);  // min −pa
        parallelRanges(m_nu, 16, [&](int64_t begin, int64_t end) {
            std::array<LocalTriangle, 2> tris;
            for (int64_t u = begin; u < end; ++u)
                for (int v = 0; v < m_nv; ++v) {
                    const int a = int(u) - extra, b = v - extra;
                    const int ci = xClass ? a : b, cj = xClass ? b : a;
                    Entry e = kEmpty;
                    float& amin = cellAmin[size_t(u) * size_t(m_nv) + size_t(v)];
                    if (cellTriangles(s, f, ci, cj, tris))
                        for (const LocalTriangle& t : tris) {
                            amin = std::min(amin, -roundUp(t.pa));
                            const double near = std::min({t.a[0], t.a[1], t.a[2]});
                            const double centre = std::min({t.b[0], t.b[1], t.b[2]}) + 0.5;
                            const double q = t.z0 + t.pa * near + t.pb * centre;
                            const double slope = std::max(std::abs(t.pa), std::abs(t.pb));
                            e.v = std::max(e.v, roundUp(q + m_rounding + kUlps * slope * span));
                            e.a = std::max(e.a, roundUp(-t.pa));
                            e.pmax = std::max(e.pmax, roundUp(-t.pb));
                            e.pmin = std::min(e.pmin, -roundUp(t.pb));
                        }
                    m_cells.data[size_t(u) * size_t(m_nv) + size_t(v)] = e;
                }
        });
        buildSquares(cellAmin);
        buildColumns();
    }

    // How many columns from column k on (at most kLast − k + 1) hold no cell that can be
    // limiting for texel segment `seg` (lowest point `lowest`); 0 when no coarse block proves
    // it. `cross`: cells across the axis (clamp: -1 .. cross − 1).
    int skipColumns(const SegmentHeights& seg, int k, int kLast, double lowest, int cross) const {
        const Frame f{m_cls};
        const bool forward = m_cls == kXPlus || m_cls == kYPlus;
        const int u = storedAlong(f, seg.a0 + k);
        const Limits limit = limits(seg);
        const int top = std::min(int(m_squares.size()) - 1, int(std::bit_width(unsigned(k + 4))));
        for (int level = top; level >= 1; --level) {
            const int size = 1 << level;
            const int start = (u >> level) << level;
            const int count = forward ? std::min(start + size, m_nu) - u : u - start + 1;
            const int kEnd = std::min(k + count - 1, kLast);
            int b0 = seg.b0 - 2 - kEnd, b1 = seg.b0 + 1 + kEnd;
            if (!m_repeat) b0 = std::max(b0, -1), b1 = std::min(b1, cross - 1);
            if (b0 > b1) return kEnd - k + 1;
            if (below(level, u, forward, b0, b1, k, seg.b0, limit)) return kEnd - k + 1;
        }
        return 0;
    }

    // Calls test(bc) for the cells bc in [b0, b1] of column k that the bounds cannot dismiss,
    // going down the pyramid from blocks about as wide as the range; true as soon as a test
    // is. In repeat mode the range may wrap (several times for a wide wedge).
    template <class Test>
    bool anyCell(const SegmentHeights& seg, int k, int b0, int b1, double lowest,
                 Test&& test) const {
        const int u = storedAlong(Frame{m_cls}, seg.a0 + k);
        const Limits limit = limits(seg);
        auto visit = [&](auto& self, int level, int bv, int v0, int v1, int offset) -> bool {
            const int lo = std::max(v0, bv << level);
            const int hi = std::min(v1, ((bv + 1) << level) - 1);
            if (lo > hi) return false;
            const Level& l = level == 0 ? m_cells : m_columns[size_t(level)];
            const Entry& e = l.data[size_t(u) * size_t(l.nv) + size_t(bv)];
            const double centre = columnCentre(level, bv) + offset + 0.5 - seg.b0;
            if (harmless(e, k, k, centre, centre, limit)) return false;
            if (level == 0) return test(lo + offset);
            return self(self, level - 1, 2 * bv, v0, v1, offset) ||
                   self(self, level - 1, 2 * bv + 1, v0, v1, offset);
        };
        auto piece = [&](int v0, int v1, int offset) {
            const int width = v1 - v0 + 1;  // up to 4 cells (column 0): the cells themselves
            const int top = width <= 4 ? 0
                                       : std::min(int(m_columns.size()) - 1,
                                                  int(std::bit_width(unsigned(width))) - 1);
            for (int bv = v0 >> top; bv <= (v1 >> top); ++bv)
                if (visit(visit, top, bv, v0, v1, offset)) return true;
            return false;
        };
        if (!m_repeat) return piece(b0 + 1, b1 + 1, -1);
        for (int b = b0; b <= b1;) {  // one period copy at a time
            const int v = wrap(b, m_nv), end = std::min(b1, b + (m_nv - 1 - v));
            if (piece(v, v + (end - b), b - v)) return true;
            b = end + 1;
        }
        return false;
    }

private:
    struct Entry {
        float v, a, pmax, pmin;  // max V, max −pa, max −pb, min −pb
    };
    struct Level {
        int nu, nv;
        std::vector<Entry> data;
    };
    // A square block's planes taken at its centre (local column K, across offset D): each cell's
    // plane reaches the test point at most v + max(−pa)·K + max(−pb·D) (K ≥ 0), v from the cells'
    // V moved to the centre with their own slopes. Over a plane the bound is the plane; the old
    // blocks' max V over 2^L columns and rows overstated it by the slope times the block's size,
    // so far from the texel on smooth land most runs went column by column (peaks6 1024²: 30 M
    // columns of texel-classes at distance 64 or more, half the block tests).
    struct SquareEntry {
        Entry planes;  // max v at the centre, max −pa, range of −pb
        float amin;    // min −pa (a child's offset along may be negative)
    };
    struct SquareLevel {
        int nu, nv;
        std::vector<SquareEntry> data;
    };
    static constexpr int kLevels = 9;    // blocks up to 256²
    static constexpr int kMaxReads = 16;  // per level tried
    static constexpr Entry kEmpty{-kInfinity, -kInfinity, -kInfinity, kInfinity};
    static constexpr SquareEntry kEmptySquare{kEmpty, kInfinity};
    static constexpr double kUlps = 8e-15;  // relative rounding allowance of a few operations

    // anyCell's blocks: 1 × 2^L cells of one column (level 0: the cells, read from the square
    // pyramid), each cell's planes taken at the block's centre row: v = max over its cells of
    // V + (−p_b)·(centre of the cell − centre of the block), so that the across term is one
    // product at the block's centre. Built level by level, a block's v holds its children's p_b
    // ranges, not each cell's: looser by curvature × size², not by slope × size. Over a plane
    // the bound is the plane itself; the square blocks' max V + max(−p_b)·δ over the block's
    // rows overstated it by the slope times the block's size and mixed 2^L columns, so on
    // smooth hills and along coasts mostly single cells were dismissed (peaks6 512²: 25 M leaf
    // reads for 2.7 M cell tests).
    static double columnCentre(int level, int bv) {
        return double(bv << level) + 0.5 * double((1 << level) - 1);
    }
    // Level 1 from the cells, each further level from the four blocks below it, as buildColumns
    // does across, here along too: a child at local offsets (sa, sb) from its parent's centre
    // bounds its cells there by v + max(amin·sa, a·sa) + max(pmin·sb, pmax·sb). Local columns
    // run against the stored ones in the backward classes, hence the sign of sa.
    void buildSquares(const std::vector<float>& cellAmin) {
        const double sign = m_cls == kXPlus || m_cls == kYPlus ? 1.0 : -1.0;
        m_squares.clear();
        m_squares.push_back({m_nu, m_nv, {}});  // level 0: the cells (m_cells)
        while (m_squares.size() < size_t(kLevels) &&
               (m_squares.back().nu > 1 || m_squares.back().nv > 1)) {
            const size_t level = m_squares.size();
            const int fineNu = m_squares.back().nu, fineNv = m_squares.back().nv;
            SquareLevel coarse{(fineNu + 1) / 2, (fineNv + 1) / 2, {}};
            coarse.data.assign(size_t(coarse.nu) * size_t(coarse.nv), kEmptySquare);
            const double offset = level == 1 ? 0.5 : double(1 << (level - 2));
            const SquareLevel* fine = level == 1 ? nullptr : &m_squares.back();
            parallelRanges(coarse.nu, 16, [&](int64_t begin, int64_t end) {
                for (int64_t bu = begin; bu < end; ++bu)
                    for (int bv = 0; bv < coarse.nv; ++bv) {
                        SquareEntry& block =
                            coarse.data[size_t(bu) * size_t(coarse.nv) + size_t(bv)];
                        double top = -kInfinity;
                        for (int cu = 2 * int(bu); cu < std::min(2 * int(bu) + 2, fineNu); ++cu)
                            for (int cv = 2 * bv; cv < std::min(2 * bv + 2, fineNv); ++cv) {
                                const size_t at = size_t(cu) * size_t(fineNv) + size_t(cv);
                                const SquareEntry e = fine ? fine->data[at]
                                                           : SquareEntry{m_cells.data[at],
                                                                         cellAmin[at]};
                                const Entry& p = e.planes;
                                if (p.v == -kInfinity) continue;
                                const double sa = sign * (cu == 2 * bu ? -offset : offset);
                                const double sb = cv == 2 * bv ? -offset : offset;
                                // Floats times powers of two are exact; the sum is not.
                                const double along =
                                    std::max(double(e.amin) * sa, double(p.a) * sa);
                                const double across =
                                    std::max(double(p.pmin) * sb, double(p.pmax) * sb);
                                top = std::max(top, double(p.v) + along + across +
                                                        kUlps * (std::abs(double(p.v)) +
                                                                 std::abs(along) +
                                                                 std::abs(across)));
                                merge(block.planes, p);
                                block.amin = std::min(block.amin, e.amin);
                            }
                        block.planes.v = top == -kInfinity ? -kInfinity : roundUp(top);
                    }
            });
            m_squares.push_back(std::move(coarse));
        }
    }

    // Level 1 from the cells, each further level from the two blocks below it, each taken at
    // its own centre: (v, p) of a child at offset s from the parent's centre bounds its cells
    // there by v + max(p_min·s, p_max·s) (one pass over the cells in all, not one per level).
    void buildColumns() {
        m_columns.resize(m_squares.size());
        for (size_t level = 1; level < m_squares.size(); ++level) {
            const Level& fine = level == 1 ? m_cells : m_columns[level - 1];
            Level& out = m_columns[level];
            out.nu = m_nu;
            out.nv = ((m_nv - 1) >> level) + 1;
            out.data.assign(size_t(out.nu) * size_t(out.nv), kEmpty);
            // The children's centres lie ±2^(L−2) (cells: ±½) from the parent's.
            const double offset = level == 1 ? 0.5 : double(1 << (level - 2));
            parallelRanges(m_nu, 16, [&](int64_t begin, int64_t end) {
                for (int64_t u = begin; u < end; ++u)
                    for (int bv = 0; bv < out.nv; ++bv) {
                        Entry& block = out.data[size_t(u) * size_t(out.nv) + size_t(bv)];
                        double top = -kInfinity;
                        for (int child = 0; child < 2; ++child) {
                            const int cv = 2 * bv + child;
                            if (cv >= fine.nv) break;
                            const Entry& e = fine.data[size_t(u) * size_t(fine.nv) + size_t(cv)];
                            if (e.v == -kInfinity) continue;
                            const double d = child == 0 ? -offset : offset;
                            // A float times a power of two is exact; the sum is not, hence the
                            // allowance before rounding up.
                            const double across =
                                std::max(double(e.pmin) * d, double(e.pmax) * d);
                            top = std::max(top, double(e.v) + across +
                                                    kUlps * (std::abs(double(e.v)) +
                                                             std::abs(across)));
                            merge(block, e);
                        }
                        block.v = top == -kInfinity ? -kInfinity : roundUp(top);
                    }
            });
        }
    }

    static float roundUp(double v) {
        const float f = float(v);
        return double(f) < v ? std::nextafter(f, kInfinity) : f;
    }
    static int wrap(int v, int n) {
        v %= n;
        return v < 0 ? v + n : v;
    }
    static void merge(Entry& to, const Entry& from) {
        to.v = std::max(to.v, from.v);
        to.a = std::max(to.a, from.a);
        to.pmax = std::max(to.pmax, from.pmax);
        to.pmin = std::min(to.pmin, from.pmin);
    }
    // isLimiting's test points b0 − ½, b0, b0 + ½ of s_τ (plane − S is linear between them):
    // a plane at or below S + eps/2 there (rounding included: S's terms here, the plane's in
    // its V, the bound's own sums in harmless) is not above S by eps anywhere.
    struct Limits {
        double at[3];
    };
    static constexpr double kPoints[3] = {-0.5, 0.0, 0.5};
    Limits limits(const SegmentHeights& seg) const {
        const double slack = 0.5e-9 * (1.0 + std::abs(seg.mid)) - m_rounding;
        return {{seg.lo + slack, seg.mid + slack, seg.hi + slack}};
    }
    // Whether the planes of the entry's cells, for cells in columns k .. kEnd with centre
    // offsets δ in [d0, d1], stay at or below the limits at the three points.
    static bool harmless(const Entry& e, double k, double kEnd, double d0, double d1,
                         const Limits& limit) {
        if (e.v == -kInfinity) return true;
        const double base = double(e.v) + double(e.a) * double(e.a >= 0.0f ? kEnd : k);
        for (int p = 0; p < 3; ++p) {
            const double lo = d0 - kPoints[p], hi = d1 - kPoints[p];
            const double across = std::max({lo * double(e.pmin), lo * double(e.pmax),
                                            hi * double(e.pmin), hi * double(e.pmax)});
            const double rounding =
                kUlps * (std::abs(double(e.v)) + std::abs(base) + std::abs(across));
            if (base + across + rounding > limit.at[p]) return false;
        }
        return true;
    }
    int storedAlong(const Frame& f, int a) const {
        int ci, cj;
        f.worldCell(a, 0, ci, cj);
        const int along = m_cls < kYPlus ? ci : cj;
        return m_repeat ? wrap(along, m_nu) : along + 1;
    }
    // Whether the block of `level` holding stored column u (local column k; the run's columns
    // all lie in it) and the blocks across it covering cells [b0, b1] (wrapping in repeat mode)
    // are at or below `limit`, each taken at its own centre; false too when that takes more than
    // kMaxReads reads or a block's centre lies behind the texel.
    bool below(int level, int u, bool forward, int b0, int b1, int k, int texelB,
               const Limits& limit) const {
        int parts[2][3];  // stored v range and the offset to local b
        int count = 1;
        bool whole = false;
        if (m_repeat && b1 - b0 + 1 >= m_nv) {
            parts[0][0] = 0, parts[0][1] = m_nv - 1, whole = true;
        } else if (m_repeat) {
            const int span = b1 - b0, v0 = wrap(b0, m_nv);
            parts[0][0] = v0, parts[0][1] = std::min(v0 + span, m_nv - 1), parts[0][2] = b0 - v0;
            if (v0 + span >= m_nv)
                parts[1][0] = 0, parts[1][1] = v0 + span - m_nv, parts[1][2] = b0 - v0 + m_nv,
                count = 2;
        } else {
            parts[0][0] = b0 + 1, parts[0][1] = b1 + 1, parts[0][2] = -1;
        }
        const SquareLevel& l = m_squares[size_t(level)];
        const int bu = u >> level;
        const double half = 0.5 * double((1 << level) - 1);  // a block's centre from its first cell
        const double centreU = double(bu << level) + half;
        const double K = double(k) + (forward ? centreU - u : u - centreU);
        if (K < 0.0) return false;
        int reads = 0;
        for (int p = 0; p < count; ++p) reads += (parts[p][1] >> level) - (parts[p][0] >> level) + 1;
        if (reads > kMaxReads) return false;
        for (int p = 0; p < count; ++p)
            for (int bv = parts[p][0] >> level; bv <= (parts[p][1] >> level); ++bv) {
                // A wrapped whole period: a stored block stands for several offsets, whose
                // centres lie within half a block of the range's cells.
                const double centre = double(bv << level) + half + parts[p][2] + 0.5 - texelB;
                const double d0 = whole ? b0 + 0.5 - texelB - half : centre;
                const double d1 = whole ? b1 + 0.5 - texelB + half : centre;
                // K ≥ 0: max(−pa)·K bounds −pa·K over the block's range of −pa.
                if (!harmless(l.data[size_t(bu) * size_t(l.nv) + size_t(bv)].planes, K, K, d0, d1,
                              limit))
                    return false;
            }
        return true;
    }

    int m_cls;
    bool m_repeat;
    int m_nu, m_nv;
    double m_rounding = 0.0;
    Level m_cells;
    std::vector<SquareLevel> m_squares;  // square blocks (skipColumns), levels 1 and up
    std::vector<Level> m_columns;  // column blocks (anyCell), levels 1 and up
};

struct Bounds {
    const CellBounds* alongY;  // x classes
    const CellBounds* alongX;  // y classes
    const PlaneBounds* planes = nullptr;  // the texel's class; none: the reference scan
};

// Limiting for the ray set of the build: all rays, or (exterior set) exterior rays only, which
// implies limiting for all rays (the cheap test filters).
bool limitingFor(const ExteriorVisibility* exterior, const Frame& f, const SegmentHeights& seg,
                 const LocalTriangle& t, double tanPhi) {
    return isLimiting(seg, t, tanPhi) && (!exterior || exterior->limiting(f, seg, t, tanPhi));
}

int scanTexel(const Surface& s, int cls, int i, int j, double tanPhi, int maxDistance,
              const Bounds* bounds, const ExteriorVisibility* exterior, int firstColumn = 0) {
    const Frame f{cls};
    const SegmentHeights seg = segmentHeights(s, f, i, j);
    const double lowest = std::min({seg.lo, seg.mid, seg.hi});
    const int ahead = columnsAhead(s, cls, i, j);
    const bool clamp = s.edge() == EdgeMode::Clamp;
    const int cross = crossCount(s, cls);
    const CellBounds* cells = bounds ? (cls < kYPlus ? bounds->alongY : bounds->alongX) : nullptr;
    std::array<LocalTriangle, 2> tris;
    const PlaneBounds* planes = bounds ? bounds->planes : nullptr;
    const int kLast = std::min(maxDistance - 1, ahead);
    int nextTry = firstColumn;  // after a failed skip, none for a while (rough terrain)
    for (int k = firstColumn; k <= kLast; ++k) {
        if (planes && k >= nextTry) {
            if (const int skip = planes->skipColumns(seg, k, kLast, lowest, cross)) {
                k += skip - 1;
                continue;
            }
            nextTry = k + 1 + k / 4;
        }
        int b0 = seg.b0 - 2 - k, b1 = seg.b0 + 1 + k;
        if (clamp) b0 = std::max(b0, -1), b1 = std::min(b1, cross - 1);
        int line, unused;
        f.worldCell(seg.a0 + k, 0, line, unused);
        if (cls >= kYPlus) f.worldCell(seg.a0 + k, 0, unused, line);
        if (!planes && cells && cells->dismiss(line, b0, b1, k, lowest, tanPhi))
            continue;  // whole column (the plane bounds do better but keep this per cell)
        auto limitingCell = [&](int bc) {
            if (cells && cells->dismiss(line, bc, bc, k, lowest, tanPhi)) return false;
            int ci, cj;
            f.worldCell(seg.a0 + k, bc, ci, cj);
            return cellTriangles(s, f, ci, cj, tris) &&
                   (limitingFor(exterior, f, seg, tris[0], tanPhi) ||
                    limitingFor(exterior, f, seg, tris[1], tanPhi));
        };
        if (planes) {
            if (planes->anyCell(seg, k, b0, b1, lowest, limitingCell)) return k;
            continue;
        }
        for (int bc = b0; bc <= b1; ++bc)
            if (limitingCell(bc)) return k;
    }
    return maxDistance;
}


// With φ_max < 0 a triangle flatter than the steepest allowed ray holds no allowed ray, so it
// cannot be limiting. The first wedge column holding a steeper cell follows a recurrence (the
// wedge of τ beyond column 0 is the union of its three successors' wedges):
// F(τ) = 0 if column 0 of τ's wedge holds one, else 1 + min over the successors. In repeat mode
// the sweep goes round twice and the result is capped at the period (exact below it).
std::vector<uint16_t> firstSteepColumns(const Surface& s, const CellBounds& cells, int cls,
                                        double tanPhi, int cap) {
    const int w = s.width(), h = s.height();
    const bool repeat = s.edge() == EdgeMode::Repeat;
    const bool xClass = cls < kYPlus;
    const int lenA = xClass ? w : h, lenB = xClass ? h : w;
    const bool forward = cls == kXPlus || cls == kYPlus;  // local a grows with the index
    const Frame f{cls};
    std::vector<uint16_t> first(size_t(w) * size_t(h), uint16_t(cap));
    auto index = [&](int a, int b) {  // a, b: world indices along / across the class axis
        return xClass ? size_t(b) * size_t(w) + size_t(a) : size_t(a) * size_t(w) + size_t(b);
    };
    std::vector<uint8_t> steep(size_t(w) * size_t(h));
    for (int a = 0; a < lenA; ++a)
        for (int b = 0; b < lenB; ++b) {
            int a0, b0;
            f.texel(xClass ? a : b, xClass ? b : a, a0, b0);
            bool any = false;
            for (int bc = b0 - 2; bc <= b0 + 1 && !any; ++bc) {
                if (!repeat && (bc < -1 || bc > lenB - 1)) continue;
                int ci, cj;
                f.worldCell(a0, bc, ci, cj);
                if (!repeat && (ci < -1 || ci > w - 1 || cj < -1 || cj > h - 1)) continue;
                const float g = xClass ? cells.cellSlope(ci, cj) : cells.cellSlope(cj, ci);
                any = double(g) >= -tanPhi;
            }
            steep[index(a, b)] = any;
        }
    const int passes = repeat ? 2 : 1;
    for (int step = 0; step < passes * lenA; ++step) {
        const int a = forward ? lenA - 1 - step % lenA : step % lenA;
        const int next = forward ? a + 1 : a - 1;
        const bool hasNext = repeat || (next >= 0 && next < lenA);
        for (int b = 0; b < lenB; ++b) {
            int best = cap;
            if (steep[index(a, b)]) {
                best = 0;
            } else if (hasNext) {
                const int na = (next + lenA) % lenA;
                for (int db = -1; db <= 1; ++db) {
                    int nb = b + db;
                    if (repeat) nb = (nb + lenB) % lenB;
                    else if (nb < 0 || nb >= lenB) continue;
                    best = std::min(best, int(first[index(na, nb)]) + 1);
                }
            }
            first[index(a, b)] = uint16_t(std::min(best, cap));
        }
    }
    if (repeat)
        for (uint16_t& v : first) v = uint16_t(std::min<int>(v, lenA));
    return first;
}

}  // namespace

Status checkBuildOptions(const Surface& s, const BuildOptions& o) {
    if (o.exterior && s.edge() == EdgeMode::Repeat)
        return makeError(ErrorKind::Unsupported,
                         "exterior-ray safety maps need --edge clamp (a tiling relief has no "
                         "outside at its sides)");
    if (o.exteriorSlope && !o.exterior)
        return makeError(ErrorKind::BadArgument, "exterior-slope=1 needs exterior=1");
    return {};
}

int safetyDistanceDirect(const Surface& s, int cls, int i, int j, double tanPhi,
                         int maxDistance, bool exterior) {
    if (!exterior) return scanTexel(s, cls, i, j, tanPhi, maxDistance, nullptr, nullptr);
    const ExteriorVisibility visibility(s);
    return scanTexel(s, cls, i, j, tanPhi, maxDistance, nullptr, &visibility);
}

namespace {

// planes: prune with PlaneBounds (the builder), else the reference scan; same maps.
DistanceMap buildDistances(const Surface& s, const BuildOptions& options, bool planes) {
    const int w = s.width(), h = s.height();
    const double tanPhi = tanPhiMax(options.phiMaxDeg);
    int maxDistance = std::clamp(options.maxDistance, 1, 65535);
    if (s.edge() == EdgeMode::Repeat) maxDistance = std::min(maxDistance, std::max(w, h));
    const CellBounds alongY(s, true), alongX(s, false);
    std::unique_ptr<const ExteriorVisibility> exterior;
    if (options.exterior) exterior = std::make_unique<const ExteriorVisibility>(s);
    DistanceMap map{w, h, kClassCount, {}};
    map.r.resize(size_t(kClassCount) * size_t(w) * size_t(h));
    std::vector<uint16_t> firstColumns[kClassCount];
    if (tanPhi < 0.0)
        for (int c = 0; c < kClassCount; ++c)
            firstColumns[c] = firstSteepColumns(s, c < kYPlus ? alongY : alongX, c, tanPhi,
                                                maxDistance);
    for (int cls = 0; cls < kClassCount; ++cls) {  // one class's plane bounds at a time (memory)
        std::unique_ptr<const PlaneBounds> classPlanes;
        if (planes) classPlanes = std::make_unique<const PlaneBounds>(s, cls);
        const Bounds bounds{&alongY, &alongX, classPlanes.get()};
        parallelRanges(h, 1, [&](int64_t begin, int64_t end) {
            for (int64_t j = begin; j < end; ++j) {
                uint16_t* out = &map.r[(size_t(cls) * size_t(h) + size_t(j)) * size_t(w)];
                const uint16_t* start = firstColumns[cls].empty()
                                            ? nullptr
                                            : &firstColumns[cls][size_t(j) * size_t(w)];
                for (int i = 0; i < w; ++i)
                    out[i] = uint16_t(scanTexel(s, cls, i, int(j), tanPhi, maxDistance, &bounds,
                                                exterior.get(), start ? start[i] : 0));
            }
        });
    }
    if (!options.isotropic) return map;
    return isotropicMinimum(map);
}

}  // namespace

DistanceMap isotropicMinimum(const DistanceMap& directional) {
    const int w = directional.width, h = directional.height;
    DistanceMap iso{w, h, 1, std::vector<uint16_t>(size_t(w) * size_t(h))};
    for (size_t k = 0; k < iso.r.size(); ++k) {
        uint16_t r = directional.r[k];
        for (int c = 1; c < directional.classes; ++c) r = std::min(r, directional.r[size_t(c) * iso.r.size() + k]);
        iso.r[k] = r;
    }
    return iso;
}

DistanceMap buildDistanceMap(const Surface& s, const BuildOptions& options) {
    return buildDistances(s, options, true);
}

DistanceMap buildDistanceMapReference(const Surface& s, const BuildOptions& options) {
    return buildDistances(s, options, false);
}

// ---- Cylinder-cone ----

namespace {

// The modified N-buffer of §6.3.2 along one axis: level l holds, for every sample, the maximum
// of the 2^l samples starting there across the class axis (wrapping in repeat mode). Only the
// even levels from 2 up are stored (16 instead of 40 bytes per texel), so a window is the max of
// two to four lookups (more only beyond the top level): the scans' windows span 2x + 5 rows, at
// least x + 3 ≥ 3 once clipped to the map, and the few under 4 rows are read from the samples.
class WindowMax {
public:
    static constexpr int kTopLevel = 9;
    static constexpr int kFirstLevel = 2;

    // alongY: windows run along Y inside one column X (the x classes); else along X.
    WindowMax(const Surface& s, bool alongY) : m_surface(s), m_alongY(alongY) {
        m_repeat = s.edge() == EdgeMode::Repeat;
        m_lines = alongY ? s.width() : s.height();
        m_length = alongY ? s.height() : s.width();
        m_levels = std::min(kTopLevel, int(std::bit_width(unsigned(m_length))) - 1) + 1;
        // A scan reads one sample per line, a line apart: lines a power of two of bytes apart
        // (1024² and every 2^n map) all fall in the same few cache sets and evict each other, so
        // each line starts on its own cache line plus one more (a sixteenth of a line at 256).
        m_stride = ((m_length + 15) / 16 + 1) * 16;
        m_data.resize(size_t(m_levels));
        m_lineMax.assign(size_t(m_lines), 0.0f);
        for (int line = 0; line < m_lines; ++line)
            for (int p = 0; p < m_length; ++p)
                m_lineMax[size_t(line)] = std::max(m_lineMax[size_t(line)], sample(line, p));
        for (int l = kFirstLevel; l < m_levels; l += 2) {
            m_data[size_t(l)].resize(size_t(m_lines) * m_stride);
            const int quarter = 1 << (l - 2);  // four entries of level l − 2 (or samples) make one
            parallelRanges(m_lines, 16, [&](int64_t begin, int64_t end) {
                for (int64_t line = begin; line < end; ++line) {
                    float* cur = &m_data[size_t(l)][size_t(line) * m_stride];
                    const float* prev = l == kFirstLevel
                                            ? nullptr
                                            : &m_data[size_t(l - 2)][size_t(line) * m_stride];
                    for (int p = 0; p < m_length; ++p) {
                        float z = -kInfinity;
                        for (int d = 0; d < 4; ++d) {
                            const int q = next(p, d * quarter);
                            z = std::max(z, prev ? prev[q] : sample(int(line), q));
                        }
                        cur[p] = z;
                    }
                }
            });
        }
    }

    // Max of samples [start, start + count) across the axis in `line` (clamped or wrapped).
    float query(int line, int start, int count) const {
        line = m_repeat ? wrap(line, m_lines) : std::clamp(line, 0, m_lines - 1);
        if (m_repeat) {
            if (count >= m_length) return m_lineMax[size_t(line)];
            start = wrap(start, m_length);
        } else {
            const int end = std::min(start + count, m_length);
            start = std::max(start, 0);
            count = end - start;
            if (count <= 0) return -kInfinity;
        }
        if (count < (1 << kFirstLevel)) {
            float best = -kInfinity;
            for (int p = start; p < start + count; ++p)
                best = std::max(best, sample(line, m_repeat ? p % m_length : p));
            return best;
        }
        int level = std::min(m_levels - 1, int(std::bit_width(unsigned(count))) - 1);
        level -= level % 2;  // the stored level below
        const int span = 1 << level;
        const float* row = &m_data[size_t(level)][size_t(line) * m_stride];
        float best = -kInfinity;
        for (int p = start;; p += span) {  // at most four whenever count < 2^(top+1)
            const int last = start + count - span;
            const int q = std::min(p, last);
            best = std::max(best, row[m_repeat ? q % m_length : q]);
            if (q == last) break;
        }
        return best;
    }

    // The slope scan's windows of n consecutive abscissas x0 .. x0 + n − 1 (n ≤ kRun): out[k] =
    // query(line0 + step·x, centre − x − 2, 2x + 5), x = x0 + k. A scan reads one window per
    // line, each a cache line of its own, and query's branches (how many lookups, where the last
    // one lies) mispredict, so its loads went one after another (28 % of the scan's profile was
    // that wait). Here a clamp-mode window of at most four spans takes exactly four lookups, the
    // surplus ones repeating the last, without a branch, so that a run's loads overlap. The
    // maxima are taken in query's order, so the results are the same bits (signed zeros too).
    static constexpr int kRun = 8;
    void queryRun(int line0, int step, int centre, int x0, int n, float* out) const {
        for (int k = 0; k < n; ++k) {
            const int x = x0 + k;
            const int line = line0 + step * x;
            int start = centre - x - 2;
            const int end = std::min(start + 2 * x + 5, m_length);
            start = std::max(start, 0);
            const int count = end - start;
            const int level = (int(std::bit_width(unsigned(std::max(count, 1)))) - 1) & ~1;
            if (m_repeat || count < (1 << kFirstLevel) || level >= m_levels ||
                line < 0 || line >= m_lines) {
                out[k] = query(line, centre - x - 2, 2 * x + 5);
                continue;
            }
            const int span = 1 << level, last = end - span;
            const float* row = &m_data[size_t(level)][size_t(line) * m_stride];
            float best = row[start];  // = max(−∞, row[start]): heights are finite
            best = std::max(best, row[std::min(start + span, last)]);
            best = std::max(best, row[std::min(start + 2 * span, last)]);
            best = std::max(best, row[std::min(start + 3 * span, last)]);
            out[k] = best;
        }
    }

private:
    static int wrap(int v, int n) {
        v %= n;
        return v < 0 ? v + n : v;
    }
    float sample(int line, int p) const {
        return m_alongY ? m_surface.sampleZ(line, p) : m_surface.sampleZ(p, line);
    }
    // Sample p + d, wrapped or held at the last one.
    int next(int p, int d) const { return m_repeat ? (p + d) % m_length : std::min(p + d, m_length - 1); }

    const Surface& m_surface;
    bool m_alongY, m_repeat;
    int m_lines, m_length, m_levels;
    size_t m_stride;  // floats from one line's entries to the next's
    std::vector<std::vector<float>> m_data;
    std::vector<float> m_lineMax;
};

// A max pyramid of the samples over aligned 2^L × 2^L blocks (world axes, shared by the four
// classes): bounds hbar over a run of slope-scan columns at once, so the scan skips the runs
// that cannot raise the slope (flat sea) instead of reading each column's window.
class SampleMax {
public:
    explicit SampleMax(const Surface& s) {
        m_repeat = s.edge() == EdgeMode::Repeat;
        // Level 0 (the samples) keeps only its size: the scan bounds runs by level 1 and up.
        m_levels.push_back({s.width(), s.height(), {}});
        while (m_levels.size() < size_t(kLevels) && (m_levels.back().w > 1 || m_levels.back().h > 1)) {
            const Level& fine = m_levels.back();
            const bool base = m_levels.size() == 1;
            Level coarse{(fine.w + 1) / 2, (fine.h + 1) / 2, {}};
            coarse.data.assign(size_t(coarse.w) * size_t(coarse.h), -kInfinity);
            for (int y = 0; y < fine.h; ++y)
                for (int x = 0; x < fine.w; ++x) {
                    float& to = coarse.data[size_t(y / 2) * size_t(coarse.w) + size_t(x / 2)];
                    to = std::max(to, base ? s.sampleZ(x, y)
                                           : fine.data[size_t(y) * size_t(fine.w) + size_t(x)]);
                }
            m_levels.push_back(std::move(coarse));
        }
    }

    int levels() const { return int(m_levels.size()); }

    // An upper bound on the samples the window lookups of lines [l0, l1] (world index along
    // the class axis, clamped or wrapped as WindowMax does) and cross samples [c0, c1] read;
    // false when level `level` needs more than kMaxReads reads (or is level 0).
    bool bound(bool xClass, int level, int l0, int l1, int c0, int c1, float& out) const {
        const Level& base = m_levels[0];
        const int lines = xClass ? base.w : base.h, length = xClass ? base.h : base.w;
        int ranges[2][2][2];  // [axis: lines, cross][part][lo/hi]
        int parts[2];
        split(l0, l1, lines, ranges[0], parts[0]);
        split(c0, c1, length, ranges[1], parts[1]);
        if (parts[1] == 0 || parts[0] == 0) return out = -kInfinity, true;
        int reads = 0;
        for (int a = 0; a < parts[0]; ++a)
            for (int b = 0; b < parts[1]; ++b)
                reads += ((ranges[0][a][1] >> level) - (ranges[0][a][0] >> level) + 1) *
                         ((ranges[1][b][1] >> level) - (ranges[1][b][0] >> level) + 1);
        if (reads > kMaxReads) return false;
        if (level < 1) return false;  // not stored
        const Level& l = m_levels[size_t(level)];
        float best = -kInfinity;
        for (int a = 0; a < parts[0]; ++a)
            for (int b = 0; b < parts[1]; ++b)
                for (int p = ranges[0][a][0] >> level; p <= ranges[0][a][1] >> level; ++p)
                    for (int q = ranges[1][b][0] >> level; q <= ranges[1][b][1] >> level; ++q) {
                        const int x = xClass ? p : q, y = xClass ? q : p;
                        best = std::max(best, l.data[size_t(y) * size_t(l.w) + size_t(x)]);
                    }
        out = best;
        return true;
    }

private:
    struct Level {
        int w, h;
        std::vector<float> data;
    };
    static constexpr int kLevels = 9;
    static constexpr int kMaxReads = 16;

    // [lo, hi] as stored ranges: clamped (clamp mode) or wrapped into at most two parts.
    void split(int lo, int hi, int n, int (&out)[2][2], int& parts) const {
        parts = 1;
        if (!m_repeat) {
            lo = std::clamp(lo, 0, n - 1), hi = std::clamp(hi, 0, n - 1);
            out[0][0] = lo, out[0][1] = hi;
            if (lo > hi) parts = 0;
            return;
        }
        if (hi - lo + 1 >= n) {
            out[0][0] = 0, out[0][1] = n - 1;
            return;
        }
        const int span = hi - lo, v = ((lo % n) + n) % n;
        out[0][0] = v, out[0][1] = std::min(v + span, n - 1);
        if (v + span >= n) out[1][0] = 0, out[1][1] = v + span - n, parts = 2;
    }

    bool m_repeat;
    std::vector<Level> m_levels;
};

// The line (world column for x classes, row for y classes) holding local abscissa a.
int lineOf(const Frame& f, int a) {
    double X, Y;
    f.world(a, 0, X, Y);
    return f.cls < kYPlus ? int(X) : int(Y);
}

// cone_ext: the lowest slope putting every vertex of an exterior-limiting triangle of columns
// r .. xEnd under the plane (abscissas r < x ≤ xEnd), starting from `slope`. Columns whose highest
// vertices (the N-buffer's hbar) cannot raise the slope are skipped, and the scan stops once
// no later vertex can; the exterior test runs only on triangles that would raise it.
template <class Hbar>
float exteriorConeSlope(const Surface& s, const ExteriorVisibility& visibility, int cls, int i,
                        int j, int r, float zc, int xEnd, float slope, double tanPhi,
                        Hbar hbar) {
    const Frame f{cls};
    const SegmentHeights seg = segmentHeights(s, f, i, j);
    const int cross = crossCount(s, cls);
    const float maxZ = s.maxZ();
    auto raises = [&](int x, double z) {
        return x > r && x <= xEnd && (float(z) - zc) / float(x - r) > slope;
    };
    std::array<LocalTriangle, 2> tris;
    for (int k = r; k <= xEnd; ++k) {
        if (slope >= 0.0f && float(k + 1 - r) * slope >= maxZ - zc) break;  // nothing later
        if (!raises(k, hbar(k)) && !raises(k + 1, hbar(k + 1))) continue;
        const int b0 = std::max(seg.b0 - 2 - k, -1), b1 = std::min(seg.b0 + 1 + k, cross - 1);
        for (int bc = b0; bc <= b1; ++bc) {
            int ci, cj;
            f.worldCell(seg.a0 + k, bc, ci, cj);
            if (!cellTriangles(s, f, ci, cj, tris)) continue;
            for (const LocalTriangle& t : tris) {
                auto column = [&](int v) { return int(std::lround(t.a[v])) - seg.a0; };
                bool any = false;
                for (int v = 0; v < 3; ++v) any = any || raises(column(v), t.z[v]);
                if (!any || !isLimiting(seg, t, tanPhi) || !visibility.limiting(f, seg, t, tanPhi))
                    continue;
                for (int v = 0; v < 3; ++v)
                    if (raises(column(v), t.z[v]))
                        slope = (float(t.z[v]) - zc) / float(column(v) - r);
            }
        }
    }
    return slope;
}

// Vertices that rays from s_τ can reach at local abscissa a0 + x lie in rows b0 ± (x + 2).
ConeTexel coneTexel(const Surface& s, const WindowMax& windows, const SampleMax* peaks, int cls,
                    int i, int j, int r, const ExteriorVisibility* exteriorSlope, double tanPhi) {
    const Frame f{cls};
    int a0, b0;
    f.texel(i, j, a0, b0);
    const bool forward = cls == kXPlus || cls == kYPlus;
    const int line0 = lineOf(f, a0), step = forward ? 1 : -1;  // line of a0 + x: line0 + step·x
    auto hbar = [&](int x) { return windows.query(line0 + step * x, b0 - x - 2, 2 * x + 5); };
    const float maxZ = s.maxZ();
    ConeTexel c;
    c.r = r;
    c.zc = std::max(hbar(r), hbar(r + 1));
    const bool repeat = s.edge() == EdgeMode::Repeat;
    const int ahead = columnsAhead(s, cls, i, j);
    int xEnd = repeat ? r + kConeScan : ahead + 1;
    float slope = -kInfinity;
    if (xEnd > r + kConeScan) {  // beyond the scan the plane must clear the highest sample
        xEnd = r + kConeScan;
        slope = (maxZ - c.zc) / float(kConeScan + 1);
    }
    if (exteriorSlope) {
        slope = exteriorConeSlope(s, *exteriorSlope, cls, i, j, r, c.zc, xEnd, slope, tanPhi,
                                  hbar);
        c.slope = slope == -kInfinity ? 0.0f : slope;
        return c;
    }
    int nextTry = r + 1;  // after a failed skip, none until past its run (rough terrain)
    float run[WindowMax::kRun];
    int runFrom = -WindowMax::kRun;  // run[k]: hbar(runFrom + k), while runFrom ≤ x < runFrom + kRun
    for (int x = r + 1; x <= xEnd; ++x) {
        if (slope >= 0.0f && float(x - r) * slope >= maxZ - c.zc) break;  // nothing can raise it
        if (peaks && slope > -kInfinity && x >= nextTry) {
            // Skip the run x .. x2 when no sample its windows read can raise the slope (the
            // quotient is monotone in the sample, so the result is the scan's own).
            const int line = line0 + step * x;
            const int top = std::min(peaks->levels() - 1, int(std::bit_width(unsigned(x + 4))));
            int skipTo = 0;
            // Three block sizes, the largest first: on smooth hills a run the two largest cannot
            // prove (the peak that set the slope lies in them) a smaller one often can; peaks6
            // 1024² reads a fifth fewer windows, 4 % less time (fbm and a sea crop: the same).
            for (int level = top; level >= std::max(1, top - 2) && !skipTo; --level) {
                const int start = (line >> level) << level;
                const int count = forward ? start + (1 << level) - line : line - start + 1;
                const int x2 = std::min(x + count - 1, xEnd);
                const int last = line0 + step * x2;
                float high;
                if (!peaks->bound(cls < kYPlus, level, std::min(line, last), std::max(line, last),
                                  b0 - x2 - 2, b0 + x2 + 2, high))
                    continue;
                const float rise = high - c.zc;
                if ((rise >= 0.0f ? rise / float(x - r) : rise / float(x2 - r)) <= slope)
                    skipTo = x2;
            }
            if (skipTo) {
                x = skipTo;
                continue;
            }
            // The next try 2·(x − r) later (distances from r grow threefold): a failed try
            // costs three bounds of up to 16 reads, and on rising flanks they fail in a row.
            // Against (x − r)/2: safety-cc 1024² on 2 threads fbm 0.93×, peaks6 0.98×, the sea
            // crop 0.96× (paired runs).
            nextTry = x + 2 * (x - r);
        }
        if (x >= runFrom + WindowMax::kRun) {  // the next run of windows, read together
            runFrom = x;
            windows.queryRun(line0, step, b0, x, std::min(WindowMax::kRun, xEnd + 1 - x), run);
        }
        // The division only where its quotient could exceed the slope: a rise below
        // slope·(x − r) by more than 2^-22 of it gives a quotient below the slope even after
        // rounding (≤ 2^-24), and max would keep the slope, so the result is the same.
        const float rise = run[x - runFrom] - c.zc;
        const double reach = double(slope) * double(x - r);
        if (slope == -kInfinity || double(rise) >= reach - std::abs(reach) * 0x1p-22)
            slope = std::max(slope, rise / float(x - r));
    }
    if (slope == -kInfinity) slope = 0.0f;
    c.slope = slope;
    return c;
}

// Round the plane up a hair so float evaluation in the tracer never dips below a vertex.
void finishTexel(ConeTexel& c, float maxZ) {
    c.zc += 1e-6f * (1.0f + maxZ);
    c.slope += 1e-6f * (1.0f + std::abs(c.slope));
    c.z0 = c.zc - float(c.r) * c.slope;
}

}  // namespace

float coneSlopeDirect(const Surface& s, int cls, int i, int j, int r, float zc, double tanPhi,
                      bool limitingOnly) {
    const Frame f{cls};
    const SegmentHeights seg = segmentHeights(s, f, i, j);
    const bool repeat = s.edge() == EdgeMode::Repeat;
    const int ahead = columnsAhead(s, cls, i, j);
    const int cross = crossCount(s, cls);
    int xEnd = repeat ? r + kConeScan : ahead + 1;
    float slope = -kInfinity;
    if (xEnd > r + kConeScan) {
        xEnd = r + kConeScan;
        slope = (s.maxZ() - zc) / float(kConeScan + 1);
    }
    std::array<LocalTriangle, 2> tris;
    auto bound = [&](double a, double z) {
        const int x = int(std::lround(a)) - seg.a0;
        if (x > r && x <= xEnd) slope = std::max(slope, (float(z) - zc) / float(x - r));
    };
    // Every triangle of columns r .. xEnd in the wedge (vertex rows b0 ± (x + 2)).
    for (int k = r; k <= xEnd; ++k) {
        int b0 = seg.b0 - 2 - k, b1 = seg.b0 + 1 + k;
        if (!repeat) b0 = std::max(b0, -1), b1 = std::min(b1, cross - 1);
        for (int bc = b0; bc <= b1; ++bc) {
            int ci, cj;
            f.worldCell(seg.a0 + k, bc, ci, cj);
            if (!cellTriangles(s, f, ci, cj, tris)) continue;
            for (const LocalTriangle& t : tris) {
                if (limitingOnly && !isLimiting(seg, t, tanPhi)) continue;
                for (int v = 0; v < 3; ++v) bound(t.a[v], t.z[v]);
            }
        }
    }
    return slope == -kInfinity ? 0.0f : slope;
}

namespace {

// Where buildCones puts the texels: the map, or the on-disk arrays (r, zc, slope per class)
// that coneMapToArrays would make of it, so a bake never holds both.
struct MapStore {
    CylinderConeMap& map;
    size_t plane;
    ConeTexel get(int slot, size_t k) const { return map.texels[size_t(slot) * plane + k]; }
    void set(int slot, size_t k, const ConeTexel& t) { map.texels[size_t(slot) * plane + k] = t; }
};
struct ArrayStore {
    std::vector<MapArray>& arrays;
    ConeTexel get(int slot, size_t k) const {
        const float* a = &arrays[size_t(slot)].data[3 * k];
        return {0.0f, a[2], int32_t(a[0]), a[1]};
    }
    void set(int slot, size_t k, const ConeTexel& t) {
        float* a = &arrays[size_t(slot)].data[3 * k];
        a[0] = float(t.r), a[1] = t.zc, a[2] = t.slope;
    }
};

// pruned: skip slope-scan runs by SampleMax (the builder), else the reference scan; same maps.
// The texels are written in place (the isotropic map takes the classes' maxima as they come),
// so the build holds the output plus one N-buffer orientation and the pyramids.
template <class Store>
void buildCones(const Surface& s, const DistanceMap& radii, const BuildOptions& options,
                bool pruned, int classes, Store& store) {
    const int w = s.width(), h = s.height();
    const size_t plane = size_t(w) * size_t(h);
    const double tanPhi = tanPhiMax(options.phiMaxDeg);
    std::unique_ptr<const ExteriorVisibility> exterior;
    if (options.exterior && options.exteriorSlope)
        exterior = std::make_unique<const ExteriorVisibility>(s);
    std::unique_ptr<const SampleMax> peaks;
    if (pruned) peaks = std::make_unique<const SampleMax>(s);
    // All four classes are needed even for the isotropic map (its plane bounds all of them).
    for (int axis = 0; axis < 2; ++axis) {  // one N-buffer orientation at a time (memory)
        const WindowMax windows(s, axis == 0);
        parallelRanges(h, 1, [&](int64_t begin, int64_t end) {
            for (int64_t j = begin; j < end; ++j)
                for (int cls = 2 * axis; cls < 2 * axis + 2; ++cls)
                    for (int i = 0; i < w; ++i) {
                        const ConeTexel t = coneTexel(s, windows, peaks.get(), cls, i, int(j),
                                                      radii.at(cls, i, int(j)), exterior.get(),
                                                      tanPhi);
                        const size_t k = size_t(j) * size_t(w) + size_t(i);
                        if (classes == kClassCount) {
                            store.set(cls, k, t);
                        } else if (cls == 0) {
                            store.set(0, k, t);  // same r (isotropic) in every class
                        } else {
                            ConeTexel o = store.get(0, k);
                            o.zc = std::max(o.zc, t.zc);
                            o.slope = std::max(o.slope, t.slope);
                            store.set(0, k, o);
                        }
                    }
        });
    }
    const float maxZ = s.maxZ();
    parallelRanges(int64_t(size_t(classes) * plane), 4096, [&](int64_t begin, int64_t end) {
        for (int64_t n = begin; n < end; ++n) {
            const int slot = int(size_t(n) / plane);
            const size_t k = size_t(n) % plane;
            ConeTexel t = store.get(slot, k);
            finishTexel(t, maxZ);
            store.set(slot, k, t);
        }
    });
}

CylinderConeMap buildConeMapWith(const Surface& s, const DistanceMap& radii,
                                 const BuildOptions& options, bool pruned) {
    const size_t plane = size_t(s.width()) * size_t(s.height());
    const int classes = options.isotropic ? 1 : kClassCount;
    CylinderConeMap map{s.width(), s.height(), classes,
                        std::vector<ConeTexel>(size_t(classes) * plane)};
    MapStore store{map, plane};
    buildCones(s, radii, options, pruned, classes, store);
    return map;
}

std::map<std::string, std::string> parameterText(const BuildOptions& o);
std::string coneArrayName(int cls, int classes);

}  // namespace

CylinderConeMap buildConeMap(const Surface& s, const DistanceMap& radii,
                             const BuildOptions& options) {
    return buildConeMapWith(s, radii, options, true);
}

CylinderConeMap buildConeMapReference(const Surface& s, const DistanceMap& radii,
                                      const BuildOptions& options) {
    return buildConeMapWith(s, radii, options, false);
}

TechniqueMaps buildConeArrays(const std::string& technique, const Surface& s,
                              const DistanceMap& radii, const BuildOptions& options) {
    const int classes = options.isotropic ? 1 : kClassCount;
    TechniqueMaps out{technique, parameterText(options), {}};
    for (int c = 0; c < classes; ++c)
        out.arrays.push_back({coneArrayName(c, classes), s.width(), s.height(), 3,
                              std::vector<float>(size_t(s.width()) * size_t(s.height()) * 3)});
    ArrayStore store{out.arrays};
    buildCones(s, radii, options, true, classes, store);
    return out;
}

// ---- On disk ----

namespace {

std::map<std::string, std::string> parameterText(const BuildOptions& o) {
    return {{"phi-max", fmt::format("{}", o.phiMaxDeg)},
            {"isotropic", o.isotropic ? "1" : "0"},
            {"max-distance", fmt::format("{}", o.maxDistance)},
            {"exterior", o.exterior ? "1" : "0"},
            {"exterior-slope", o.exteriorSlope ? "1" : "0"}};
}

Result<double> parameterNumber(const TechniqueMaps& maps, const std::string& name) {
    auto it = maps.parameters.find(name);
    if (it == maps.parameters.end())
        return makeError(ErrorKind::InvalidInput, "{} maps: parameter '{}' missing",
                         maps.technique, name);
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (!end || *end != '\0' || !std::isfinite(v))
        return makeError(ErrorKind::InvalidInput, "{} maps: parameter '{}' = '{}' is not a number",
                         maps.technique, name, it->second);
    return v;
}

Status checkArray(const TechniqueMaps& maps, const MapArray* a, const std::string& name,
                  int width, int height, int channels) {
    if (!a)
        return makeError(ErrorKind::InvalidInput, "{} maps: array '{}' missing", maps.technique,
                         name);
    if (a->width != width || a->height != height || a->channels != channels ||
        a->data.size() != size_t(width) * size_t(height) * size_t(channels))
        return makeError(ErrorKind::InvalidInput,
                         "{} maps: array '{}' is {}x{}x{}, expected {}x{}x{}", maps.technique,
                         name, a->width, a->height, a->channels, width, height, channels);
    return {};
}

std::string coneArrayName(int cls, int classes) {
    return classes == 1 ? std::string("cc") : std::string("cc") + kClassNames[cls];
}

}  // namespace

Result<BuildOptions> optionsFromArrays(const TechniqueMaps& maps) {
    BuildOptions o;
    auto phi = parameterNumber(maps, "phi-max");
    if (!phi) return phi.error();
    auto iso = parameterNumber(maps, "isotropic");
    if (!iso) return iso.error();
    auto dist = parameterNumber(maps, "max-distance");
    if (!dist) return dist.error();
    if (*phi < -89.0 || *phi > 90.0 || (*iso != 0.0 && *iso != 1.0) || *dist < 1 || *dist > 65535)
        return makeError(ErrorKind::InvalidInput, "{} maps: parameters out of range",
                         maps.technique);
    o.phiMaxDeg = *phi;
    o.isotropic = *iso != 0.0;
    o.maxDistance = int(*dist);
    // Maps baked before exterior rays existed are all-ray maps.
    for (auto [name, flag] : {std::pair{"exterior", &o.exterior},
                              std::pair{"exterior-slope", &o.exteriorSlope}}) {
        if (!maps.parameters.count(name)) continue;
        auto v = parameterNumber(maps, name);
        if (!v) return v.error();
        if (*v != 0.0 && *v != 1.0)
            return makeError(ErrorKind::InvalidInput, "{} maps: parameter '{}' out of range",
                             maps.technique, name);
        *flag = *v != 0.0;
    }
    return o;
}

TechniqueMaps distanceMapToArrays(const std::string& technique, const DistanceMap& map,
                                  const BuildOptions& options) {
    TechniqueMaps out{technique, parameterText(options), {}};
    MapArray a{"sd", map.width, map.height, map.classes, {}};
    a.data.resize(size_t(map.width) * size_t(map.height) * size_t(map.classes));
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i)
            for (int c = 0; c < map.classes; ++c)
                a.data[(size_t(j) * size_t(map.width) + size_t(i)) * size_t(map.classes) +
                       size_t(c)] = float(map.at(c, i, j));
    out.arrays.push_back(std::move(a));
    return out;
}

Result<DistanceMap> distanceMapFromArrays(const TechniqueMaps& maps, int width, int height) {
    auto options = optionsFromArrays(maps);
    if (!options) return options.error();
    const int classes = options->isotropic ? 1 : kClassCount;
    const MapArray* a = maps.find("sd");
    if (Status s = checkArray(maps, a, "sd", width, height, classes); !s) return s.error();
    DistanceMap map{width, height, classes, {}};
    map.r.resize(a->data.size());
    const size_t plane = size_t(width) * size_t(height);
    for (size_t p = 0; p < plane; ++p)
        for (int c = 0; c < classes; ++c) {
            const float v = a->data[p * size_t(classes) + size_t(c)];
            if (!(v >= 0.0f && v <= 65535.0f && v == std::floor(v)))
                return makeError(ErrorKind::InvalidInput, "{} maps: bad safety distance {}",
                                 maps.technique, v);
            map.r[size_t(c) * plane + p] = uint16_t(v);
        }
    return map;
}

TechniqueMaps coneMapToArrays(const std::string& technique, const CylinderConeMap& map,
                              const BuildOptions& options) {
    TechniqueMaps out{technique, parameterText(options), {}};
    for (int c = 0; c < map.classes; ++c) {
        MapArray a{coneArrayName(c, map.classes), map.width, map.height, 3, {}};
        a.data.reserve(size_t(map.width) * size_t(map.height) * 3);
        for (int j = 0; j < map.height; ++j)
            for (int i = 0; i < map.width; ++i) {
                const ConeTexel& t = map.at(c, i, j);
                a.data.insert(a.data.end(), {float(t.r), t.zc, t.slope});
            }
        out.arrays.push_back(std::move(a));
    }
    return out;
}

Result<CylinderConeMap> coneMapFromArrays(const TechniqueMaps& maps, int width, int height) {
    auto options = optionsFromArrays(maps);
    if (!options) return options.error();
    const int classes = options->isotropic ? 1 : kClassCount;
    const size_t plane = size_t(width) * size_t(height);
    CylinderConeMap map{width, height, classes, std::vector<ConeTexel>(size_t(classes) * plane)};
    for (int c = 0; c < classes; ++c) {
        const std::string name = coneArrayName(c, classes);
        const MapArray* a = maps.find(name);
        if (Status s = checkArray(maps, a, name, width, height, 3); !s) return s.error();
        for (size_t p = 0; p < plane; ++p) {
            const float r = a->data[3 * p], zc = a->data[3 * p + 1], slope = a->data[3 * p + 2];
            if (!(r >= 0.0f && r <= 65535.0f && r == std::floor(r)) || !std::isfinite(zc) ||
                !std::isfinite(slope))
                return makeError(ErrorKind::InvalidInput, "{} maps: bad texel in '{}'",
                                 maps.technique, name);
            ConeTexel& t = map.texels[size_t(c) * plane + p];
            t.r = int32_t(r);
            t.zc = zc;
            t.slope = slope;
            t.z0 = zc - r * slope;
        }
    }
    return map;
}

std::vector<std::pair<std::string, double>> mapSummary(const TechniqueMaps& maps) {
    if (maps.arrays.empty()) return {};
    const int width = maps.arrays.front().width, height = maps.arrays.front().height;
    double sum = 0;
    size_t count = 0;
    if (auto sd = distanceMapFromArrays(maps, width, height)) {
        for (uint16_t r : sd->r) sum += r;
        count = sd->r.size();
    } else if (auto cc = coneMapFromArrays(maps, width, height)) {
        for (const ConeTexel& t : cc->texels) sum += t.r;
        count = cc->texels.size();
    }
    if (count == 0) return {};
    return {{"mean_r", sum / double(count)}};
}

}  // namespace relief::safety
