#pragma once
// The canonical surface S (DESIGN §2): sample (i,j) is the vertex (i+0.5, j+0.5, D·h[i][j]); each
// cell between four neighbouring samples is split along its lower diagonal, so inside a cell S is
// the maximum of two planes (a convex valley). In clamp mode the relief is a solid filling the
// box [0,W]×[0,H]×[0,D] below S, with the half-texel border strips extended outward; in repeat
// mode cells wrap and the box is infinite in x and y.
//
// Cell (ci, cj) spans x in [ci+0.5, ci+1.5], y in [cj+0.5, cj+1.5]. In clamp mode cells -1..W-1
// cover the box (cell -1 and cell W-1 are the border strips); in repeat mode any integer cell is
// valid and wraps modulo W, H.
#include <relief/core/check.h>
#include <relief/core/heightfield.h>
#include <relief/core/math.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace relief {

enum class EdgeMode { Clamp, Repeat };
std::string_view toString(EdgeMode mode);

// Index of the texel (per-texel map entry) in [0, n) for any integer i: clamped or wrapped.
inline int texelIndex(int i, int n, EdgeMode edge) {
    if (edge == EdgeMode::Clamp) return i < 0 ? 0 : (i >= n ? n - 1 : i);
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// A plane z = z0 + sx·u + sy·v over a cell's local coordinates u = x - (ci+0.5), v = y - (cj+0.5).
struct CellPlane {
    float z0, sx, sy;
    float at(float u, float v) const { return z0 + sx * u + sy * v; }
};

// The two triangle planes of a cell; S = max(first, second) over the cell.
struct CellPlanes {
    CellPlane first, second;
    float at(float u, float v) const { return std::max(first.at(u, v), second.at(u, v)); }
};

// The four corner heights of a cell, in texel units (already scaled by D).
struct CellCorners {
    float z00, z10, z01, z11;
};

inline CellPlanes planesFromCorners(const CellCorners& c) {
    if (c.z00 + c.z11 <= c.z10 + c.z01) {  // 00–11 is the lower diagonal (ties included)
        return {{c.z00, c.z10 - c.z00, c.z11 - c.z10}, {c.z00, c.z11 - c.z01, c.z01 - c.z00}};
    }
    return {{c.z00, c.z10 - c.z00, c.z01 - c.z00},
            {c.z10 + c.z01 - c.z11, c.z11 - c.z01, c.z11 - c.z10}};
}

// The interval of a ray inside the relief's box (clamp) or its z slab (repeat), clipped to
// [0, ray.tMax]. Empty when tEnter > tExit.
struct RayInterval {
    float tEnter = 0.0f;
    float tExit = -1.0f;
    bool empty() const { return !(tEnter <= tExit); }
};

class Surface {
public:
    // In repeat mode a ray that stays inside the z slab is followed for at most this many times
    // max(W, H) texels of horizontal travel (a ray parallel to the base could go on forever).
    static constexpr float kRepeatTravelFactor = 8.0f;

    Surface(std::shared_ptr<const Heightfield> heightfield, float depth, EdgeMode edge);

    int width() const { return m_width; }
    int height() const { return m_height; }
    float depth() const { return m_depth; }
    EdgeMode edge() const { return m_edge; }
    float maxZ() const { return m_maxZ; }
    const Heightfield& heightfield() const { return *m_heightfield; }
    std::shared_ptr<const Heightfield> heightfieldPtr() const { return m_heightfield; }
    // The (W+2)×(H+2) heights D·h, row-major; entry (i+1, j+1) is sample (i, j) for i in [-1, W],
    // j in [-1, H] (clamped or wrapped by the edge mode). The GL backend uploads it as is.
    std::span<const float> paddedHeights() const { return m_padded; }

    // Height D·h of sample (i, j) for any integer i, j (clamped or wrapped by the edge mode).
    float sampleZ(int i, int j) const {
        return m_padded[size_t(wrapRow(j) + 1) * size_t(m_width + 2) + size_t(wrapColumn(i) + 1)];
    }
    // Corners of cell (ci, cj); ci in [-1, W-1] for clamp, any integer for repeat.
    CellCorners cellCorners(int ci, int cj) const {
        const int i = cellColumn(ci) + 1, j = cellRow(cj) + 1;
        const size_t stride = size_t(m_width + 2);
        const float* row0 = &m_padded[size_t(j) * stride + size_t(i)];
        const float* row1 = row0 + stride;
        return {row0[0], row0[1], row1[0], row1[1]};
    }
    CellPlanes cellPlanes(int ci, int cj) const { return planesFromCorners(cellCorners(ci, cj)); }

    // S(x, y), exact: the max of the containing cell's two planes.
    float heightAt(float x, float y) const;
    // What a GPU bilinear texture fetch of the height map returns at (x, y), times D. Equals S on
    // centerlines; approximate methods use it as their height lookup.
    float bilinearZ(float x, float y) const;
    // The shading normal at a point of the solid: the plane that is highest there, or the box wall
    // when the point lies on a side face below S (clamp mode).
    vec3 normalAt(const vec3& p) const;

    RayInterval clip(const Ray& ray) const;

    // Float tracers lose the ray when its origin is far from the box (1e12 texels away a float
    // step is 65536 texels). Beyond kNearBoxFactor·max(W, H, D) outside the box, the ray is moved
    // in double precision to just before where it enters the box (repeat: its z slab, and x, y
    // wrapped by whole periods); `offset` is how far it moved, to add to the hit's t. A ray that
    // misses the box comes back with tMax 0 (clip: empty); a near one comes back as it is.
    static constexpr double kNearBoxFactor = 4.0;
    Ray nearBox(const Ray& ray, double& offset) const;
    // clip() misses rays whose origin is beyond this (float ulp 32 texels): nothing traced from
    // there lands inside the box reliably; nearBox() them first.
    static constexpr float kMaxOriginCoordinate = float(1 << 28);

    // Cell index containing coordinate x (cells start at k+0.5), clamped to the valid range.
    int cellOfX(float x) const { return clampCellX(int(std::floor(x - 0.5f))); }
    int cellOfY(float y) const { return clampCellY(int(std::floor(y - 0.5f))); }

private:
    int wrapColumn(int i) const;
    int wrapRow(int j) const;
    int cellColumn(int ci) const;
    int cellRow(int cj) const;
    int clampCellX(int ci) const;
    int clampCellY(int cj) const;

    std::shared_ptr<const Heightfield> m_heightfield;
    int m_width, m_height;
    float m_depth;
    EdgeMode m_edge;
    float m_maxZ = 0.0f;
    std::vector<float> m_padded;  // (W+2)×(H+2) heights, one border sample on each side
};

inline int Surface::wrapColumn(int i) const {
    if (m_edge == EdgeMode::Clamp) return std::clamp(i, -1, m_width);
    const int r = i % m_width;
    return r < 0 ? r + m_width : r;
}
inline int Surface::wrapRow(int j) const {
    if (m_edge == EdgeMode::Clamp) return std::clamp(j, -1, m_height);
    const int r = j % m_height;
    return r < 0 ? r + m_height : r;
}
// Cells read corners (ci, ci+1); the padded row holds -1..W so the wrapped ci stays in [-1, W-1].
inline int Surface::cellColumn(int ci) const {
    if (m_edge == EdgeMode::Clamp) {
        RELIEF_DCHECK(ci >= -1 && ci <= m_width - 1);
        return ci;
    }
    return wrapColumn(ci);
}
inline int Surface::cellRow(int cj) const {
    if (m_edge == EdgeMode::Clamp) {
        RELIEF_DCHECK(cj >= -1 && cj <= m_height - 1);
        return cj;
    }
    return wrapRow(cj);
}
inline int Surface::clampCellX(int ci) const {
    return m_edge == EdgeMode::Clamp ? std::clamp(ci, -1, m_width - 1) : ci;
}
inline int Surface::clampCellY(int cj) const {
    return m_edge == EdgeMode::Clamp ? std::clamp(cj, -1, m_height - 1) : cj;
}

}  // namespace relief
