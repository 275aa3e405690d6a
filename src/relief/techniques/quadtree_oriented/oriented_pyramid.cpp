#include <relief/core/parallel.h>
#include <relief/techniques/quadtree_oriented/oriented_pyramid.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace relief {

namespace {

// Relative margin added to each plane: 2e-6 of the sum of the corner magnitudes, ≥ 16 ulps of
// each stored height. It covers the float rounding of the offset search (≤ 3 ulps), rounding
// the heights to float (½ ulp, so no explicit rounding up is needed) and the tracer's float
// evaluation of the plane from them (a few ulps).
constexpr double kPlaneMargin = 2e-6;

// Mean of the existing children maxima in a column (or row) of the 2×2 block, or NaN if none.
double meanMax(const MaxPyramid& maxima, int level, int x, int y, bool column) {
    const PyramidLayout& layout = maxima.layout();
    double sum = 0.0;
    int count = 0;
    for (int k = 0; k < 2; ++k) {
        const int cx = column ? x : x + k, cy = column ? y + k : y;
        if (cx >= layout.widthAt(level) || cy >= layout.heightAt(level)) continue;
        sum += maxima.at(level, cx, cy);
        ++count;
    }
    return count ? sum / count : std::nan("");
}

// The slope of a node at `level` along one axis: the difference of its children's maxima over the
// distance between the children's centres (0 when there is a single child along that axis).
double childSlope(const MaxPyramid& maxima, int level, int nx, int ny, bool alongX) {
    const int fine = level - 1, x = 2 * nx, y = 2 * ny;
    const double low = meanMax(maxima, fine, x, y, alongX);
    const double high =
        alongX ? meanMax(maxima, fine, x + 1, y, true) : meanMax(maxima, fine, x, y + 1, false);
    if (std::isnan(high)) return 0.0;
    return (high - low) / double(1 << fine);
}

// Max over the vertices lo..hi (inclusive: cell k has corners k and k+1) of h - sx·u - sy·v,
// u, v relative to (lo, loY): the lowest offset that puts the plane on or above all of them.
// Float, four accumulators: the rounding (≤ 3 ulps of the largest term) is far below the
// margin added afterwards.
double lowestOffset(const VertexGrid& vertices, int loX, int hiX, int loY, int hiY, double sx,
                    double sy, std::vector<float>& ramp) {
    const int n = hiX - loX + 1;
    for (int u = 0; u < n; ++u) ramp[size_t(u)] = float(sx * u);
    float offset = -std::numeric_limits<float>::infinity();
    for (int l = loY; l <= hiY; ++l) {
        const float* row = vertices.row(l) + loX;
        float m[4] = {row[0] - ramp[0], row[0] - ramp[0], row[0] - ramp[0], row[0] - ramp[0]};
        int u = 0;
        for (; u + 4 <= n; u += 4)
            for (int j = 0; j < 4; ++j) m[j] = std::max(m[j], row[u + j] - ramp[size_t(u + j)]);
        for (; u < n; ++u) m[0] = std::max(m[0], row[u] - ramp[size_t(u)]);
        const float rowMax = std::max(std::max(m[0], m[1]), std::max(m[2], m[3]));
        offset = std::max(offset, rowMax - float(sy * (l - loY)));
    }
    return double(offset);
}

}  // namespace

OrientedPyramid::OrientedPyramid(const VertexGrid& vertices, const MaxPyramid& maxima)
    : m_layout(maxima.layout()) {
    size_t count = 0;
    for (int level = 1; level < m_layout.levels; ++level)
        count += Index::size(m_layout.widthAt(level), m_layout.heightAt(level));
    m_nodes.resize(count);
    size_t offset = 0;
    for (int level = 1; level < m_layout.levels; ++level) {
        m_levels[size_t(level)] = {m_nodes.data() + offset, Index::of(m_layout.widthAt(level))};
        offset += Index::size(m_layout.widthAt(level), m_layout.heightAt(level));
        buildLevel(level, vertices, maxima);
    }
}

void OrientedPyramid::buildLevel(int level, const VertexGrid& vertices, const MaxPyramid& maxima) {
    const int side = 1 << level, width = m_layout.widthAt(level);
    parallelRanges(m_layout.heightAt(level), 1, [&](int64_t begin, int64_t end) {
        std::vector<float> ramp(size_t(side) + 1);
        for (int ny = int(begin); ny < int(end); ++ny) {
            const int loY = ny * side, hiY = std::min(loY + side, m_layout.cellsY);
            for (int nx = 0; nx < width; ++nx) {
                const int loX = nx * side, hiX = std::min(loX + side, m_layout.cellsX);
                const double sx = childSlope(maxima, level, nx, ny, true);
                const double sy = childSlope(maxima, level, nx, ny, false);
                const double offset = lowestOffset(vertices, loX, hiX, loY, hiY, sx, sy, ramp);
                const double c10 = offset + sx * side, c01 = offset + sy * side;
                const double margin =
                    kPlaneMargin * (std::abs(offset) + std::abs(c10) + std::abs(c01) + 1.0);
                const Level& out = m_levels[size_t(level)];
                out.nodes[out.index(nx, ny)] = {float(offset + margin), float(c10 + margin),
                                                float(c01 + margin), maxima.at(level, nx, ny)};
            }
        }
    });
}

}  // namespace relief
