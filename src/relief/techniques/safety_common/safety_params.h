#pragma once
// Parameters shared by `safety-sd` and `safety-cc` and how they meet baked maps: the map's own
// build parameters (phi-max, isotropic) win; asking for a different non-default value is an error.
#include <relief/techniques/safety_common/safety_march.h>
#include <relief/techniques/technique.h>

namespace relief::safety {

inline constexpr ParamSpec kSafetyParams[] = {
    {"max-steps", 0, 0, 1e9, true, "iteration cap (0 = none, exact); N > 0 is approximate"},
    {"phi-max", 90, -89, 90, false,
     "viewing-angle restriction (deg, §6.2.5): maps serve rays whose elevation angle is below "
     "it (the paper uses -45); other rays take the exact walk; 90 = none"},
    {"isotropic", 0, 0, 1, true, "1 = one shape for the four ray classes (their minimum)"},
    {"view-dependent", 0, 0, 1, true,
     "1 = S linear along the ray between test positions (§7; approximate)"},
    {"positive-distance", 0, 0, 1, true,
     "1 = safety distances clamped to >= 1 (§7; approximate at sharp edges)"},
};

BuildOptions buildOptionsFrom(const ParamValues& params);
MarchOptions marchOptionsFrom(const ParamValues& params, const BuildOptions& build);
// The renderer's warning when primary rays fall outside phi-max (they stay exact, but take the
// slow exact walk). Uses the requested phi-max; empty when all rays are within it.
std::string phiMaxViewWarning(const ParamValues& params, std::span<const Ray> rays);

// The build options of baked maps, checked against the requested parameters.
Result<BuildOptions> bakedOptions(const ParamValues& params, const TechniqueMaps& maps);

}  // namespace relief::safety
