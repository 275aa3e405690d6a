#pragma once
// Built-in heightfields (DESIGN §5), deterministic from a seed: sine, peaks6, fbm, walls, spikes,
// terraces, ramp, flat, bricks (which also has a matching colour map).
#include <relief/core/heightfield.h>
#include <relief/core/image.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace relief {

std::vector<std::string_view> generatorNames();

// Generates NAME at width×height; unknown names are an error listing the known ones.
Result<Heightfield> generateHeightfield(std::string_view name, int width, int height,
                                        uint64_t seed = 1);
// The colour map (sRGB) that matches NAME's heightfield of the same size and seed; an error for
// generators without one.
Result<ImageRgb8> generateColorMap(std::string_view name, int width, int height,
                                   uint64_t seed = 1);

}  // namespace relief
