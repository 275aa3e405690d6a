// The contract harness (DESIGN §3): every technique in the registry is traced against `exact` on
// random and adversarial rays over all standard generators, both edge modes and odd sizes.
// exact → same hit/miss and |Δt| ≤ 1e-3; conservative → never past the first hit (t ≤ t_ref +
// 1e-4) and converged within 1e-3 at its default cap; approximate → statistics are recorded.
#include <support/contract_harness.h>

#include <relief/core/generators.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace relief {
namespace {

using testing::checkAndReport;
using testing::Tally;

class ContractTest : public ::testing::TestWithParam<std::string_view> {};

TEST_P(ContractTest, AgainstExactReference) {
    const TechniqueInfo& info = *findTechnique(GetParam());
    const testing::ContractRun run = testing::runContractHarness(info);
    ASSERT_TRUE(run.error.empty()) << run.error;
    for (const std::string& map : run.brokenOn)
        ADD_FAILURE() << info.name << " broke its contract on " << map;
    const Tally& tally = run.tally;
    EXPECT_GE(tally.rays, 100000u);
    switch (info.contract) {
        case Contract::Exact:
            EXPECT_EQ(tally.wrongHitMiss, 0u);
            EXPECT_EQ(tally.beyondTolerance, 0u);
            break;
        case Contract::Conservative:
            EXPECT_EQ(tally.pastFirstHit, 0u);
            EXPECT_EQ(tally.wrongHitMiss, 0u);
            EXPECT_EQ(tally.beyondTolerance, 0u);
            break;
        case Contract::Approximate:
            break;  // recorded above; the bench reports it
    }
}

std::vector<std::string_view> allTechniqueNames() {
    std::vector<std::string_view> names;
    for (const TechniqueInfo& info : techniques()) names.push_back(info.name);
    return names;
}

std::string techniqueTestName(const ::testing::TestParamInfo<std::string_view>& info) {
    std::string name(info.param);
    for (char& c : name)
        if (c == '-') c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(Registry, ContractTest, ::testing::ValuesIn(allTechniqueNames()),
                         techniqueTestName);

// Each named variant other than the defaults (the test above) runs on the same rays: one that
// promises something (exact, conservative) keeps its own contract (DESIGN §3: every variant
// declares one); an approximate one (a paper's own method) has its errors recorded.
struct VariantCase {
    std::string_view technique;
    const VariantSpec* variant;
};

std::vector<VariantCase> nonDefaultVariants() {
    std::vector<VariantCase> cases;
    for (const TechniqueInfo& info : techniques())
        for (const VariantSpec& v : info.variants) {
            const auto params = resolveParams(info, *parseParamList(v.params));
            const bool isDefault = params && params->all() == resolveParams(info, {})->all();
            if (!isDefault) cases.push_back({info.name, &v});
        }
    return cases;
}

void PrintTo(const VariantCase& c, std::ostream* out) {
    *out << c.technique << " " << c.variant->label << " (" << c.variant->params << ")";
}

class VariantContractTest : public ::testing::TestWithParam<VariantCase> {};

TEST_P(VariantContractTest, AgainstExactReference) {
    const TechniqueInfo& info = *findTechnique(GetParam().technique);
    const VariantSpec& variant = *GetParam().variant;
    // An approximate variant promises nothing the harness could catch breaking: it records its
    // statistics and checks that its hits lie on their rays. That needs no 64x64 maps, whose bakes
    // dominate for the costliest forms (safety's sampled precomputation, 2048 rays per texel and
    // direction class: ~100 s per set of 64x64 maps on 2 cores, 5x that under ASan).
    const bool oddSizesOnly = variant.contract == Contract::Approximate;
    const testing::ContractRun run = testing::runContractHarness(
        info, *parseParamList(variant.params), variant.clampOnly, oddSizesOnly);
    ASSERT_TRUE(run.error.empty()) << run.error;
    EXPECT_EQ(run.contract, variant.contract);
    for (const std::string& map : run.brokenOn)
        ADD_FAILURE() << info.name << " " << variant.label << " broke its contract on " << map;
    EXPECT_GE(run.tally.rays, 100000u);
    EXPECT_TRUE(testing::keepsContract(run));
}

INSTANTIATE_TEST_SUITE_P(Registry, VariantContractTest, ::testing::ValuesIn(nonDefaultVariants()),
                         [](const ::testing::TestParamInfo<VariantCase>& p) {
                             std::string name = std::string(p.param.technique) + "_" +
                                                std::string(p.param.variant->label);
                             for (char& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

TEST(Registry, EveryRowIsComplete) {
    for (const TechniqueInfo& info : techniques()) {
        EXPECT_FALSE(info.name.empty());
        EXPECT_FALSE(info.paper.empty()) << info.name;
        EXPECT_FALSE(info.summary.empty()) << info.name;
        EXPECT_NE(info.create, nullptr) << info.name;
        EXPECT_EQ(findTechnique(info.name), &info) << "duplicate name " << info.name;
        // Rows with maps describe their channels (exports, docs/maps.md); rows without have none.
        EXPECT_EQ(info.buildMaps != nullptr, !info.mapChannels.empty()) << info.name;
        for (const MapChannelSpec& c : info.mapChannels)
            EXPECT_FALSE(c.array.empty() || c.name.empty() || c.meaning.empty() ||
                         c.range.empty() || c.depth.empty())
                << info.name << " " << c.array << " " << c.name;
        for (const ParamSpec& p : info.params) {
            EXPECT_LE(p.minValue, p.defaultValue) << info.name << " " << p.name;
            EXPECT_LE(p.defaultValue, p.maxValue) << info.name << " " << p.name;
        }
    }
}

TEST(Registry, RejectsUnknownAndOutOfRangeParameters) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("flat", 4, 4));
    auto surface = std::make_shared<const Surface>(hf, 1.0f, EdgeMode::Clamp);
    auto unknown = createTracer("linear", surface, {{"no-such", 1.0}});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("no parameter 'no-such'"), std::string::npos);
    auto range = createTracer("linear", surface, {{"max-steps", 0.0}});
    ASSERT_FALSE(range.ok());
    EXPECT_NE(range.error().message.find("out of range"), std::string::npos);
    EXPECT_FALSE(createTracer("nope", surface).ok());
}


// Degenerate inputs for every row (issue 11): 1×1, 1×N and N×1 maps, depth 0, a very large
// depth, origins exactly on the box's faces and edges, directions with zero components, and rays
// with NaN or infinite components (the readers refuse those; a tracer handed one must still
// return, with a miss). The contract is checked against exact on every finite ray.
class EdgeCaseTest : public ::testing::TestWithParam<std::string_view> {};

std::vector<Ray> boxFaceRays(const Surface& s) {
    const float w = float(s.width()), h = float(s.height()), top = s.depth();
    std::vector<Ray> rays;
    const vec3 directions[] = {{1, 0, 0}, {0, 1, 0}, {0, 0, -1}, {-1, 0, 0}, {0, -1, 0},
                               glm::normalize(vec3(1, 0, -1)), glm::normalize(vec3(0, -1, -1)),
                               glm::normalize(vec3(1, 1, -0.5f)), glm::normalize(vec3(-1, 1, -2))};
    const vec3 origins[] = {{0, 0, top}, {w, h, top}, {0, 0.5f * h, 0.5f * top}, {0.5f * w, 0, top},
                            {w, 0.5f * h, top}, {0.5f * w, 0.5f * h, top}, {0.5f, 0.5f, top},
                            {0, 0, 0}, {w, h, 0}};
    for (const vec3& o : origins)
        for (const vec3& d : directions) rays.push_back(Ray{o, d, kInfinity});
    return rays;
}

std::vector<Ray> nonFiniteRays() {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity;
    return {Ray{vec3(nan, 0, 1), vec3(0, 0, -1), kInfinity}, Ray{vec3(0, 0, 1), vec3(nan, 0, -1), kInfinity},
            Ray{vec3(inf, 1, 1), vec3(-1, 0, 0), kInfinity}, Ray{vec3(1, 1, inf), vec3(0, 0, -1), kInfinity},
            Ray{vec3(1, 1, 1), vec3(inf, 0, -inf), kInfinity}, Ray{vec3(1, 1, 1), vec3(0, 0, 0), kInfinity}};
}

TEST_P(EdgeCaseTest, DegenerateMapsAndRays) {
    const TechniqueInfo& info = *findTechnique(GetParam());
    struct Case {
        const char* generator;
        int width, height;
        float depth;
    };
    const Case cases[] = {{"fbm", 1, 1, 1.0f}, {"fbm", 1, 9, 2.0f}, {"fbm", 9, 1, 2.0f}, {"fbm", 2, 2, 1.0f},
                          {"fbm", 16, 16, 0.0f}, {"spikes", 16, 12, 1e4f}, {"walls", 13, 17, 4.0f}};
    Tally tally;
    uint32_t seed = 7;
    for (const Case& c : cases)
        for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
            SCOPED_TRACE(::testing::Message() << info.name << " " << c.generator << " " << c.width << "x" << c.height
                                              << " depth " << c.depth << " " << toString(edge));
            auto hf = std::make_shared<const Heightfield>(*generateHeightfield(c.generator, c.width, c.height, seed));
            auto surface = std::make_shared<const Surface>(hf, c.depth, edge);
            auto tracer = createTracer(info.name, surface);
            ASSERT_TRUE(tracer.ok()) << tracer.error().message;
            auto exact = createTracer("exact", surface);
            testing::RaySets sets(*surface, seed++);
            std::vector<Ray> rays = sets.all(60);
            for (const Ray& r : boxFaceRays(*surface)) rays.push_back(r);
            std::vector<Hit> hits(rays.size()), reference(rays.size());
            (*tracer)->traceBatch(rays, hits);
            (*exact)->traceBatch(rays, reference);
            const Tally before = tally;
            for (size_t k = 0; k < rays.size(); ++k)
                checkAndReport(info, info.contract, rays[k], hits[k], reference[k], tally);
            if (info.contract != Contract::Approximate) {
                EXPECT_TRUE(tally.wrongHitMiss == before.wrongHitMiss && tally.pastFirstHit == before.pastFirstHit &&
                            tally.beyondTolerance == before.beyondTolerance)
                    << "hit/miss " << tally.wrongHitMiss - before.wrongHitMiss << ", past first hit "
                    << tally.pastFirstHit - before.pastFirstHit << ", |dt| > 1e-3 "
                    << tally.beyondTolerance - before.beyondTolerance;
            }
            const std::vector<Ray> bad = nonFiniteRays();
            std::vector<Hit> badHits(bad.size());
            (*tracer)->traceBatch(bad, badHits);
            for (size_t k = 0; k < bad.size(); ++k) EXPECT_FALSE(badHits[k].hit) << "non-finite ray " << k;
        }
}

INSTANTIATE_TEST_SUITE_P(Registry, EdgeCaseTest, ::testing::ValuesIn(allTechniqueNames()),
                         techniqueTestName);

}  // namespace
}  // namespace relief
