// quadtree-oriented's baked maps: the flat max pyramid ("level0" .. , common/max_pyramid_maps.cpp)
// and the oriented one ("oriented1" .. "oriented<top>", 4 channels: c00, c10, c01, zmax). The GL
// backend reads the same arrays (gl/shader_interface.h).
#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>

namespace relief {

namespace {
std::string orientedName(int level) { return "oriented" + std::to_string(level); }
}  // namespace

OrientedPyramid::OrientedPyramid(const PyramidLayout& layout) : m_layout(layout) {
    size_t count = 0;
    for (int level = 1; level < m_layout.levels; ++level)
        count += Index::size(m_layout.widthAt(level), m_layout.heightAt(level));
    m_nodes.resize(count);
    size_t offset = 0;
    for (int level = 1; level < m_layout.levels; ++level) {
        m_levels[size_t(level)] = {m_nodes.data() + offset, Index::of(m_layout.widthAt(level))};
        offset += Index::size(m_layout.widthAt(level), m_layout.heightAt(level));
    }
}

std::vector<MapArray> OrientedPyramid::toArrays() const {
    std::vector<MapArray> arrays;
    for (int level = 1; level < m_layout.levels; ++level) {
        MapArray a{orientedName(level), m_layout.widthAt(level), m_layout.heightAt(level), 4, {}};
        a.data.reserve(size_t(a.width) * size_t(a.height) * 4);
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) {
                const OrientedNode& n = at(level, x, y);
                a.data.insert(a.data.end(), {n.c00, n.c10, n.c01, n.zmax});
            }
        arrays.push_back(std::move(a));
    }
    return arrays;
}

Result<OrientedPyramid> OrientedPyramid::fromArrays(const PyramidLayout& layout,
                                                    const TechniqueMaps& maps) {
    OrientedPyramid pyramid(layout);
    for (int level = 1; level < layout.levels; ++level) {
        const std::string name = orientedName(level);
        const MapArray* a = maps.find(name);
        const int w = layout.widthAt(level), h = layout.heightAt(level);
        if (!a)
            return makeError(ErrorKind::InvalidInput,
                             "{} maps: no array '{}' (oriented levels 1..{} expected)",
                             maps.technique, name, layout.topLevel());
        if (a->width != w || a->height != h || a->channels != 4 ||
            a->data.size() != size_t(w) * size_t(h) * 4)
            return makeError(ErrorKind::InvalidInput,
                             "{} maps: array '{}' is {}×{}×{} ({} floats), expected {}×{}×4",
                             maps.technique, name, a->width, a->height, a->channels,
                             a->data.size(), w, h);
        const Level& out = pyramid.m_levels[size_t(level)];
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const float* v = &a->data[(size_t(y) * size_t(w) + size_t(x)) * 4];
                out.nodes[out.index(x, y)] = {v[0], v[1], v[2], v[3]};
            }
    }
    if (maps.find(orientedName(layout.levels)))
        return makeError(ErrorKind::InvalidInput, "{} maps: array '{}' beyond the top level {}",
                         maps.technique, orientedName(layout.levels), layout.topLevel());
    return pyramid;
}

OrientedMaps::OrientedMaps(std::shared_ptr<const MaxPyramid> maxima, OrientedPyramid planes)
    : maxima(std::move(maxima)), planes(std::move(planes)) {}

namespace {
// Baked planes spot-checked (the max pyramid is checked by maxPyramidFor): at up to 64 nodes of
// each level, on a 5×5 grid over the node's footprint (clipped to the box in clamp mode), the
// plane as the tracer evaluates it and the node's flat maximum lie on or above S.
Status spotCheckPlanes(const Surface& s, const PyramidLayout& layout,
                       const OrientedPyramid& planes) {
    const float tolerance = 1e-4f * std::max(1.0f, s.depth());
    for (int level = 1; level < layout.levels; ++level) {
        const size_t count = size_t(layout.widthAt(level)) * size_t(layout.heightAt(level));
        const size_t stride = std::max<size_t>(1, count / 64);
        for (size_t k = stride / 2; k < count; k += stride) {
            const int nx = int(k % size_t(layout.widthAt(level))),
                      ny = int(k / size_t(layout.widthAt(level)));
            const OrientedNode& n = planes.at(level, nx, ny);
            const int lo = nx << level, loY = ny << level;
            const float nodeX = float(layout.firstCell + lo) + 0.5f,
                        nodeY = float(layout.firstCell + loY) + 0.5f;
            float x0 = nodeX,
                  x1 = float(layout.firstCell + std::min(lo + (1 << level), layout.cellsX)) + 0.5f;
            float y0 = nodeY,
                  y1 = float(layout.firstCell + std::min(loY + (1 << level), layout.cellsY)) + 0.5f;
            if (!layout.repeat) {
                x0 = std::max(x0, 0.0f), x1 = std::min(x1, float(s.width()));
                y0 = std::max(y0, 0.0f), y1 = std::min(y1, float(s.height()));
            }
            const float scale = kInverseSides[size_t(level)];
            for (int j = 0; j <= 4; ++j)
                for (int i = 0; i <= 4; ++i) {
                    const float x = x0 + (x1 - x0) * float(i) / 4.0f,
                                y = y0 + (y1 - y0) * float(j) / 4.0f;
                    const float plane = n.c00 + (n.c10 - n.c00) * scale * (x - nodeX) +
                                        (n.c01 - n.c00) * scale * (y - nodeY);
                    const float z = s.heightAt(x, y);
                    if (!(plane >= z - tolerance && n.zmax >= z - tolerance))
                        return makeError(ErrorKind::InvalidInput,
                                         "quadtree-oriented maps: '{}{}' node ({}, {}) "
                                         "lies below the surface at ({}, {}) (plane {}, max {}, "
                                         "surface {}); the maps "
                                         "were edited or built wrongly, bake them again",
                                         "oriented", level, nx, ny, x, y, plane, n.zmax, z);
                }
        }
    }
    return {};
}
}  // namespace

Result<std::shared_ptr<const OrientedMaps>> orientedMapsFor(const TechniqueInput& input) {
    if (!input.maps) return std::make_shared<const OrientedMaps>(*input.surface);
    auto maxima = maxPyramidFor(input);
    if (!maxima) return maxima.error();
    auto planes = OrientedPyramid::fromArrays((*maxima)->layout(), *input.maps);
    if (!planes) return planes.error();
    if (Status s = spotCheckPlanes(*input.surface, (*maxima)->layout(), *planes); !s)
        return s.error();
    return std::make_shared<const OrientedMaps>(std::move(*maxima), std::move(*planes));
}

Result<TechniqueMaps> buildQuadtreeOrientedMaps(const TechniqueInput& input) {
    const OrientedMaps built(*input.surface);
    TechniqueMaps maps;
    maps.technique = "quadtree-oriented";
    maps.arrays = built.maxima->toArrays();
    for (MapArray& a : built.planes.toArrays()) maps.arrays.push_back(std::move(a));
    return maps;
}

}  // namespace relief
