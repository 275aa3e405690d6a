#pragma once
// max pyramid — the maximum mipmap shared by `quadtree`, `maxmip` and `quadtree-oriented`.
// Paper: Schroders & van Gulik 2006 §3 ("a mip mapped version of the height map ... the maximum
//   is calculated"); Tevs, Ihrke & Seidel 2008 (maximum mipmaps).
// Invariant: the value of a node is the maximum of the samples at the corners of the cells it
//   covers, hence ≥ S everywhere over the node (S is the max of two planes through those
//   corners, so over a cell it never exceeds its highest corner), and it equals the max of S
//   over the node.
// The same pyramid over texel boxes (overTexels, `box-surface=2`): level 0 = the box tops.
// Layout (level 0 = one value per cell, level L+1 = max of 2×2 nodes of level L):
//   - pyramid index k of level 0 is the cell `firstCell + k`; clamp: cells -1..W-1 (W+1 cells,
//     the half-texel border strips included, firstCell = -1); repeat: cells 0..W-1 (W cells).
//   - level L has ceil(n / 2^L) nodes per axis; node a covers the level-0 indices
//     [a·2^L, min((a+1)·2^L, n)): with odd sizes the last node of a level is narrower. The top
//     level is 1×1. Any W×H works, not only powers of two.
//   - repeat mode: the plane is tiled with copies of the map, and nodes never straddle the tile
//     seam. In tile t (x in [t·W, (t+1)·W) + 0.5) node a covers the cells t·W + [a·2^L,
//     min((a+1)·2^L, W)); the truncated last node bounds exactly the cells it covers, and
//     crossing the seam moves to node 0 of the next tile (the walk then restarts at the root).
// Encoding: one float per node, texel units (D·h), each level in 4×4 tiles (one cache line).
//   Baked at bits 16 / 8 (`quadtree` and `maxmip`'s `bits`), a node's max m is stored as the
//   code value k / (2^bits − 1) of D, k = ceil(m / D · (2^bits − 1)) raised until it decodes to
//   ≥ m (rounded UP: a node maximum stays an upper bound of S, so a skip stays safe; the
//   leaves' cell test reads the heights, so the tracers stay exact); decode m' = v · D · (1 + kPyramidDecodeMargin). The
//   pyramid in memory then holds the decoded m', the same whether built now or read back.
//   Memory: ≈ 4/3 · (W+1)(H+1) floats (tiles pad each level to a multiple of 4).
// Build: O(WH), parallel over rows (about 0.1 s at 4096² on two cores).
#include <relief/core/error.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>

#include <array>
#include <cstddef>
#include <memory>
#include <string_view>
#include <vector>

namespace relief {

// Sizes of a cell pyramid over the surface's cells (shared by the max and oriented pyramids).
struct PyramidLayout {
    static constexpr int kMaxLevels = 20;

    int cellsX = 0, cellsY = 0;  // level-0 size
    int firstCell = 0;           // global cell index of pyramid index 0: -1 clamp, 0 repeat
    int levels = 0;              // the top level (levels - 1) is 1×1
    bool repeat = false;
    // Where index k's edges lie: k + edge and k + 1 + edge. Cells 0.5; texel boxes 0 (ofTexels).
    float edge = 0.5f;

    static PyramidLayout of(const Surface& surface);
    // Over the W×H texels instead (surface/texel_boxes.h): index k is texel k, firstCell 0.
    static PyramidLayout ofTexels(const Surface& surface);
    bool texels() const { return edge == 0.0f; }
    int widthAt(int level) const { return ((cellsX - 1) >> level) + 1; }
    int heightAt(int level) const { return ((cellsY - 1) >> level) + 1; }
    int topLevel() const { return levels - 1; }
    size_t nodeCount() const;
};

// Where node (nx, ny) of a level lives: levels are stored in square tiles of 2^kLog × 2^kLog
// nodes, one 64-byte cache line, tiles row-major, so that a node's neighbours and the 2×2
// children of a node mostly share a line (the walk reads them in sequence).
template <int kLog>
struct TiledIndex {
    int tilesPerRow = 0;

