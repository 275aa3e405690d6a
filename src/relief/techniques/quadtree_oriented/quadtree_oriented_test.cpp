// quadtree-oriented: the plane of every node bounds S (brute force), fits a ramp, and the tracer
// is exact against the reference.
#include <gtest/gtest.h>
#include <support/walk_test_support.h>
#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>
#include <relief/techniques/registry.h>

namespace relief {
namespace {

using walk_test::MapSpec;

// The node's plane as the tracer evaluates it, at texel position (x, y).
float planeAt(const OrientedNode& n, int level, float x0, float y0, float x, float y) {
    const float scale = kInverseSides[size_t(level)];
    return n.c00 + (n.c10 - n.c00) * scale * (x - x0) + (n.c01 - n.c00) * scale * (y - y0);
}

// Calls f(level, nx, ny, node, x0, y0, x1, y1) for every node of levels ≥ 1 (tile 0; clamp:
// footprint clipped to the box).
template <class F>
void forEachNode(const Surface& s, const OrientedMaps& maps, F f) {
    const PyramidLayout& layout = maps.maxima->layout();
    for (int level = 1; level < layout.levels; ++level)
        for (int ny = 0; ny < layout.heightAt(level); ++ny)
            for (int nx = 0; nx < layout.widthAt(level); ++nx) {
                const int lo = nx << level, hi = std::min(lo + (1 << level), layout.cellsX);
                const int loY = ny << level, hiY = std::min(loY + (1 << level), layout.cellsY);
                const float nodeX = float(layout.firstCell + lo) + 0.5f;
                const float nodeY = float(layout.firstCell + loY) + 0.5f;
                float x0 = nodeX, x1 = float(layout.firstCell + hi) + 0.5f;
                float y0 = nodeY, y1 = float(layout.firstCell + hiY) + 0.5f;
                if (!layout.repeat) {
                    x0 = std::max(x0, 0.0f), x1 = std::min(x1, float(s.width()));
                    y0 = std::max(y0, 0.0f), y1 = std::min(y1, float(s.height()));
                }
                f(level, maps.planes.at(level, nx, ny), nodeX, nodeY, x0, x1, y0, y1);
            }
}

class OrientedInvariant : public ::testing::TestWithParam<MapSpec> {};

TEST_P(OrientedInvariant, PlaneAndMaxBoundSOverEveryNode) {
    const auto surface = walk_test::makeSurface(GetParam(), 5);
    const OrientedMaps maps(*surface);
    size_t samples = 0;
    forEachNode(*surface, maps,
                [&](int level, const OrientedNode& n, float nodeX, float nodeY, float x0, float x1,
                    float y0, float y1) {
                    const int steps = 5 * (1 << level);
                    for (int j = 0; j <= steps; ++j)
                        for (int i = 0; i <= steps; ++i) {
                            const float x = x0 + (x1 - x0) * float(i) / float(steps);
                            const float y = y0 + (y1 - y0) * float(j) / float(steps);
                            const float s = surface->heightAt(x, y);
                            ASSERT_GE(planeAt(n, level, nodeX, nodeY, x, y), s)
                                << "level " << level << " at " << x << "," << y;
                            ASSERT_GE(n.zmax, s);
                            ++samples;
                        }
                });
    EXPECT_GT(samples, 0u);
}

const MapSpec kOrientedMaps[] = {
    {"fbm", 5, 7, EdgeMode::Clamp, 0.5f},        {"spikes", 33, 17, EdgeMode::Clamp, 1.0f},
    {"peaks6", 1, 9, EdgeMode::Clamp, 0.5f},     {"ramp", 37, 21, EdgeMode::Clamp, 0.5f},
    {"terraces", 40, 40, EdgeMode::Clamp, 0.3f}, {"fbm", 5, 7, EdgeMode::Repeat, 0.5f},
    {"walls", 33, 17, EdgeMode::Repeat, 0.5f},   {"ramp", 37, 21, EdgeMode::Repeat, 0.5f},
    {"sine", 64, 64, EdgeMode::Repeat, 0.3f},
};

INSTANTIATE_TEST_SUITE_P(Maps, OrientedInvariant, ::testing::ValuesIn(kOrientedMaps),
                         [](const auto& info) {
                             const MapSpec& m = info.param;
                             return std::string(m.generator) + "_" + std::to_string(m.width) + "x" +
                                    std::to_string(m.height) + "_" + std::string(toString(m.edge));
                         });

// On a ramp (clamp, away from the flat border strips) the plane is the ramp itself.
TEST(QuadtreeOriented, PlaneFitsARamp) {
    const auto surface = walk_test::makeSurface({"ramp", 64, 64, EdgeMode::Clamp, 0.5f});
    const OrientedMaps maps(*surface);
    int checked = 0;
    forEachNode(*surface, maps,
                [&](int level, const OrientedNode& n, float nodeX, float nodeY, float x0, float x1,
                    float y0, float y1) {
                    if (x0 < 0.5f || x1 > 63.5f) return;  // touches a border strip
                    const float x = 0.5f * (x0 + x1), y = 0.5f * (y0 + y1);
                    EXPECT_NEAR(planeAt(n, level, nodeX, nodeY, x, y), surface->heightAt(x, y),
                                1e-3f);
                    ++checked;
                });
    EXPECT_GT(checked, 10);
}

auto orientedMaker(WalkLimits limits = {}) {
    return [=](const std::shared_ptr<const Surface>& surface) {
        return QuadtreeOrientedTracer(surface, std::make_shared<const OrientedMaps>(*surface),
                                      limits);
    };
}

TEST(QuadtreeOriented, ExactAgainstReference) {
    const auto tally = walk_test::contractOnAllMaps(orientedMaker(), 300, "quadtree-oriented");
    EXPECT_GE(tally.rays, 100000u);
    EXPECT_EQ(tally.wrong, 0u);
}

TEST(QuadtreeOriented, CappedCursorNeverPassesFirstHit) {
    walk_test::cursorNeverPassesFirstHit(
        [](const std::shared_ptr<const Surface>& surface, int cap) {
            return orientedMaker({cap, false})(surface);
        },
        "quadtree-oriented");
}

// Grazing a ramp: the planes follow the slope, flat maxima cannot.
TEST(QuadtreeOriented, FewerStepsThanFlatNodesOnARamp) {
    const auto surface = walk_test::makeSurface({"ramp", 256, 256, EdgeMode::Clamp, 0.2f});
    const auto oriented = orientedMaker()(surface);
    const MaxPyramid flat(*surface);
    const MaxBound bound(flat);
    int64_t stepsOriented = 0, stepsFlat = 0;
    for (int k = 0; k < 64; ++k) {
        const Ray ray{vec3(255.0f, 4.0f * k + 2.0f, 52.0f), glm::normalize(vec3(-1, 0.1f, -0.21f)),
                      kInfinity};
        stepsOriented += oriented.trace(ray).steps;
        stepsFlat += walkPyramid<Ascent::Parent>(*surface, flat.layout(), bound, ray, {}).steps;
    }
    EXPECT_LT(stepsOriented * 2, stepsFlat);
}

TEST(QuadtreeOriented, RegistryRow) {
    const TechniqueInfo* info = findTechnique("quadtree-oriented");
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(info->contract, Contract::Exact);
}

}  // namespace
}  // namespace relief
