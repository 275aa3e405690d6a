#pragma once
// The map-file mutator's judge (issue 22), shared by tests/map_file_test.cpp and
// fuzz/fuzz_map_file.cpp: the hits a row traces with given maps, or the error that refused them
// (techniqueInput runs the row's check, which spot-checks the maps), and exact hit equality.
#include <relief/techniques/registry.h>

#include <memory>
#include <span>
#include <vector>

namespace relief::testing {

inline Result<std::vector<Hit>> hitsWithMaps(const TechniqueInfo& info,
                                             std::shared_ptr<const Surface> surface,
                                             const MapFile& maps, std::span<const Ray> rays) {
    auto input = techniqueInput(info, std::move(surface), {}, &maps, "edited.exr");
    if (!input) return input.error();
    auto tracer = info.create(*input);
    if (!tracer) return tracer.error();
    std::vector<Hit> hits(rays.size());
    (*tracer)->traceBatch(rays, hits);
    return hits;
}

inline bool sameHits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
    if (a.size() != b.size()) return false;
    for (size_t k = 0; k < a.size(); ++k)
        if (a[k].hit != b[k].hit ||
            (a[k].hit && (a[k].t != b[k].t || a[k].position != b[k].position)))
            return false;
    return true;
}

}  // namespace relief::testing
