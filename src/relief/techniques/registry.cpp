#include <relief/techniques/registry.h>

#include <relief/core/memory_budget.h>

#include <relief/techniques/curves/curves.h>
#include <relief/techniques/exact/exact.h>
#include <relief/techniques/cone/cone.h>
#include <relief/techniques/relaxed_cone/relaxed_cone.h>
#include <relief/techniques/linear/linear.h>
#include <relief/techniques/parallax/parallax.h>
#include <relief/techniques/qdm/qdm.h>
#include <relief/techniques/qdm/qdm_paper.h>
#include <relief/techniques/maxmip/maxmip.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>
#include <relief/techniques/safety_cc/safety_cc.h>
#include <relief/techniques/safety_common/safety_params.h>
#include <relief/techniques/safety_sd/safety_sd.h>

#include <relief/core/check.h>
#include <relief/sphere/sphere_reference.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace relief {

namespace {

// Forms whose contract differs from the row's, or that a paper's claim is judged with.
constexpr VariantSpec kQuadtreeVariants[] = {
    {"paper-walk", "ascend=0", Contract::Exact, "the paper's walk: stay at the level after a jump"},
    {"cell-boxes", "box-surface=1", Contract::Approximate, "cell boxes at the corner maximum: stops at the first level-0 node"},
    {"paper-surface", "box-surface=2", Contract::Approximate, "the paper's texel boxes at the sample height",
     false, true, "texel boxes (surface/texel_boxes.h)"},
};
constexpr VariantSpec kMaxmipVariants[] = {
    {"paper-surface", "box-surface=2", Contract::Approximate, "texel boxes at the sample height (as quadtree's)",
     false, true, "texel boxes (surface/texel_boxes.h)"},
};
constexpr VariantSpec kConeVariants[] = {
    {"safe", "variant=0", Contract::Conservative, "footprint-frustum cones, exact cell finish"},
    {"faithful", "variant=1", Contract::Approximate, "Dummer's cones (texel centres): can step past a hit"},
};
constexpr VariantSpec kQdmVariants[] = {
    {"safe", "variant=0", Contract::Conservative, "footprint profile, exact cell finish"},
    {"paper", "variant=1", Contract::Approximate, "the published map and Algorithm 1: can step past a hit"},
};
constexpr VariantSpec kSafetyVariants[] = {
    {"phi-outside", "phi-outside=1", Contract::Approximate,
     "rays outside phi-max march on the maps anyway (the paper's rendering, §6.2.5/§8)", false, true},
    {"sampled", "precompute=1", Contract::Approximate,
     "sampled safety distances (§8: 8 positions x 256 directions): can step past a hit"},
    {"view-dependent", "view-dependent=1", Contract::Approximate, "S linear between test positions (§7)"},
    {"positive-distance", "positive-distance=1", Contract::Approximate, "distances clamped to >= 1 (§7)"},
    {"exterior", "exterior=1", Contract::Exact, "maps for exterior rays only (§6.2)", true},
};

// `exact` on the sphere: the sphere's reference (DESIGN §6).
Result<std::unique_ptr<Tracer>> createExactSphere(std::shared_ptr<const SphereSurface> sphere,
                                                  const ParamValues& params) {
    if (params.getInt("max-steps") != 0)
        return makeError(ErrorKind::Unsupported, "exact on the sphere: the sphere reference has "
                                                  "no iteration cap (max-steps)");
    return makeBatchTracer(SphereReference(std::move(sphere)));
}

// A row's `check` from the loader its create uses: the loader's errors on baked maps
// (input.maps), its result dropped (for safety-sd/-cc the decoded map with its march options, no
// Tracer). Without input.maps there is nothing to check: buildMaps makes them right.
template <auto Load>
Status checkMaps(const TechniqueInput& input) {
    if (!input.maps) return {};
    auto loaded = Load(input);
    return loaded ? Status() : Status(loaded.error());
}

// The samplers of the rows' shader-library functions (shaders/relief/).
constexpr ShaderSampler kHeightsSampler[] = {{"heights", ""}};
constexpr ShaderSampler kConeSamplers[] = {{"heights", ""}, {"cones", "cones"}};
constexpr ShaderSampler kPyramidSamplers[] = {{"heights", ""}, {"pyramid", "level0", true}};
constexpr ShaderSampler kOrientedSamplers[] = {
    {"heights", ""}, {"pyramid", "level0", true}, {"oriented", "oriented1", true}};
constexpr ShaderSampler kQdmSamplers[] = {{"heights", ""}, {"qdm", "qdm"}};
constexpr ShaderSampler kSafetyCcSamplers[] = {{"heights", ""},
                                               {"ccxPlus", "ccx+", false, "cc"},
                                               {"ccxMinus", "ccx-", false, "cc"},
                                               {"ccyPlus", "ccy+", false, "cc"},
                                               {"ccyMinus", "ccy-", false, "cc"}};
constexpr ShaderSampler kSafetySdSamplers[] = {{"heights", ""}, {"sd", "sd"}};

// Parameter sets that take the GLSL down another path (encodings, policies, variants).
constexpr PathCase kQuadtreePathCases[] = {{"ascend=0"}, {"max-steps=6"}, {"bits=16"}};
constexpr PathCase kMaxmipPathCases[] = {{"bits=16"}};
constexpr PathCase kConePathCases[] = {{"bits=16,sqrt=1"}, {"bits=8,variant=1"}};
constexpr PathCase kRelaxedConePathCases[] = {{"bits=16,binary-steps=4"}};
constexpr PathCase kQdmPathCases[] = {
    {"max-distance=3,max-steps=20"},
    {"height-ratio=0.5,convex-bound=0", true},
    {"variant=1"},
    {"variant=1,max-steps=6,height-ratio=0.5"},
};
constexpr PathCase kSafetySdPathCases[] = {
    {"isotropic=1,positive-distance=1"},
    {"exterior=1", true},  // exterior-ray maps exist in clamp mode only
};
constexpr PathCase kSafetyCcPathCases[] = {
    {"view-dependent=1,phi-max=-30"},
    {"isotropic=1,max-steps=5"},
    {"exterior=1,exterior-slope=1", true},
};

// The rows' studies: `relief bench --preset NAME` (src/relief/bench/presets.cpp reads them).
constexpr int kQdmPaperCaps[] = {4, 6, 8, 12, 24, 48, 200};
// bench_qdm's experiments (Kiglics et al. 2023 §5): qdm against safe cones by elevation and cap
// over nine maps (five generators, two DEMs at their 400², two crops of global relief at the map
// size: the Andes from the SRTM mosaic, Africa and Europe from the topography), and qdm builds.
constexpr std::string_view kQdmStudyMaps[] = {"gen:sine:1024x1024:1", "gen:peaks6:1024x1024:1", "gen:fbm:1024x1024:1",
                                              "gen:terraces:1024x1024:1", "gen:walls:1024x1024:1",
                                              "data/colorado-elevation-400.png",
                                              "data/finland-topography-400-16bit.png",
                                              "../shared/data/earth-srtm-5400x2700.png@crop=1500,1100,1024,1024",
                                              "data/earth-topology-2048x1024.png@crop=900,0,1024,1024"};
constexpr std::string_view kQdmStudyRows[] = {"qdm", "cone"};
constexpr int kCapsAndDefault[] = {0, 4, 6, 8, 12, 24, 48, 200};  // 0 = the row's default cap
constexpr std::string_view kQdmBuildMaps[] = {"gen:fbm:{N}x{N}:1", "gen:peaks6:{N}x{N}:1"};
constexpr std::string_view kQdmBuildRows[] = {"qdm"};
constexpr int kBuildSizes[] = {256, 512, 1024, 2048, 4096};
// The QDM paper's page (docs/papers/qdm.md, `relief bench --preset qdm`): its own comparison,
// the paper's QDM against Dummer's cones, beside ours (safe against safe), and its height-ratio
// sweep. Maps: the paper's nine kinds at 512² (the paper: 1024²; the published builder takes
// minutes per 1024² map on gently rising ground, on 2 cores), peaks6 at 256² for that reason.
constexpr std::string_view kQdmClaimMaps[] = {"gen:sine:512x512:1", "gen:peaks6:256x256:1", "gen:fbm:512x512:1",
                                              "gen:terraces:512x512:1", "gen:walls:512x512:1",
                                              "data/colorado-elevation-400.png",
                                              "data/finland-topography-400-16bit.png",
                                              "../shared/data/earth-srtm-5400x2700.png@crop=1750,1350,512,512",
                                              "data/earth-topology-2048x1024.png@crop=1150,250,512,512"};
constexpr std::string_view kQdmClaimRows[] = {"qdm:variant=1", "cone:variant=1", "qdm", "cone"};
constexpr std::string_view kQdmHeightRatioMaps[] = {"gen:sine:512x512:1", "gen:fbm:512x512:1",
                                                    "data/colorado-elevation-400.png"};
constexpr std::string_view kQdmHeightRatioRows[] = {"qdm:variant=1:height-ratio=0", "qdm:variant=1:height-ratio=0.2",
                                                    "qdm:variant=1:height-ratio=0.5", "qdm:variant=1:height-ratio=1"};
constexpr int kQdmHeightRatioCaps[] = {8, 200};
constexpr std::string_view kQdmPageParts[] = {"qdm-claims", "qdm-height-ratio"};
constexpr ClaimMeasure kQdmVsDummer{"qdm:variant=1", "cone:variant=1"};
constexpr ClaimMeasure kQdmSafeVsCone{"qdm", "cone"};
constexpr std::string_view kStepsDecideSpeed =
    "On the CPU a quadric step costs several cone steps (two roots, two fetches), so the speed ratio "
    "follows the step ratio only where steps fall by more than that.";
constexpr ClaimSpec kQdmClaims[] = {
    {.source = "Fig. 9", .claim = "quadric stepping has lower error than cone step mapping, more so for fewer steps (4 iterations)",
     .paper = "lower at every cap, most at 4", .part = "qdm-claims", .metric = ClaimMetric::MeanError,
     .paperVariant = kQdmVsDummer, .safeVariant = kQdmSafeVsCone, .cap = 4, .high = 1.0,
     .whyAgrees = "the parabola's broad top advances further than the cone from the same texel",
     .whyDisagrees = "c = max c_j lets the farthest rings set the parabola, which then leaves the cone steeply "
                     "(docs/qdm.md): the first steps are shorter than Dummer's cones"},
    {.source = "Fig. 9", .claim = "the same at 12 iterations", .paper = "lower", .part = "qdm-claims",
     .metric = ClaimMetric::MeanError, .paperVariant = kQdmVsDummer, .safeVariant = kQdmSafeVsCone, .cap = 12,
     .high = 1.0, .whyAgrees = "the parabola's advance outweighs its flatter cone part",
     .whyDisagrees = "as at 4 iterations: the fitted parabolas are narrower than Dummer's cones near the surface"},
    {.source = "Fig. 10", .claim = "below 45° quadric mapping requires fewer iterations to converge",
     .paper = "fewer", .part = "qdm-claims", .metric = ClaimMetric::Steps, .paperVariant = kQdmVsDummer,
     .safeVariant = kQdmSafeVsCone, .maxElevation = 45.0f, .high = 1.0,
     .whyAgrees = "grazing rays cross the parabolas' wide upper parts",
     .whyDisagrees = "the published map's parabolas are narrow (c = max c_j), so grazing rays take more, shorter steps"},
    {.source = "Fig. 10", .claim = "above 45° the method slows down as it approaches the surface (more iterations than cones)",
     .paper = "more", .part = "qdm-claims", .metric = ClaimMetric::Steps, .paperVariant = kQdmVsDummer,
     .safeVariant = kQdmSafeVsCone, .minElevation = 45.0f, .low = 1.0,
     .whyAgrees = "steep rays reach the cone parts quickly, where QDM's cone (to height ratio 0.2) is narrower",
     .whyDisagrees = "steep rays converge in a few steps with both maps"},
    {.source = "Fig. 11, §5.2", .claim = "better performance for view angles below 45° on all textures and caps",
     .paper = "faster by 5–20 %", .part = "qdm-claims", .metric = ClaimMetric::Speed, .paperVariant = kQdmVsDummer,
     .safeVariant = kQdmSafeVsCone, .maxElevation = 45.0f, .low = 1.0, .whyAgrees = kStepsDecideSpeed,
     .whyDisagrees = kStepsDecideSpeed},
    {.source = "Fig. 11", .claim = "above 30° QDM becomes 1–5 % slower than cones", .paper = "0.95–0.99×",
     .part = "qdm-claims", .metric = ClaimMetric::Speed, .paperVariant = kQdmVsDummer,
     .safeVariant = kQdmSafeVsCone, .minElevation = 30.0f, .low = 0.95, .high = 0.99,
     .whyAgrees = kStepsDecideSpeed, .whyDisagrees = kStepsDecideSpeed},
    {.source = "Table 1", .claim = "the mean rendering time over all angles is reduced", .paper = "−0.32 ms summed (< 1 % of the time)",
     .part = "qdm-claims", .metric = ClaimMetric::Speed, .paperVariant = kQdmVsDummer,
     .safeVariant = kQdmSafeVsCone, .low = 1.0, .whyAgrees = kStepsDecideSpeed, .whyDisagrees = kStepsDecideSpeed},
    {.source = "§5", .claim = "quadric steps need no refinement: they do not enter the surface", .paper = "0 %",
     .part = "qdm-claims", .metric = ClaimMetric::PastFirstHitPercent, .paperVariant = {"qdm:variant=1"},
     .safeVariant = {"qdm"}, .high = 0.0,
     .whyAgrees = "no ray stepped past its first hit",
     .whyDisagrees = "the published map is not conservative: apex at the sample, distances between sample centres "
                     "and the parabola past its top let rays cross thin features between samples"},
    {.source = "(not in the paper)", .claim = "how often Dummer's cones step past the first hit", .paper = "not reported",
     .part = "qdm-claims", .metric = ClaimMetric::PastFirstHitPercent, .paperVariant = {"cone:variant=1"},
     .safeVariant = {"cone"}},
    {.source = "§5", .claim = "height ratio 0.2 gives the best performance (vs 0)", .paper = "0.2 best",
     .part = "qdm-height-ratio", .metric = ClaimMetric::Steps,
     .paperVariant = {"qdm:variant=1:height-ratio=0.2", "qdm:variant=1:height-ratio=0"}, .high = 1.0,
     .whyAgrees = "fewer steps to converge with 0.2", .whyDisagrees = "the other ratio converges in fewer steps here"},
    {.source = "§5", .claim = "height ratio 0.2 gives the best performance (vs 0.5)", .paper = "0.2 best",
     .part = "qdm-height-ratio", .metric = ClaimMetric::Steps,
     .paperVariant = {"qdm:variant=1:height-ratio=0.2", "qdm:variant=1:height-ratio=0.5"}, .high = 1.0,
     .whyAgrees = "fewer steps to converge with 0.2", .whyDisagrees = "the other ratio converges in fewer steps here"},
    {.source = "§5", .claim = "height ratio 0.2 gives the best performance (vs 1)", .paper = "0.2 best",
     .part = "qdm-height-ratio", .metric = ClaimMetric::Steps,
     .paperVariant = {"qdm:variant=1:height-ratio=0.2", "qdm:variant=1:height-ratio=1"}, .high = 1.0,
     .whyAgrees = "fewer steps to converge with 0.2", .whyDisagrees = "the other ratio converges in fewer steps here"},
};
constexpr StudySpec kQdmStudies[] = {
    {.name = "qdm", .description = "the QDM paper's page: its claims judged by qdm-claims and qdm-height-ratio",
     .kind = StudyKind::Paper,
     .paperNotes = "Quadratic displacement maps (Kiglics et al. 2023): the paper's claims, measured\n\n"
                   "The paper's own comparison is its QDM (`qdm:variant=1`: the published map and Algorithm 1, "
                   "no exact finish) against Dummer's cone step mapping (`cone:variant=1`); ours is the safe qdm "
                   "against the safe cone. Departures from the paper's setup: CPU rays instead of a GTX 1060M "
                   "(speed claims are CPU ratios on the same rays, steps and errors do not depend on the "
                   "hardware); the nine maps at 512² instead of 1024² (peaks6 at 256²) because the published "
                   "builder takes minutes per 1024² map on gently rising ground on 2 cores; 320×256 rays per "
                   "view instead of 1920×1080; errors against the exact reference instead of 200 linear + 20 "
                   "binary steps; `cone:variant=1` ends with our exact cell test where Dummer's has none, which "
                   "favours the cone in the error claims.",
     .parts = kQdmPageParts, .claims = kQdmClaims, .paperFile = "quadratic-displacement-maps.md"},
    {.name = "qdm-claims", .description = "the paper's QDM vs Dummer's cones and safe qdm vs safe cones, 9 maps, 8 elevations, caps 4-200",
     .maps = kQdmClaimMaps, .techniques = kQdmClaimRows, .caps = kQdmPaperCaps, .width = 320, .height = 256,
     .distance = 1.2f},
    {.name = "qdm-height-ratio", .description = "the paper's QDM at height ratios 0, 0.2, 0.5, 1",
     .maps = kQdmHeightRatioMaps, .techniques = kQdmHeightRatioRows, .caps = kQdmHeightRatioCaps, .width = 320,
     .height = 256, .distance = 1.2f},
    {.name = "qdm-cone", .description = "qdm vs safe cones by elevation and cap, Fig. 9-11 / Table 1 (was bench_qdm)",
     .maps = kQdmStudyMaps, .techniques = kQdmStudyRows, .caps = kCapsAndDefault, .width = 320,
     .height = 256, .distance = 1.2f, .compare = "qdm/cone"},
    {.name = "qdm-builds", .description = "qdm build time, wall and CPU, 256²-4096² (was bench_qdm --builds)",
     .kind = StudyKind::Builds, .maps = kQdmBuildMaps, .techniques = kQdmBuildRows, .sizes = kBuildSizes},
};

// bench_safety's sections (docs/safety.md): precomputation per size, Fig. 29 / Table 1 on this CPU
// beside Embree, and exterior-ray maps (§6.2): their builds and their gain per elevation.
constexpr std::string_view kFbmBySize[] = {"gen:fbm:{N}x{N}:1"};
constexpr std::string_view kSafetyBuildRows[] = {"safety-sd", "safety-cc", "safety-sd:phi-max=-45"};
constexpr std::string_view kSafetyCompareMaps[] = {"gen:fbm:256x256:1", "gen:fbm:512x512:1", "gen:fbm:1024x1024:1"};
constexpr std::string_view kSafetyCompareRows[] = {
    "exact", "linear:max-steps=16", "linear:max-steps=32", "linear:max-steps=64",
    "relaxed-cone:max-steps=8", "relaxed-cone:max-steps=15", "relaxed-cone:max-steps=35",
    "safety-sd", "safety-sd:isotropic=1", "safety-sd:phi-max=-45", "safety-sd:positive-distance=1",
    "safety-sd:view-dependent=1", "safety-cc", "safety-cc:isotropic=1", "safety-cc:phi-max=-45",
    "safety-cc:positive-distance=1", "safety-cc:view-dependent=1"};
constexpr float kSafetyCompareElevations[] = {52.7f};
constexpr std::string_view kSafetyExteriorMaps[] = {"gen:fbm:512x512:1"};
constexpr std::string_view kSafetyExteriorRows[] = {"safety-sd", "safety-sd:exterior=1", "safety-cc",
                                                    "safety-cc:exterior=1", "safety-cc:exterior=1:exterior-slope=1"};
constexpr int kSafetyExteriorSizes[] = {256, 512, 1024};
// The `safety` paper page (docs/papers/safety.md): Fig. 29 like for like (MM, NA, LS, RC, SD, CC,
// isotropic as the paper's fair comparison and directional, φ_max with views inside it and the
// paper's maps-used-anyway rendering outside it, d > 0) on fbm and on terrain, Table 1 per size,
// Table 1's exterior rows. Terrain at 256²: the safety bakes of large flat regions are slow.
constexpr std::string_view kSafetyFig29Rows[] = {
    "maxmip", "exact", "linear:max-steps=16", "linear:max-steps=32", "linear:max-steps=64",
    "relaxed-cone:max-steps=8", "relaxed-cone:max-steps=15", "relaxed-cone:max-steps=35",
    "safety-sd:isotropic=1", "safety-sd", "safety-cc:isotropic=1", "safety-cc",
    "safety-sd:isotropic=1:phi-max=-45", "safety-cc:isotropic=1:phi-max=-45",
    "safety-cc:isotropic=1:phi-max=-45:phi-outside=1", "safety-sd:isotropic=1:positive-distance=1",
    "safety-cc:isotropic=1:positive-distance=1"};
constexpr std::string_view kSafetyFig29Maps[] = {"gen:fbm:256x256:1", "gen:fbm:512x512:1"};
// A 256² window of the SRTM mosaic over the Chilean coast and the Andes (76.7-59.6° W,
// 16.7-33.7° S: ocean floor, the trench, the cordillera), and peaks6, the smooth relief.
constexpr std::string_view kSafetyTerrainMaps[] = {
    "../shared/data/earth-srtm-5400x2700.png@crop=1550,1600,256,256", "gen:peaks6:256x256:1"};
// 40.2°: the standard view, its far rays outside φ_max = −45°; 80°: every primary ray (corners
// 33.5° off axis at fov 45°, 5:4) descends at more than 45°, inside the restriction.
constexpr float kSafetyFig29Elevations[] = {40.2f, 80.0f};
constexpr std::string_view kSafetyTable1Maps[] = {"gen:fbm:256x256:1", "gen:fbm:512x512:1",
                                                  "gen:fbm:1024x1024:1"};
constexpr std::string_view kSafetyTable1Rows[] = {"exact", "safety-sd:isotropic=1", "safety-cc:isotropic=1",
                                                  "safety-sd", "safety-cc"};
// Table 1's exterior rows (cyl_ext, cyl_ext + cone_all, cyl_ext + cone_ext) at 128²: cone_ext
// takes ~36 s at 256² on an idle core pair, past the quick run's budget.
constexpr std::string_view kSafetyExteriorTable1Maps[] = {"gen:fbm:128x128:1"};
constexpr std::string_view kSafetyExteriorTable1Rows[] = {
    "safety-sd:isotropic=1", "safety-sd:isotropic=1:exterior=1", "safety-cc:isotropic=1",
    "safety-cc:isotropic=1:exterior=1", "safety-cc:isotropic=1:exterior=1:exterior-slope=1"};
// Map statistics (mean r) and build seconds of the page's maps, φ_max rows at 256² only.
constexpr std::string_view kSafetyBuildsTerrainMaps[] = {
    "gen:fbm:256x256:1", "../shared/data/earth-srtm-5400x2700.png@crop=1550,1600,256,256", "gen:peaks6:256x256:1"};
constexpr std::string_view kSafetyBuildsTerrainRows[] = {"safety-sd:isotropic=1", "safety-sd",
                                                         "safety-sd:isotropic=1:phi-max=-45"};
// §8: exact against sampled precomputation (8 positions × 256 directions). At 64²: our sampler
// walks every sampled ray cell by cell (~30 s at 128², ~190 s at 256² on 2 loaded cores).
constexpr std::string_view kSafetySampledMaps[] = {"gen:fbm:64x64:1"};
constexpr std::string_view kSafetySampledRows[] = {"exact", "safety-sd:isotropic=1", "safety-sd:isotropic=1:precompute=1",
                                                   "safety-cc:isotropic=1", "safety-cc:isotropic=1:precompute=1"};
// Fig. 8: shadow rays toward a light at 30°, traced from the light toward each point (relaxed
// cones forbid upward rays), from the reference's primary hits, against the reference's shadows.
constexpr std::string_view kSafetyShadowMaps[] = {"gen:fbm:512x512:1"};
constexpr std::string_view kSafetyShadowRows[] = {"relaxed-cone", "relaxed-cone:max-steps=35", "linear:max-steps=32",
                                                  "safety-sd", "safety-cc"};
constexpr std::string_view kSafetyPaperParts[] = {"safety-fig29", "safety-fig29-terrain", "safety-table1",
                                                  "safety-table1-exterior", "safety-builds-terrain",
                                                  "safety-sampled", "safety-shadows"};
constexpr std::string_view kFbm256 = "fbm:256x256:1", kFbm512 = "fbm:512x512:1", kFbm1024 = "fbm:1024x1024:1";
constexpr std::string_view kSrtmCrop = "earth-srtm-5400x2700@256x256+1550+1600", kPeaks6 = "peaks6:256x256:1";
constexpr std::string_view kSdIso = "safety-sd:isotropic=1", kCcIso = "safety-cc:isotropic=1";
constexpr std::string_view kSdIsoPhi = "safety-sd:isotropic=1:phi-max=-45";
constexpr std::string_view kCcIsoPhi = "safety-cc:isotropic=1:phi-max=-45";
constexpr std::string_view kCcIsoPhiOutside = "safety-cc:isotropic=1:phi-max=-45:phi-outside=1";
constexpr std::string_view kWhySpeedOrder =
    "see the steps column: CPU time follows the steps per ray and the cost of each step";
constexpr ClaimSpec kSafetyClaims[] = {
    // Fig. 8 / §3: relaxed cones' shadow rays, marched from the light, stop early.
    {.source = "§3, Fig. 8", .claim = "relaxed cones' shadow rays (marched from the light) terminate early: virtual occlusions",
     .paper = "artefacts (Fig. 8)", .part = "safety-shadows", .metric = ClaimMetric::ShadowWrongPercent,
     .paperVariant = {"relaxed-cone"}, .safeVariant = {"safety-cc"}, .low = 0.1,
     .whyAgrees = "the march from the light ends at its step cap or its binary search settles on a nearer "
                  "surface, so lit points read as occluded; SD and CC (safe column) find every point's light",
     .whyDisagrees = "on this map and light RC's shadow rays reach their points within its cap"},
    {.source = "§3, Fig. 8", .claim = "even a larger step budget (35) does not remove them easily",
     .paper = "\"even thresholding cannot address easily\"", .part = "safety-shadows",
     .metric = ClaimMetric::ShadowWrongPercent, .paperVariant = {"relaxed-cone:max-steps=35"},
     .safeVariant = {"safety-sd"}, .low = 0.1,
     .whyAgrees = "more steps leave wrong shadows where the relaxed cones' apexes stall the march",
     .whyDisagrees = "35 steps bring the shadow rays to their points on this map"},
    // Table 1, rendering (isotropic shapes, the paper's fair comparison; directional beside them).
    {"Table 1", "CC renders faster than SD, 256²", "548 / 304 Hz = 1.80×", "safety-table1", ClaimMetric::Speed,
     {kCcIso, kSdIso, kFbm256, kFbm256}, {"safety-cc", "safety-sd", kFbm256, kFbm256}, -90, 90, -1, 0.9, 3.6,
     "CC takes far fewer steps than SD: its slanted plane jumps where SD's radius is 0", kWhySpeedOrder},
    {"Table 1", "CC renders faster than SD, 512²", "444 / 190 Hz = 2.34×", "safety-table1", ClaimMetric::Speed,
     {kCcIso, kSdIso, kFbm512, kFbm512}, {"safety-cc", "safety-sd", kFbm512, kFbm512}, -90, 90, -1, 1.17, 4.68,
     "CC takes far fewer steps than SD: its slanted plane jumps where SD's radius is 0", kWhySpeedOrder},
    {"Table 1", "CC renders faster than SD, 1024²", "313 / 85 Hz = 3.68×", "safety-table1", ClaimMetric::Speed,
     {kCcIso, kSdIso, kFbm1024, kFbm1024}, {"safety-cc", "safety-sd", kFbm1024, kFbm1024}, -90, 90, -1, 1.84, 7.36,
     "SD's steps grow with the map (a walk of ~1 texel per step), CC's do not", kWhySpeedOrder},
    {"Table 1", "CC keeps its speed from 256² to 1024²", "313 / 548 Hz = 0.57×", "safety-table1",
     ClaimMetric::Speed, {kCcIso, kCcIso, kFbm1024, kFbm256}, {"safety-cc", "safety-cc", kFbm1024, kFbm256}, -90,
     90, -1, 0.285, 1.14, "CC's steps per ray hardly grow with the map size",
     "outside a factor of 2 of the paper's ratio: see the steps per size"},
    {"Table 1", "SD slows down with the map size, 256² to 1024²", "85 / 304 Hz = 0.28×", "safety-table1",
     ClaimMetric::Speed, {kSdIso, kSdIso, kFbm1024, kFbm256}, {"safety-sd", "safety-sd", kFbm1024, kFbm256}, -90,
     90, -1, 0.14, 0.56, "SD's steps grow about linearly with N on fbm (radii near 0)",
     "outside a factor of 2 of the paper's ratio: see the steps per size"},
    {"§8 / Table 1", "directional shapes render 20% faster than isotropic ones (CC)", "1.2×", "safety-table1",
     ClaimMetric::Speed, {"safety-cc", kCcIso}, {"safety-sd", kSdIso}, -90, 90, -1, 1.0, 1.44,
     "one distance per ray class is longer than their minimum: fewer steps",
     "see the steps: the directional maps save steps, yet each step fetches a class-specific texel"},
    {"Table 1", "φ_max = −45° speeds SD up (views inside the restriction), 512²", "284 / 190 Hz = 1.49×",
     "safety-fig29", ClaimMetric::Speed, {kSdIsoPhi, kSdIso, kFbm512, kFbm512}, {}, 79, 90, -1, 1.1, 3.0,
     "the restricted distances are far longer (safety-builds-terrain's mean r): fewer steps per ray",
     "see the steps at the inside view"},
    {"Table 1", "φ_max = −45° speeds CC up (views inside the restriction), 512²", "492 / 444 Hz = 1.11×",
     "safety-fig29", ClaimMetric::Speed, {kCcIsoPhi, kCcIso, kFbm512, kFbm512}, {}, 79, 90, -1, 1.0, 2.0,
     "longer cylinders under the same slanted plane: fewer steps",
     "CC already takes few steps; a longer radius saves little, and steep views are short walks"},
    {"Table 1 / §8", "rendering outside φ_max with the maps anyway: artefacts very limited (CC, 40.2°)",
     "no number (\"very limited\"); ≤ 1% of the pixels taken as limited", "safety-fig29",
     ClaimMetric::WrongPercent, {kCcIsoPhiOutside, {}}, {kCcIsoPhi, {}}, 40, 41, -1, 0.0, 1.0,
     "the rays outside φ_max rarely meet a ridge inside the longer radii",
     "the far rays step over ridges the restricted maps no longer guard (see the images)"},
    {"Table 1 / §8", "rendering outside φ_max with the maps anyway, terrain (CC, 40.2°)",
     "no number (\"very limited\"); ≤ 1% of the pixels taken as limited", "safety-fig29-terrain",
     ClaimMetric::WrongPercent, {kCcIsoPhiOutside, {}}, {kCcIsoPhi, {}}, 40, 41, -1, 0.0, 1.0,
     "the rays outside φ_max rarely meet a ridge inside the longer radii",
     "the far rays step over ridges the restricted maps no longer guard"},
    // Fig. 29: accuracy and ordering.
    {"Fig. 29", "SD and CC are accurate in all situations (CC, fbm)", "0 wrong pixels", "safety-fig29",
     ClaimMetric::WrongPercent, {kCcIso, {}}, {"safety-cc", {}}, -90, 90, -1, 0.0, 0.0,
     "exact by construction: centerline tests, bisection, an exact cell finish",
     "a bug: the rows are exact by contract"},
    {"Fig. 29", "SD and CC are accurate in all situations (SD, terrain)", "0 wrong pixels",
     "safety-fig29-terrain", ClaimMetric::WrongPercent, {kSdIso, {}}, {"safety-sd", {}}, -90, 90, -1, 0.0, 0.0,
     "exact by construction", "a bug: the rows are exact by contract"},
    {"Fig. 29", "CC is faster than the accurate naive walk NA, 512²", "bar chart (CC > NA)", "safety-fig29",
     ClaimMetric::Speed, {kCcIso, "exact", kFbm512, kFbm512}, {"safety-cc", "exact", kFbm512, kFbm512}, -90, 90,
     -1, 1.0, 1e300, "CC's steps are a fraction of NA's one-cell steps", kWhySpeedOrder},
    {"Fig. 29", "CC is faster than NA on terrain (SRTM crop)", "bar chart (CC > NA)", "safety-fig29-terrain",
     ClaimMetric::Speed, {kCcIso, "exact", kSrtmCrop, kSrtmCrop}, {"safety-cc", "exact", kSrtmCrop, kSrtmCrop},
     -90, 90, -1, 1.0, 1e300, "CC's steps are a fraction of NA's one-cell steps", kWhySpeedOrder},
    {"Fig. 29", "SD is faster than NA, 512²", "bar chart (SD > NA)", "safety-fig29", ClaimMetric::Speed,
     {kSdIso, "exact", kFbm512, kFbm512}, {"safety-sd", "exact", kFbm512, kFbm512}, -90, 90, -1, 1.0, 1e300,
     "SD's radii skip enough cells to pay for its test per step",
     "on fbm at depth 0.1·N nearly every radius is 0 (safety-builds-terrain's mean r): SD walks like NA "
     "plus its marching work (steps column)"},
    {"Fig. 29", "SD is faster than NA on terrain (peaks6, long radii)", "bar chart (SD > NA)",
     "safety-fig29-terrain", ClaimMetric::Speed, {kSdIso, "exact", kPeaks6, kPeaks6},
     {"safety-sd", "exact", kPeaks6, kPeaks6}, -90, 90, -1, 1.0, 1e300,
     "the smooth relief gives radii of several texels (safety-builds-terrain's mean r)",
     "the isotropic radius (the minimum over the classes) is short even on peaks6 (safety-builds-terrain's "
     "mean r), and SD takes more steps than NA (steps column)"},
    {"Fig. 29", "minmax mipmaps (MM) are slower than NA", "bar chart (MM < NA)", "safety-fig29",
     ClaimMetric::Speed, {"maxmip", "exact"}, {}, -90, 90, -1, 0.0, 1.0,
     "the pyramid's ascents and descents cost more than the cells they skip",
     "our maxmip skips empty space fast on the CPU (its steps column): the paper's GPU MM had a costlier "
     "traversal"},
    {"Fig. 29", "LS (16 steps) is very error-prone", "dashed bar (artefacts); > 0.1% wrong pixels taken as "
     "artefacts", "safety-fig29", ClaimMetric::WrongPercent, {"linear:max-steps=16", {}}, {}, -90, 90, -1, 0.1,
     1e300, "fixed steps skip thin features", "few pixels are wrong at this depth: the fbm relief is smooth "
     "at the step length of 16 steps"},
    {"Fig. 29", "RC shows artefacts even with 35 steps", "dashed bar (artefacts); > 0.1% wrong pixels taken as "
     "artefacts", "safety-fig29", ClaimMetric::WrongPercent, {"relaxed-cone:max-steps=35", {}}, {}, -90, 90, -1,
     0.1, 1e300, "relaxed cones let the ray step into the relief and across thin features before the "
     "binary search", "the relaxed cones hold on this relief"},
    {"Fig. 29", "RC needs few steps (8) to match SD/CC's speed", "bar chart (RC 8 ≈ CC)", "safety-fig29",
     ClaimMetric::Speed, {"relaxed-cone:max-steps=8", kCcIso}, {"relaxed-cone:max-steps=8", "safety-cc"}, -90,
     90, -1, 0.5, 2.0, "within a factor of 2 of CC", "outside a factor of 2 of CC's speed"},
    {"Fig. 29 / §7", "d > 0 is faster (CC) and approximates only some silhouettes", "bar chart (d > 0 > CC)",
     "safety-fig29", ClaimMetric::Speed, {"safety-cc:isotropic=1:positive-distance=1", kCcIso}, {}, -90, 90, -1,
     1.0, 1e300, "radius 0 becomes 1: one naive step saved per zero-radius test",
     "the clamped jumps overshoot and pay bisections (steps column)"},
    {"Fig. 29 / §7", "d > 0: artefacts limited to some silhouettes (CC)", "no number; ≤ 1% wrong pixels taken "
     "as limited", "safety-fig29", ClaimMetric::WrongPercent, {"safety-cc:isotropic=1:positive-distance=1", {}},
     {}, -90, 90, -1, 0.0, 1.0, "only rays skipping a one-texel feature go wrong",
     "many rays skip one-texel features of this relief"},
    // Table 1, exterior rays (128² here, see the notes).
    {"Table 1", "exterior visibility speeds SD up (cyl_ext / cyl_all), 256² in the paper", "358 / 304 Hz = 1.18×",
     "safety-table1-exterior", ClaimMetric::Speed, {"safety-sd:isotropic=1:exterior=1", kSdIso}, {}, -90, 90, -1,
     1.05, 1e300, "the exterior radii are longer: fewer steps (steps column)",
     "the exterior radii are barely longer than the all-ray ones on fbm (steps column; docs/safety.md: "
     "borderline line sets keep triangles limiting)"},
    {"Table 1", "exterior visibility matters less for CC (cyl_ext + cone_all / cyl_all + cone_all)",
     "563 / 548 Hz = 1.03×", "safety-table1-exterior", ClaimMetric::Speed, {"safety-cc:isotropic=1:exterior=1",
     kCcIso}, {}, -90, 90, -1, 0.9, 1.15, "CC's slanted plane already carries most of the jump",
     "see the steps"},
    // §8, sampled precomputation (8 positions on s_τ × 256 directions; 64² here, see the notes).
    {"§8", "sampled precomputation (8 × 256) renders as fast as the exact one (SD)", "\"the same rendering "
     "performance\"", "safety-sampled", ClaimMetric::Speed, {"safety-sd:isotropic=1:precompute=1", kSdIso},
     {"safety-cc:isotropic=1:precompute=1", kCcIso}, -90, 90, -1, 0.8, 1.25,
     "the sampled radii are about the exact ones (steps column)", "see the steps column"},
    {"§8", "sampled precomputation results in artefacts (SD)", "\"results in artifacts\" (> 0 wrong pixels)",
     "safety-sampled", ClaimMetric::WrongPercent, {"safety-sd:isotropic=1:precompute=1", {}},
     {"safety-cc:isotropic=1:precompute=1", {}}, -90, 90, -1, 1e-9, 1e300,
     "rays between the samples leave S inside the sampled radius and the march steps over them",
     "the 2048 sampled rays per texel and class found the limiting columns that matter for these views "
     "(steps and radii almost those of the exact maps)"},
    {"§8", "sampled precomputation is ~10× slower than the exact one", "\"roughly 10 times slower\"",
     "safety-sampled", ClaimMetric::BuildSeconds, {"safety-sd:isotropic=1:precompute=1", kSdIso},
     {"safety-cc:isotropic=1:precompute=1", kCcIso}, -90, 90, -1, 2.0, 50.0,
     "the same order as the paper's", "our exact scan dismisses whole columns by a bound (docs/safety.md) "
     "while our sampler walks each of the 2048 rays cell by cell: a plain, not a \"fairly optimized\", sampler"},
    // Table 1, precomputation.
    {"Table 1", "cone_all adds little to cyl_all's build (1024²)", "16.1 / 15.2 s = 1.06×", "safety-table1",
     ClaimMetric::BuildSeconds, {kCcIso, kSdIso, kFbm1024, kFbm1024}, {"safety-cc", "safety-sd", kFbm1024,
     kFbm1024}, -90, 90, -1, 0.5, 2.0, "the N-buffer slope scan is cheap beside the distances",
     "our exact SD scan is fast on the CPU (a bound dismisses most cells); the slope scan, two N-buffer "
     "lookups per abscissa, dominates"},
    {"Table 1", "cyl_ext builds far slower than cyl_all (256² in the paper)", "14 / 1.8 s = 7.8×",
     "safety-table1-exterior", ClaimMetric::BuildSeconds, {"safety-sd:isotropic=1:exterior=1", kSdIso}, {}, -90,
     90, -1, 3.9, 1e300, "the exterior test subtracts blockers in line space per (texel, triangle)",
     "see the build seconds"},
};
constexpr StudySpec kSafetyStudies[] = {
    {.name = "safety-builds", .description = "safety-sd / safety-cc precomputation 256²-4096² (was bench_safety)",
     .kind = StudyKind::Builds, .maps = kFbmBySize, .techniques = kSafetyBuildRows, .sizes = kBuildSizes},
    {.name = "safety-compare", .description = "Fig. 29 / Table 1 on this CPU, beside Embree (was bench_safety)",
     .maps = kSafetyCompareMaps, .techniques = kSafetyCompareRows, .elevations = kSafetyCompareElevations,
     .width = 1280, .height = 1024, .distance = 0.6f, .peerTable = true},
    {.name = "safety-exterior-builds", .description = "exterior-ray maps (§6.2): build time per size",
     .kind = StudyKind::Builds, .maps = kFbmBySize, .techniques = kSafetyExteriorRows,
     .sizes = kSafetyExteriorSizes},
    {.name = "safety-exterior", .description = "exterior-ray maps (§6.2): time and steps per elevation",
     .maps = kSafetyExteriorMaps, .techniques = kSafetyExteriorRows, .width = 1280, .height = 1024,
     .distance = 0.6f},
    {.name = "safety-fig29", .description = "safety paper page: Fig. 29 like for like on fbm 256² and 512²",
     .maps = kSafetyFig29Maps, .techniques = kSafetyFig29Rows, .elevations = kSafetyFig29Elevations,
     .distance = 0.6f},
    {.name = "safety-fig29-terrain", .description = "safety paper page: Fig. 29 on terrain (SRTM crop, peaks6; 256²)",
     .maps = kSafetyTerrainMaps, .techniques = kSafetyFig29Rows, .elevations = kSafetyFig29Elevations,
     .distance = 0.6f},
    {.name = "safety-table1", .description = "safety paper page: Table 1 rendering and builds, fbm 256²-1024²",
     .maps = kSafetyTable1Maps, .techniques = kSafetyTable1Rows, .elevations = kSafetyFig29Elevations,
     .distance = 0.6f},
    {.name = "safety-table1-exterior", .description = "safety paper page: Table 1's exterior-ray rows (fbm 128²)",
     .maps = kSafetyExteriorTable1Maps, .techniques = kSafetyExteriorTable1Rows,
     .elevations = kSafetyFig29Elevations, .distance = 1.2f},
    {.name = "safety-sampled", .description = "safety paper page: exact vs sampled precomputation (§8), fbm 64²",
     .maps = kSafetySampledMaps, .techniques = kSafetySampledRows, .elevations = kSafetyFig29Elevations,
     .distance = 0.6f},
    {.name = "safety-shadows", .description = "safety paper page: shadow artefacts of RC, LS, SD, CC (Fig. 8), fbm 512², light at 30°",
     .maps = kSafetyShadowMaps, .techniques = kSafetyShadowRows, .elevations = kSafetyFig29Elevations,
     .distance = 0.6f, .shadowElevation = 30.0f},
    {.name = "safety-builds-terrain", .description = "safety paper page: mean r and build time on fbm and terrain (256²)",
     .kind = StudyKind::Builds, .maps = kSafetyBuildsTerrainMaps, .techniques = kSafetyBuildsTerrainRows},
    {.name = "safety", .description = "precomputed safety shapes: the paper's page (Fig. 29, Table 1, §7-§8)",
     .kind = StudyKind::Paper,
     .paperNotes = "Precomputed safety shapes (Baboud, Eisemann & Seidel 2011): the paper's claims, measured\n\n"
                   "§8's Fig. 29 (MM, NA, LS, RC, SD, CC on a 512² terrain "
                   "covering a 1280×1024 screen, GTX 285; stairs for 256², 512², 1024²) and Table 1 "
                   "(precomputation seconds, rendering Hz without / with φ_max = −45°). The paper's "
                   "timings use isotropic shapes (its fair comparison); our directional defaults are "
                   "the \"safe variant\" column. SD and CC are exact in both forms; the paper's own "
                   "approximate ways are φ_max maps used outside the restriction (`phi-outside=1`) and "
                   "d > 0 (`positive-distance=1`). Cut for time on a loaded 2-core machine: 640×512 "
                   "rays per view instead of 1280×1024, two views (40.2°, and 80° where every ray is "
                   "inside φ_max = −45°), φ_max rows at 256² and 512² only (the restricted build is "
                   "O(r²) per texel: minutes at 1024²), terrain at 256², Table 1's exterior rows at "
                   "128² (cone_ext takes ~36 s at 256² on an idle core pair, 24111 s at 1024² in the "
                   "paper), the §8 sampled precomputation (`precompute=1`: 8 positions on s_τ × 256 "
                   "directions, our plain cell-by-cell sampler: ~30 s at 128²) at 64² instead of the paper's 512². "
                   "Not measured: the mesh-rasterization comparison (a GPU figure). GPU: not measured.",
     .parts = kSafetyPaperParts, .claims = kSafetyClaims, .paperFile = "precomputed-safety-shapes.md"},
};

// bench_quadtree's evidence: steps per ray against map size, and throughput beside Embree.
constexpr std::string_view kQuadtreeScalingMaps[] = {"gen:fbm:{N}x{N}:1", "../shared/data/earth-srtm-10800x5400.png"};
constexpr std::string_view kQuadtreeScalingRows[] = {"quadtree", "quadtree:ascend=0", "maxmip", "quadtree-oriented",
                                                     "exact"};
constexpr int kQuadtreeScalingSizes[] = {256, 512, 1024, 2048, 4096, 8192};
constexpr std::string_view kQuadtreeSpeedMaps[] = {"gen:fbm:1024x1024:1", "gen:fbm:4096x4096:1"};
constexpr float kQuadtreeSpeedElevations[] = {15.3f, 40.2f, 65.1f};
// The paper's page (`relief bench --preset quadtree`, docs/papers/quadtree.md): Table 1 and
// Figs. 8-10 like for like. Relief mapping as the paper ran it (§6): Policarpo's step counts for
// 256² (10 linear + 5 binary, as a shader listing of that work has them; the paper gives no number),
// linear steps doubled and one binary step added per doubling of the map side: one `linear` row
// per size, each judged on its own size.
constexpr std::string_view kQuadtreeTable1Maps[] = {"gen:fbm:256x256", "gen:fbm:512x512", "gen:fbm:1024x1024",
                                                    "gen:fbm:2048x2048"};
constexpr std::string_view kQuadtreeTable1Rows[] = {
    "parallax", "linear:max-steps=10:binary-steps=5", "linear:max-steps=20:binary-steps=6",
    "linear:max-steps=40:binary-steps=7", "linear:max-steps=80:binary-steps=8", "quadtree:box-surface=2", "quadtree"};
// Fig. 8 (512², white = not found within 10, 15, 25 iterations) and §4 (1024²: 20 iterations are
// enough): the paper's fixed loop; a pixel the cap cuts is reported at the cursor, so it is wrong
// against the reference unless the cursor happens to lie within 0.5 texel of the hit.
constexpr std::string_view kQuadtreeIterationMaps[] = {"gen:fbm:512x512", "gen:fbm:1024x1024"};
constexpr std::string_view kQuadtreeIterationRows[] = {
    "quadtree:box-surface=2:max-steps=10", "quadtree:box-surface=2:max-steps=15", "quadtree:box-surface=2:max-steps=20",
    "quadtree:box-surface=2:max-steps=25", "quadtree:box-surface=2", "quadtree:max-steps=10", "quadtree:max-steps=15",
    "quadtree:max-steps=20", "quadtree:max-steps=25"};
// Fig. 9 (the method at various heights): Table 1's 1024² comparison at half and twice its depth.
constexpr std::string_view kQuadtreeDepthMaps[] = {"gen:fbm:1024x1024"};
constexpr std::string_view kQuadtreeDepthRows[] = {"linear:max-steps=40:binary-steps=7", "quadtree:box-surface=2",
                                                   "quadtree"};
// §6 / Fig. 10 (artefacts of relief mapping on an irregular surface): Policarpo's 256² step count
// on Table 1's fbm and on two surfaces with features a linear step can miss.
constexpr std::string_view kQuadtreeArtefactMaps[] = {"gen:fbm:256x256", "gen:walls:256x256", "gen:terraces:256x256"};
constexpr std::string_view kQuadtreeArtefactRows[] = {"linear:max-steps=10:binary-steps=5", "quadtree:box-surface=2",
                                                      "quadtree"};
constexpr std::string_view kQuadtreeParts[] = {"quadtree-table1", "quadtree-iterations", "quadtree-artefacts",
                                               "quadtree-depth-0.05", "quadtree-depth-0.2"};
constexpr std::string_view kQtPaper = "quadtree:box-surface=2", kQtSafe = "quadtree";
constexpr std::string_view kRm256 = "linear:max-steps=10:binary-steps=5", kRm512 = "linear:max-steps=20:binary-steps=6",
                           kRm1024 = "linear:max-steps=40:binary-steps=7",
                           kRm2048 = "linear:max-steps=80:binary-steps=8";
constexpr std::string_view kQtFbm256 = "fbm:256x256", kQtFbm512 = "fbm:512x512", kQtFbm1024 = "fbm:1024x1024",
                           kQtFbm2048 = "fbm:2048x2048";
// Bands, fixed before the run: a frame-rate ratio agrees within a factor 1.5 of the paper's (and
// on its side of 1 where the paper's claim is a crossover); a step ratio 2048² / 256² is "like
// log p" when it lies nearer log p (22 / 16 = 1.375) than sqrt p (8) on a log scale (< 3.32).
constexpr std::string_view kWhyFewerArtefacts =
    "Fewer wrong pixels than relief mapping; the paper variant's are where texel boxes differ from S (it is "
    "exact on its boxes), the safe variant has none.";
constexpr std::string_view kWhyMoreArtefacts =
    "Against S the paper's texel boxes are themselves an approximation (a box wall half a texel from S's "
    "sloped cell, a flat top over a peak): they differ from S on more pixels than relief mapping's steps miss. "
    "The safe variant (S) has none.";
constexpr ClaimSpec kQuadtreeClaims[] = {
    {.source = "Table 1", .claim = "quadtree's frame rate 2048² / 256² (scales well to large maps)",
     .paper = "63 / 95 fps = 0.66", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {kQtPaper, kQtPaper, kQtFbm2048, kQtFbm256}, .safeVariant = {kQtSafe, kQtSafe, kQtFbm2048, kQtFbm256},
     .cap = 0, .low = 0.44, .high = 1.0,
     .whyAgrees = "Within a factor 1.5 of the paper's loss: the walk adds a few levels per doubling of the side, "
                  "as the step rows below show.",
     .whyDisagrees = "Outside a factor 1.5 of the paper's: the steps grow about as log p (the step rows below), "
                     "so the rest is the cost per step on the larger pyramid, memory-bound on this CPU as the "
                     "parallax row's single fetch shows."},
    {.source = "Table 1", .claim = "quadtree's frame rate 1024² / 256²", .paper = "71 / 95 fps = 0.75",
     .part = "quadtree-table1", .metric = ClaimMetric::Speed, .paperVariant = {kQtPaper, kQtPaper, kQtFbm1024, kQtFbm256},
     .safeVariant = {kQtSafe, kQtSafe, kQtFbm1024, kQtFbm256}, .cap = 0, .low = 0.5, .high = 1.0,
     .whyAgrees = "Within a factor 1.5 of the paper's: steps grow slowly with the map (log p in most views).",
     .whyDisagrees = "Outside a factor 1.5 of the paper's: per-step cost on this CPU depends on the pyramid's "
                     "size (cache), not only the step count."},
    {.source = "Table 1", .claim = "relief mapping's frame rate 2048² / 256², linear steps doubled per doubling "
                                   "of the side (80+8 vs 10+5)",
     .paper = "< 9 / 188 fps < 0.048", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {kRm2048, kRm256, kQtFbm2048, kQtFbm256}, .cap = 0, .low = 0.0, .high = 0.048,
     .whyAgrees = "The cost grows at least as fast as the step count, as on the paper's GPU.",
     .whyDisagrees = "Our `linear` stops at the first sample below the surface (a dynamic loop; the paper's GPU "
                     "ran every step), so its steps per pixel (the part's rows) grow less than the 8× budget, and "
                     "its time follows them; the paper's fall below 9 fps is more than even the full 8× explains."},
    {.source = "Table 1", .claim = "relief mapping's frame rate 1024² / 256² (40+7 vs 10+5 steps)",
     .paper = "48 / 188 fps = 0.26", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {kRm1024, kRm256, kQtFbm1024, kQtFbm256}, .cap = 0, .low = 0.17, .high = 0.38,
     .whyAgrees = "Within a factor 1.5 of the paper's; our time follows our steps per pixel (the part's rows), "
                  "which grow less than the 4× budget as the loop stops at the first sample below the surface.",
     .whyDisagrees = "Outside a factor 1.5: our `linear` leaves its loop at the first step below the surface, "
                     "so its time grows less than its step budget."},
    {.source = "Table 1", .claim = "parallax mapping's frame rate 2048² / 256² (one fetch: size-independent)",
     .paper = "354 / 360 fps = 0.98", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {"parallax", "parallax", kQtFbm2048, kQtFbm256}, .cap = 0, .low = 0.8, .high = 1.25,
     .whyAgrees = "One fetch per pixel whatever the map size.",
     .whyDisagrees = "Parallax does the same single fetch per pixel at every size, so the loss is that fetch's "
                     "memory cost: a 2048² map of floats (16 MiB) does not stay in this CPU's caches, a 256² one "
                     "does."},
    {.source = "Table 1", .claim = "quadtree / relief mapping at 256²: relief mapping is faster on small maps",
     .paper = "95 / 188 fps = 0.51", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {kQtPaper, kRm256, kQtFbm256, kQtFbm256}, .safeVariant = {kQtSafe, kRm256, kQtFbm256, kQtFbm256},
     .cap = 0, .low = 0.0, .high = 1.0,
     .whyAgrees = "Relief mapping's 10 + 5 fetches are at least as fast as the quadtree's walk at 256², as in "
                  "the paper.",
     .whyDisagrees = "The quadtree walk is already cheaper than 10 linear + 5 binary fetches here."},
    {.source = "Table 1", .claim = "quadtree / relief mapping at 512²: about even", .paper = "82 / 84 fps = 0.98",
     .part = "quadtree-table1", .metric = ClaimMetric::Speed, .paperVariant = {kQtPaper, kRm512, kQtFbm512, kQtFbm512},
     .safeVariant = {kQtSafe, kRm512, kQtFbm512, kQtFbm512}, .cap = 0, .low = 0.67, .high = 1.5,
     .whyAgrees = "Within a factor 1.5 of even, as in the paper.",
     .whyDisagrees = "More than a factor 1.5 from even: the crossover lies at another size on this CPU."},
    {.source = "Abstract, Table 1", .claim = "quadtree / relief mapping at 1024²: quadtree is faster above 512²",
     .paper = "71 / 48 fps = 1.48", .part = "quadtree-table1", .metric = ClaimMetric::Speed,
     .paperVariant = {kQtPaper, kRm1024, kQtFbm1024, kQtFbm1024}, .safeVariant = {kQtSafe, kRm1024, kQtFbm1024, kQtFbm1024},
     .cap = 0, .low = 1.0,
     .whyAgrees = "Relief mapping with a budget of 40 + 7 steps is slower than the quadtree's walk at 1024².",
     .whyDisagrees = "Relief mapping's 40 + 7 fetches are still cheaper than the quadtree's walk on this CPU."},
    {.source = "Abstract, Table 1", .claim = "quadtree / relief mapping at 2048²", .paper = "63 / < 9 fps > 7",
     .part = "quadtree-table1", .metric = ClaimMetric::Speed, .paperVariant = {kQtPaper, kRm2048, kQtFbm2048, kQtFbm2048},
     .safeVariant = {kQtSafe, kRm2048, kQtFbm2048, kQtFbm2048}, .cap = 0, .low = 1.0,
     .whyAgrees = "Relief mapping with a budget of 80 + 8 steps is slower than the quadtree's walk at 2048².",
     .whyDisagrees = "Relief mapping's 80 + 8 fetches are still cheaper than the quadtree's walk on this CPU."},
    {.source = "Abstract, §6, Fig. 8", .claim = "steps 2048² / 256² over all views: close to log p in most cases",
     .paper = "log p: 22 / 16 = 1.375 (sqrt p: 8)", .part = "quadtree-table1", .metric = ClaimMetric::Steps,
     .paperVariant = {kQtPaper, kQtPaper, kQtFbm2048, kQtFbm256}, .safeVariant = {kQtSafe, kQtSafe, kQtFbm2048, kQtFbm256},
     .cap = 0, .low = 0.0, .high = 3.32,
     .whyAgrees = "Nearer log p than sqrt p: the walk adds about a level per doubling of the side.",
     .whyDisagrees = "Nearer sqrt p: with the depth scaled with the map (0.1 N) the rays cross N-proportional "
                     "runs of cells at the finest levels."},
    {.source = "§2", .claim = "steps 2048² / 256², steep views (60°-90°): log p (one node per level)",
     .paper = "log p: 1.375", .part = "quadtree-table1", .metric = ClaimMetric::Steps,
     .paperVariant = {kQtPaper, kQtPaper, kQtFbm2048, kQtFbm256}, .safeVariant = {kQtSafe, kQtSafe, kQtFbm2048, kQtFbm256},
     .minElevation = 60.0f, .cap = 0, .low = 0.0, .high = 3.32,
     .whyAgrees = "Nearer log p than sqrt p, as a (nearly) vertical ray visits about one node per level.",
     .whyDisagrees = "Nearer sqrt p even for steep rays."},
    {.source = "§2", .claim = "steps 2048² / 256², grazing views (≤ 20°): between log p and sqrt p",
     .paper = "Ω(log p) to O(sqrt p): 1.375 to 8", .part = "quadtree-table1", .metric = ClaimMetric::Steps,
     .paperVariant = {kQtPaper, kQtPaper, kQtFbm2048, kQtFbm256}, .safeVariant = {kQtSafe, kQtSafe, kQtFbm2048, kQtFbm256},
     .maxElevation = 20.0f, .cap = 0, .low = 1.375, .high = 8.0,
     .whyAgrees = "Within §2's bounds; how far above log p (1.375) it lies, against the steep row, is how much "
                  "more grazing rays grow.",
     .whyDisagrees = "Outside the bounds of §2."},
    {.source = "§6, Fig. 10", .claim = "wrong pixels, quadtree / relief mapping (10+5) at 256², fbm (Table 1's "
                                       "surface): fewer artefacts (safe column: S's own wrong %)",
     .paper = "artefacts in relief mapping, none in quadtree (images only)", .part = "quadtree-artefacts",
     .metric = ClaimMetric::WrongPercent, .paperVariant = {kQtPaper, kRm256, kQtFbm256, kQtFbm256},
     .safeVariant = {kQtSafe, "", kQtFbm256}, .cap = 0, .low = 0.0, .high = 1.0,
     .whyAgrees = kWhyFewerArtefacts, .whyDisagrees = kWhyMoreArtefacts},
    {.source = "§6, Fig. 10", .claim = "the same on walls (one-texel walls a linear step can jump)",
     .paper = "artefacts in relief mapping, none in quadtree (images only)", .part = "quadtree-artefacts",
     .metric = ClaimMetric::WrongPercent, .paperVariant = {kQtPaper, kRm256, "walls:256x256", "walls:256x256"},
     .safeVariant = {kQtSafe, "", "walls:256x256"}, .cap = 0, .low = 0.0, .high = 1.0,
     .whyAgrees = kWhyFewerArtefacts, .whyDisagrees = kWhyMoreArtefacts},
    {.source = "§6, Fig. 10", .claim = "the same on terraces (flat steps and cliffs)",
     .paper = "artefacts in relief mapping, none in quadtree (images only)", .part = "quadtree-artefacts",
     .metric = ClaimMetric::WrongPercent, .paperVariant = {kQtPaper, kRm256, "terraces:256x256", "terraces:256x256"},
     .safeVariant = {kQtSafe, "", "terraces:256x256"}, .cap = 0, .low = 0.0, .high = 1.0,
     .whyAgrees = kWhyFewerArtefacts, .whyDisagrees = kWhyMoreArtefacts},
    {.source = "Fig. 8", .claim = "512², pixels not found within 10 iterations (white)",
     .paper = "large white areas (image only)", .part = "quadtree-iterations", .metric = ClaimMetric::WrongPercent,
     .paperVariant = {"quadtree:box-surface=2:max-steps=10", "", kQtFbm512}, .safeVariant = {"quadtree:max-steps=10", "", kQtFbm512},
     .cap = 0, .low = 1.0, .high = 100.0,
     .whyAgrees = "At least 1 % of the pixels wrong at 10 iterations, as the figure's white areas: a cut walk "
                  "reports the cursor, still above the hit. Both columns count against S; the paper variant's "
                  "include where texel boxes differ from S at any cap (the part's uncapped row).",
     .whyDisagrees = "Under 1 % of the pixels wrong at 10 iterations."},
    {.source = "Fig. 8", .claim = "512², pixels not found within 25 iterations: almost none",
     .paper = "almost no white (image only)", .part = "quadtree-iterations", .metric = ClaimMetric::WrongPercent,
     .paperVariant = {"quadtree:box-surface=2:max-steps=25", "", kQtFbm512}, .safeVariant = {"quadtree:max-steps=25", "", kQtFbm512},
     .cap = 0, .low = 0.0, .high = 5.0,
     .whyAgrees = "At most 5 % of the pixels wrong at 25 iterations (the paper variant's include where texel "
                  "boxes differ from S: compare the part's uncapped row).",
     .whyDisagrees = "More than 5 % of the pixels wrong at 25 iterations: grazing views need more (the steps grow "
                     "toward sqrt p there)."},
    {.source = "§4", .claim = "1024², a fixed loop of 20 iterations is enough", .paper = "\"20 iterations is enough\"",
     .part = "quadtree-iterations", .metric = ClaimMetric::WrongPercent,
     .paperVariant = {"quadtree:box-surface=2:max-steps=20", "", kQtFbm1024}, .safeVariant = {"quadtree:max-steps=20", "", kQtFbm1024},
     .cap = 0, .low = 0.0, .high = 5.0,
     .whyAgrees = "At most 5 % of the pixels wrong with 20 iterations at 1024² (the paper variant's include "
                  "where texel boxes differ from S).",
     .whyDisagrees = "More than 5 % of the pixels wrong with 20 iterations at 1024², mostly at grazing views."},
    {.source = "Fig. 9", .claim = "quadtree / relief mapping at 1024², half the depth (0.05 N)",
     .paper = "images only (Table 1 at 0.1 N: 1.48)", .part = "quadtree-depth-0.05", .metric = ClaimMetric::Speed,
     .paperVariant = {kQtPaper, kRm1024}, .safeVariant = {kQtSafe, kRm1024}, .cap = 0, .low = 1.0,
     .whyAgrees = "Quadtree stays faster than relief mapping at a shallower relief.",
     .whyDisagrees = "Relief mapping is faster at this depth on this CPU."},
    {.source = "Fig. 9", .claim = "quadtree / relief mapping at 1024², twice the depth (0.2 N)",
     .paper = "images only (Table 1 at 0.1 N: 1.48)", .part = "quadtree-depth-0.2", .metric = ClaimMetric::Speed,
     .paperVariant = {kQtPaper, kRm1024}, .safeVariant = {kQtSafe, kRm1024}, .cap = 0, .low = 1.0,
     .whyAgrees = "Quadtree stays faster than relief mapping at a deeper relief.",
     .whyDisagrees = "Relief mapping (a fixed step count, whatever the depth) is faster at this depth on this "
                     "CPU; the quadtree's steps grow with the depth."},
};
constexpr std::string_view kQuadtreePageNotes =
    "Quadtree relief mapping (Schroders & van Gulik 2006): the paper's claims, measured\n\n"
    "Table 1 and Figs. 8-10, like for like on this CPU. Paper variant: "
    "`quadtree:box-surface=2`, the paper's surface (texel boxes at the sample height) walked by its Algorithm 1 "
    "(exact on the boxes, CPU only); safe variant: `quadtree` on S (exact). Relief mapping is `linear` run the "
    "paper's way (§6): Policarpo's 256² step count, 10 linear + 5 binary steps (as in a "
    "relief-mapping shader listing of that work; copies with 15 linear steps also circulate, and the paper names no "
    "number), the linear steps doubled and one binary step added per doubling of the side: 20+6 at "
    "512², 40+7 at 1024², 80+8 at 2048², one row per size, each judged on its own size. Our `linear` leaves its "
    "linear loop at the first sample below the surface; the paper's GPU loop ran every step. Surface: fbm "
    "(periodic value noise down to the texel) as the paper's \"highly irregular surface\", depth 0.1 N (Fig. 9's "
    "depths: 0.05 N and 0.2 N at 1024²); Fig. 10 adds walls and terraces. Views: the 8 standard elevations, "
    "2.9° to 90° at azimuth 30° (\"from top down to grazing\"); a claim's ratio is the geometric mean of the "
    "per-view ratios (the paper averages fps over the angles). Speed is Mrays/s on 2 threads of this shared "
    "machine, not fps on two GeForce 6600GT in SLI; on this shared, loaded machine a speed ratio moved by up to a "
    "third between two runs of this preset, so a speed verdict near its band's edge is not firm. GPU: not measured (no GPU machine for this run; the paper "
    "variant has no GLSL). Wrong pixels: hit/miss differs from `exact` (S) or |Δt| > 0.5 texel; for the paper "
    "variant they include where its boxes differ from S, so Fig. 8's \"not found\" is read as wrong at the cap "
    "(a cut walk reports its cursor). Cut relative to the paper: 320×256 primary rays instead of a screen, best "
    "of 3 repeats; Figs. 8 and 9 as numbers rather than images; Fig. 11 (perceived height) is not measured.";
constexpr StudySpec kQuadtreeStudies[] = {
    {.name = "quadtree-scaling", .description = "steps per ray vs map size 256²-8192² and the earth SRTM map",
     .kind = StudyKind::Scaling, .maps = kQuadtreeScalingMaps, .techniques = kQuadtreeScalingRows,
     .sizes = kQuadtreeScalingSizes, .width = 320, .height = 256, .distance = 0.6f},
    {.name = "quadtree-speed", .description = "quadtree, maxmip, oriented, exact beside Embree at 1024² and 4096²",
     .maps = kQuadtreeSpeedMaps, .techniques = kQuadtreeScalingRows, .elevations = kQuadtreeSpeedElevations,
     .width = 1280, .height = 1024, .distance = 0.6f, .peerTable = true},
    {.name = "quadtree", .description = "the quadtree relief mapping paper's page: Table 1, Figs. 8-10 judged by its parts",
     .kind = StudyKind::Paper, .paperNotes = kQuadtreePageNotes, .parts = kQuadtreeParts, .claims = kQuadtreeClaims,
     .paperFile = "quadtree-relief-mapping.md"},
    {.name = "quadtree-table1", .description = "Table 1: parallax, relief mapping (steps scaled with the size), quadtree on texel boxes and on S, 256²-2048²",
     .maps = kQuadtreeTable1Maps, .techniques = kQuadtreeTable1Rows, .width = 320, .height = 256},
    {.name = "quadtree-iterations", .description = "Fig. 8 / §4: quadtree's fixed loop of 10, 15, 20, 25 iterations at 512² and 1024²",
     .maps = kQuadtreeIterationMaps, .techniques = kQuadtreeIterationRows, .width = 320, .height = 256},
    {.name = "quadtree-artefacts", .description = "§6 / Fig. 10: wrong pixels of relief mapping (10+5 steps) and quadtree at 256² on fbm, walls, terraces",
     .maps = kQuadtreeArtefactMaps, .techniques = kQuadtreeArtefactRows, .width = 320, .height = 256},
    {.name = "quadtree-depth-0.05", .description = "Fig. 9: quadtree vs relief mapping at 1024², depth 0.05 N",
     .maps = kQuadtreeDepthMaps, .techniques = kQuadtreeDepthRows, .width = 320, .height = 256, .depthRatio = 0.05f},
    {.name = "quadtree-depth-0.2", .description = "Fig. 9: quadtree vs relief mapping at 1024², depth 0.2 N",
     .maps = kQuadtreeDepthMaps, .techniques = kQuadtreeDepthRows, .width = 320, .height = 256, .depthRatio = 0.2f},
};

constexpr std::string_view kCurvesPaperMaps[] = {"gen:sine:512x512"};
// Table 1 and its cost beside the reference on the same sample rays (docs/curves.md).
constexpr std::string_view kCurvesTable1Rows[] = {"curves:epsilon=0.25", "curves:epsilon=0.001"};
constexpr float kCurvesTable1Elevations[] = {65.1f, 15.3f};  // unslanted, slanted
// The page (docs/papers/curves.md): Table 1's counts (sine map, 2 samples per pixel) as ratios the
// paper states in §6, unslanted (65.1°) and slanted (15.3°), generous (ε = 0.25) and strict (0.001).
// The paper gives neither the sine's amplitude nor its image size or camera; the claims are judged
// on the gentle sine (depth 0.02·N, as docs/curves.md's Table 1), the steep one (0.1·N) is the
// second part, for comparison. The method has no safe variant: every claim is the paper's renderer.
constexpr std::string_view kCurvesPageParts[] = {"curves-table1-gentle", "curves-table1"};
constexpr ClaimMeasure kCurvesGenerous{"curves:epsilon=0.25"};
constexpr ClaimMeasure kCurvesStrict{"curves:epsilon=0.001"};
constexpr float kUnslanted = 45.0f;  // curves-table1's elevations: 65.1° above, 15.3° below
constexpr ClaimSpec kCurvesClaims[] = {
    {.source = "Table 1, §6", .claim = "unslanted: extra samples are about 10 % of the inside samples",
     .paper = "37,728 / 374,996 = 10.1 %", .part = "curves-table1-gentle", .metric = ClaimMetric::ExtraSamplesPercent,
     .paperVariant = kCurvesGenerous, .minElevation = kUnslanted, .low = 5.0, .high = 15.0,
     .whyAgrees = "the silhouette lies close to the mapped region's edge at a high view",
     .whyDisagrees = "extra samples grow with the sine's amplitude against the view, which the paper does not give (see the steep part)"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.25: a little more than one advance step per sample",
     .paper = "472,559 / 412,724 = 1.14", .part = "curves-table1-gentle", .metric = ClaimMetric::AdvancePerSample,
     .paperVariant = kCurvesGenerous, .minElevation = kUnslanted, .low = 1.0, .high = 1.5,
     .whyAgrees = "coherence along the curve: each sample starts at its neighbour's intersection",
     .whyDisagrees = "with our amplitude and sample spacing a sample starts further from its intersection than the paper's; it gives neither"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.25: almost no reverses", .paper = "15 / 412,724 ≈ 0.00004",
     .part = "curves-table1-gentle", .metric = ClaimMetric::ReversePerSample, .paperVariant = kCurvesGenerous,
     .minElevation = kUnslanted, .high = 0.01, .whyAgrees = "generous steps rarely overshoot at a high view",
     .whyDisagrees = "reverses at ε = 0.25 follow the slope of the eye-facing faces against the eye rays', set by the amplitude the paper does not give"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.001: about three advance steps per sample",
     .paper = "1,180,941 / 411,083 = 2.87", .part = "curves-table1-gentle", .metric = ClaimMetric::AdvancePerSample,
     .paperVariant = kCurvesStrict, .minElevation = kUnslanted, .low = 2.0, .high = 4.0,
     .whyAgrees = "the strict threshold needs more steps to converge",
     .whyDisagrees = "the count depends on the amplitude and sample spacing, which the paper does not give"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.001: more than half the samples produce a reverse",
     .paper = "265,689 / 411,083 = 0.65", .part = "curves-table1-gentle", .metric = ClaimMetric::ReversePerSample,
     .paperVariant = kCurvesStrict, .minElevation = kUnslanted, .low = 0.5,
     .whyAgrees = "advance steps past the intersection are likely at a strict threshold",
     .whyDisagrees = "the count depends on the amplitude and sample spacing, which the paper does not give"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.001: four to five binary cuts per reverse",
     .paper = "1,219,162 / 265,689 = 4.6", .part = "curves-table1-gentle", .metric = ClaimMetric::BinaryCutsPerReverse,
     .paperVariant = kCurvesStrict, .minElevation = kUnslanted, .low = 4.0, .high = 5.0,
     .whyAgrees = "halving the bracket to 0.001 of the sample spacing takes that many cuts",
     .whyDisagrees = "cuts per reverse follow the bracket's length in sample spacings, set by the advance step we measure"},
    {.source = "Table 1, §6", .claim = "unslanted, ε = 0.001: about six evaluations per sample in total",
     .paper = "2,665,792 / 411,083 = 6.5", .part = "curves-table1-gentle", .metric = ClaimMetric::EvaluationsPerSample,
     .paperVariant = kCurvesStrict, .minElevation = kUnslanted, .low = 5.0, .high = 8.0,
     .whyAgrees = "advance, reverse and binary counts all match the paper's order",
     .whyDisagrees = "the counters above differ: see their rows"},
    {.source = "Table 1, §6", .claim = "slanted: well over a quarter of the samples are extra",
     .paper = "69,775 / 238,706 = 29 % of inside", .part = "curves-table1-gentle", .metric = ClaimMetric::ExtraSamplesPercent,
     .paperVariant = kCurvesGenerous, .maxElevation = kUnslanted, .low = 25.0,
     .whyAgrees = "at a low view the silhouette stands far from the underlying surface",
     .whyDisagrees = "our 15.3° view is lower than the paper's slanted one (a third of its covered pixels) and our sine gentler"},
    {.source = "Table 1, §6", .claim = "slanted, ε = 0.25: reverses on about a fifth of the samples",
     .paper = "60,340 / 308,481 = 0.20", .part = "curves-table1-gentle", .metric = ClaimMetric::ReversePerSample,
     .paperVariant = kCurvesGenerous, .maxElevation = kUnslanted, .low = 0.1, .high = 0.3,
     .whyAgrees = "grazing advance steps overshoot far more often", .whyDisagrees = "our 15.3° view is lower than the paper's slanted one, so more grazing steps overshoot"},
    {.source = "Table 1, §6", .claim = "slanted, ε = 0.25: less than two binary cuts per reverse",
     .paper = "98,944 / 60,340 = 1.64", .part = "curves-table1-gentle", .metric = ClaimMetric::BinaryCutsPerReverse,
     .paperVariant = kCurvesGenerous, .maxElevation = kUnslanted, .high = 2.0,
     .whyAgrees = "a generous threshold is reached after few cuts", .whyDisagrees = "cuts per reverse follow the bracket's length in sample spacings, set by the advance step we measure"},
    {.source = "Table 1, §6", .claim = "slanted, ε = 0.001: six to seven evaluations per sample",
     .paper = "1,917,079 / 305,036 = 6.3", .part = "curves-table1-gentle", .metric = ClaimMetric::EvaluationsPerSample,
     .paperVariant = kCurvesStrict, .maxElevation = kUnslanted, .low = 5.5, .high = 7.5,
     .whyAgrees = "the slanted view costs little more than the unslanted one at a strict threshold",
     .whyDisagrees = "our 15.3° view is lower than the paper's slanted one, so more grazing steps overshoot and bisect"},
    {.source = "§6", .claim = "the generous threshold renders the unslanted view well", .paper = "artifact-free (Fig. 10)",
     .part = "curves-table1-gentle", .metric = ClaimMetric::WrongPercent, .paperVariant = kCurvesGenerous,
     .minElevation = kUnslanted, .high = 1.0,
     .whyAgrees = "under 1 % of the samples differ from the exact reference on their own rays",
     .whyDisagrees = "over 1 % of the samples differ from the exact reference on their own rays"},
    {.source = "§6, Fig. 9", .claim = "the slanted view needs the strict threshold: ε = 0.25 leaves artifacts there",
     .paper = "artifacts at the edges (Fig. 9)", .part = "curves-table1-gentle", .metric = ClaimMetric::WrongPercent,
     .paperVariant = {"curves:epsilon=0.25", "curves:epsilon=0.001"}, .maxElevation = kUnslanted, .low = 1.0,
     .whyAgrees = "more samples differ from the exact reference with ε = 0.25 than with 0.001",
     .whyDisagrees = "ε = 0.25 is no worse than 0.001 on our slanted view"},
};
constexpr StudySpec kCurvesStudies[] = {
    {.name = "curves", .description = "the visibility-curves paper's page: Table 1's claims judged by curves-table1",
     .kind = StudyKind::Paper,
     .paperNotes = "Geometric displacement on plane and sphere by visibility curves: the paper's claims, measured\n\n"
                   "Table 1's counts (sine map, 2 samples per pixel), as the ratios §6 states them. The paper "
                   "gives neither its image size, its camera nor the sine's amplitude: the claims are judged on "
                   "a gentle sine (depth 0.02·N, part curves-table1-gentle, as docs/curves.md's Table 1 is) at "
                   "640×480, unslanted = 65.1°, slanted = 15.3° (lower than the paper's slanted view, which "
                   "covers three times our pixels); the steep sine (0.1·N) is the second part. The method has no "
                   "safe variant here; the wrong-pixel claims compare each sample with the exact reference on "
                   "its own ray. docs/curves.md discusses the counts.",
     .parts = kCurvesPageParts, .claims = kCurvesClaims, .paperFile = "geometric-displacement-plane-sphere.md"},
    {.name = "curves-table1-gentle", .description = "curves-table1 on the gentle sine (depth 0.02·N), as docs/curves.md's Table 1",
     .maps = kCurvesPaperMaps, .techniques = kCurvesTable1Rows, .elevations = kCurvesTable1Elevations,
     .width = 640, .height = 480, .depthRatio = 0.02f, .distance = 1.2f, .imageMethod = true},
    {.name = "curves-table1", .description = "visibility-curve renderer: Table 1 counts and cost vs exact on the same samples (was bench_curves)",
     .maps = kCurvesPaperMaps, .techniques = kCurvesTable1Rows, .elevations = kCurvesTable1Elevations,
     .width = 640, .height = 480, .distance = 1.2f, .imageMethod = true},
};

// exact against Embree on the same triangles and rays (docs/benchmarks-exact-embree.md).
constexpr std::string_view kExactEmbreeMaps[] = {"gen:fbm:512x512:1", "gen:fbm:2048x2048:1",
                                                 "data/earth-topology-2048x1024.png"};
constexpr std::string_view kExactEmbreeRows[] = {"exact"};
constexpr float kExactEmbreeElevations[] = {15.3f, 52.7f};
constexpr StudySpec kExactStudies[] = {
    {.name = "exact-embree", .description = "exact vs Embree rtcIntersect1/16, same rays (was bench_exact_embree)",
     .maps = kExactEmbreeMaps, .techniques = kExactEmbreeRows, .elevations = kExactEmbreeElevations,
     .width = 1280, .height = 1024, .distance = 0.6f, .peerTable = true},
};

// bench_cones: cone and relaxed-cone builders (safe and faithful), build time per size, and error
// vs cap / steps vs elevation per builder, on fbm and an N×N window of the SRTM mosaic centred on
// the Himalaya (86° E, 28° N: sample 7980, 1860), moved inside the map.
constexpr std::string_view kConeBuildRows[] = {"cone:variant=0", "cone:variant=1", "relaxed-cone"};
constexpr int kConeBuildSizes[] = {256, 512, 1024, 2048};
constexpr std::string_view kConeBuildMaps[] = {"gen:fbm:{N}x{N}:1",
                                               "../shared/data/earth-srtm-10800x5400.png@centre=7980,1860,{N},{N}"};
constexpr std::string_view kConeQualityMaps[] = {"gen:fbm:1024x1024:1", "gen:peaks6:1024x1024:1",
                                                 "../shared/data/earth-srtm-10800x5400.png@centre=7980,1860,1024,1024"};
constexpr std::string_view kConeQualityRows[] = {"cone:variant=0", "cone:variant=1", "relaxed-cone"};
constexpr StudySpec kConeStudies[] = {
    {.name = "cones-builds", .description = "cone map builds (safe, faithful, relaxed faithful), wall and CPU",
     .kind = StudyKind::Builds, .maps = kConeBuildMaps, .techniques = kConeBuildRows, .sizes = kConeBuildSizes},
    {.name = "cones-quality", .description = "cone builders: error vs cap, steps vs elevation, throughput",
     .maps = kConeQualityMaps, .techniques = kConeQualityRows, .caps = kCapsAndDefault, .width = 256,
     .height = 256, .distance = 1.2f},
};

// The channels of the baked arrays (docs/maps.md, `relief bake --format png|ktx2`). D is the
// depth in texel units (the map parameter-free source depth, MapSource::depth).
constexpr MapChannelSpec kConeChannels[] = {
    {"cones", "apex", "height a where the texel's cone starts (a frustum over its footprint)",
     "bits 8/16: a / D in [0, 1] on the grid k / (2^bits - 1); bits 32: texel units, 0..D",
     MapValueKind::Unit, MapRounding::Up, MapFilter::Nearest,
     "bits 8/16: divided by D (decode a = v * D * (1 + 2^-20)); bits 32: texel units",
     "--param bits=16 (or 8)"},
    {"cones", "ratio", "cone ratio c (horizontal / vertical) no point of S lies inside",
     "c / cone-max in [0, 1] (sqrt(c / cone-max) with sqrt=1), on the code grid at bits 8/16",
     MapValueKind::Unit, MapRounding::Down, MapFilter::Nearest,
     "none in the value; cone-max (map parameter) is from the box, decode c = v * cone-max * "
     "(1 - 2^-20)",
     "--param bits=16 (or 8)"},
};
constexpr std::string_view kPyramidMaxMeaning = "maximum of S over the node (its cells' corner maximum)";
constexpr MapChannelSpec kPyramidChannels[] = {
    {"level*", "max", kPyramidMaxMeaning,
     "bits 8/16: max / D in [0, 1] on the grid k / (2^bits - 1), rounded up; bits 32: texel "
     "units, 0..D; level L has ceil(n / 2^L) nodes per axis, n = W+1 from cell -1 (clamp) or W "
     "(repeat)",
     MapValueKind::Unit, MapRounding::Up, MapFilter::Nearest,
     "bits 8/16: divided by D (decode max = v * D * (1 + 2^-20)); bits 32: texel units",
     "--param bits=16 (or 8)"},
};
constexpr MapChannelSpec kOrientedChannels[] = {
    {"level*", "max", kPyramidMaxMeaning,
     "texel units, 0..D; level L has ceil(n / 2^L) nodes per axis, n = W+1 from cell -1 (clamp) "
     "or W (repeat)",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
    {"oriented*", "c00", "plane over the node at its lower-left corner", "texel units",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
    {"oriented*", "c10", "plane at the lower-right corner", "texel units", MapValueKind::Float,
     MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
    {"oriented*", "c01", "plane at the upper-left corner", "texel units", MapValueKind::Float,
     MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
    {"oriented*", "zmax", "flat maximum of the node (the pre-test)", "texel units",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
};
constexpr MapChannelSpec kQdmChannels[] = {
    {"qdm", "a", "end of the cone part of the profile (horizontal distance)", "texels, >= 0",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "none (horizontal)"},
    {"qdm", "b", "profile height at a", "texel units, >= 0", MapValueKind::Float,
     MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
    {"qdm", "c", "where the parabola tops out (horizontal distance)", "texels, >= a",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "none (horizontal)"},
    {"qdm", "h", "max of S over the texel's footprint (the profile's base)", "texel units, 0..D",
     MapValueKind::Float, MapRounding::Exact, MapFilter::Nearest, "heights times D (texel units)"},
};
constexpr MapChannelSpec kSafetySdChannels[] = {
    {"sd", "x+", "safety distance r of ray class x+ (centerlines free of limiting triangles)",
     "whole texels 0..max-distance (255 by default); isotropic=1: one channel, the minimum",
     MapValueKind::Integer, MapRounding::Exact, MapFilter::Nearest, "built for D (not scaled)"},
    {"sd", "x-", "safety distance of ray class x-", "whole texels", MapValueKind::Integer,
     MapRounding::Exact, MapFilter::Nearest, "built for D (not scaled)"},
    {"sd", "y+", "safety distance of ray class y+", "whole texels", MapValueKind::Integer,
     MapRounding::Exact, MapFilter::Nearest, "built for D (not scaled)"},
    {"sd", "y-", "safety distance of ray class y-", "whole texels", MapValueKind::Integer,
     MapRounding::Exact, MapFilter::Nearest, "built for D (not scaled)"},
};
constexpr MapChannelSpec kSafetyCcChannels[] = {
    {"cc*", "r", "cylinder radius (the class's safety distance); arrays ccx+, ccx-, ccy+, ccy- "
     "(cc with isotropic=1)", "whole texels", MapValueKind::Integer, MapRounding::Exact,
     MapFilter::Nearest, "built for D (not scaled)"},
    {"cc*", "zc", "height of the slanted plane at the cylinder's rim (raised by 1e-6 (1 + max))",
     "texel units", MapValueKind::Float, MapRounding::Up, MapFilter::Nearest,
     "heights times D (texel units)"},
    {"cc*", "slope", "slope s_c of the plane beyond r (raised by 1e-6 (1 + |s|))",
     "texel units per texel", MapValueKind::Float, MapRounding::Up, MapFilter::Nearest,
     "heights times D per texel"},
};

// The built-in rows. A function-local table, so that a row registered by another translation
// unit's static initializer (a plug-in, a test) never sees it uninitialized.
std::span<const TechniqueInfo> builtinRows() {
// clang-format off
static const TechniqueInfo kTechniques[] = {
    {.name = "exact", .paper = "Baboud & Décoret 2006; Amanatides & Woo 1987 (safety shapes §5.2.1)",
     .summary = "reference: cell-by-cell grid traversal, two triangle tests per cell",
     .contract = Contract::Exact, .params = kExactParams, .create = createExact,
     .check = checkExact, .glsl = "exact/exact.glsl", .studies = kExactStudies, .reference = true, .createSphere = createExactSphere},
    {.name = "linear", .paper = "Policarpo, Oliveira & Comba 2005 (relief mapping)",
     .summary = "N linear steps then M binary refinement steps on bilinear fetches",
     .contract = Contract::Approximate, .params = kLinearParams, .create = createLinear,
     .glsl = "linear/linear.glsl", .shaderFile = "linear.glsl", .shaderFunction = "reliefLinear",
     .shaderSamplers = kHeightsSampler},
    {.name = "parallax", .paper = "Kaneko et al. 2001; Welsh 2004 (offset limiting)",
     .summary = "one height fetch, offset-limited parallax shift",
     .contract = Contract::Approximate, .params = {}, .create = createParallax,
     .glsl = "parallax/parallax.glsl", .shaderFile = "parallax.glsl",
     .shaderFunction = "reliefParallax", .shaderSamplers = kHeightsSampler},
    {.name = "quadtree", .paper = "Schroders & van Gulik 2006 (quadtree relief mapping)",
     .summary = "max quadtree, jump to the neighbour node, exact cell test at the leaves",
     .contract = Contract::Exact, .params = kQuadtreeParams, .create = createQuadtree,
     .buildMaps = buildQuadtreeMaps, .mapBytesPerTexel = 16, .check = checkMaps<maxPyramidFor>,
     .glsl = "quadtree/quadtree.glsl", .glslConstants = kPyramidWalkGlslConstants,
     .variants = kQuadtreeVariants, .pathCases = kQuadtreePathCases,
     .studies = kQuadtreeStudies, .mapChannels = kPyramidChannels,
     .shaderFile = "quadtree.glsl", .shaderFunction = "reliefQuadtree",
     .shaderSamplers = kPyramidSamplers},
    {.name = "maxmip", .paper = "Tevs, Ihrke & Seidel 2008 (maximum mipmaps)",
     .summary = "max pyramid walked like a ray tracer (up to the common ancestor)",
     .contract = Contract::Exact, .params = kMaxmipParams, .create = createMaxmip,
     .buildMaps = buildMaxmipMaps, .mapBytesPerTexel = 16, .check = checkMaps<maxPyramidFor>,
     .glsl = "maxmip/maxmip.glsl", .glslConstants = kPyramidWalkGlslConstants,
     .variants = kMaxmipVariants, .pathCases = kMaxmipPathCases, .mapChannels = kPyramidChannels,
     .shaderFile = "maxmip.glsl", .shaderFunction = "reliefMaxmip",
     .shaderSamplers = kPyramidSamplers},
    {.name = "quadtree-oriented", .paper = "Schroders & van Gulik 2006 §5 (oriented quadtree)",
     .summary = "quadtree whose nodes carry a plane lying on S, flat max as pre-test",
     .contract = Contract::Exact, .params = kQuadtreeOrientedParams,
     .create = createQuadtreeOriented, .buildMaps = buildQuadtreeOrientedMaps, .mapBytesPerTexel = 28,
     .check = checkMaps<orientedMapsFor>, .glsl = "quadtree_oriented/quadtree_oriented.glsl",
     .glslConstants = kPyramidWalkGlslConstants, .mapChannels = kOrientedChannels,
     .shaderFile = "quadtree_oriented.glsl",
     .shaderFunction = "reliefQuadtreeOriented", .shaderSamplers = kOrientedSamplers},
    {.name = "cone", .paper = "Dummer 2006 (cone step mapping)",
     .summary = "conservative cone steps (footprint frustum) with an exact cell finish",
     .contract = Contract::Conservative, .params = kConeParams, .create = createCone,
     .buildMaps = buildConeMaps, .mapBytesPerTexel = 24, .check = checkCone, .glsl = "cone/cone.glsl",
     .glslConstants = kConeGlslConstants, .variants = kConeVariants, .pathCases = kConePathCases,
     .studies = kConeStudies, .mapChannels = kConeChannels,
     .shaderFile = "cone.glsl", .shaderFunction = "reliefCone",
     .shaderSamplers = kConeSamplers},
    {.name = "relaxed-cone", .paper = "Policarpo & Oliveira 2007 (GPU Gems 3 ch. 18)",
     .summary = "relaxed cone steps (the published map) then binary refinement",
     .contract = Contract::Approximate, .params = kRelaxedConeParams,
     .create = createRelaxedCone, .buildMaps = buildRelaxedConeMaps,
     // peak RSS of a 4096² bake, 2026-12-04 (the walk-reject tables: 50 bytes a cell)
     .mapBytesPerTexel = 96, .check = checkRelaxedCone,
     .glsl = "relaxed_cone/relaxed_cone.glsl", .glslConstants = kConeMapGlslConstants,
     .pathCases = kRelaxedConePathCases, .mapChannels = kConeChannels,
     .shaderFile = "relaxed_cone.glsl", .shaderFunction = "reliefRelaxedCone",
     .shaderSamplers = kConeSamplers},
    {.name = "qdm", .paper = "Kiglics, Valasek, Bálint & Bán 2023 (quadratic displacement maps)",
     .summary = "cone + revolved parabola steps (footprint profile) with an exact cell finish",
     .contract = Contract::Conservative, .params = kQdmParams, .create = createQdm,
     .buildMaps = buildQdmMaps, .mapBytesPerTexel = 40, .check = checkMaps<qdmMapFor>, .glsl = "qdm/qdm.glsl",
     .glslConstants = kQdmGlslConstants, .variants = kQdmVariants, .pathCases = kQdmPathCases,
     .studies = kQdmStudies, .mapChannels = kQdmChannels,
     .shaderFile = "qdm.glsl", .shaderFunction = "reliefQdm",
     .shaderSamplers = kQdmSamplers},
    {.name = "safety-sd", .paper = "Baboud, Eisemann & Seidel 2011 (precomputed safety shapes §5.2.2, §6.1)",
     .summary = "safety distances per texel and ray class, centerline jumps, bisection, exact cells",
     .contract = Contract::Exact, .params = kSafetySdParams, .create = createSafetySd,
     // peak RSS of a 4096² bake: 71 bytes per texel (docs/benchmarks-bakes.md, 2026-12-03)
     .buildMaps = buildSafetySdMaps, .mapBytesPerTexel = 72, .check = checkMaps<makeSafetySdTracer>,
     .viewWarning = safety::viewWarning,
     .glsl = "safety_sd/safety_sd.glsl", .glslConstants = safety::kSafetyMarchGlslConstants,
     .variants = kSafetyVariants, .pathCases = kSafetySdPathCases, .mapSummary = safety::mapSummary,
     .mapChannels = kSafetySdChannels,
     .shaderFile = "safety_sd.glsl", .shaderFunction = "reliefSafetySd",
     .shaderSamplers = kSafetySdSamplers},
    {.name = "safety-cc", .paper = "Baboud, Eisemann & Seidel 2011 (precomputed safety shapes §6.3)",
     .summary = "cylinder-cone safety shapes (N-buffer slopes), centerline jumps, exact cells",
     .contract = Contract::Exact, .params = kSafetyCcParams, .create = createSafetyCc,
     .buildMaps = buildSafetyCcMaps, .mapBytesPerTexel = 192, .check = checkMaps<makeSafetyCcTracer>,
     .viewWarning = safety::viewWarning,
     .glsl = "safety_cc/safety_cc.glsl", .glslConstants = safety::kSafetyMarchGlslConstants,
     .variants = kSafetyVariants, .pathCases = kSafetyCcPathCases, .studies = kSafetyStudies,
     .mapSummary = safety::mapSummary, .mapChannels = kSafetyCcChannels,
     .shaderFile = "safety_cc.glsl",
     .shaderFunction = "reliefSafetyCc", .shaderSamplers = kSafetyCcSamplers},
    {.name = "curves", .paper = "Fourquet, Cowan & Mann 2008 (geometric displacement on plane and sphere)",
     .summary = "visibility-curve stepping; per ray: walks the ray's own curve from its leading edge",
     .contract = Contract::Approximate, .params = kCurvesParams, .create = createCurves,
     .studies = kCurvesStudies, .image = ImageMethod::VisibilityCurves},
};
// clang-format on
return kTechniques;
}

// The built-in rows plus any registered at start-up. Capacity is fixed so that the pointers
// findTechnique hands out stay valid.
constexpr size_t kMaxRows = 64;
std::vector<TechniqueInfo>& rows() {
    static std::vector<TechniqueInfo> all = [] {
        std::vector<TechniqueInfo> v;
        v.reserve(kMaxRows);
        const std::span<const TechniqueInfo> builtin = builtinRows();
        v.assign(builtin.begin(), builtin.end());
        return v;
    }();
    return all;
}

}  // namespace

std::span<const TechniqueInfo> techniques() { return rows(); }

Status registerTechnique(const TechniqueInfo& info) {
    if (findTechnique(info.name))
        return makeError(ErrorKind::BadArgument, "technique '{}' is already registered", info.name);
    if (info.reference || !info.create || info.name.empty())
        return makeError(ErrorKind::BadArgument, "technique '{}': a row needs a name and a "
                         "create function, and cannot be the reference", info.name);
    if (rows().size() == kMaxRows)
        return makeError(ErrorKind::Unsupported, "the registry holds {} techniques", kMaxRows);
    rows().push_back(info);
    return {};
}

const TechniqueInfo& referenceTechnique() {
    for (const TechniqueInfo& info : techniques())
        if (info.reference) return info;
    RELIEF_CHECK(false);  // RegistryTest.ExactlyOneReference
    return techniques().front();
}

const TechniqueInfo* findTechnique(std::string_view name) {
    for (const TechniqueInfo& info : techniques())
        if (info.name == name) return &info;
    return nullptr;
}

std::string techniqueNames(std::string_view separator) {
    std::string names;
    for (const TechniqueInfo& info : techniques()) {
        if (!names.empty()) names += separator;
        names += info.name;
    }
    return names;
}

Result<ParamValues> resolveParams(const TechniqueInfo& info,
                                  const std::vector<std::pair<std::string, double>>& overrides) {
    ParamValues values;
    for (const ParamSpec& spec : info.params) values.set(std::string(spec.name), spec.defaultValue);
    for (const auto& [name, value] : overrides) {
        const ParamSpec* spec = nullptr;
        for (const ParamSpec& s : info.params)
            if (s.name == name) spec = &s;
        if (!spec)
            return makeError(ErrorKind::BadArgument,
                             "technique '{}' has no parameter '{}'{}", info.name, name,
                             info.params.empty() ? " (it takes none)" : "");
        if (!std::isfinite(value) || value < spec->minValue || value > spec->maxValue ||
            (spec->integer && value != std::floor(value)))
            return makeError(ErrorKind::BadArgument,
                             "technique '{}': parameter '{}' = {} is out of range ({} {} to {})",
                             info.name, name, value, spec->integer ? "an integer" : "a number",
                             spec->minValue, spec->maxValue);
        values.set(name, value);
    }
    return values;
}

Result<const TechniqueInfo*> lookupTechnique(std::string_view name) {
    if (const TechniqueInfo* info = findTechnique(name)) return info;
    return makeError(ErrorKind::BadArgument, "unknown technique '{}' (known: {})", name,
                     techniqueNames());
}

Status reserveMapMemory(const TechniqueInfo& info, const Surface& surface) {
    const int64_t texels = int64_t(surface.width()) * surface.height();
    return reserveMemory(int64_t(double(texels) * info.mapBytesPerTexel),
                         fmt::format("{}: building maps for {}x{} texels", info.name,
                                     surface.width(), surface.height()));
}

namespace {

// What baked maps record of how they were built (bits, sqrt, builder options, variant, φ_max,
// visibility) is taken from the file where the caller did not set it: a map baked with bits=16 is
// traced as baked rather than refused for the default bits=32. A value the caller did set and the
// file contradicts is still refused by the row's check. The file's values pass through
// resolveParams like the caller's, so a tampered one out of range is refused, never used.
std::vector<std::pair<std::string, double>> withBakedParameters(
    const TechniqueInfo& info, const std::vector<std::pair<std::string, double>>& overrides,
    const TechniqueMaps* baked) {
    if (!baked) return overrides;
    std::vector<std::pair<std::string, double>> merged;
    for (const ParamSpec& spec : info.params) {
        const bool recorded = spec.role == ParamRole::Encoding || spec.role == ParamRole::MapShape ||
                              spec.role == ParamRole::Variant || spec.role == ParamRole::PhiMax ||
                              spec.role == ParamRole::Visibility;
        const auto found = baked->parameters.find(std::string(spec.name));
        if (!recorded || found == baked->parameters.end()) continue;
        if (std::any_of(overrides.begin(), overrides.end(),
                        [&](const auto& o) { return o.first == spec.name; }))
            continue;
        char* end = nullptr;
        const double value = std::strtod(found->second.c_str(), &end);
        if (end == found->second.c_str() || *end != '\0') continue;  // not a number: the check judges it
        merged.emplace_back(std::string(spec.name), value);
    }
    merged.insert(merged.end(), overrides.begin(), overrides.end());
    return merged;
}

}  // namespace

Result<TechniqueInput> techniqueInput(const TechniqueInfo& info,
                                      std::shared_ptr<const Surface> surface,
                                      const std::vector<std::pair<std::string, double>>& overrides,
                                      const MapFile* maps, std::string_view mapsPath) {
    const TechniqueMaps* baked = maps && info.buildMaps ? maps->find(std::string(info.name)) : nullptr;
    auto params = resolveParams(info, withBakedParameters(info, overrides, baked));
    if (!params)
        return baked ? makeError(params.error().kind, "{}: {}", mapsPath, params.error().message)
                     : params.error();
    TechniqueInput input{std::move(surface), std::move(*params), nullptr};
    if (!maps && info.buildMaps)
        if (Status s = reserveMapMemory(info, *input.surface); !s) return s.error();
    if (maps && info.buildMaps) {
        input.maps = maps->find(std::string(info.name));
        if (!input.maps)
            return makeError(ErrorKind::InvalidInput, "{}: holds no maps for '{}'; bake them with "
                             "relief bake --maps {}", mapsPath, info.name, info.name);
        // The row's check decodes the maps and spot-checks their invariant (cone widths, pyramid
        // maxima, distances): refused here, with the file named, before any tracer is made.
        if (info.check)
            if (Status s = info.check(input); !s)
                return s.error().kind == ErrorKind::InvalidInput
                           ? makeError(ErrorKind::InvalidInput, "{}: {}", mapsPath,
                                       s.error().message)
                           : s.error();
    }
    return input;
}

Result<TechniqueMaps> bakeMaps(const TechniqueInfo& info, std::shared_ptr<const Surface> surface,
                               const std::vector<std::pair<std::string, double>>& overrides,
                               BuildShare* share) {
    if (!info.buildMaps) {
        std::string known;
        for (const TechniqueInfo& row : techniques())
            if (row.buildMaps) known += (known.empty() ? "" : ", ") + std::string(row.name);
        return makeError(ErrorKind::BadArgument,
                         "bake: '{}' has no maps to bake (techniques with maps: {})", info.name,
                         known.empty() ? "none yet" : known);
    }
    auto params = resolveParams(info, overrides);
    if (!params) return params.error();
    TechniqueInput input{std::move(surface), std::move(*params), nullptr, share};
    if (Status s = reserveMapMemory(info, *input.surface); !s) return s.error();
    auto maps = info.buildMaps(input);
    if (!maps) return maps.error();
    // A parameter the maps do not record cannot have changed them (the tracer reads it):
    // accepting it would ignore it silently.
    for (const auto& [name, value] : overrides)
        if (!maps->parameters.count(name))
            return makeError(ErrorKind::BadArgument,
                             "bake: {}: parameter '{}' does not change the maps (the tracer reads "
                             "it: give it to render or trace)",
                             info.name, name);
    return maps;
}

Result<std::unique_ptr<Tracer>> createTracer(
    std::string_view name, std::shared_ptr<const Surface> surface,
    const std::vector<std::pair<std::string, double>>& overrides, const MapFile* maps,
    std::string_view mapsPath) {
    auto info = lookupTechnique(name);
    if (!info) return info.error();
    auto input = techniqueInput(**info, std::move(surface), overrides, maps, mapsPath);
    if (!input) return input.error();
    return (*info)->create(*input);
}

}  // namespace relief
