#include <relief/techniques/quadtree/max_pyramid.h>

#include <relief/core/parallel.h>

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
    : m_layout(layout) {
    m_values.resize(layout.nodeCount());
    size_t offset = 0;
    for (int level = 0; level < layout.levels; ++level) {
        m_levels[size_t(level)] = {m_values.data() + offset, layout.widthAt(level)};
        offset += size_t(layout.widthAt(level)) * size_t(layout.heightAt(level));
    }
    buildFinest(vertices);
    for (int level = 1; level < layout.levels; ++level) buildCoarser(level);
}

void MaxPyramid::buildFinest(const VertexGrid& vertices) {
    const int w = m_layout.cellsX;
    float* out = m_levels[0].values;
    parallelRanges(m_layout.cellsY, 16, [&](int64_t begin, int64_t end) {
        for (int l = int(begin); l < int(end); ++l) {
            const float* v0 = vertices.row(l);
            const float* v1 = vertices.row(l + 1);
            float* o = out + size_t(l) * size_t(w);
            for (int k = 0; k < w; ++k)
                o[k] = std::max(std::max(v0[k], v0[k + 1]), std::max(v1[k], v1[k + 1]));
        }
    });
}

void MaxPyramid::buildCoarser(int level) {
    const Level& fine = m_levels[size_t(level - 1)];
    const int fineW = fine.width, fineH = m_layout.heightAt(level - 1);
    const int w = m_layout.widthAt(level);
    float* out = m_levels[size_t(level)].values;
    parallelRanges(m_layout.heightAt(level), 8, [&](int64_t begin, int64_t end) {
        for (int y = int(begin); y < int(end); ++y) {
            const float* r0 = fine.values + size_t(2 * y) * size_t(fineW);
            const float* r1 = 2 * y + 1 < fineH ? r0 + fineW : r0;  // odd height: last row alone
            float* o = out + size_t(y) * size_t(w);
            for (int x = 0; x < w; ++x) {
                const int x0 = 2 * x, x1 = std::min(2 * x + 1, fineW - 1);
                o[x] = std::max(std::max(r0[x0], r0[x1]), std::max(r1[x0], r1[x1]));
            }
        }
    });
}

}  // namespace relief
