// qdm variant `paper`: the fast builder against the paper's Θ(N⁴) builder (bit for bit), the
// convex-bound search against the plain one, the map on a hand-checked spike, and Algorithm 1's
// step (line and parabola).
#include <support/cone_test_support.h>

#include <relief/core/generators.h>
#include <relief/io/heightfield_crop.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/qdm/qdm_paper.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>

namespace relief {
namespace {

TEST(QdmPaperMap, FastBuilderEqualsThePapersBuilder) {
    for (const char* g : {"fbm", "walls", "terraces", "spikes", "peaks6", "sine", "ramp", "flat"})
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (float ratio : {0.2f, 0.5f, 0.0f})
                for (float maxDistance : {0.0f, 3.0f})
                    for (auto [w, h] : {std::pair{13, 10}, std::pair{24, 17}}) {
                        const auto s = testing::makeSurface(g, w, h, edge);
                        QdmBuildParams params{ratio, maxDistance, false};
                        params.paper = true;
                        const auto brute = buildQdmPaperBruteForce(*s, params);
                        const auto fast = buildQdmPaper(*s, params);
                        params.ringWalkBudget = 0;  // the cone from its last record everywhere
                        const auto probed = buildQdmPaper(*s, params);
                        params.convexBound = true;
                        const auto convex = buildQdmPaperBruteForce(*s, params);
                        ASSERT_EQ(fast.size(), brute.size());
                        size_t differ = 0;
                        for (size_t k = 0; k < fast.size(); ++k) {
                            differ += std::memcmp(&fast[k], &brute[k], sizeof(QdmTexel)) != 0;
                            differ += std::memcmp(&probed[k], &brute[k], sizeof(QdmTexel)) != 0;
                            // The same c in exact arithmetic (the parabola is concave).
                            ASSERT_EQ(convex[k].a, brute[k].a);
                            ASSERT_EQ(convex[k].b, brute[k].b);
                            ASSERT_NEAR(convex[k].c, brute[k].c,
                                        1e-5f * (1.0f + std::abs(brute[k].c)));
                        }
                        EXPECT_EQ(differ, 0u)
                            << g << " " << toString(edge) << " ratio " << ratio << " max-distance "
                            << maxDistance << " " << w << "x" << h;
                    }
}

// The cone from its last record (the default, and with no ring walk before it) against the
// ring-by-ring walk: the same map bit for bit, on generators, adversarial maps (a bowl and a ramp rising every ring, gently rising
// ground whose ring slopes tie within the rounding bound, terraces and planes with exact ties,
// flat sea beside land, a lone spike) and crops of real terrain, clamp and repeat, several
// height ratios and max-distance.
TEST(QdmPaperMap, SkippingRingsChangesNothing) {
    using Field = std::function<float(int, int, int, int)>;
    auto fromFunction = [](int w, int h, const Field& f) {
        Heightfield hf{w, h, std::vector<float>(size_t(w) * size_t(h))};
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) hf.at(i, j) = f(i, j, w, h);
        return std::make_shared<const Heightfield>(std::move(hf));
    };
    auto radius2 = [](int i, int j, int w, int h) {
        const float dx = float(i - w / 2), dy = float(j - h / 2);
        return dx * dx + dy * dy;
    };
    auto crop = [](const std::string& file, int x, int y, int n) {
        auto hf = loadHeightfield(std::string(RELIEF_SOURCE_DIR) + "/data/" + file);
        EXPECT_TRUE(bool(hf)) << file;
        auto cut = cropHeightfield(*hf, {x, y, n, n, false}, file);
        EXPECT_TRUE(bool(cut)) << file;
        return std::make_shared<const Heightfield>(*cut);
    };
    std::vector<std::pair<std::string, std::shared_ptr<const Heightfield>>> maps;
    for (const char* g : {"peaks6", "fbm", "sine", "ramp", "terraces", "walls", "spikes", "flat"})
        maps.push_back({g, std::make_shared<const Heightfield>(*generateHeightfield(g, 40, 36, 3))});
    maps.push_back({"bowl", fromFunction(41, 37, [&](int i, int j, int w, int h) {
                        return radius2(i, j, w, h) / float(w * w);
                    })});
    maps.push_back({"gentle", fromFunction(44, 40, [&](int i, int j, int w, int h) {
                        return 0.5f + 1e-4f * std::sqrt(radius2(i, j, w, h)) +
                               1e-7f * radius2(i, j, w, h);
                    })});
    maps.push_back({"plane", fromFunction(36, 36, [](int i, int j, int, int) {
                        return float(i + 2 * j) / 108.0f;
                    })});
    maps.push_back({"coast", fromFunction(48, 30, [](int i, int j, int w, int) {
                        const float land = float(i - w / 2) + 3.0f * std::sin(0.7f * float(j));
                        return land <= 0.0f ? 0.0f : std::min(1.0f, 0.03f * land);
                    })});
    maps.push_back({"spike", fromFunction(30, 22, [](int i, int j, int w, int h) {
                        return i == w / 3 && j == h / 2 ? 1.0f : 0.0f;
                    })});
    maps.push_back({"earth coast", crop("earth-topology-2048x1024.png", 700, 330, 48)});
    maps.push_back({"earth sea", crop("earth-topology-2048x1024.png", 100, 500, 40)});
    maps.push_back({"colorado", crop("colorado-elevation-400.png", 150, 150, 48)});
    maps.push_back({"finland", crop("finland-topography-400-16bit.png", 100, 120, 48)});
    size_t texels = 0;
    for (const auto& [name, hf] : maps)
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat})
            for (float ratio : {0.2f, 0.5f, 1.0f, 0.0f})
                for (float maxDistance : {0.0f, 7.0f}) {
                    const Surface s(hf, 0.1f * float(hf->width), edge);
                    QdmBuildParams params{ratio, maxDistance, true};
                    params.paper = true;
                    params.skipRings = false;
                    const auto walked = buildQdmPaper(s, params);
                    params.skipRings = true;
                    for (int64_t budget : {int64_t(-1), int64_t(0)}) {  // default; probes only
                        params.ringWalkBudget = budget;
                        const auto skipped = buildQdmPaper(s, params);
                        ASSERT_EQ(walked.size(), skipped.size());
                        size_t differ = 0;
                        for (size_t k = 0; k < walked.size(); ++k)
                            differ += std::memcmp(&walked[k], &skipped[k], sizeof(QdmTexel)) != 0;
                        texels += walked.size();
                        EXPECT_EQ(differ, 0u) << name << " " << toString(edge) << " ratio " << ratio
                                              << " max-distance " << maxDistance << " budget "
                                              << budget;
                    }
                }
    EXPECT_GT(texels, 100000u);
}

