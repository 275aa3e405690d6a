// The bricks generator (issue 19): mortar below the stones, a matching colour map, deterministic
// from the seed.
#include <relief/core/generators.h>

#include <gtest/gtest.h>

namespace relief {
namespace {

TEST(BricksGenerator, MortarLiesBelowTheStones) {
    const Heightfield hf = *generateHeightfield("bricks", 256, 256, 3);
    const ImageRgb8 color = *generateColorMap("bricks", 256, 256, 3);
    // 256 texels: 10 courses 25.6 texels high, 5 bricks per course 51.2 wide; row 0 is the joint
    // below the first course, column 0 the joint between two of its bricks.
    float mortar = 0.0f, stone = 1.0f;
    for (int i = 0; i < 256; ++i) mortar = std::max(mortar, hf.at(i, 0));
    for (int j = 0; j < 256; ++j)
        if (int((j + 0.5) / 25.6) % 2 == 0) mortar = std::max(mortar, hf.at(0, j));
    for (int b = 0; b < 5; ++b) stone = std::min(stone, hf.at(int(51.2 * b + 25.6), 12));
    EXPECT_LT(mortar, 0.2f);
    EXPECT_GT(stone, 0.7f);
    // The colour map follows: grey mortar, reddish stones.
    EXPECT_NEAR(color.at(10, 0).x, color.at(10, 0).z, 30);
    EXPECT_GT(int(color.at(25, 12).x), int(color.at(25, 12).z) + 40);
}

TEST(BricksGenerator, DeterministicFromTheSeed) {
    const Heightfield a = *generateHeightfield("bricks", 96, 64, 7);
    const Heightfield b = *generateHeightfield("bricks", 96, 64, 7);
    const Heightfield c = *generateHeightfield("bricks", 96, 64, 8);
    EXPECT_EQ(a.samples, b.samples);
    EXPECT_NE(a.samples, c.samples);
    EXPECT_EQ(generateColorMap("bricks", 96, 64, 7)->pixels,
              generateColorMap("bricks", 96, 64, 7)->pixels);
    for (float v : a.samples) {
        EXPECT_GE(v, 0.0f);
        EXPECT_LE(v, 1.0f);
    }
}

TEST(BricksGenerator, ColourMapsOnlyWhereAGeneratorHasOne) {
    EXPECT_TRUE(generateColorMap("bricks", 8, 8));
    const auto none = generateColorMap("fbm", 8, 8);
    ASSERT_FALSE(none);
    EXPECT_NE(none.error().message.find("generators with one: bricks"), std::string::npos);
}

}  // namespace
}  // namespace relief
