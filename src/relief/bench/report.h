#pragma once
// What `relief bench` writes from its rows, one schema (BenchRow) in four forms: results.csv,
// results.json, report.md and index.html (the per-row summary with speed ratios to the reference
// and to the backend's peer, measured on the same rays in the same run; error-vs-cap,
// steps-vs-elevation, map build and scaling tables; the paper's figures beside ours), plus the
// SVG plots.
#include <relief/bench/presets.h>
#include <relief/render/compare.h>
#include <relief/techniques/common/curve_stepper.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace relief::bench {

// A row drawn by the visibility-curve renderer (BenchConfig::imageMethod): the paper's Table 1
// counters, and the reference traced on the very same sample rays. Its stats are per sample.
struct CurvesFigures {
    curves::StepCounts counts;
    double referenceCellsPerRay = 0;  // mean steps of the reference on the sample rays
    double msamplesPerSecond = 0;     // every sample, extra ones included
    double referenceMraysPerSecond = 0;
};

struct BenchRow {
    std::string technique;  // the row's label: NAME[:P=V...], or a peer's name
    std::string contract, map, backend;
    float elevation = 0;
    int cap = 0;  // 0 = the technique's default / none
    ErrorStats stats;
    double shadowMraysPerSecond = 0;  // BenchConfig::shadowTiming: the shadow rays (0: not timed)
    double shadowWrongRate = -1;  // StudySpec::shadowElevation: pixels with the wrong shadow / pixels; < 0: not run
    double agreeRate = 0;  // pixels with the reference's hit/miss and |Δt| <= 1e-3 texel (the exact contract)
    Summary boxSteps;      // steps over the rays that enter the relief's box
    int64_t mapSamples = 0;
    double mraysPerSecond = 0, msPerFrame = 0, buildSeconds = 0, buildCpuSeconds = 0, bytesPerTexel = 0;
    std::string images;  // file prefix relative to the output folder, empty if none
    std::optional<CurvesFigures> curves;
    std::vector<std::pair<std::string, double>> mapSummary;  // the row's TechniqueInfo::mapSummary of its maps
    // BenchConfig::pairedPeers: the row's speed over each Embree peer's on the same rays, keyed by
    // the peer's call (embreeQuery): the median over the repeats of the row and the peer timed
    // back to back. Empty when not paired.
    std::map<std::string, double> pairedRatios;
};

// Geometric mean of positive ratios; 0 when there are none.
class RatioMean {
public:
    void add(double numerator, double denominator) {
        if (numerator <= 0 || denominator <= 0) return;
        m_logSum += std::log(numerator / denominator);
        ++m_count;
    }
    double value() const { return m_count ? std::exp(m_logSum / m_count) : 0.0; }
    int count() const { return m_count; }

private:
    double m_logSum = 0;
    int m_count = 0;
};

// A table both writers render (report.md and index.html), so that they cannot disagree.
struct ReportTable {
    ReportTable(std::string titleText, std::string captionText)
        : title(std::move(titleText)), caption(std::move(captionText)) {}
    std::string title, caption;
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;
};

struct BenchMeta {
    std::string preset, machine, imageSize, date, glDevice, commandLine, loadBefore, loadAfter;
    int threads = 0;
    bool timings = true;  // false with --deterministic
};

// One line of the summary: a technique on one backend, averaged over the maps and views at its
// largest cap. Speed ratios are geometric means over (map, view) of per-view ratios.
struct TechniqueSummary {
    std::string technique, contract, backend;
    double errorMean = 0, errorP95 = 0, wrongPercent = 0, stepsMean = 0;
    double mraysPerSecond = 0, vsExact = 0, vsPeer = 0, buildSeconds = 0, bytesPerTexel = 0;
};

std::vector<TechniqueSummary> summarize(const std::vector<BenchRow>& rows, const BenchConfig& config);

// Our value for one of the paper's figures: the speed ratio it names, from the rows ("-" when the
// run lacks one side).
std::string measuredRatio(const std::vector<BenchRow>& rows, const PaperRatio& ratio);

nlohmann::json rowJson(const BenchRow& row, bool timings);
std::string resultsJson(const std::vector<BenchRow>& rows, const nlohmann::json& meta, bool timings);
std::string resultsCsv(const std::vector<BenchRow>& rows, bool timings);
// error_vs_cap.svg and steps_vs_elevation.svg, in that order.
std::pair<std::string, std::string> benchPlots(const std::vector<BenchRow>& rows, const BenchConfig& config);
// A Scaling study's steps_vs_map_size.svg: at the lowest elevation, mean steps per ray of every
// row but the reference (left) and the 99th percentile of every row (right, log scale) against
// log2 of the map's samples, over the maps the study sweeps by size.
inline constexpr const char* kScalingPlotName = "steps_vs_map_size.svg";
std::string scalingPlot(const std::vector<BenchRow>& rows, const BenchConfig& config);

// `assetPrefix` is prepended to the plot file names (the report may live in another folder).
std::string benchMarkdown(const std::vector<BenchRow>& rows, const BenchConfig& config,
                          const BenchMeta& meta, const std::string& assetPrefix);
std::string benchHtml(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta);

}  // namespace relief::bench
