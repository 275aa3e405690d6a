// Every registry row is complete and self-consistent: what consumers read from a row (roles,
// variants and their contracts, path cases, studies) must name real parameters and values.
#include <relief/core/generators.h>
#include <relief/techniques/registry.h>
#include <support/ray_sets.h>

#include <gtest/gtest.h>

#include <set>

namespace relief {
namespace {

void expectValidParamList(const TechniqueInfo& info, std::string_view text, std::string_view what) {
    auto list = parseParamList(text);
    ASSERT_TRUE(list) << info.name << " " << what << ": " << list.error().message;
    auto resolved = resolveParams(info, *list);
    EXPECT_TRUE(resolved) << info.name << " " << what << ": " << resolved.error().message;
}

TEST(RegistryTest, ExactlyOneReference) {
    int count = 0;
    for (const TechniqueInfo& info : techniques()) count += info.reference;
    EXPECT_EQ(count, 1);
    EXPECT_EQ(referenceTechnique().contract, Contract::Exact);
}

TEST(RegistryTest, RowsAreComplete) {
    std::set<std::string_view> names;
    for (const TechniqueInfo& info : techniques()) {
        EXPECT_TRUE(names.insert(info.name).second) << "duplicate row " << info.name;
        EXPECT_FALSE(info.paper.empty()) << info.name;
        EXPECT_FALSE(info.summary.empty()) << info.name;
        EXPECT_NE(info.create, nullptr) << info.name;
        int caps = 0;
        std::set<std::string_view> params;
        for (const ParamSpec& p : info.params) {
            EXPECT_TRUE(params.insert(p.name).second) << info.name << ": duplicate " << p.name;
            EXPECT_LE(p.minValue, p.defaultValue) << info.name << " " << p.name;
            EXPECT_LE(p.defaultValue, p.maxValue) << info.name << " " << p.name;
            EXPECT_FALSE(p.help.empty()) << info.name << " " << p.name;
            caps += p.role == ParamRole::IterationCap;
        }
        EXPECT_LE(caps, 1) << info.name << " has more than one iteration cap";
        for (const VariantSpec& v : info.variants) {
            EXPECT_FALSE(v.label.empty()) << info.name;
            expectValidParamList(info, v.params, v.label);
        }
        for (const PathCase& c : info.pathCases) expectValidParamList(info, c.params, "path case");
        for (const GlslConstant& c : info.glslConstants) {
            EXPECT_EQ(c.name.substr(0, 1), "k") << info.name << ": " << c.name;
            if (c.integer) {
                EXPECT_EQ(c.value, double(int64_t(c.value))) << c.name;
            }
        }
    }
}

TEST(RegistryTest, ContractPerVariant) {
    const TechniqueInfo& cone = *findTechnique("cone");
    EXPECT_EQ(contractOf(cone, *resolveParams(cone, {})), Contract::Conservative);
    EXPECT_EQ(contractOf(cone, *resolveParams(cone, {{"variant", 1}})), Contract::Approximate);
    const TechniqueInfo& quadtree = *findTechnique("quadtree");
    EXPECT_EQ(contractOf(quadtree, *resolveParams(quadtree, {})), Contract::Exact);
    EXPECT_EQ(contractOf(quadtree, *resolveParams(quadtree, {{"box-surface", 1}})),
              Contract::Approximate);
    EXPECT_EQ(contractOf(quadtree, *resolveParams(quadtree, {{"max-steps", 8}})),
              Contract::Approximate);
    const TechniqueInfo& exact = referenceTechnique();
    EXPECT_EQ(contractOf(exact, *resolveParams(exact, {})), Contract::Exact);
}

TEST(RegistryTest, ParamListParsing) {
    auto list = parseParamList("variant=1,bits=16");
    ASSERT_TRUE(list);
    ASSERT_EQ(list->size(), 2u);
    EXPECT_EQ((*list)[1].first, "bits");
    EXPECT_EQ((*list)[1].second, 16.0);
    EXPECT_TRUE(parseParamList("")->empty());
    for (const char* bad : {"variant", "=1", "variant=x", "variant=1,", "a=1,,b=2"})
        EXPECT_FALSE(parseParamList(bad)) << bad;
}

}  // namespace
}  // namespace relief

