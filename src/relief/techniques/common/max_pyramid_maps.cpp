// The max pyramid as baked maps (shared by `quadtree`, `maxmip` and `quadtree-oriented`): one
// array per level, "level0" .. "level<top>", row-major, one float per node (max_pyramid.h). The GL
// backend reads the same arrays (gl/shader_interface.h), so this is also the GPU layout.
#include <relief/core/huge_pages.h>
#include <relief/techniques/common/max_pyramid.h>
#include <relief/techniques/technique.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

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
    adviseHugePages(m_values.data(), bytes());  // before the build writes it: no copy
    size_t offset = 0;
    for (int level = 0; level < layout.levels; ++level) {
        m_levels[size_t(level)] = {m_values.data() + offset, Index::of(layout.widthAt(level))};
        offset += Index::size(layout.widthAt(level), layout.heightAt(level));
    }
}

float encodePyramidMax(float max, float depth, int bits) {
    if (bits >= 32) return max;
    if (!(depth > 0.0f) || !(max > 0.0f)) return 0.0f;  // code 0 decodes to 0 ≥ max
    const uint32_t top = (1u << bits) - 1u;
    auto k = uint32_t(std::clamp(std::ceil(max / depth * float(top)), 0.0f, float(top)));
    while (k < top && decodePyramidCode(float(k) / float(top), depth) < max) ++k;
    return float(k) / float(top);
}

void MaxPyramid::roundUp(int bits, float depth) {
    if (bits >= 32) return;
    for (float& v : m_values) v = decodePyramidCode(encodePyramidMax(v, depth, bits), depth);
}

std::vector<MapArray> MaxPyramid::toArrays(int bits, float depth) const {
    std::vector<MapArray> arrays;
    for (int level = 0; level < m_layout.levels; ++level) {
        MapArray a{levelName(level), m_layout.widthAt(level), m_layout.heightAt(level), 1, {}};
        a.data.reserve(size_t(a.width) * size_t(a.height));
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x)
                a.data.push_back(encodePyramidMax(at(level, x, y), depth, bits));
        arrays.push_back(std::move(a));
    }
    return arrays;
}

Result<MaxPyramid> MaxPyramid::fromArrays(const Surface& surface, const TechniqueMaps& maps,
                                          int bits, bool texels) {
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
            for (int x = 0; x < w; ++x) {
                const float v = a->data[size_t(y) * size_t(w) + size_t(x)];
                out.values[out.index(x, y)] = bits < 32 ? decodePyramidCode(v, surface.depth()) : v;
            }
    }
    if (Status s = pyramid.spotCheck(surface, maps.technique, bits); !s) return s.error();
    if (maps.find(levelName(layout.levels)))
        return makeError(ErrorKind::InvalidInput, "{} maps: array '{}' beyond the top level {} of "
                         "this surface's pyramid", maps.technique, levelName(layout.levels),
                         layout.topLevel());
    return pyramid;
}

// Baked maps are checksummed; this catches values edited by hand or a faulty builder. Every node
// above level 0 must equal the max of its children (exact: max rounds nothing, and rounding up
// is monotone, so it commutes with max), and up to 4096 level-0 cells spread over the map the
// max of the cell's corners, rounded up at `bits`. Linear in the nodes, far less than reading
// the file.
Status MaxPyramid::spotCheck(const Surface& surface, const std::string& technique,
                             int bits) const {
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
        const float corners = std::max(std::max(vertices.at(x, y), vertices.at(x + 1, y)),
                                       std::max(vertices.at(x, y + 1), vertices.at(x + 1, y + 1)));
        const float expected =
            bits < 32 ? decodePyramidCode(encodePyramidMax(corners, surface.depth(), bits),
                                          surface.depth())
                      : corners;
        if (at(0, x, y) != expected) return refuse(0, x, y, at(0, x, y), expected);
    }
    return {};
}

int pyramidBits(const ParamValues& params) {
    return params.has("bits") ? params.getInt("bits") : 32;
}

namespace {
Status checkBits(int bits, std::string_view technique) {
    if (bits != 8 && bits != 16 && bits != 32)
        return makeError(ErrorKind::BadArgument, "{}: bits must be 8, 16 or 32 (got {})",
                         technique, bits);
    return {};
}
}  // namespace

Result<std::shared_ptr<const MaxPyramid>> maxPyramidFor(const TechniqueInput& input) {
    const int bits = pyramidBits(input.params);
    const Surface& s = *input.surface;
    const bool texels = usesTexelBoxes(input);
    const std::string_view technique = input.maps ? std::string_view(input.maps->technique)
                                                  : std::string_view("max pyramid");
    if (Status st = checkBits(bits, technique); !st) return st.error();
    // The texel boxes are level 0 itself: rounding it up would move the surface.
    if (texels && bits != 32)
        return makeError(ErrorKind::BadArgument,
                         "{}: box-surface=2 traces the pyramid's level 0 as the surface, so it "
                         "needs bits=32 (got bits={})", technique, bits);
    if (input.maps && bakedOverTexels(*input.maps) != texels)
        return makeError(ErrorKind::InvalidInput,
                         "{} maps: baked {} box-surface=2, traced {} it: bake them with the same "
                         "box-surface", input.maps->technique,
                         texels ? "without" : "with", texels ? "with" : "without");
    if (!input.maps) {
        if (texels) return std::make_shared<const MaxPyramid>(MaxPyramid::overTexels(s));
        MaxPyramid pyramid(s);
        pyramid.roundUp(bits, s.depth());
        return std::make_shared<const MaxPyramid>(std::move(pyramid));
    }
    const TechniqueMaps& maps = *input.maps;
    // Maps without the key are float pyramids (quadtree-oriented's, and bakes before `bits`).
    const auto found = maps.parameters.find("bits");
    const std::string baked = found == maps.parameters.end() ? "32" : found->second;
    if (baked != std::to_string(bits))
        return makeError(ErrorKind::InvalidInput,
                         "{}: baked maps have bits={} but the tracer asks for bits={}",
                         maps.technique, baked, bits);
    auto pyramid = MaxPyramid::fromArrays(s, maps, bits, texels);
    if (!pyramid) return pyramid.error();
    return std::make_shared<const MaxPyramid>(std::move(*pyramid));
}

Result<TechniqueMaps> maxPyramidMaps(const TechniqueInput& input, std::string_view technique) {
    const int bits = pyramidBits(input.params);
    if (Status st = checkBits(bits, technique); !st) return st.error();
    TechniqueMaps maps;
    maps.technique = std::string(technique);
    maps.parameters["bits"] = std::to_string(bits);  // decode: value · D at 16 / 8 (header)
    if (usesTexelBoxes(input)) {  // recorded: the arrays are the texels' pyramid
        if (bits != 32)
            return makeError(ErrorKind::BadArgument,
                             "{}: box-surface=2 traces the pyramid's level 0 as the surface, so it "
                             "needs bits=32 (got bits={})", technique, bits);
        maps.parameters["box-surface"] = "2";
        maps.arrays = MaxPyramid::overTexels(*input.surface).toArrays();
        return maps;
    }
    maps.arrays = MaxPyramid(*input.surface).toArrays(bits, input.surface->depth());
    return maps;
}

}  // namespace relief
