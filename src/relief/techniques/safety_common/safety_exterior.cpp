#include <relief/techniques/safety_common/safety_exterior.h>

#include <algorithm>
#include <cmath>

namespace relief::safety {

namespace {

// The line through primal points u and v (oriented +a).
PrimalLine lineThrough(const PlanePoint& u, const PlanePoint& v) {
    const double l1 = u.b * v.w - u.w * v.b;
    const double l2 = u.w * v.a - u.a * v.w;
    const double l3 = u.a * v.b - u.b * v.a;
    return {l1, l2, l3, std::abs(l1) + std::abs(l2) + std::abs(l3)};
}

// Vertex k of a polygon: the line through the points of edges k and k + 1 (cached).
const PrimalLine& vertexLine(const LinePolygon& lines, size_t k) { return lines[k].toNext; }

void cacheVertices(LinePolygon& lines) {
    for (size_t k = 0; k < lines.size(); ++k)
        lines[k].toNext = lineThrough(lines[k].point, lines[(k + 1) % lines.size()].point);
}

// Where point p lies relative to line l: +1 above, −1 below, 0 on it, within rounding, or when
// l is not a line of the class (then every half-plane keeps the vertex: conservative).
int sideOf(const PlanePoint& p, const PrimalLine& l) {
    const double value = l.l1 * p.a + l.l2 * p.b + l.l3 * p.w;
    const double scale = l.norm * (std::abs(p.a) + std::abs(p.b) + std::abs(p.w));
    if (l.l2 == 0.0 || std::abs(value) <= 1e-12 * scale) return 0;
    return (value > 0.0) == (l.l2 > 0.0) ? 1 : -1;
}


// Does the blocker leave the piece whole? True when every line of the piece (its vertices: a
// convex set of lines is the hull of them) passes strictly on the same side of both endpoints,
// all above both or all below both: then one of the two clips keeps it unchanged and the other
// leaves nothing, and no copy is made.
bool leavesWhole(const LinePolygon& piece, const BlockerSegment& blocker) {
    int common = 0;
    const size_t n = piece.size();
    for (size_t k = 0; k < n; ++k) {
        const PrimalLine& l = vertexLine(piece, k);
        const int sp = sideOf(blocker.p, l);
        if (sp == 0 || sideOf(blocker.q, l) != sp || (common != 0 && sp != common)) return false;
        common = sp;
    }
    return true;
}

// Beyond: call T limiting (conservative). Reached by 6 % of the tests on fbm 256²; a cap of 16
// halves the build time there but shortens some distances (docs/safety.md).
constexpr size_t kMaxPieces = 64;

}  // namespace

LinePolygon linesThroughSegment(double a0, double y0, double y1, double lo, double hi) {
    LinePolygon lines{
        {{a0, y0, 1.0}, -1}, {{1.0, hi, 0.0}, +1}, {{a0, y1, 1.0}, +1}, {{1.0, lo, 0.0}, -1}};
    cacheVertices(lines);
    return lines;
}

bool clipLines(LinePolygon& lines, const LineHalfPlane& h) {
    const size_t n = lines.size();
    // Vertex k is the line through the points of edges k and k + 1.
    auto inside = [&](size_t k) { return sideOf(h.point, vertexLine(lines, k)) * h.side >= 0; };
    uint64_t in = 0;
    size_t count = 0;
    for (size_t k = 0; k < n && k < 64; ++k)
        if (inside(k)) in |= uint64_t(1) << k, ++count;
    if (n > 64 || count == n) return true;  // untouched (or too big to track: keep, conservative)
    if (count == 0) {
        lines.clear();
        return false;
    }
    auto isIn = [&](size_t k) { return (in >> (k % n)) & 1; };
    size_t start = 0;
    while (!(isIn(start) && !isIn(start + n - 1))) ++start;
    size_t run = 0;
    while (isIn(start + run)) ++run;
    if (run != count) return true;  // not one run: rounding; keep everything (conservative)
    LinePolygon out;
    out.reserve(run + 2);
    for (size_t k = 0; k <= run; ++k) out.push_back(lines[(start + k) % n]);
    out.push_back(h);
    // Vertices between kept edges are kept; the two beside the new edge are new.
    out[run].toNext = lineThrough(out[run].point, h.point);
    out[run + 1].toNext = lineThrough(h.point, out[0].point);
    lines = std::move(out);
    return true;
}

void subtractBlocker(std::vector<LinePolygon>& pieces, const BlockerSegment& blocker) {
    const size_t count = pieces.size();
    for (size_t k = 0; k < count; ++k) {
        if (leavesWhole(pieces[k], blocker)) continue;
        LinePolygon below = pieces[k];  // lines passing below both endpoints
        if (!(clipLines(pieces[k], {blocker.p, +1}) && clipLines(pieces[k], {blocker.q, +1})))
            pieces[k].clear();
        if (clipLines(below, {blocker.p, -1}) && clipLines(below, {blocker.q, -1}))
            pieces.push_back(std::move(below));
    }
    std::erase_if(pieces, [](const LinePolygon& piece) { return piece.empty(); });
}

// ---- ExteriorVisibility ----

ExteriorVisibility::ExteriorVisibility(const Surface& s, bool traceWitnesses)
    : m_surface(s), m_traceWitnesses(traceWitnesses) {
    m_blocksY = (s.height() + 1 + 15) / 16;
    m_blocksX = (s.width() + 1 + 15) / 16;
    m_alongY.assign(size_t(s.width() + 1) * size_t(m_blocksY), Block{kInfinity, -kInfinity});
    m_alongX.assign(size_t(s.height() + 1) * size_t(m_blocksX), Block{kInfinity, -kInfinity});
    for (int cj = -1; cj < s.height(); ++cj)
        for (int ci = -1; ci < s.width(); ++ci) {
            const CellCorners c = s.cellCorners(ci, cj);
            const float lo = std::min({c.z00, c.z10, c.z01, c.z11});
            const float hi = std::max({c.z00, c.z10, c.z01, c.z11});
            for (Block* b : {&m_alongY[size_t(ci + 1) * size_t(m_blocksY) + size_t((cj + 1) >> 4)],
                             &m_alongX[size_t(cj + 1) * size_t(m_blocksX) + size_t((ci + 1) >> 4)]}) {
                b->lo = std::min(b->lo, lo);
                b->hi = std::max(b->hi, hi);
            }
        }
}

const ExteriorVisibility::Block& ExteriorVisibility::block(bool xClass, int line, int cell) const {
    return xClass ? m_alongY[size_t(line + 1) * size_t(m_blocksY) + size_t((cell + 1) >> 4)]
                  : m_alongX[size_t(line + 1) * size_t(m_blocksX) + size_t((cell + 1) >> 4)];
}

namespace {

double planeAt(const LocalTriangle& t, double a, double b) { return t.z0 + t.pa * a + t.pb * b; }

// Lowest and highest of T's plane over the rectangle [a0, a1] × [b0, b1].
void planeRange(const LocalTriangle& t, double a0, double a1, double b0, double b1, double& lo,
                double& hi) {
    const double za = t.pa >= 0.0 ? t.pa : -t.pa, zb = t.pb >= 0.0 ? t.pb : -t.pb;
    const double mid = planeAt(t, 0.5 * (a0 + a1), 0.5 * (b0 + b1));
    const double half = 0.5 * (za * (a1 - a0) + zb * (b1 - b0));
    lo = mid - half, hi = mid + half;
}

// The box [0, W] × [0, H] in a frame's local (a, b): border cells reach half a texel beyond it,
// and nothing outside the box blocks (DESIGN §1).
struct LocalBox {
    double a0, a1, b0, b1;
};

LocalBox localBox(const Surface& s, const Frame& f) {
    double a[2], b[2];
    f.local(-0.5, -0.5, a[0], b[0]);
    f.local(s.width() - 0.5, s.height() - 0.5, a[1], b[1]);
    return {std::min(a[0], a[1]), std::max(a[0], a[1]), std::min(b[0], b[1]), std::max(b[0], b[1])};
}

// Clips [p, q] to the box (Liang–Barsky); false when nothing is left.
bool clipToBox(const LocalBox& box, PlanePoint& p, PlanePoint& q) {
    double t0 = 0.0, t1 = 1.0;
    const double da = q.a - p.a, db = q.b - p.b;
    auto edge = [&](double num, double den) {  // keep den·t ≤ num
        if (den == 0.0) return num >= 0.0;
        const double t = num / den;
        if (den > 0.0) t1 = std::min(t1, t); else t0 = std::max(t0, t);
        return t0 <= t1;
    };
    if (!(edge(p.a - box.a0, -da) && edge(box.a1 - p.a, da) && edge(p.b - box.b0, -db) &&
          edge(box.b1 - p.b, db)))
        return false;
    const PlanePoint from = p;
    p = {from.a + t0 * da, from.b + t0 * db, 1.0};
    q = {from.a + t1 * da, from.b + t1 * db, 1.0};
    return true;
}

// Are the four corners of world cell (ci, cj) all above P_T or all below it (beyond the
// tolerance)? Then neither triangle of the cell meets P_T and addBlocker would find nothing:
// the same differences, without building the triangles.
bool cellClearOf(const Surface& s, const Frame& f, const LocalTriangle& t, int ci, int cj,
                 double tolerance) {
    const CellCorners c = s.cellCorners(ci, cj);
    const double z[4] = {c.z00, c.z10, c.z01, c.z11};
    int above = 0, below = 0;
    for (int k = 0; k < 4; ++k) {
        double a, b;
        f.local(double(ci + (k & 1)), double(cj + (k >> 1)), a, b);
        const double gap = z[k] - planeAt(t, a, b);
        above += gap > tolerance;
        below += gap < -tolerance;
    }
    return above == 4 || below == 4;
}

// The segment S ∩ P_T on triangle `tri` (where its plane meets T's) inside the box, if any.
void addBlocker(const LocalTriangle& t, const LocalTriangle& tri, double tolerance,
                const LocalBox& box, std::vector<BlockerSegment>& out) {
    double f[3];
    for (int v = 0; v < 3; ++v) {
        f[v] = tri.z[v] - planeAt(t, tri.a[v], tri.b[v]);
        if (std::abs(f[v]) <= tolerance) f[v] = 0.0;
    }
    const double lo = std::min({f[0], f[1], f[2]}), hi = std::max({f[0], f[1], f[2]});
    // Wholly below or above P_T: no segment (a region of S above P_T is entered through the
    // segment of a neighbour); coplanar: lines on it only touch S, its edges are neighbours'.
    if (lo > 0.0 || hi < 0.0 || (lo == 0.0 && hi == 0.0)) return;
    PlanePoint points[3];
    int count = 0;
    for (int v = 0; v < 3 && count < 3; ++v) {
        if (f[v] == 0.0) points[count++] = {tri.a[v], tri.b[v], 1.0};
        const int w = (v + 1) % 3;
        if ((f[v] < 0.0 && f[w] > 0.0) || (f[v] > 0.0 && f[w] < 0.0)) {
            const double s = f[v] / (f[v] - f[w]);
            points[count++] = {tri.a[v] + s * (tri.a[w] - tri.a[v]),
                               tri.b[v] + s * (tri.b[w] - tri.b[v]), 1.0};
        }
    }
    if (count < 2) return;  // a single touching point blocks no line in the closed sense
    PlanePoint p = points[0], q = points[count - 1];
    if (clipToBox(box, p, q)) out.push_back({p, q});
}

// The line l in slope–intercept form about abscissa a (b = c + m·(x − a)); false when l is
// (nearly) vertical, i.e. not a line of the class.
bool asDualLine(const PrimalLine& l, double a, DualLine& out) {
    if (std::abs(l.l2) <= 1e-12 * (std::abs(l.l1) + std::abs(l.l3))) return false;
    out = {-l.l1 / l.l2, -(l.l1 * a + l.l3) / l.l2};
    return true;
}

// Has some line of the pieces left for good, at abscissa `a` (all blockers in [a, a0) already
// removed)? A vertex of a piece is one line (through two of its points); it has left when it is
// outside the box across the axis there, or at or above every sample and not descending
// backward. One such line is a witness: T is limiting.
bool someLineEscaped(const std::vector<LinePolygon>& pieces, const LocalTriangle& t, double a,
                     const LocalBox& box, double maxZ) {
    for (const LinePolygon& piece : pieces)
        for (size_t k = 0; k < piece.size(); ++k) {
            DualLine line;
            if (!asDualLine(vertexLine(piece, k), a, line)) continue;
            if (line.c < box.b0 || line.c > box.b1) return true;
            if (planeAt(t, a, line.c) >= maxZ && t.pa + t.pb * line.m <= 0.0) return true;
        }
    return false;
}

// The centroid of a piece's vertex lines in the dual plane: a line inside the piece (convex).
bool pieceCentroid(const LinePolygon& piece, double a0, DualLine& out) {
    if (piece.empty()) return false;
    double m = 0.0, c = 0.0;
    for (size_t k = 0; k < piece.size(); ++k) {
        DualLine vertex;
        if (!asDualLine(vertexLine(piece, k), a0, vertex)) return false;
        m += vertex.m, c += vertex.c;
    }
    const double count = double(piece.size());
    out = {m / count, c / count};
    return true;
}

}  // namespace

bool ExteriorVisibility::someLineTracedOut(const Frame& f, const LocalTriangle& t, double a0,
                                           double from, const std::vector<LinePolygon>& pieces) const {
    for (const LinePolygon& piece : pieces) {
        DualLine line;
        // The pieces may hold a few lines a blocker should have removed (borderline decisions
        // keep lines), so a line that gets out from `from` is traced again from a0.
        if (pieceCentroid(piece, a0, line) && escapesBackward(f, t, a0, from, line) &&
            (from == a0 || escapesBackward(f, t, a0, a0, line)))
            return true;
    }
    return false;
}

// Traced backward from `from` (≤ a0), does the line stay above S by a margin until it leaves
// the box or rises above every sample? A witness of exterior-limiting when traced from a0. S is the max of two planes inside a cell (convex) and the line is
// straight, so their gap is concave on each cell's piece of the line: checking it where the
// line crosses the cell grid (integer a or b) checks it everywhere.
bool ExteriorVisibility::escapesBackward(const Frame& f, const LocalTriangle& t, double a0,
                                         double from, const DualLine& line) const {
    const Surface& s = m_surface;
    const LocalBox box = localBox(s, f);
    const double rise = t.pa + t.pb * line.m;  // dz/da along the line
    const double margin = 1e-6 * (1.0 + double(s.maxZ()));
    auto bAt = [&](double a) { return line.c + line.m * (a - a0); };
    auto gap = [&](double a) {
        const double b = bAt(a);
        double X, Y;
        f.world(a, b, X, Y);
        return planeAt(t, a, b) - double(s.heightAt(float(X + 0.5), float(Y + 0.5)));
    };
    // The next grid lines crossed backward (integer counters: progress whatever the rounding).
    double gridA = std::ceil(from) - 1.0;
    double gridB = line.m > 0.0 ? std::ceil(bAt(from)) - 1.0 : std::floor(bAt(from)) + 1.0;
    const double boxExit = line.m > 0.0   ? a0 + (box.b0 - line.c) / line.m
                           : line.m < 0.0 ? a0 + (box.b1 - line.c) / line.m
                                          : -kInfinity;
    if (!(gap(from) > margin)) return false;
    for (double a = from;;) {
        const double b = bAt(a);
        if (a <= box.a0 || b <= box.b0 || b >= box.b1) return true;
        if (rise <= 0.0 && planeAt(t, a, b) > double(s.maxZ()) + margin) return true;
        const double crossB = line.m != 0.0 ? a0 + (gridB - line.c) / line.m : -kInfinity;
        if (crossB >= gridA) {
            a = crossB;
            gridB += line.m > 0.0 ? -1.0 : 1.0;
        } else {
            a = gridA;
            gridA -= 1.0;
        }
        const bool leaves = a <= std::max(box.a0, boxExit);  // through a box face: checked too
        a = std::max({a, box.a0, boxExit});
        if (!(gap(a) > margin)) return false;
        if (leaves) return true;
    }
}

bool ExteriorVisibility::columnBlockers(const Frame& f, const SegmentHeights& seg,
                                        const LocalTriangle& t, int ac, double mlo, double mhi,
                                        std::vector<BlockerSegment>& out) const {
    const Surface& s = m_surface;
    const bool xClass = f.cls < kYPlus;
    int ci, cj;
    f.worldCell(ac, 0, ci, cj);
    const int line = xClass ? ci : cj;
    if (line < -1 || line > (xClass ? s.width() : s.height()) - 1) return false;
    const int cross = xClass ? s.height() : s.width();
    // The shaft of lines through s_τ with slopes in [mlo, mhi], over this column.
    const double d0 = double(seg.a0 - ac - 1), d1 = double(seg.a0 - ac);
    const double bmin = std::min(seg.b0 - 0.5 - mhi * d0, seg.b0 - 0.5 - mhi * d1);
    const double bmax = std::max(seg.b0 + 0.5 - mlo * d0, seg.b0 + 0.5 - mlo * d1);
    const int bc0 = std::max(int(std::floor(bmin)), -1);
    const int bc1 = std::min(int(std::floor(bmax)), cross - 1);
    const double tolerance = 1e-12 * (1.0 + double(s.maxZ()));
    const LocalBox box = localBox(s, f);
    std::array<LocalTriangle, 2> tris;
    for (int bc = bc0; bc <= bc1;) {
        const int blockEnd = std::min(bc1, (((bc + 1) >> 4) + 1) * 16 - 2);
        double lo, hi;
        planeRange(t, ac, ac + 1, bc, blockEnd + 1, lo, hi);
        const Block& b = block(xClass, line, bc);
        if (double(b.hi) < lo || double(b.lo) > hi) {  // the plane misses S over the block
            bc = blockEnd + 1;
            continue;
        }
        for (; bc <= blockEnd; ++bc) {
            f.worldCell(ac, bc, ci, cj);
            if (cellClearOf(s, f, t, ci, cj, tolerance)) continue;
            if (!cellTriangles(s, f, ci, cj, tris)) continue;
            for (const LocalTriangle& tri : tris) addBlocker(t, tri, tolerance, box, out);
        }
    }
    return true;
}

bool ExteriorVisibility::limiting(const Frame& f, const SegmentHeights& seg,
                                  const LocalTriangle& t, double tanPhi) const {
    m_tests.fetch_add(1, std::memory_order_relaxed);
    double lo[2], hi[2];
    const int arcs = allowedDirections(t.pa, t.pb, tanPhi, lo, hi);
    if (arcs == 0) return false;
    const double a0 = seg.a0, b0 = seg.b0;
    // σ: where P_T is above S on s_τ (S − P_T is linear on each half of s_τ).
    const double eps = 1e-9 * (1.0 + std::abs(seg.mid));
    auto gap = [&](double b) { return planeAt(t, a0, b) - seg.at(b) - eps; };
    double sigma[2][2];
    int sigmas = 0;
    const double halves[2][2] = {{b0 - 0.5, b0}, {b0, b0 + 0.5}};
    for (const auto& half : halves) {
        const double g0 = gap(half[0]), g1 = gap(half[1]);
        if (g0 < 0.0 && g1 < 0.0) continue;
        double y0 = half[0], y1 = half[1];
        if (g0 < 0.0) y0 = half[0] + (half[1] - half[0]) * g0 / (g0 - g1);
        if (g1 < 0.0) y1 = half[0] + (half[1] - half[0]) * g0 / (g0 - g1);
        if (sigmas == 1 && sigma[0][1] == y0) {
            sigma[0][1] = y1;  // one interval across the kink
            continue;
        }
        sigma[sigmas][0] = y0, sigma[sigmas][1] = y1, ++sigmas;
    }
    if (sigmas == 0) return false;
    // Initial pieces: through σ, slopes in an arc, crossing edge v0v1 or v1v2 of T (any line
    // crossing the triangle crosses one of them), from either side.
    std::vector<LinePolygon> pieces;
    double mlo = 1.0, mhi = -1.0;
    for (int k = 0; k < arcs; ++k) mlo = std::min(mlo, lo[k]), mhi = std::max(mhi, hi[k]);
    for (int si = 0; si < sigmas; ++si)
        for (int k = 0; k < arcs; ++k)
            for (int e = 0; e < 2; ++e)
                for (int side : {+1, -1}) {
                    LinePolygon lines =
                        linesThroughSegment(a0, sigma[si][0], sigma[si][1], lo[k], hi[k]);
                    const PlanePoint p{t.a[e], t.b[e], 1.0}, q{t.a[e + 1], t.b[e + 1], 1.0};
                    if (clipLines(lines, {p, side}) && clipLines(lines, {q, -side}))
                        pieces.push_back(std::move(lines));
                }
    if (pieces.empty()) return false;
    // Lines through s_τ and T: their slopes lie between those towards T's vertices (when T is
    // strictly ahead), which narrows the shaft searched for blockers.
    bool ahead = true;
    double slo = kInfinity, shi = -kInfinity;
    for (int v = 0; v < 3; ++v) {
        const double da = t.a[v] - a0;
        if (da <= 1e-9) ahead = false;
        if (!ahead) break;
        for (double y : {b0 - 0.5, b0 + 0.5}) {
            slo = std::min(slo, (t.b[v] - y) / da);
            shi = std::max(shi, (t.b[v] - y) / da);
        }
    }
    if (ahead && std::max(mlo, slo) <= std::min(mhi, shi))
        mlo = std::max(mlo, slo), mhi = std::min(mhi, shi);
    // Blockers column by column backward from s_τ (nearest first: they cut most), until no
    // line is left, the box ends, or the shaft is above every sample for good.
    const double maxZ = m_surface.maxZ();
    const double riseLo = -t.pa - t.pb * mhi, riseHi = -t.pa - t.pb * mlo;  // dz/d(backward)
    std::vector<BlockerSegment> blockers;
    uint64_t used = 0;
    const LocalBox box = localBox(m_surface, f);
    // Most tested triangles are limiting, and the line that shows it is usually found long before
    // the blockers are exhausted: every few columns (after 0, 1, 2, 4, … of them) one line inside
    // each piece, clear of every blocker subtracted so far, is traced on from there.
    int witnessColumn = seg.a0 - 1;
    for (int ac = seg.a0 - 1;; --ac) {
        if (someLineEscaped(pieces, t, ac + 1, box, maxZ)) break;
        if (m_traceWitnesses && ac == witnessColumn) {
            if (someLineTracedOut(f, t, a0, double(ac + 1), pieces)) {
                m_witnessed.fetch_add(1, std::memory_order_relaxed);
                break;
            }
            witnessColumn = seg.a0 - 1 - 2 * (seg.a0 - 1 - ac) - 1;
        }
        const double d0 = double(seg.a0 - ac - 1);
        const double zLo = planeAt(t, a0 - d0, b0 - 0.5 - mhi * d0);
        const double zHi = planeAt(t, a0 - d0, b0 + 0.5 - mlo * d0);
        if (std::min(zLo, zHi) > maxZ && riseLo >= 0.0 && riseHi >= 0.0) break;  // sky
        blockers.clear();
        if (!columnBlockers(f, seg, t, ac, mlo, mhi, blockers)) break;  // out of the box
        used += blockers.size();
        for (const BlockerSegment& b : blockers) {
            subtractBlocker(pieces, b);
            if (pieces.empty()) break;
            if (pieces.size() > kMaxPieces) {
                m_blockers.fetch_add(used, std::memory_order_relaxed);
                return true;
            }
        }
        if (pieces.empty()) break;
    }
    m_blockers.fetch_add(used, std::memory_order_relaxed);
    return !pieces.empty();
}

}  // namespace relief::safety