// One spike of height z at the centre of a flat 5×5 map (clamp). From sample (0, 2), two rings
// from the spike: m(1) = 0, m(2) = z, m(3) = m(4) = 0 (ring 4: the far corners, √20). Cone:
// b = max(1·0, 0) = 0 at a = 1, then b = max(2·0, z) = z > 0.2·z at a = 2: (a, b) = (2, z).
// c = max(c_3, c_4) with c_j = (2 + j)/2 − z / (2(j − 2)): max(2.5 − z/2, 3 − z/4).
TEST(QdmPaperMap, SpikeMatchesTheDefinition) {
    std::vector<float> values(25, 0.0f);
    values[2 * 5 + 2] = 1.0f;
    const auto hf = std::make_shared<const Heightfield>(Heightfield{5, 5, values});
    const float depth = 3.0f;
    const Surface s(hf, depth, EdgeMode::Clamp);
    QdmBuildParams params;
    params.paper = true;
    const auto texels = buildQdmPaperBruteForce(s, params);
    const QdmTexel& q = texels[2 * 5 + 0];
    const float z = depth;
    EXPECT_EQ(q.h, 0.0f);
    EXPECT_EQ(q.a, 2.0f);
    EXPECT_EQ(q.b, z);
    EXPECT_FLOAT_EQ(q.c, std::max(2.5f - z / 2.0f, 3.0f - z / 4.0f));
    const auto fast = buildQdmPaper(s, params);
    EXPECT_EQ(std::memcmp(&fast[2 * 5], &q, sizeof(QdmTexel)), 0);
    // The spike itself: everything lower, so the cone never rises and reaches the last ring.
    const QdmTexel& top = texels[2 * 5 + 2];
    EXPECT_EQ(top.h, z);
    EXPECT_EQ(top.a, 2.0f);  // √8 → ring 2, the last
    EXPECT_EQ(top.b, 0.0f);
    EXPECT_EQ(top.c, top.a);  // no ring beyond a
}

