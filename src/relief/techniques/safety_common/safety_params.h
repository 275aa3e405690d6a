#pragma once
// Parameters shared by `safety-sd` and `safety-cc` and how they meet baked maps: the map's own
// build parameters (phi-max, isotropic, exterior, exterior-slope) win; asking for a different non-default value is an error.
#include <relief/techniques/safety_common/safety_maps.h>
#include <relief/techniques/safety_common/safety_march.h>
#include <relief/techniques/technique.h>

#include <memory>
#include <utility>

namespace relief::safety {

namespace param {
inline constexpr ParamSpec kMaxSteps{"max-steps", 0, 0, 1e9, true,
                                     "iteration cap (0 = none, exact); N > 0 is approximate",
                                     ParamRole::IterationCap};
inline constexpr ParamSpec kPhiMax{
    "phi-max", 90, -89, 90, false,
    "viewing-angle restriction (deg, §6.2.5): maps serve rays whose elevation angle is below "
    "it (the paper uses -45); other rays take the exact walk; 90 = none",
    ParamRole::PhiMax};
inline constexpr ParamSpec kIsotropic{"isotropic", 0, 0, 1, true,
                                      "1 = one shape for the four ray classes (their minimum)",
                                      ParamRole::MapShape};
inline constexpr ParamSpec kViewDependent{
    "view-dependent", 0, 0, 1, true,
    "1 = S linear along the ray between test positions (§7; approximate)", ParamRole::Variant};
inline constexpr ParamSpec kPositiveDistance{
    "positive-distance", 0, 0, 1, true,
    "1 = safety distances clamped to >= 1 (§7; approximate at sharp edges)", ParamRole::Variant};
inline constexpr ParamSpec kPhiOutside{
    "phi-outside", 0, 0, 1, true,
    "1 = rays outside phi-max use the maps anyway (the paper's rendering; approximate: they can "
    "step past a hit); 0 = they take the exact walk", ParamRole::Variant};
inline constexpr ParamSpec kPrecompute{
    "precompute", 0, 0, 1, true,
    "safety distances: 0 = exact (§6.1, every ray), 1 = sampled (§8: 8 positions on s_tau x 256 "
    "directions; approximate, the distances can be too long)", ParamRole::MapShape};
inline constexpr ParamSpec kExterior{
    "exterior", 0, 0, 1, true,
    "1 = maps for exterior rays only (§6.2, viewpoint outside the box; clamp mode): longer "
    "distances; rays starting inside the box take the exact walk (results stay exact)",
    ParamRole::Visibility};
inline constexpr ParamSpec kExteriorSlope{
    "exterior-slope", 0, 0, 1, true,
    "1 = cone slope over exterior-limiting triangles only (cone_ext, slow build; needs "
    "exterior=1); 0 = N-buffer slope over all vertices (cone_all)", ParamRole::MapShape};
}  // namespace param

inline constexpr ParamSpec kSafetyParams[] = {
    param::kMaxSteps,      param::kPhiMax,           param::kIsotropic,
    param::kViewDependent, param::kPositiveDistance, param::kExterior, param::kPhiOutside,
    param::kPrecompute,
};
// safety-cc adds the choice of cone slope.
inline constexpr ParamSpec kSafetyCcParamList[] = {
    param::kMaxSteps,         param::kPhiMax,   param::kIsotropic,     param::kViewDependent,
    param::kPositiveDistance, param::kExterior, param::kExteriorSlope, param::kPhiOutside,
    param::kPrecompute,
};

BuildOptions buildOptionsFrom(const ParamValues& params);
MarchOptions marchOptionsFrom(const ParamValues& params, const BuildOptions& build);
// The renderer's warning when primary rays fall outside phi-max (they stay exact, but take the
// slow exact walk). Uses the requested phi-max; empty when all rays are within it.
std::string phiMaxViewWarning(const ParamValues& params, std::span<const Ray> rays);
// phiMaxViewWarning, plus, with exterior=1, that a camera inside the relief's box takes the
// exact walk (the warning cannot see the box, so it names the camera position).
std::string viewWarning(const ParamValues& params, std::span<const Ray> rays);

// The build options of baked maps, checked against the requested parameters.
Result<BuildOptions> bakedOptions(const ParamValues& params, const TechniqueMaps& maps);

// A safety row's map and the options it was built with: decoded from input.maps by
// `decode(maps, W, H)` (the baked options win) or built now by `build(surface, options)`.
template <class Map, class Decode, class Build>
Result<std::pair<std::shared_ptr<const Map>, BuildOptions>> mapFor(const TechniqueInput& input,
                                                                    Decode&& decode,
                                                                    Build&& build) {
    if (input.maps) {
        auto baked = bakedOptions(input.params, *input.maps);
        if (!baked) return baked.error();
        auto loaded = decode(*input.maps, input.surface->width(), input.surface->height());
        if (!loaded) return loaded.error();
        adviseHugePages(*loaded);
        return std::pair{std::make_shared<const Map>(std::move(*loaded)), *baked};
    }
    const BuildOptions options = buildOptionsFrom(input.params);
    if (Status ok = checkBuildOptions(*input.surface, options); !ok) return ok.error();
    Map built = build(*input.surface, options);
    adviseHugePages(built);
    return std::pair{std::make_shared<const Map>(std::move(built)), options};
}

}  // namespace relief::safety
