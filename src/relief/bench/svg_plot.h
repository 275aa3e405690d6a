#pragma once
// Line plots written as standalone SVG: no plotting tool needed at run time.
#include <string>
#include <vector>

namespace relief::bench {

struct PlotSeries {
    std::string label;
    std::vector<double> x, y;
};

struct PlotSpec {
    std::string title, xLabel, yLabel;
    bool logX = false, logY = false;
    int width = 640, height = 400;
};

// Non-positive values are skipped on log axes.
std::string svgLinePlot(const PlotSpec& spec, const std::vector<PlotSeries>& series);

// Plots from svgLinePlot side by side in one SVG, left to right.
std::string svgSideBySide(const std::vector<std::pair<PlotSpec, std::vector<PlotSeries>>>& panels);

}  // namespace relief::bench
