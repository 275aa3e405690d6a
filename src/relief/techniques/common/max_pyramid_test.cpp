// The max pyramid's invariant by brute force: every node equals the max of the corner samples of
// the cells it covers, and is ≥ S sampled densely over its footprint (odd sizes, both modes).
#include <gtest/gtest.h>
#include <relief/techniques/common/max_pyramid.h>
#include <support/walk_test_support.h>

#include <chrono>
#include <cmath>

namespace relief {
namespace {

using walk_test::MapSpec;

// Brute-force max of the corners of cells [lo, hi) × [loY, hiY) (pyramid indices).
float cornerMax(const Surface& s, const PyramidLayout& layout, int lo, int hi, int loY, int hiY) {
    float m = -kInfinity;
    for (int l = loY; l < hiY; ++l)
        for (int k = lo; k < hi; ++k) {
            const CellCorners c = s.cellCorners(layout.firstCell + k, layout.firstCell + l);
            m = std::max({m, c.z00, c.z10, c.z01, c.z11});
        }
    return m;
}

// Max of S over the footprint of cells [lo, hi) × [loY, hiY), sampled 6 times per cell and axis
// (clamp: clipped to the box).
float sampledMaxS(const Surface& s, const PyramidLayout& layout, int lo, int hi, int loY, int hiY) {
    auto range = [&](int a, int b, float size) {
        float x0 = float(layout.firstCell + a) + 0.5f, x1 = float(layout.firstCell + b) + 0.5f;
        if (!layout.repeat) x0 = std::max(x0, 0.0f), x1 = std::min(x1, size);
        return std::pair{x0, x1};
    };
    const auto [x0, x1] = range(lo, hi, float(s.width()));
    const auto [y0, y1] = range(loY, hiY, float(s.height()));
    const int nx = 6 * (hi - lo), ny = 6 * (hiY - loY);
    float m = -kInfinity;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
            m = std::max(m, s.heightAt(x0 + (x1 - x0) * float(i) / float(nx),
                                       y0 + (y1 - y0) * float(j) / float(ny)));
    return m;
}

class MaxPyramidInvariant : public ::testing::TestWithParam<MapSpec> {};

TEST_P(MaxPyramidInvariant, NodesBoundSAndEqualTheirCornerMax) {
    const auto surface = walk_test::makeSurface(GetParam(), 7);
    const MaxPyramid pyramid(*surface);
    const PyramidLayout& layout = pyramid.layout();
    const bool repeat = GetParam().edge == EdgeMode::Repeat;
    EXPECT_EQ(layout.cellsX, surface->width() + (repeat ? 0 : 1));
    EXPECT_EQ(layout.widthAt(layout.topLevel()), 1);
    EXPECT_EQ(layout.heightAt(layout.topLevel()), 1);
    EXPECT_EQ(pyramid.at(layout.topLevel(), 0, 0),
              cornerMax(*surface, layout, 0, layout.cellsX, 0, layout.cellsY));
    for (int level = 0; level < layout.levels; ++level)
        for (int ny = 0; ny < layout.heightAt(level); ++ny)
            for (int nx = 0; nx < layout.widthAt(level); ++nx) {
                const int lo = nx << level, hi = std::min(lo + (1 << level), layout.cellsX);
                const int loY = ny << level, hiY = std::min(loY + (1 << level), layout.cellsY);
                const float value = pyramid.at(level, nx, ny);
                ASSERT_EQ(value, cornerMax(*surface, layout, lo, hi, loY, hiY))
                    << "level " << level << " node " << nx << "," << ny;
                ASSERT_GE(value, sampledMaxS(*surface, layout, lo, hi, loY, hiY))
                    << "level " << level << " node " << nx << "," << ny;
            }
}

// bits 16 / 8: every node's code is on the grid k / (2^bits − 1), decodes to ≥ the node's float
// max, and to less than one code step (plus the decode margin) above it; the pyramid read back
// from the codes is the one rounded up in memory, node for node.
TEST_P(MaxPyramidInvariant, CodesRoundUpAndReadBackAsRoundedUp) {
    const auto surface = walk_test::makeSurface(GetParam(), 7);
    const MaxPyramid exact(*surface);
    const PyramidLayout& layout = exact.layout();
    const float depth = surface->depth();
    for (int bits : {8, 16}) {
        const float top = float((1u << bits) - 1u);
        TechniqueMaps maps;
        maps.technique = "maxmip";
        maps.arrays = exact.toArrays(bits, depth);
        auto read = MaxPyramid::fromArrays(*surface, maps, bits);
        ASSERT_TRUE(read) << read.error().message;
        MaxPyramid rounded(*surface);
        rounded.roundUp(bits, depth);
        for (int level = 0; level < layout.levels; ++level) {
            const MapArray& a = maps.arrays[size_t(level)];
            for (int ny = 0; ny < layout.heightAt(level); ++ny)
                for (int nx = 0; nx < layout.widthAt(level); ++nx) {
                    const float code = a.data[size_t(ny) * size_t(a.width) + size_t(nx)];
                    const float m = exact.at(level, nx, ny), up = read->at(level, nx, ny);
                    ASSERT_EQ(code, std::round(code * top) / top) << bits << " bits";
                    ASSERT_GE(up, m) << bits << " bits, level " << level;
                    ASSERT_LE(up, m + depth * (1.0f / top + 2e-6f)) << bits << " bits";
                    ASSERT_EQ(up, rounded.at(level, nx, ny)) << bits << " bits";
                }
        }
    }
}

const MapSpec kPyramidMaps[] = {
    {"fbm", 5, 7, EdgeMode::Clamp, 0.5f},      {"spikes", 33, 17, EdgeMode::Clamp, 0.5f},
    {"walls", 1, 1, EdgeMode::Clamp, 0.5f},    {"peaks6", 1, 9, EdgeMode::Clamp, 0.5f},
    {"terraces", 9, 1, EdgeMode::Clamp, 0.5f}, {"fbm", 16, 16, EdgeMode::Clamp, 0.5f},
    {"walls", 31, 33, EdgeMode::Clamp, 0.5f},
};

std::vector<MapSpec> pyramidMaps() {
    std::vector<MapSpec> maps;
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
        for (const MapSpec& m : kPyramidMaps)
            maps.push_back({m.generator, m.width, m.height, edge, 0.5f});
    return maps;
}

INSTANTIATE_TEST_SUITE_P(Maps, MaxPyramidInvariant, ::testing::ValuesIn(pyramidMaps()),
                         [](const auto& info) {
                             const MapSpec& m = info.param;
                             return std::string(m.generator) + "_" + std::to_string(m.width) + "x" +
                                    std::to_string(m.height) + "_" + std::string(toString(m.edge));
                         });

TEST(MaxPyramid, LayoutOfOddSizes) {
    PyramidLayout layout;
    layout.cellsX = 34;
    layout.cellsY = 18;
    layout.levels = 7;
    EXPECT_EQ(layout.widthAt(1), 17);
    EXPECT_EQ(layout.widthAt(2), 9);
    EXPECT_EQ(layout.widthAt(5), 2);
    EXPECT_EQ(layout.widthAt(6), 1);
    EXPECT_EQ(layout.heightAt(5), 1);
    EXPECT_EQ(layout.nodeCount(), size_t(34 * 18 + 17 * 9 + 9 * 5 + 5 * 3 + 3 * 2 + 2 + 1));
}

TEST(MaxPyramid, MemoryIsAboutAThirdExtra) {
    const auto repeat = walk_test::makeSurface({"flat", 256, 256, EdgeMode::Repeat, 0.1f});
    EXPECT_LT(double(MaxPyramid(*repeat).bytes()) / double(256 * 256 * sizeof(float)), 1.34);
    // Clamp: 257² cells, tiles pad each level to a multiple of 4.
    const auto clamp = walk_test::makeSurface({"flat", 256, 256, EdgeMode::Clamp, 0.1f});
    EXPECT_LT(double(MaxPyramid(*clamp).bytes()) / double(257 * 257 * sizeof(float)), 1.4);
}

}  // namespace
}  // namespace relief
