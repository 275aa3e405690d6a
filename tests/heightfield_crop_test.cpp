// The crop of a source string (FILE@crop=X,Y,W,H): the window's samples, renormalized over it.
#include <relief/io/heightfield_crop.h>
#include <relief/render/surface_source.h>

#include <gtest/gtest.h>

namespace relief {
namespace {

// A 6×4 ramp h(i, j) = (i + 10 j) / 35: a window's min and max are its corners.
Heightfield ramp() {
    Heightfield hf{6, 4, {}};
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 6; ++i) hf.samples.push_back(float(i + 10 * j) / 35.0f);
    return hf;
}

TEST(IoCrop, WindowIsRenormalizedOverItself) {
    const Heightfield world = ramp();
    auto crop = cropHeightfield(world, {1, 2, 3, 2}, "ramp");
    ASSERT_TRUE(crop) << crop.error().message;
    ASSERT_EQ(crop->width, 3);
    ASSERT_EQ(crop->height, 2);
    // Raw values 21..23 and 31..33: the window spans 21..33.
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i) EXPECT_NEAR(crop->at(i, j), float(i + 10 * j) / 12.0f, 1e-6f) << i << "," << j;
}

TEST(IoCrop, ConstantWindowIsZeroAndWholeMapIsKept) {
    const Heightfield flat{4, 4, std::vector<float>(16, 0.7f)};
    auto zero = cropHeightfield(flat, {1, 1, 2, 2}, "flat");
    ASSERT_TRUE(zero);
    for (float v : zero->samples) EXPECT_EQ(v, 0.0f);
    const Heightfield world = ramp();
    auto whole = cropHeightfield(world, {0, 0, 6, 4}, "ramp");
    ASSERT_TRUE(whole);
    EXPECT_EQ(whole->at(0, 0), 0.0f);
    EXPECT_EQ(whole->at(5, 3), 1.0f);
}

TEST(IoCrop, WindowOutsideTheMapIsInvalidInput) {
    const Heightfield world = ramp();
    for (CropWindow w : {CropWindow{4, 0, 3, 1}, CropWindow{0, 3, 1, 2}, CropWindow{-1, 0, 2, 2},
                         CropWindow{0, 0, 0, 2}, CropWindow{2147483647, 0, 2, 2}}) {
        auto crop = cropHeightfield(world, w, "ramp");
        ASSERT_FALSE(crop) << w.x << "," << w.y << " " << w.width << "x" << w.height;
        EXPECT_EQ(crop.error().kind, ErrorKind::InvalidInput);
        EXPECT_NE(crop.error().message.find("not inside the 6x4 map"), std::string::npos) << crop.error().message;
    }
}

TEST(IoCrop, CentredWindowMovesInsideTheMap) {
    const Heightfield world = ramp();
    auto inside = cropHeightfield(world, {3, 2, 2, 2, true}, "ramp");    // corner (2, 1)
    auto moved = cropHeightfield(world, {5, 0, 4, 2, true}, "ramp");     // corner (2, 0), not (3, −1)
    auto expectedInside = cropHeightfield(world, {2, 1, 2, 2}, "ramp");
    auto expectedMoved = cropHeightfield(world, {2, 0, 4, 2}, "ramp");
    ASSERT_TRUE(inside && moved && expectedInside && expectedMoved);
    EXPECT_EQ(inside->samples, expectedInside->samples);
    EXPECT_EQ(moved->samples, expectedMoved->samples);
    auto tooLarge = cropHeightfield(world, {3, 2, 7, 2, true}, "ramp");
    ASSERT_FALSE(tooLarge);
    EXPECT_EQ(tooLarge.error().kind, ErrorKind::InvalidInput);
}

TEST(IoCrop, SourceSuffixParses) {
    auto plain = parseSourceSpec("data/a@b.png");
    ASSERT_TRUE(plain);
    EXPECT_EQ(plain->base, "data/a@b.png");
    EXPECT_FALSE(plain->crop);
    auto spec = parseSourceSpec("gen:fbm:64x64:1@crop=8,4,20,10");
    ASSERT_TRUE(spec);
    EXPECT_EQ(spec->base, "gen:fbm:64x64:1");
    EXPECT_EQ(spec->suffix, "@crop=8,4,20,10");
    ASSERT_TRUE(spec->crop);
    EXPECT_EQ(spec->crop->x, 8);
    EXPECT_EQ(spec->crop->height, 10);
    auto centred = parseSourceSpec("x.png@centre=7980,1860,64,32");
    ASSERT_TRUE(centred && centred->crop);
    EXPECT_TRUE(centred->crop->centred);
    EXPECT_EQ(centred->base, "x.png");
    EXPECT_EQ(centred->crop->width, 64);
    for (const char* bad : {"x.png@centre=1,2,3", "x.png@crop=", "x.png@crop=1,2,3", "x.png@crop=1,2,3,4,", "x.png@crop=1,2,3,4x",
                            "x.png@crop=1,,3,4", "x.png@crop=1.5,2,3,4", "x.png@crop=99999999999,0,1,1"}) {
        auto parsed = parseSourceSpec(bad);
        ASSERT_FALSE(parsed) << bad;
        EXPECT_EQ(parsed.error().kind, ErrorKind::BadArgument);
    }
}

// Through the one loader: the crop of a generated map is that map's window, renormalized.
TEST(IoCrop, LoaderCropsAfterLoading) {
    SurfaceOptions whole, window;
    whole.source = "gen:fbm:32x32:3";
    window.source = "gen:fbm:32x32:3@crop=4,8,10,6";
    auto full = loadHeightfield(whole);
    auto part = loadHeightfield(window);
    ASSERT_TRUE(full && part);
    auto expected = cropHeightfield(**full, {4, 8, 10, 6}, "fbm");
    ASSERT_TRUE(expected);
    EXPECT_EQ((*part)->samples, expected->samples);
}

}  // namespace
}  // namespace relief
