#include <relief/core/generators.h>
#include <relief/surface/surface.h>

#include <gtest/gtest.h>

namespace relief {
namespace {

std::shared_ptr<const Heightfield> makeField(std::initializer_list<float> values, int w, int h) {
    auto hf = std::make_shared<Heightfield>();
    hf->width = w;
    hf->height = h;
    hf->samples = values;
    return hf;
}

TEST(Surface, LowerDiagonalMakesAValley) {
    // 00 and 11 are low: the 00–11 diagonal is lower, S along it is the interpolation of 0 and 0.
    Surface s(makeField({0, 1, 1, 0}, 2, 2), 1.0f, EdgeMode::Clamp);
    EXPECT_FLOAT_EQ(s.heightAt(1.0f, 1.0f), 0.0f);   // cell centre lies on the 00–11 diagonal
    EXPECT_FLOAT_EQ(s.heightAt(1.5f, 0.5f), 1.0f);   // sample (1,0)
    EXPECT_FLOAT_EQ(s.heightAt(1.0f, 0.5f), 0.5f);   // centerline: bilinear
    EXPECT_FLOAT_EQ(s.bilinearZ(1.0f, 1.0f), 0.5f);  // bilinear differs inside the cell
}

TEST(Surface, ClampBorderStripsAreConstantAcross) {
    Surface s(makeField({0.2f, 0.8f, 0.4f, 0.6f}, 2, 2), 10.0f, EdgeMode::Clamp);
    EXPECT_FLOAT_EQ(s.heightAt(0.1f, 0.5f), 2.0f);
    EXPECT_FLOAT_EQ(s.heightAt(0.3f, 0.5f), 2.0f);
    EXPECT_FLOAT_EQ(s.heightAt(0.2f, 1.0f), 3.0f);  // linear along the strip
    EXPECT_FLOAT_EQ(s.heightAt(1.9f, 1.9f), 6.0f);  // flat corner square
}

TEST(Surface, RepeatWraps) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("fbm", 8, 6, 3));
    Surface s(hf, 4.0f, EdgeMode::Repeat);
    for (float x : {0.3f, 2.7f, 7.9f})
        for (float y : {0.1f, 3.3f})
            EXPECT_NEAR(s.heightAt(x, y), s.heightAt(x + 8.0f, y - 6.0f), 1e-5f);
}

}  // namespace
}  // namespace relief
