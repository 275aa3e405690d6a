#pragma once
// The bench run: rows (techniques with their variant parameters) × heightfields × views × caps ×
// backends, with the peers in the same run, or a study's map builds / scaling; writes
// results.csv, results.json, report.md, index.html, images and SVG plots into one folder.
#include <relief/bench/presets.h>
#include <relief/core/error.h>

#include <optional>
#include <string>
#include <vector>

namespace relief::bench {

struct RunOptions {
    std::string preset = "default";
    BenchOverrides overrides;
    std::vector<std::string> params;  // --param NAME=V, for every row that has NAME
    std::string mapsPath;             // --maps FILE: baked maps, checked against each heightfield
    std::string visibility;           // "", "all" or "exterior": the rows' ParamRole::Visibility
    std::optional<double> phiMax;     // degrees: the rows' ParamRole::PhiMax
    std::string outDir = "bench-out";
    std::string markdownPath;  // also write the Markdown report here (links relative to it)
    int threads = 0;
    bool noImages = false;
    bool deterministic = false;
    bool judge = false;  // fail (runtime error) when a row breaks its contract or a peer disagrees
};

// The command that reproduces this run, for the report's first line.
std::string commandLine(const RunOptions& options);

// Runs the bench; progress on stderr, the written paths on stdout.
Status run(const RunOptions& options);

// "name (row) description" per preset, one a line.
std::string presetTable();

}  // namespace relief::bench
