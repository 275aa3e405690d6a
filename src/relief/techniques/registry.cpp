#include <relief/techniques/registry.h>

#include <relief/techniques/exact/exact.h>
#include <relief/techniques/linear/linear.h>
#include <relief/techniques/parallax/parallax.h>

#include <cmath>

namespace relief {

namespace {

// clang-format off
const TechniqueInfo kTechniques[] = {
    {"exact", "Baboud & Décoret 2006; Amanatides & Woo 1987 (safety shapes §5.2.1)",
     "reference: cell-by-cell grid traversal, two triangle tests per cell",
     Contract::Exact, kExactParams, createExact},
    {"linear", "Policarpo, Oliveira & Comba 2005 (relief mapping)",
     "N linear steps then M binary refinement steps on bilinear fetches",
     Contract::Approximate, kLinearParams, createLinear},
    {"parallax", "Kaneko et al. 2001; Welsh 2004 (offset limiting)",
     "one height fetch, offset-limited parallax shift",
     Contract::Approximate, {}, createParallax},
};
// clang-format on

}  // namespace

std::span<const TechniqueInfo> techniques() { return kTechniques; }

const TechniqueInfo* findTechnique(std::string_view name) {
    for (const TechniqueInfo& info : kTechniques)
        if (info.name == name) return &info;
    return nullptr;
}

std::string techniqueNames(std::string_view separator) {
    std::string names;
    for (const TechniqueInfo& info : kTechniques) {
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

Result<std::unique_ptr<Tracer>> createTracer(
    std::string_view name, std::shared_ptr<const Surface> surface,
    const std::vector<std::pair<std::string, double>>& overrides) {
    const TechniqueInfo* info = findTechnique(name);
    if (!info)
        return makeError(ErrorKind::BadArgument, "unknown technique '{}' (known: {})", name,
                         techniqueNames());
    auto params = resolveParams(*info, overrides);
    if (!params) return params.error();
    return info->create(TechniqueInput{std::move(surface), std::move(*params)});
}

}  // namespace relief
