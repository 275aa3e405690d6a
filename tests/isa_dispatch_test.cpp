// Runtime ISA dispatch (core/isa.h): every registry row's CPU tracer gives bit-identical hits
// (hit, t, position, steps, fetches) through the baseline loop and through each wider ISA this
// CPU runs, on > 10^5 rays per row over fbm, a real terrain crop and an adversarial map, clamp and
// repeat, for the row's defaults and every variant and path case.
#include <support/packet_test_support.h>
#include <support/ray_sets.h>

#include <relief/core/generators.h>
#include <relief/core/isa.h>
#include <relief/io/heightfield_crop.h>
#include <relief/io/heightfield_io.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <bit>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

namespace relief {
namespace {

TEST(Isa, ParsesNamesAndRefusesOthers) {
    EXPECT_EQ(*parseIsa("baseline"), Isa::Baseline);
    EXPECT_EQ(*parseIsa("auto"), bestSupportedIsa());
    for (Isa isa : kAllIsas) {
        EXPECT_EQ(parseIsa(toString(isa)).ok(), isaSupported(isa)) << toString(isa);
        EXPECT_EQ(setTracerIsa(isa).ok(), isaSupported(isa)) << toString(isa);
    }
    const Result<Isa> bad = parseIsa("avx9");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().kind, ErrorKind::BadArgument);
    EXPECT_NE(bad.error().message.find("baseline, sse4, avx2 or auto"), std::string::npos);
    EXPECT_TRUE(isaSupported(Isa::Baseline));
    {
        IsaOverride baseline(Isa::Baseline);
        EXPECT_EQ(tracerIsa(), "baseline");
    }
    ASSERT_TRUE(setTracerIsa(bestSupportedIsa()).ok());
    EXPECT_EQ(activeIsa(), bestSupportedIsa());
}

struct Field {
    std::string label;
    std::shared_ptr<const Heightfield> heightfield;
};

std::vector<Field> fields() {
    std::vector<Field> out;
    out.push_back({"fbm 72x64", std::make_shared<const Heightfield>(*generateHeightfield("fbm", 72, 64, 3))});
    const auto colorado = loadHeightfield(std::string(RELIEF_SOURCE_DIR) + "/data/colorado-elevation-400.png");
    EXPECT_TRUE(colorado.ok()) << colorado.error().message;
    if (colorado)
        out.push_back({"colorado crop 64x64",
                       std::make_shared<const Heightfield>(
                           *cropHeightfield(*colorado, {.x = 170, .y = 150, .width = 64, .height = 64}, "colorado"))});
    // Walls: flat cells beside vertical steps, rays on cell edges (ties in every comparison).
    out.push_back({"walls 48x40", std::make_shared<const Heightfield>(*generateHeightfield("walls", 48, 40, 5))});
    return out;
}

// The row's defaults, its variants and its path cases, each once.
std::vector<std::pair<std::string, bool>> paramSets(const TechniqueInfo& info) {
    std::vector<std::pair<std::string, bool>> sets{{"", false}};
    std::set<std::string> seen{""};
    for (const VariantSpec& v : info.variants)
        if (seen.insert(std::string(v.params)).second) sets.push_back({std::string(v.params), v.clampOnly});
    for (const PathCase& p : info.pathCases)
        if (seen.insert(std::string(p.params)).second) sets.push_back({std::string(p.params), p.clampOnly});
    return sets;
}

class IsaDispatchTest : public ::testing::TestWithParam<std::string_view> {};

TEST_P(IsaDispatchTest, EveryIsaTracesBitIdentically) {
    const TechniqueInfo& info = *findTechnique(GetParam());
    std::vector<Isa> wider;
    for (Isa isa : {Isa::Sse4, Isa::Avx2})
        if (isaSupported(isa)) wider.push_back(isa);
    if (wider.empty())
        std::printf("[ isa ] this CPU has neither SSE4.2 nor AVX2: baseline compared with baseline\n");
    const std::vector<Field> maps = fields();
    size_t rays = 0, differing = 0;
    uint32_t seed = 11;
    for (const auto& [params, clampOnly] : paramSets(info)) {
        const auto overrides = parseParamList(params);
        ASSERT_TRUE(overrides.ok()) << params;
        size_t setRays = 0;
        for (const Field& field : maps)
            for (EdgeMode edge : {EdgeMode::Clamp, EdgeMode::Repeat}) {
                if (clampOnly && edge != EdgeMode::Clamp) continue;
                auto surface = std::make_shared<const Surface>(
                    field.heightfield, 0.2f * float(field.heightfield->width), edge);
                auto tracer = createTracer(info.name, surface, *overrides);
                ASSERT_TRUE(tracer.ok()) << params << ": " << tracer.error().message;
                testing::RaySets sets(*surface, seed++);
                // 3 kinds × 5600 rays × 6 map cases ≥ 10^5 rays per parameter set.
                const std::vector<Ray> batch = sets.all(clampOnly ? 11200 : 5600);
                std::vector<Hit> base(batch.size());
                {
                    IsaOverride baseline(Isa::Baseline);
                    traceAll(**tracer, batch, base);
                }
                for (Isa isa : wider.empty() ? std::vector<Isa>{Isa::Baseline} : wider) {
                    std::vector<Hit> other(batch.size());
                    {
                        IsaOverride use(isa);
                        traceAll(**tracer, batch, other);
                    }
                    size_t here = 0;
                    for (size_t k = 0; k < batch.size(); ++k)
                        if (!packet_test::identical(base[k], other[k]) && here++ < 3)
                            ADD_FAILURE() << info.name << " [" << params << "] " << field.label << " "
                                          << toString(edge) << " ray " << k << ": baseline (" << base[k].hit
                                          << ", t " << base[k].t << ", steps " << base[k].steps << ") vs "
                                          << toString(isa) << " (" << other[k].hit << ", t " << other[k].t
                                          << ", steps " << other[k].steps << ")";
                    differing += here;
                }
                setRays += batch.size();
            }
        EXPECT_GE(setRays, 100000u) << params;
        rays += setRays;
    }
    std::printf("[ isa ] %-18s %zu rays, baseline vs", std::string(info.name).c_str(), rays);
    for (Isa isa : wider) std::printf(" %s", std::string(toString(isa)).c_str());
    std::printf(": %zu differ\n", differing);
    EXPECT_EQ(differing, 0u);
}

std::vector<std::string_view> rowNames() {
    std::vector<std::string_view> names;
    for (const TechniqueInfo& info : techniques()) names.push_back(info.name);
    return names;
}

INSTANTIATE_TEST_SUITE_P(Registry, IsaDispatchTest, ::testing::ValuesIn(rowNames()),
                         [](const ::testing::TestParamInfo<std::string_view>& p) {
                             std::string name(p.param);
                             for (char& c : name)
                                 if (c == '-') c = '_';
                             return name;
                         });

}  // namespace
}  // namespace relief

namespace relief {
namespace {

// RELIEF_ISA is checked before any command runs: a bad value is exit 1 with the choices named.
TEST(Isa, BadEnvironmentValueIsAnError) {
    const std::string err = ::testing::TempDir() + "relief_isa_env_err.txt";
    const std::string command = std::string("RELIEF_ISA=avx9 ") + RELIEF_CLI_PATH +
                                " info gen:flat:8x8 >/dev/null 2>" + err;
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1);
    FILE* file = std::fopen(err.c_str(), "r");
    ASSERT_NE(file, nullptr);
    char text[512] = {};
    text[std::fread(text, 1, sizeof(text) - 1, file)] = '\0';
    std::fclose(file);
    EXPECT_NE(std::string(text).find("RELIEF_ISA: unknown ISA 'avx9'"), std::string::npos) << text;
    const std::string good = std::string("RELIEF_ISA=baseline ") + RELIEF_CLI_PATH +
                             " info gen:flat:8x8 --format json | grep -q '\"tracer_isa\": \"baseline\"'";
    EXPECT_EQ(std::system(good.c_str()), 0);
}

}  // namespace
}  // namespace relief
