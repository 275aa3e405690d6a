// The max pyramid as baked maps (shared by `quadtree`, `maxmip` and `quadtree-oriented`): one
// array per level, "level0" .. "level<top>", row-major, one float per node (max_pyramid.h). The GL
// backend reads the same arrays (gl/shader_interface.h), so this is also the GPU layout.
#include <relief/techniques/common/max_pyramid.h>
#include <relief/techniques/technique.h>

#include <algorithm>

namespace relief {

namespace {
std::string levelName(int level) { return "level" + std::to_string(level); }
// box-surface = 2 (quadtree, maxmip): the texel-box pyramid (MaxPyramid::overTexels).
bool usesTexelBoxes(const TechniqueInput& input) {
    return input.params.has("box-surface") && input.params.getInt("box-surface") == 2;
}
bool bakedOverTexels(const TechniqueMaps& maps) {
    const auto it = maps.parameters.find("box-surface");
    return it != maps.parameters.end() && it->second == "2";
}
}  // namespace

MaxPyramid::MaxPyramid(const PyramidLayout& layout) : m_layout(layout) {
    size_t total = 0;
    for (int level = 0; level < layout.levels; ++level)
        total += Index::size(layout.widthAt(level), layout.heightAt(level));
    m_values.assign(total, 0.0f);
    size_t offset = 0;
    for (int level = 0; level < layout.levels; ++level) {
        m_levels[size_t(level)] = {m_values.data() + offset, Index::of(layout.widthAt(level))};
        offset += Index::size(layout.widthAt(level), layout.heightAt(level));
    }
}

std::vector<MapArray> MaxPyramid::toArrays() const {
    std::vector<MapArray> arrays;
    for (int level = 0; level < m_layout.levels; ++level) {
        MapArray a{levelName(level), m_layout.widthAt(level), m_layout.heightAt(level), 1, {}};
        a.data.reserve(size_t(a.width) * size_t(a.height));
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) a.data.push_back(at(level, x, y));
        arrays.push_back(std::move(a));
    }
    return arrays;
}

Result<MaxPyramid> MaxPyramid::fromArrays(const Surface& surface, const TechniqueMaps& maps,
                                          bool texels) {
    const PyramidLayout layout = texels ? PyramidLayout::ofTexels(surface) : PyramidLayout::of(surface);
    MaxPyramid pyramid(layout);
    for (int level = 0; level < layout.levels; ++level) {
        const std::string name = levelName(level);
        const MapArray* a = maps.find(name);
        const int w = layout.widthAt(level), h = layout.heightAt(level);
        if (!a)
            return makeError(ErrorKind::InvalidInput,
                             "{} maps: no array '{}' (a {}-level max pyramid over {}×{} {} {} "
                             "expected)", maps.technique, name, layout.levels, layout.cellsX,
                             layout.cellsY, surface.edge() == EdgeMode::Repeat ? "repeat" : "clamp",
                             texels ? "texels" : "cells");
        if (a->width != w || a->height != h || a->channels != 1 ||
            a->data.size() != size_t(w) * size_t(h))
            return makeError(ErrorKind::InvalidInput,
                             "{} maps: array '{}' is {}×{}×{} ({} floats), expected {}×{}×1",
                             maps.technique, name, a->width, a->height, a->channels,
                             a->data.size(), w, h);
        const Level& out = pyramid.m_levels[size_t(level)];
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                out.values[out.index(x, y)] = a->data[size_t(y) * size_t(w) + size_t(x)];
    }
    if (Status s = pyramid.spotCheck(surface, maps.technique); !s) return s.error();
    if (maps.find(levelName(layout.levels)))
        return makeError(ErrorKind::InvalidInput, "{} maps: array '{}' beyond the top level {} of "
                         "this surface's pyramid", maps.technique, levelName(layout.levels),
                         layout.topLevel());
    return pyramid;
}

