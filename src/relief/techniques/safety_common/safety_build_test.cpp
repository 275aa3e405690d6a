// The pruned builders (safety distances, cylinder-cones) against their reference scans:
// bit-identical maps on many small maps
// (generators, adversarial flats, spikes and coasts, crops of real terrain), every build option,
// clamp and repeat.
#include <support/safety_test_support.h>

#include <relief/io/heightfield_crop.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/safety_common/safety_maps.h>

#include <cstring>

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

}  // namespace
}  // namespace relief::safety
