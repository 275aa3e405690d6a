#include <relief/core/parallel.h>
#include <relief/techniques/common/max_pyramid.h>

#include <algorithm>
#include <bit>

namespace relief {

PyramidLayout PyramidLayout::of(const Surface& surface) {
    PyramidLayout layout;
    layout.repeat = surface.edge() == EdgeMode::Repeat;
    layout.firstCell = layout.repeat ? 0 : -1;
    layout.cellsX = surface.width() + (layout.repeat ? 0 : 1);
    layout.cellsY = surface.height() + (layout.repeat ? 0 : 1);
    const int largest = std::max(layout.cellsX, layout.cellsY);
    layout.levels = int(std::bit_width(unsigned(largest - 1))) + 1;
    RELIEF_CHECK(layout.levels <= kMaxLevels);
    return layout;
}

PyramidLayout PyramidLayout::ofTexels(const Surface& surface) {
    PyramidLayout layout = of(surface);
    layout.firstCell = 0;
    layout.cellsX = surface.width();
    layout.cellsY = surface.height();
    layout.levels = int(std::bit_width(unsigned(std::max(layout.cellsX, layout.cellsY) - 1))) + 1;
    layout.edge = 0.0f;
    return layout;
}

size_t PyramidLayout::nodeCount() const {
    size_t count = 0;
    for (int level = 0; level < levels; ++level) count += size_t(widthAt(level)) * heightAt(level);
    return count;
}

VertexGrid::VertexGrid(const Surface& surface) {
    const PyramidLayout layout = PyramidLayout::of(surface);
    m_width = layout.cellsX + 1;
    const int rows = layout.cellsY + 1;
    m_z.resize(size_t(m_width) * size_t(rows));
    parallelRanges(rows, 16, [&](int64_t begin, int64_t end) {
        for (int l = int(begin); l < int(end); ++l)
            for (int k = 0; k < m_width; ++k)
                m_z[size_t(l) * size_t(m_width) + size_t(k)] =
                    surface.sampleZ(layout.firstCell + k, layout.firstCell + l);
    });
}

MaxPyramid::MaxPyramid(const Surface& surface)
    : MaxPyramid(VertexGrid(surface), PyramidLayout::of(surface)) {}

MaxPyramid::MaxPyramid(const VertexGrid& vertices, const PyramidLayout& layout)
    : MaxPyramid(layout) {  // the allocation, max_pyramid_maps.cpp
    buildFinest(vertices);
    for (int level = 1; level < layout.levels; ++level) buildCoarser(level);
}

MaxPyramid MaxPyramid::overTexels(const Surface& surface) {
    return overSamples(surface, PyramidLayout::ofTexels(surface));
}

MaxPyramid MaxPyramid::overCellOrigins(const Surface& surface) {
    return overSamples(surface, PyramidLayout::of(surface));
}

MaxPyramid MaxPyramid::overSamples(const Surface& surface, const PyramidLayout& layout) {
    MaxPyramid pyramid(layout);
    const Level& out = pyramid.m_levels[0];
    parallelRanges(layout.cellsY, 16, [&](int64_t begin, int64_t end) {
        for (int l = int(begin); l < int(end); ++l)
            for (int k = 0; k < layout.cellsX; ++k)
                out.values[out.index(k, l)] =
                    surface.sampleZ(layout.firstCell + k, layout.firstCell + l);
    });
    for (int level = 1; level < layout.levels; ++level) pyramid.buildCoarser(level);
    return pyramid;
}

void MaxPyramid::buildFinest(const VertexGrid& vertices) {
    const Level& out = m_levels[0];
    parallelRanges(m_layout.cellsY, 16, [&](int64_t begin, int64_t end) {
        for (int l = int(begin); l < int(end); ++l) {
            const float* v0 = vertices.row(l);
            const float* v1 = vertices.row(l + 1);
            for (int k = 0; k < m_layout.cellsX; ++k)
                out.values[out.index(k, l)] =
                    std::max(std::max(v0[k], v0[k + 1]), std::max(v1[k], v1[k + 1]));
        }
    });
}

void MaxPyramid::buildCoarser(int level) {
    const Level& fine = m_levels[size_t(level - 1)];
    const Level& out = m_levels[size_t(level)];
    const int fineW = m_layout.widthAt(level - 1), fineH = m_layout.heightAt(level - 1);
    parallelRanges(m_layout.heightAt(level), 8, [&](int64_t begin, int64_t end) {
        for (int y = int(begin); y < int(end); ++y) {
            const int y0 = 2 * y, y1 = std::min(2 * y + 1, fineH - 1);  // odd sizes: one child
            for (int x = 0; x < m_layout.widthAt(level); ++x) {
                const int x0 = 2 * x, x1 = std::min(2 * x + 1, fineW - 1);
                out.values[out.index(x, y)] = std::max(
                    std::max(fine.values[fine.index(x0, y0)], fine.values[fine.index(x1, y0)]),
                    std::max(fine.values[fine.index(x0, y1)], fine.values[fine.index(x1, y1)]));
            }
        }
    });
}

}  // namespace relief
