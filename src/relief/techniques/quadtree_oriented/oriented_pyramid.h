#pragma once
// The oriented max pyramid of `quadtree-oriented`: per node (levels ≥ 1) a plane lying on top of
// S over the node, plus the node's flat maximum. See quadtree_oriented.h for the proof that the
// plane bounds S.
#include <relief/techniques/common/max_pyramid.h>

#include <array>
#include <vector>

namespace relief {

// RGBA of the paper's "oriented quadtree": the plane's heights at three corners of the node's
// nominal 2^L × 2^L square (lower-left, lower-right, upper-left; the upper-right one is
// c10 + c01 - c00) and the flat maximum of the node (the pre-test).
struct OrientedNode {
    float c00, c10, c01, zmax;
};
static_assert(sizeof(OrientedNode) == 16);

class OrientedPyramid {
public:
    // Slopes from the child maxima at level L-1 of `maxima`; heights exact over the vertices.
    OrientedPyramid(const VertexGrid& vertices, const MaxPyramid& maxima);
    OrientedPyramid(OrientedPyramid&&) = default;  // level pointers move with the buffer
    OrientedPyramid(const OrientedPyramid&) = delete;
    OrientedPyramid& operator=(const OrientedPyramid&) = delete;

    const OrientedNode& at(int level, int nx, int ny) const {
        const Level& l = m_levels[size_t(level)];
        return l.nodes[l.index(nx, ny)];
    }
    size_t bytes() const { return m_nodes.size() * sizeof(OrientedNode); }

    // Baked form (quadtree_oriented_maps.cpp): arrays "oriented1" .. "oriented<top>", level L of
    // widthAt(L) × heightAt(L) nodes, 4 channels (c00, c10, c01, zmax), row-major (untiled).
    std::vector<MapArray> toArrays() const;
    static Result<OrientedPyramid> fromArrays(const PyramidLayout& layout,
                                              const TechniqueMaps& maps);

private:
    explicit OrientedPyramid(const PyramidLayout& layout);  // levels allocated, not built
    using Index = TiledIndex<1>;  // 2×2 nodes of 16 bytes per tile
    struct Level {
        OrientedNode* nodes;
        Index index;
    };
    void buildLevel(int level, const VertexGrid& vertices, const MaxPyramid& maxima);

    PyramidLayout m_layout;
    std::vector<OrientedNode> m_nodes;  // levels 1..top, tiled
    std::array<Level, PyramidLayout::kMaxLevels> m_levels{};
};

}  // namespace relief
