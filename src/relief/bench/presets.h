#pragma once
// What `relief bench` runs: the bench-global presets (quick, default, gpu), the studies the
// registry rows contribute (TechniqueInfo::studies), and command-line overrides.
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/techniques/technique.h>

#include <optional>
#include <string>
#include <vector>

namespace relief::bench {

// One of a paper's published speed ratios, set beside ours in the report: the speed (Mrays/s, or
// fps on GL) of the numerator row on its map over the denominator's, per view, on the same rays.
// An empty map means every map of the run.
struct PaperRatio {
    std::string what;   // what is compared
    std::string paper;  // the published figure and its source
    std::string numeratorTechnique, numeratorMap, denominatorTechnique, denominatorMap;
    std::string backend = "cpu";
};

// One of issue 21's speed targets (the cpu-peers page): a row's Mrays/s over a CPU peer's on the
// same rays, primary or shadow (the peer's occlusion query: embree-1 → rtcOccluded1, embree-16 →
// rtcOccluded16), at least `ratio` on every view of the maps in scope, or as a geometric mean.
struct PeerTarget {
    std::string row, peer;
    double ratio = 1;
    bool shadow = false;
    int64_t maxSamples = 0;  // the maps in scope: at most this many samples (0 = every map)
    bool everyView = false;  // each view must meet it (else the geometric mean over the views)
};

struct BenchConfig {
    std::string name;  // the preset
    StudyKind kind = StudyKind::Views;
    std::vector<std::string> maps;        // gen:NAME:WxH or paths (relative to the repo's root)
    std::vector<std::string> techniques;  // rows: NAME or NAME:PARAM=V[:PARAM=V]
    std::vector<float> elevations;
    std::vector<int> caps;   // for rows with an iteration cap
    std::vector<int> sizes;  // map sizes N for Builds and Scaling: a map with {N} in it, once per size
    std::vector<std::string> backends{"cpu"};
    ivec2 size{640, 512};
    float azimuth = 30.0f;
    float distance = 1.0f;
    float depthRatio = 0.1f;
    std::optional<float> depth;  // texels; overrides depthRatio
    std::string edge = "clamp";
    int repeats = 3;
    int glFrames = 10;  // timed GL frames per row
    bool embree = true;
    bool peerTable = false;  // the reference against each CPU peer, per map and view
    std::string compare;     // "A/B": two rows side by side by elevation and cap (cap 0 = default)
    std::string paperNotes;  // the paper's claims, shown beside ours
    std::vector<PaperRatio> paperRatios;
    bool imageMethod = false;  // rows with an image method of their own (curves) are drawn with it
    // Every CPU row also behind an Embree user geometry (embree/heightfield_geometry.h), traced
    // with rtcIntersect1 and rtcIntersect16 on the same rays as the triangles; memory per texel of
    // both; the report's "Embree user geometry" table.
    bool userGeometry = false;
    // StudyKind::Paper: the studies it runs, in order, and the claims it judges from their rows.
    float shadowElevation = 0.0f;  // StudySpec::shadowElevation
    // With shadowElevation: also time the shadow rays, each CPU row tracing them from the light
    // (the shadow rays of every row), the Embree peers answering occlusion queries on the same
    // segments (rtcOccluded1, rtcOccluded16 on 4×4 tiles of pixels).
    bool shadowTiming = false;
    // Each CPU row's timed repeats each followed by one run of each Embree peer on the same rays
    // (primary, and shadow with shadowTiming): the ratios to the peers are the medians of these
    // pairs (BenchRow::pairedRatios), so that a row and its peer share the machine's load of the
    // moment. The rows' and peers' Mrays/s stay their best repeats.
    bool pairedPeers = false;
    // Rows skipped on maps of more samples than given (row label, samples): bakes too slow there.
    std::vector<std::pair<std::string, int64_t>> rowMaxSamples;
    std::vector<PeerTarget> targets;  // non-empty: the report's cpu-peers tables (bench/peers_report.h)
    std::vector<std::string> parts;
    std::span<const ClaimSpec> claims;
    std::string paperFile;
};

// Command-line overrides of a preset; empty strings / unset values keep the preset's.
struct BenchOverrides {
    std::string techniques, maps, elevations, caps, backends, size, sizes, edge;
    std::optional<float> depth, depthRatio, azimuth, distance;
    int repeats = 0;
    bool smoke = false;  // cut the run to seconds: maps 64², one view, 32×32 rays, one repeat
    // cut the run to about a minute with every view kept: generated maps and windows to at most
    // 256², map sizes to at most 512, 160×128 rays, one repeat
    bool quick = false;
};

struct PresetEntry {
    std::string name, description, owner;  // owner: the registry row, empty for bench-global ones
};
std::vector<PresetEntry> presetList();
std::string presetNames();
// A preset's configuration; rows it names that this build lacks are dropped.
Result<BenchConfig> presetConfig(const std::string& name);
Status applyOverrides(BenchConfig& config, const BenchOverrides& overrides);

// A row of the run: a technique with its variant parameters ("cone:variant=1").
struct RowSpec {
    std::string label;  // as given, the row's name in the outputs
    const TechniqueInfo* info = nullptr;
    std::vector<std::pair<std::string, double>> params;
};
Result<RowSpec> parseRowSpec(const std::string& text);

}  // namespace relief::bench
