// The pruned builders (safety distances, cylinder-cones) against their reference scans:
// bit-identical maps on many small maps
// (generators, adversarial flats, spikes and coasts, crops of real terrain), every build option,
// clamp and repeat.
#include <support/safety_test_support.h>

#include <relief/io/heightfield_crop.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/safety_common/safety_maps.h>

#include <algorithm>
#include <cstring>
#include <limits>

namespace relief::safety {
namespace {

using testing::makeSurface;

std::shared_ptr<const Heightfield> fromFunction(int w, int h, float (*f)(int, int, int, int)) {
    auto hf = std::make_shared<Heightfield>();
    hf->width = w, hf->height = h;
    hf->samples.resize(size_t(w) * size_t(h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) hf->at(i, j) = f(i, j, w, h);
    return hf;
}

// Sea (one level) beside land: the case the pruning is for, where distances run long.
float coast(int i, int j, int w, int) {
    const float land = float(i - w / 2) + 3.0f * std::sin(0.7f * float(j));
    return land <= 0.0f ? 0.0f : std::min(1.0f, 0.08f * land + 0.1f * float((i * 7 + j * 3) % 5));
}
// Sea, then a one-texel cliff up to land.
float cliff(int i, int j, int w, int) { return i < w / 2 ? 0.0f : 1.0f - 0.05f * float(j % 3); }
float flat(int, int, int, int) { return 0.5f; }
float spike(int i, int j, int w, int h) { return i == w / 3 && j == h / 2 ? 1.0f : 0.0f; }
float pit(int i, int j, int w, int h) { return i == w / 2 && j == h / 3 ? 0.0f : 1.0f; }
float ridge(int i, int j, int, int) { return (i + j) % 9 == 0 ? 1.0f : 0.2f * float(j % 4); }
float island(int i, int j, int w, int h) {
    const float dx = float(i - w / 2), dy = float(j - h / 2);
    return std::max(0.0f, 1.0f - 0.01f * (dx * dx + dy * dy));
}

std::shared_ptr<const Heightfield> realCrop(const std::string& file, int x, int y, int n) {
    auto hf = loadHeightfield(std::string(RELIEF_SOURCE_DIR) + "/data/" + file);
    EXPECT_TRUE(bool(hf)) << file;
    if (!hf) return nullptr;
    auto crop = cropHeightfield(*hf, {x, y, n, n, false}, file);
    EXPECT_TRUE(bool(crop)) << file;
    return crop ? std::make_shared<const Heightfield>(*crop) : nullptr;
}

struct Case {
    std::string name;
    std::shared_ptr<const Heightfield> hf;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    auto gen = [&](const char* name, int w, int h) {
        out.push_back({name, std::make_shared<const Heightfield>(*generateHeightfield(name, w, h, 3))});
    };
    gen("fbm", 24, 20);
    gen("peaks6", 20, 20);
    gen("walls", 22, 18);
    gen("spikes", 16, 16);
    gen("terraces", 20, 24);
    out.push_back({"fig11", testing::thinFeatures(20, 20)});
    out.push_back({"coast", fromFunction(40, 28, coast)});
    out.push_back({"flat", fromFunction(18, 18, flat)});
    out.push_back({"spike", fromFunction(30, 22, spike)});
    out.push_back({"pit", fromFunction(20, 20, pit)});
    out.push_back({"ridge", fromFunction(26, 26, ridge)});
    out.push_back({"island", fromFunction(33, 29, island)});
    // Coasts of the world map (flat sea) and a mountain DEM.
    out.push_back({"earth coast", realCrop("earth-topology-2048x1024.png", 700, 330, 40)});
    out.push_back({"earth sea", realCrop("earth-topology-2048x1024.png", 100, 500, 36)});
    out.push_back({"colorado", realCrop("colorado-elevation-400.png", 150, 150, 32)});
    return out;
}

// Every option once: all rays, both φ_max signs, isotropic, a short cap, exterior rays.
std::vector<BuildOptions> optionSets(EdgeMode edge) {
    auto make = [](double phi, bool iso, int maxDistance, bool exterior, bool exteriorSlope) {
        BuildOptions o;
        o.phiMaxDeg = phi, o.isotropic = iso, o.maxDistance = maxDistance;
        o.exterior = exterior, o.exteriorSlope = exteriorSlope;
        return o;
    };
    std::vector<BuildOptions> out = {make(90.0, false, kMaxDistance, false, false),
                                     make(30.0, true, kMaxDistance, false, false),
                                     make(-45.0, false, kMaxDistance, false, false),
                                     make(90.0, true, 9, false, false)};
    if (edge == EdgeMode::Clamp) {
        out.push_back(make(90.0, false, kMaxDistance, true, false));
        out.push_back(make(-45.0, false, kMaxDistance, true, true));
    }
    return out;
}

TEST(SafetyBuild, PrunedMapsEqualReference) {
    size_t texels = 0, maps = 0;
    for (const Case& c : cases()) {
        ASSERT_TRUE(c.hf) << c.name;
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (float ratio : {0.05f, 0.3f}) {
                const Surface s(c.hf, ratio * float(std::max(c.hf->width, c.hf->height)), edge);
                for (const BuildOptions& o : optionSets(edge)) {
                    const DistanceMap fast = buildDistanceMap(s, o);
                    const DistanceMap ref = buildDistanceMapReference(s, o);
                    ASSERT_EQ(fast.classes, ref.classes);
                    size_t differ = 0;
                    for (size_t k = 0; k < ref.r.size(); ++k) differ += fast.r[k] != ref.r[k];
                    EXPECT_EQ(differ, 0u) << c.name << " " << toString(edge) << " depth " << ratio
                                          << " phi " << o.phiMaxDeg << " iso " << o.isotropic
                                          << " max " << o.maxDistance << " ext " << o.exterior
                                          << o.exteriorSlope;
                    texels += ref.r.size();
                    ++maps;
                    const CylinderConeMap cones = buildConeMap(s, ref, o);
                    const CylinderConeMap coneRef = buildConeMapReference(s, ref, o);
                    ASSERT_EQ(cones.texels.size(), coneRef.texels.size());
                    EXPECT_EQ(std::memcmp(cones.texels.data(), coneRef.texels.data(),
                                          cones.texels.size() * sizeof(ConeTexel)),
                              0)
                        << c.name << " " << toString(edge) << " cones";
                }
            }
    }
    std::printf("[ safety   ] pruned = reference on %zu distance maps (%zu texel-classes)\n", maps,
                texels);
}

// A wide sea against a cliff as high as the map is wide: where a rounding allowance for the
// whole map (from its steepest cell) outgrew isLimiting's eps, so that no sea cell was ever
// dismissed; with each cell's own allowance they are, and the maps must still be the reference's.
TEST(SafetyBuild, SteepCliffBesideWideSea) {
    const auto hf = fromFunction(320, 4, cliff);
    for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
        const Surface s(hf, 320.0f, edge);
        for (const BuildOptions& o : optionSets(edge)) {
            if (o.isotropic) continue;
            const DistanceMap fast = buildDistanceMap(s, o);
            const DistanceMap ref = buildDistanceMapReference(s, o);
            ASSERT_EQ(fast.classes, ref.classes);
            size_t differ = 0;
            for (size_t k = 0; k < ref.r.size(); ++k) differ += fast.r[k] != ref.r[k];
            EXPECT_EQ(differ, 0u) << toString(edge) << " phi " << o.phiMaxDeg << " ext "
                                  << o.exterior << o.exteriorSlope;
        }
    }
}

// Smooth ground, where the plane bound's column blocks (each cell's planes taken at the block's
// centre row) do the dismissing and distances run long: a tilted plane (there the block bound is
// the plane itself, S + rounding, right at isLimiting's eps) with a ridge at its far end, a
// smooth hill, gentle waves and peaks6 on maps wide enough for blocks of 16 and 32 rows.
float tiltedPlane(int i, int j, int w, int) {
    return i > w - 4 ? 1.0f : 0.3f + 0.004f * float(j) - 0.002f * float(i);
}
float waves(int i, int j, int, int) {
    return 0.5f + 0.25f * std::sin(0.21f * float(i)) * std::cos(0.17f * float(j)) + 0.002f * float(j);
}
float hill(int i, int j, int w, int h) {
    const float dx = float(i - w / 3) / float(w), dy = float(j - h / 2) / float(h);
    return 1.0f / (1.0f + 12.0f * (dx * dx + dy * dy));
}

TEST(SafetyBuild, SmoothGroundColumnBlocksEqualReference) {
    const std::vector<Case> smooth = {
        {"tilted plane", fromFunction(72, 40, tiltedPlane)},
        {"hill", fromFunction(64, 48, hill)},
        {"waves", fromFunction(70, 52, waves)},
        {"peaks6", std::make_shared<const Heightfield>(*generateHeightfield("peaks6", 64, 64, 5))}};
    for (const Case& c : smooth)
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (float ratio : {0.05f, 0.2f}) {
                const Surface s(c.hf, ratio * float(std::max(c.hf->width, c.hf->height)), edge);
                for (const BuildOptions& o : optionSets(edge)) {
                    if (o.isotropic || o.exterior) continue;  // same scan, other ray sets
                    const DistanceMap fast = buildDistanceMap(s, o);
                    const DistanceMap ref = buildDistanceMapReference(s, o);
                    size_t differ = 0;
                    for (size_t k = 0; k < ref.r.size(); ++k) differ += fast.r[k] != ref.r[k];
                    EXPECT_EQ(differ, 0u) << c.name << " " << toString(edge) << " depth "
                                          << ratio << " phi " << o.phiMaxDeg;
                }
            }
}

// The bake's arrays, built without the map, are the arrays of the map.
TEST(SafetyBuild, ConeArraysEqualMapArrays) {
    for (const Case& c : cases()) {
        ASSERT_TRUE(c.hf) << c.name;
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            const Surface s(c.hf, 0.1f * float(std::max(c.hf->width, c.hf->height)), edge);
            for (const BuildOptions& o : optionSets(edge)) {
                const DistanceMap radii = buildDistanceMap(s, o);
                const TechniqueMaps want = coneMapToArrays("safety-cc", buildConeMap(s, radii, o), o);
                const TechniqueMaps got = buildConeArrays("safety-cc", s, radii, o);
                EXPECT_EQ(got.parameters, want.parameters);
                ASSERT_EQ(got.arrays.size(), want.arrays.size()) << c.name;
                for (size_t a = 0; a < want.arrays.size(); ++a) {
                    const MapArray &g = got.arrays[a], &w = want.arrays[a];
                    EXPECT_EQ(g.name, w.name);
                    EXPECT_EQ(g.width * 100000 + g.height * 10 + g.channels,
                              w.width * 100000 + w.height * 10 + w.channels);
                    ASSERT_EQ(g.data.size(), w.data.size());
                    EXPECT_EQ(std::memcmp(g.data.data(), w.data.data(), w.data.size() * sizeof(float)), 0)
                        << c.name << " " << toString(edge) << " " << w.name;
                }
            }
        }
    }
}

// The N-buffer (which keeps no levels under 4 samples) against the samples read one by one: each
// texel's cylinder top z_c is the highest sample of its windows at abscissas r and r + 1
// (rows b0 ± (x + 2), clipped at the border or wrapped), plus the builder's rounding margin.
TEST(SafetyBuild, ConeTopsAreWindowMaxima) {
    size_t texels = 0;
    for (const Case& c : cases()) {
        ASSERT_TRUE(c.hf) << c.name;
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            const Surface s(c.hf, 0.3f * float(std::max(c.hf->width, c.hf->height)), edge);
            const BuildOptions o;
            const CylinderConeMap map = buildConeMap(s, buildDistanceMap(s, o), o);
            const bool repeat = edge == EdgeMode::Repeat;
            for (int cls = 0; cls < kClassCount; ++cls) {
                const Frame f{cls};
                const bool xClass = cls < kYPlus;
                const int lines = xClass ? s.width() : s.height();
                const int length = xClass ? s.height() : s.width();
                auto wrap = [](int v, int n) { return ((v % n) + n) % n; };
                for (int j = 0; j < s.height(); ++j)
                    for (int i = 0; i < s.width(); ++i) {
                        const ConeTexel& t = map.at(cls, i, j);
                        int a0, b0;
                        f.texel(i, j, a0, b0);
                        float top = -std::numeric_limits<float>::infinity();
                        for (int x = t.r; x <= t.r + 1; ++x) {
                            double X, Y;
                            f.world(a0 + x, 0, X, Y);
                            int line = xClass ? int(X) : int(Y);
                            line = repeat ? wrap(line, lines) : std::clamp(line, 0, lines - 1);
                            for (int b = b0 - x - 2; b <= b0 + x + 2; ++b) {
                                if (!repeat && (b < 0 || b >= length)) continue;
                                const int row = repeat ? wrap(b, length) : b;
                                top = std::max(top, xClass ? s.sampleZ(line, row) : s.sampleZ(row, line));
                            }
                        }
                        top += 1e-6f * (1.0f + s.maxZ());  // as the builder rounds it up
                        EXPECT_EQ(t.zc, top) << c.name << " " << toString(edge) << " class " << cls
                                             << " texel " << i << "," << j;
                        ++texels;
                    }
            }
        }
    }
    std::printf("[ safety   ] cylinder tops = window maxima on %zu texel-classes\n", texels);
}

}  // namespace
}  // namespace relief::safety
