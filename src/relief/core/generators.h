#pragma once
// Built-in heightfields (DESIGN §5), deterministic from a seed: sine, peaks6, fbm, walls, spikes,
// terraces, ramp, flat.
#include <relief/core/heightfield.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace relief {

std::vector<std::string_view> generatorNames();

// Generates NAME at width×height; unknown names are an error listing the known ones.
Result<Heightfield> generateHeightfield(std::string_view name, int width, int height,
                                        uint64_t seed = 1);

}  // namespace relief
