#pragma once
// The sampled precomputation the safety-shapes paper compares its exact one with (§8: "a sampling
// with 8 positions on s_τ and 256 angular directions", the approach of [19]): per texel and ray
// class, rays from just above S at sampled points of s_τ along sampled directions of the class
// wedge; the safety distance is the first column where one of them leaves S after entering it.
// Rays between the samples are not seen, so the distances can be too long: approximate (the
// paper: "results in artifacts"). `precompute=1` of safety-sd / safety-cc.
#include <relief/core/error.h>
#include <relief/io/map_file.h>
#include <relief/techniques/safety_common/safety_maps.h>
#include <relief/techniques/technique.h>

namespace relief::safety {

struct SamplingOptions {
    int positions = 8;    // on s_τ
    int azimuths = 16;    // across the class wedge (±45°)
    int elevations = 16;  // from straight down to φ_max (azimuths × elevations = 256 directions)
};

// The sampled safety distances (directional, or their minimum with options.isotropic); exterior
// maps are not sampled (checkSampledPrecompute refuses them).
DistanceMap buildSampledDistanceMap(const Surface& surface, const BuildOptions& options,
                                    const SamplingOptions& sampling = {});

// The row's `precompute` parameter: 1 = sampled.
bool sampledPrecompute(const ParamValues& params);
// The safety distances `precompute` asks for: exact (buildDistanceMap) or sampled.
DistanceMap buildDistanceMapFor(const Surface& surface, const BuildOptions& options, bool sampled);
// The same from input.share when another row of this bake built them with the same options (or
// built now and left there for the next): safety-sd's map is safety-cc's radii.
std::shared_ptr<const DistanceMap> sharedDistanceMap(const TechniqueInput& input,
                                                     const BuildOptions& options, bool sampled,
                                                     const std::string& row);
// What `precompute=1` cannot serve: exterior maps, and baked maps whose own precomputation
// (the "precompute" parameter they record; none = exact) differs from the request.
Status checkSampledPrecompute(const ParamValues& params, const TechniqueMaps* maps);
// Records a sampled bake in its maps' parameters.
void recordPrecompute(TechniqueMaps& maps, bool sampled);

}  // namespace relief::safety