namespace relief {
namespace {

// One bake's rows share what they both build (safety-sd's distances are safety-cc's radii): the
// maps are those each row bakes alone, the reuse is reported, and rows baked with different
// options (or the sampled precomputation) build their own.
TEST(RegistryTest, SharedBuildsGiveTheMapsOfSeparateOnes) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("peaks6", 48, 40, 3));
    auto surface = std::make_shared<const Surface>(hf, 9.0f, EdgeMode::Clamp);
    const TechniqueInfo& sd = *findTechnique("safety-sd");
    const TechniqueInfo& cc = *findTechnique("safety-cc");
    using Overrides = std::vector<std::pair<std::string, double>>;
    auto alone = [&](const TechniqueInfo& row, const Overrides& o) {
        auto maps = bakeMaps(row, surface, o);
        EXPECT_TRUE(maps) << maps.error().message;
        return *maps;
    };
    auto expectSame = [](const TechniqueMaps& a, const TechniqueMaps& b) {
        ASSERT_EQ(a.arrays.size(), b.arrays.size());
        for (size_t k = 0; k < a.arrays.size(); ++k) EXPECT_EQ(a.arrays[k].data, b.arrays[k].data);
        EXPECT_EQ(a.parameters, b.parameters);
    };
    for (const bool ccFirst : {false, true}) {
        SCOPED_TRACE(ccFirst ? "safety-cc first" : "safety-sd first");
        BuildShare share;
        const TechniqueInfo& first = ccFirst ? cc : sd;
        const TechniqueInfo& second = ccFirst ? sd : cc;
        auto a = bakeMaps(first, surface, {}, &share);
        ASSERT_TRUE(a) << a.error().message;
        EXPECT_TRUE(share.takeNotes().empty());
        auto b = bakeMaps(second, surface, {}, &share);
        ASSERT_TRUE(b) << b.error().message;
        EXPECT_EQ(share.takeNotes(),
                  std::vector<std::string>{"safety distances from " + std::string(first.name)});
        expectSame(*a, alone(first, {}));
        expectSame(*b, alone(second, {}));
    }
    for (const Overrides& other : {Overrides{{"phi-max", -45}}, Overrides{{"isotropic", 1}},
                                   Overrides{{"precompute", 1}}, Overrides{{"exterior", 1}}}) {
        SCOPED_TRACE(other.front().first);
        BuildShare share;
        ASSERT_TRUE(bakeMaps(sd, surface, {}, &share));
        auto b = bakeMaps(cc, surface, other, &share);
        ASSERT_TRUE(b) << b.error().message;
        EXPECT_TRUE(share.takeNotes().empty());
        expectSame(*b, alone(cc, other));
    }
}

// Maps record how they were built: a tracer given them takes bits (and the other build options)
// from the file unless the caller sets them, refuses a caller's value the file contradicts, and
// refuses a recorded value out of range (a tampered file) with the file named.
TEST(RegistryTest, BakedMapsAreTracedAsBaked) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("fbm", 48, 40, 3));
    auto surface = std::make_shared<const Surface>(hf, 12.0f, EdgeMode::Clamp);
    testing::RaySets sets(*surface, 11);
    const std::vector<Ray> rays = sets.all(200);
    for (const char* row : {"cone", "quadtree", "maxmip", "relaxed-cone"}) {
        SCOPED_TRACE(row);
        const TechniqueInfo& info = *findTechnique(row);
        auto baked = bakeMaps(info, surface, {{"bits", 16}});
        ASSERT_TRUE(baked) << baked.error().message;
        MapFile file;
        file.source = mapSourceOf(*surface);
        file.techniques.push_back(*baked);
        auto asBaked = createTracer(row, surface, {}, &file, "test.maps.exr");
        ASSERT_TRUE(asBaked) << asBaked.error().message;
        auto explicit16 = createTracer(row, surface, {{"bits", 16}}, &file, "test.maps.exr");
        ASSERT_TRUE(explicit16) << explicit16.error().message;
        std::vector<Hit> a(rays.size()), b(rays.size());
        (*asBaked)->traceBatch(rays, a);
        (*explicit16)->traceBatch(rays, b);
        for (size_t k = 0; k < rays.size(); ++k) {
            ASSERT_EQ(a[k].hit, b[k].hit) << k;
            if (a[k].hit) {
                ASSERT_EQ(a[k].t, b[k].t) << k;
            }
        }
        auto contradicted = createTracer(row, surface, {{"bits", 8}}, &file, "test.maps.exr");
        ASSERT_FALSE(contradicted);
        EXPECT_NE(contradicted.error().message.find("bits"), std::string::npos);
        file.techniques.front().parameters["bits"] = "7";
        auto tampered = createTracer(row, surface, {}, &file, "test.maps.exr");
        ASSERT_FALSE(tampered);
        EXPECT_NE(tampered.error().message.find("test.maps.exr"), std::string::npos)
            << tampered.error().message;
    }
}

}  // namespace
}  // namespace relief