// Baked maps are checksummed; this catches values edited by hand or a faulty builder. Every node
// above level 0 must equal the max of its children (exact: max rounds nothing), and up to 4096
// level-0 cells spread over the map the max of the cell's corners. Linear in the nodes, far less
// than reading the file.
Status MaxPyramid::spotCheck(const Surface& surface, const std::string& technique) const {
    auto refuse = [&](int level, int x, int y, float stored, float expected) {
        return makeError(ErrorKind::InvalidInput,
                         "{} maps: '{}' node ({}, {}) is {} but {} gives {}; the "
                         "maps were edited or built wrongly, bake them again",
                         technique, levelName(level), x, y, stored,
                         level == 0 ? "the heightfield" : "its children", expected);
    };
    for (int level = 1; level < m_layout.levels; ++level) {
        const int fineW = m_layout.widthAt(level - 1), fineH = m_layout.heightAt(level - 1);
        for (int y = 0; y < m_layout.heightAt(level); ++y)
            for (int x = 0; x < m_layout.widthAt(level); ++x) {
                const int x1 = std::min(2 * x + 1, fineW - 1), y1 = std::min(2 * y + 1, fineH - 1);
                const float expected =
                    std::max(std::max(at(level - 1, 2 * x, 2 * y), at(level - 1, x1, 2 * y)),
                             std::max(at(level - 1, 2 * x, y1), at(level - 1, x1, y1)));
                if (at(level, x, y) != expected)
                    return refuse(level, x, y, at(level, x, y), expected);
            }
    }
    const size_t count = size_t(m_layout.cellsX) * size_t(m_layout.cellsY);
    const size_t stride = std::max<size_t>(1, count / 4096);
    if (m_layout.texels()) {  // level 0 holds the samples
        for (size_t k = stride / 2; k < count; k += stride) {
            const int x = int(k % size_t(m_layout.cellsX)), y = int(k / size_t(m_layout.cellsX));
            if (at(0, x, y) != surface.sampleZ(x, y))
                return refuse(0, x, y, at(0, x, y), surface.sampleZ(x, y));
        }
        return {};
    }
    const VertexGrid vertices(surface);
    for (size_t k = stride / 2; k < count; k += stride) {
        const int x = int(k % size_t(m_layout.cellsX)), y = int(k / size_t(m_layout.cellsX));
        const float expected = std::max(std::max(vertices.at(x, y), vertices.at(x + 1, y)),
                                        std::max(vertices.at(x, y + 1), vertices.at(x + 1, y + 1)));
        if (at(0, x, y) != expected) return refuse(0, x, y, at(0, x, y), expected);
    }
    return {};
}

Result<std::shared_ptr<const MaxPyramid>> maxPyramidFor(const TechniqueInput& input) {
    const bool texels = usesTexelBoxes(input);
    if (input.maps && bakedOverTexels(*input.maps) != texels)
        return makeError(ErrorKind::InvalidInput,
                         "{} maps: baked {} box-surface=2, traced {} it: bake them with the same "
                         "box-surface", input.maps->technique,
                         texels ? "without" : "with", texels ? "with" : "without");
    if (texels && !input.maps)
        return std::make_shared<const MaxPyramid>(MaxPyramid::overTexels(*input.surface));
    if (texels) {
        auto pyramid = MaxPyramid::fromArrays(*input.surface, *input.maps, true);
        if (!pyramid) return pyramid.error();
        return std::make_shared<const MaxPyramid>(std::move(*pyramid));
    }
    if (!input.maps) return std::make_shared<const MaxPyramid>(*input.surface);
    auto pyramid = MaxPyramid::fromArrays(*input.surface, *input.maps);
    if (!pyramid) return pyramid.error();
    return std::make_shared<const MaxPyramid>(std::move(*pyramid));
}

Result<TechniqueMaps> maxPyramidMaps(const TechniqueInput& input, std::string_view technique) {
    TechniqueMaps maps;
    maps.technique = std::string(technique);
    if (usesTexelBoxes(input)) {  // recorded: the arrays are the texels' pyramid
        maps.parameters["box-surface"] = "2";
        maps.arrays = MaxPyramid::overTexels(*input.surface).toArrays();
        return maps;
    }
    maps.arrays = MaxPyramid(*input.surface).toArrays();
    return maps;
}

}  // namespace relief
