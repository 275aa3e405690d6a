#include <relief/techniques/registry.h>

#include <relief/techniques/curves/curves.h>
#include <relief/techniques/exact/exact.h>
#include <relief/techniques/cone/cone.h>
#include <relief/techniques/relaxed_cone/relaxed_cone.h>
#include <relief/techniques/linear/linear.h>
#include <relief/techniques/parallax/parallax.h>
#include <relief/techniques/qdm/qdm.h>
#include <relief/techniques/maxmip/maxmip.h>
#include <relief/techniques/quadtree/quadtree.h>
#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>
#include <relief/techniques/safety_cc/safety_cc.h>
#include <relief/techniques/safety_common/safety_params.h>
#include <relief/techniques/safety_sd/safety_sd.h>

#include <relief/core/check.h>
#include <relief/sphere/sphere_reference.h>

#include <cmath>

namespace relief {

namespace {

// Forms whose contract differs from the row's, or that a paper's claim is judged with.
constexpr VariantSpec kQuadtreeVariants[] = {
    {"paper-walk", "ascend=0", Contract::Exact, "the paper's walk: stay at the level after a jump"},
    {"paper-surface", "box-surface=1", Contract::Approximate, "stops at the first level-0 node reached"},
};
constexpr VariantSpec kConeVariants[] = {
    {"safe", "variant=0", Contract::Conservative, "footprint-frustum cones, exact cell finish"},
    {"faithful", "variant=1", Contract::Approximate, "Dummer's cones (texel centres): can step past a hit"},
};
constexpr VariantSpec kRelaxedConeVariants[] = {
    {"safe", "variant=0", Contract::Approximate, "strict footprint cones, then binary refinement"},
    {"faithful", "variant=1", Contract::Approximate, "Policarpo & Oliveira's relaxed cones"},
};
constexpr VariantSpec kSafetyVariants[] = {
    {"view-dependent", "view-dependent=1", Contract::Approximate, "S linear between test positions (§7)"},
    {"positive-distance", "positive-distance=1", Contract::Approximate, "distances clamped to >= 1 (§7)"},
    {"exterior", "exterior=1", Contract::Exact, "maps for exterior rays only (§6.2)"},
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

// Parameter sets that take the GLSL down another path (encodings, policies, variants).
constexpr PathCase kQuadtreePathCases[] = {{"ascend=0"}, {"max-steps=6"}};
constexpr PathCase kConePathCases[] = {{"bits=16,sqrt=1"}, {"bits=8,variant=1"}};
constexpr PathCase kRelaxedConePathCases[] = {{"bits=16,binary-steps=4"}};
constexpr PathCase kQdmPathCases[] = {
    {"max-distance=3,max-steps=20"},
    {"height-ratio=0.5,convex-bound=0", true},
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

// The built-in rows. A function-local table, so that a row registered by another translation
// unit's static initializer (a plug-in, a test) never sees it uninitialized.
std::span<const TechniqueInfo> builtinRows() {
// clang-format off
static const TechniqueInfo kTechniques[] = {
    {.name = "exact", .paper = "Baboud & Décoret 2006; Amanatides & Woo 1987 (safety shapes §5.2.1)",
     .summary = "reference: cell-by-cell grid traversal, two triangle tests per cell",
     .contract = Contract::Exact, .params = kExactParams, .create = createExact,
     .check = checkExact, .glsl = "exact/exact.glsl", .reference = true, .createSphere = createExactSphere},
    {.name = "linear", .paper = "Policarpo, Oliveira & Comba 2005 (relief mapping)",
     .summary = "N linear steps then M binary refinement steps on bilinear fetches",
     .contract = Contract::Approximate, .params = kLinearParams, .create = createLinear,
     .glsl = "linear/linear.glsl"},
    {.name = "parallax", .paper = "Kaneko et al. 2001; Welsh 2004 (offset limiting)",
     .summary = "one height fetch, offset-limited parallax shift",
     .contract = Contract::Approximate, .params = {}, .create = createParallax,
     .glsl = "parallax/parallax.glsl"},
    {.name = "quadtree", .paper = "Schroders & van Gulik 2006 (quadtree relief mapping)",
     .summary = "max quadtree, jump to the neighbour node, exact cell test at the leaves",
     .contract = Contract::Exact, .params = kQuadtreeParams, .create = createQuadtree,
     .buildMaps = buildQuadtreeMaps, .check = checkMaps<maxPyramidFor>,
     .glsl = "quadtree/quadtree.glsl", .glslConstants = kPyramidWalkGlslConstants,
     .variants = kQuadtreeVariants, .pathCases = kQuadtreePathCases},
    {.name = "maxmip", .paper = "Tevs, Ihrke & Seidel 2008 (maximum mipmaps)",
     .summary = "max pyramid walked like a ray tracer (up to the common ancestor)",
     .contract = Contract::Exact, .params = kMaxmipParams, .create = createMaxmip,
     .buildMaps = buildMaxmipMaps, .check = checkMaps<maxPyramidFor>,
     .glsl = "maxmip/maxmip.glsl", .glslConstants = kPyramidWalkGlslConstants},
    {.name = "quadtree-oriented", .paper = "Schroders & van Gulik 2006 §5 (oriented quadtree)",
     .summary = "quadtree whose nodes carry a plane lying on S, flat max as pre-test",
     .contract = Contract::Exact, .params = kQuadtreeOrientedParams,
     .create = createQuadtreeOriented, .buildMaps = buildQuadtreeOrientedMaps,
     .check = checkMaps<orientedMapsFor>, .glsl = "quadtree_oriented/quadtree_oriented.glsl",
     .glslConstants = kPyramidWalkGlslConstants},
    {.name = "cone", .paper = "Dummer 2006 (cone step mapping)",
     .summary = "conservative cone steps (footprint frustum) with an exact cell finish",
     .contract = Contract::Conservative, .params = kConeParams, .create = createCone,
     .buildMaps = buildConeMaps, .check = checkCone, .glsl = "cone/cone.glsl",
     .glslConstants = kConeGlslConstants, .variants = kConeVariants, .pathCases = kConePathCases},
    {.name = "relaxed-cone", .paper = "Policarpo & Oliveira 2007 (GPU Gems 3 ch. 18)",
     .summary = "relaxed cone steps then binary refinement; safe variant = strict cones",
     .contract = Contract::Approximate, .params = kRelaxedConeParams,
     .create = createRelaxedCone, .buildMaps = buildRelaxedConeMaps, .check = checkRelaxedCone,
     .glsl = "relaxed_cone/relaxed_cone.glsl", .glslConstants = kConeMapGlslConstants,
     .variants = kRelaxedConeVariants, .pathCases = kRelaxedConePathCases},
    {.name = "qdm", .paper = "Kiglics, Valasek, Bálint & Bán 2023 (quadratic displacement maps)",
     .summary = "cone + revolved parabola steps (footprint profile) with an exact cell finish",
     .contract = Contract::Conservative, .params = kQdmParams, .create = createQdm,
     .buildMaps = buildQdmMaps, .check = checkMaps<qdmMapFor>, .glsl = "qdm/qdm.glsl",
     .pathCases = kQdmPathCases},
    {.name = "safety-sd", .paper = "Baboud, Eisemann & Seidel 2011 (precomputed safety shapes §5.2.2, §6.1)",
     .summary = "safety distances per texel and ray class, centerline jumps, bisection, exact cells",
     .contract = Contract::Exact, .params = kSafetySdParams, .create = createSafetySd,
     .buildMaps = buildSafetySdMaps, .check = checkMaps<makeSafetySdTracer>,
     .viewWarning = safety::viewWarning,
     .glsl = "safety_sd/safety_sd.glsl", .glslConstants = safety::kSafetyMarchGlslConstants,
     .variants = kSafetyVariants, .pathCases = kSafetySdPathCases},
    {.name = "safety-cc", .paper = "Baboud, Eisemann & Seidel 2011 (precomputed safety shapes §6.3)",
     .summary = "cylinder-cone safety shapes (N-buffer slopes), centerline jumps, exact cells",
     .contract = Contract::Exact, .params = kSafetyCcParams, .create = createSafetyCc,
     .buildMaps = buildSafetyCcMaps, .check = checkMaps<makeSafetyCcTracer>,
     .viewWarning = safety::viewWarning,
     .glsl = "safety_cc/safety_cc.glsl", .glslConstants = safety::kSafetyMarchGlslConstants,
     .variants = kSafetyVariants, .pathCases = kSafetyCcPathCases},
    {.name = "curves", .paper = "Fourquet, Cowan & Mann 2008 (geometric displacement on plane and sphere)",
     .summary = "visibility-curve stepping; per ray: walks the ray's own curve from its leading edge",
     .contract = Contract::Approximate, .params = kCurvesParams, .create = createCurves,
     .image = ImageMethod::VisibilityCurves},
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

Result<TechniqueInput> techniqueInput(const TechniqueInfo& info,
                                      std::shared_ptr<const Surface> surface,
                                      const std::vector<std::pair<std::string, double>>& overrides,
                                      const MapFile* maps, std::string_view mapsPath) {
    auto params = resolveParams(info, overrides);
    if (!params) return params.error();
    TechniqueInput input{std::move(surface), std::move(*params), nullptr};
    if (maps && info.buildMaps) {
        input.maps = maps->find(std::string(info.name));
        if (!input.maps)
            return makeError(ErrorKind::InvalidInput, "{}: holds no maps for '{}'; bake them with "
                             "relief bake --maps {}", mapsPath, info.name, info.name);
    }
    return input;
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
