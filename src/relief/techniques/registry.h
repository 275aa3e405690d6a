#pragma once
// The single table of techniques. The CLI, renderer, GL backend, bench and tests iterate it.
#include <relief/techniques/technique.h>

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace relief {

std::span<const TechniqueInfo> techniques();
// Adds a row (a plug-in or a test's toy technique) before the registry is used; its strings and
// spans must outlive the process. Refuses a second row of the same name or a second reference.
Status registerTechnique(const TechniqueInfo& info);
const TechniqueInfo* findTechnique(std::string_view name);
// The row every other one is judged against (DESIGN §3: `exact`).
const TechniqueInfo& referenceTechnique();
std::string techniqueNames(std::string_view separator = ", ");

// Defaults for every parameter of `info`, overridden by `overrides` (name → value). Unknown names
// and out-of-range values are errors naming the technique and the parameter.
Result<ParamValues> resolveParams(const TechniqueInfo& info,
                                  const std::vector<std::pair<std::string, double>>& overrides);

// The row's input: parameters resolved, and its maps taken from `maps` (a map file already
// checked against the surface, named `mapsPath` in messages) when given; null `maps` = build
// them. A file without this row's maps is an error that names the bake command.
// The row's map estimate (mapBytesPerTexel × the surface's texels) against the memory budget:
// techniqueInput calls it when the maps are to be built, bake before buildMaps.
Status reserveMapMemory(const TechniqueInfo& info, const Surface& surface);
Result<TechniqueInput> techniqueInput(const TechniqueInfo& info,
                                      std::shared_ptr<const Surface> surface,
                                      const std::vector<std::pair<std::string, double>>& overrides,
                                      const MapFile* maps = nullptr,
                                      std::string_view mapsPath = {});

// One row's maps as `relief bake` writes them: parameters resolved, the memory budget checked,
// the maps built. A row without maps, and a parameter the maps do not record (the tracer reads
// it), are refused. `share` (one per surface) lets the rows of one bake reuse each other's
// intermediate products (BuildShare).
Result<TechniqueMaps> bakeMaps(const TechniqueInfo& info, std::shared_ptr<const Surface> surface,
                               const std::vector<std::pair<std::string, double>>& overrides,
                               BuildShare* share = nullptr);

// The one way to a CPU tracer (CLI, viewer, bench, tests): looks the technique up, resolves its
// parameters and creates its tracer (the map file, if any, must outlive it).
Result<std::unique_ptr<Tracer>> createTracer(
    std::string_view name, std::shared_ptr<const Surface> surface,
    const std::vector<std::pair<std::string, double>>& overrides = {},
    const MapFile* maps = nullptr, std::string_view mapsPath = {});
// findTechnique, or an error listing the known names.
Result<const TechniqueInfo*> lookupTechnique(std::string_view name);

}  // namespace relief