    static TiledIndex of(int width) { return {((width - 1) >> kLog) + 1}; }
    static size_t size(int width, int height) {
        return (size_t((width - 1) >> kLog) + 1) * (size_t((height - 1) >> kLog) + 1) << (2 * kLog);
    }
    size_t operator()(int nx, int ny) const {
        constexpr int kMask = (1 << kLog) - 1;
        const size_t tile = size_t(ny >> kLog) * size_t(tilesPerRow) + size_t(nx >> kLog);
        return (tile << (2 * kLog)) + size_t(((ny & kMask) << kLog) + (nx & kMask));
    }
};

// The corners of all cells, as a (cellsX+1)×(cellsY+1) grid: vertex (k, l) is the sample
// (firstCell + k, firstCell + l) of the surface (clamped or wrapped). Used while building.
class VertexGrid {
public:
    explicit VertexGrid(const Surface& surface);
    int width() const { return m_width; }
    float at(int k, int l) const { return m_z[size_t(l) * size_t(m_width) + size_t(k)]; }
    const float* row(int l) const { return &m_z[size_t(l) * size_t(m_width)]; }

private:
    int m_width;
    std::vector<float> m_z;
};

class MaxPyramid {
public:
    explicit MaxPyramid(const Surface& surface);
    // The texel-box pyramid (layout ofTexels): level 0 holds each sample's height D·h, the
    // box's top, so a node's value is the maximum of the boxes it covers (baked with the
    // parameter box-surface = 2 recorded).
    static MaxPyramid overTexels(const Surface& surface);
    // The layout of the cell pyramid, but level 0 holds each cell's 00 corner only (the sample
    // firstCell + k): a node's value is the highest sample the published cone maps take as a
    // candidate in it, below the cell pyramid's by the corners the cells share with neighbours.
    static MaxPyramid overCellOrigins(const Surface& surface);
    MaxPyramid(const VertexGrid& vertices, const PyramidLayout& layout);
    MaxPyramid(MaxPyramid&&) = default;  // level pointers stay valid: the buffer moves along
    MaxPyramid(const MaxPyramid&) = delete;
    MaxPyramid& operator=(const MaxPyramid&) = delete;

    const PyramidLayout& layout() const { return m_layout; }
    float at(int level, int nx, int ny) const {
        const Level& l = m_levels[size_t(level)];
        return l.values[l.index(nx, ny)];
    }
    size_t bytes() const { return m_values.size() * sizeof(float); }
    // The raw tiled storage, for gathers (pyramid_walk_packet.cpp): a level's first value (its
    // offset from `values()`) and its tiles per row; node (nx, ny) is at TiledIndex<2>.
    const float* values() const { return m_values.data(); }
    const float* levelValues(int level) const { return m_levels[size_t(level)].values; }
    int levelTilesPerRow(int level) const { return m_levels[size_t(level)].index.tilesPerRow; }

    // Every node replaced by the decoded value of its `bits` code (bits 32: unchanged).
    void roundUp(int bits, float depth);

    // Baked form (max_pyramid_maps.cpp): arrays "level0" .. "level<top>", level L of
    // widthAt(L) × heightAt(L) nodes, 1 channel, row-major (untiled); codes at bits 16 / 8 (of a
    // pyramid not rounded up).
    std::vector<MapArray> toArrays(int bits = 32, float depth = 0.0f) const;
    // Nodes against their children and sampled level-0 cells against `surface` (fromArrays).
    Status spotCheck(const Surface& surface, const std::string& technique, int bits) const;
    // From those arrays, decoded; an error naming the array when one is missing or has the wrong
    // size, or when spotCheck fails. texels: the layout ofTexels (box-surface = 2, bits 32 only).
    static Result<MaxPyramid> fromArrays(const Surface& surface, const TechniqueMaps& maps,
                                         int bits = 32, bool texels = false);

private:
    explicit MaxPyramid(const PyramidLayout& layout);  // levels allocated, not built
    // Level 0 index (k, l) = the sample (firstCell + k, firstCell + l) (overTexels, overCellOrigins).
    static MaxPyramid overSamples(const Surface& surface, const PyramidLayout& layout);
    using Index = TiledIndex<2>;  // 4×4 floats per tile
    struct Level {
        float* values;
        Index index;
    };
    void buildFinest(const VertexGrid& vertices);
    void buildCoarser(int level);

    PyramidLayout m_layout;
    std::vector<float> m_values;  // all levels, finest first, tiled
    std::array<Level, PyramidLayout::kMaxLevels> m_levels{};
};

// The bits encoding (header): the stored value of a node max m, and a stored value decoded.
inline constexpr float kPyramidDecodeMargin = 1.0f / float(1 << 20);
float encodePyramidMax(float max, float depth, int bits);
inline float decodePyramidCode(float value, float depth) {
    return value * depth * (1.0f + kPyramidDecodeMargin);
}

// The pyramid to trace with: from input.maps (checked) or built now (max_pyramid_maps.cpp),
// at the row's `bits` (32 for rows without one); with box-surface = 2 the texel-box one (maps
// baked with box-surface = 2 only, and back; bits 32 only: its level 0 is the surface).
struct TechniqueInput;
class ParamValues;
int pyramidBits(const ParamValues& params);
Result<std::shared_ptr<const MaxPyramid>> maxPyramidFor(const TechniqueInput& input);
// input's pyramid as the baked maps of `technique` ("quadtree", "maxmip").
Result<TechniqueMaps> maxPyramidMaps(const TechniqueInput& input, std::string_view technique);

}  // namespace relief
