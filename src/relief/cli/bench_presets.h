#pragma once
// What `relief bench` runs: named presets (one per paper's experiment) and command-line overrides.
#include <relief/core/error.h>
#include <relief/core/math.h>

#include <string>
#include <vector>

namespace relief::cli {

// One of a paper's published speed ratios, set beside ours in the report: the speed (Mrays/s, or
// fps on GL) of the numerator technique on its map over the denominator's, per view, on the same
// rays. An empty map means every map of the run.
struct PaperRatio {
    std::string what;   // what is compared
    std::string paper;  // the published figure and its source
    std::string numeratorTechnique, numeratorMap, denominatorTechnique, denominatorMap;
    std::string backend = "cpu";
};

struct BenchConfig {
    std::vector<std::string> maps;        // gen:NAME:WxH or paths (relative to the repo's root)
    std::vector<std::string> techniques;  // registry names present in this build
    std::vector<float> elevations;
    std::vector<int> caps;  // for techniques with an iteration cap
    std::vector<std::string> backends{"cpu"};
    ivec2 size{640, 512};
    float azimuth = 30.0f;
    float distance = 1.0f;
    float depthRatio = 0.1f;
    int repeats = 3;
    int glFrames = 10;  // timed GL frames per row
    bool embree = true;
    std::string paperNotes;  // the paper's claims, shown beside ours
    std::vector<PaperRatio> paperRatios;
};

std::string presetNames();
// A preset's configuration; techniques it names that this build lacks are dropped.
Result<BenchConfig> presetConfig(const std::string& name);
// Comma-separated overrides; empty strings keep the preset's value.
Status applyOverrides(BenchConfig& config, const std::string& techniques, const std::string& maps,
                      const std::string& elevations, const std::string& caps,
                      const std::string& backends, const std::string& size, int repeats);

}  // namespace relief::cli