// Algorithm 1: the line to (a, b) while alpha ≤ 1, else the parabola's smaller root.
TEST(QdmPaperTracer, StepIsAlgorithmOne) {
    const QdmTexel q{2.0f, 1.0f, 3.0f, 0.0f};
    const float hv = 0.8f, dz = -0.6f;
    const float line = paperStep(q, 2.0f, hv, dz);
    EXPECT_FLOAT_EQ(line, 2.0f);  // x = 1.6 ≤ a, where 2 − 0.6 t = (b / a) 0.8 t
    const float t = paperStep(q, 3.0f, hv, dz);
    const float x = hv * t;
    ASSERT_GT(x, q.a);
    EXPECT_NEAR(3.0f + dz * t, -(x - q.c) * (x - q.c) + q.b + (q.c - q.a) * (q.c - q.a), 1e-4f);
    // Past the top the parabola descends: a ray high above it misses (no real root).
    EXPECT_EQ(paperStep(q, 5.0f, hv, dz), kInfinity);
}

// What c = max c_j makes of the parabola (docs/qdm.md): set by the farthest rings, it leaves
// (a, b) far steeper than the cone part on the standard generators (printed for the doc).
TEST(QdmPaperMap, ParabolaLeavesTheConeSteeply) {
    for (const char* g : {"fbm", "sine", "terraces"}) {
        const auto hf = std::make_shared<const Heightfield>(*generateHeightfield(g, 128, 128, 1));
        const auto s = std::make_shared<const Surface>(hf, 12.8f, EdgeMode::Clamp);  // depth 0.1·N
        QdmBuildParams params;
        params.paper = true;
        double a = 0.0, rise = 0.0, cone = 0.0;
        size_t n = 0;
        for (const QdmTexel& q : buildQdmPaper(*s, params)) {
            if (!(q.a > 0.0f)) continue;
            a += q.a, rise += 2.0 * (q.c - q.a), cone += q.b / q.a, ++n;
        }
        ASSERT_GT(n, 0u);
        std::printf(
            "[ qdm paper ] %s 128²: mean a %.1f, parabola slope at a %.1f, cone slope %.2f\n", g,
            a / double(n), rise / double(n), cone / double(n));
        EXPECT_GT(rise, 10.0 * cone) << g;
    }
}

// Baked maps record the variant: paper maps are used by the paper variant and refused by the safe
// one (and the other way round); maps without the key are the safe variant's.
TEST(QdmPaperMap, BakedMapsRecordTheVariant) {
    const auto s = testing::makeSurface("fbm", 16, 12, EdgeMode::Clamp);
    const TechniqueInfo& info = *findTechnique("qdm");
    auto paper = resolveParams(info, {{"variant", 1.0}});
    auto safe = resolveParams(info, {});
    auto paperMaps = info.buildMaps(TechniqueInput{s, *paper});
    auto safeMaps = info.buildMaps(TechniqueInput{s, *safe});
    ASSERT_TRUE(paperMaps.ok() && safeMaps.ok());
    EXPECT_TRUE(info.create(TechniqueInput{s, *paper, &*paperMaps}).ok());
    auto refused = info.create(TechniqueInput{s, *safe, &*paperMaps});
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("variant"), std::string::npos);
    EXPECT_FALSE(info.create(TechniqueInput{s, *paper, &*safeMaps}).ok());
    TechniqueMaps older = *safeMaps;
    older.parameters.erase("variant");
    EXPECT_TRUE(info.create(TechniqueInput{s, *safe, &older}).ok());
    EXPECT_FALSE(info.create(TechniqueInput{s, *paper, &older}).ok());
}

}  // namespace
}  // namespace relief
