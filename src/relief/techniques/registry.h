#pragma once
// The single table of techniques. The CLI, renderer, GL backend, bench and tests iterate it.
#include <relief/techniques/technique.h>

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace relief {

std::span<const TechniqueInfo> techniques();
const TechniqueInfo* findTechnique(std::string_view name);
// The row every other one is judged against (DESIGN §3: `exact`).
const TechniqueInfo& referenceTechnique();
std::string techniqueNames(std::string_view separator = ", ");

// Defaults for every parameter of `info`, overridden by `overrides` (name → value). Unknown names
// and out-of-range values are errors naming the technique and the parameter.
Result<ParamValues> resolveParams(const TechniqueInfo& info,
                                  const std::vector<std::pair<std::string, double>>& overrides);

// Looks the technique up, resolves its parameters and creates its tracer.
Result<std::unique_ptr<Tracer>> createTracer(
    std::string_view name, std::shared_ptr<const Surface> surface,
    const std::vector<std::pair<std::string, double>>& overrides = {});

}  // namespace relief
