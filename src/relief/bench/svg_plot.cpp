#include <relief/bench/svg_plot.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace relief::bench {

namespace {

const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                                "#8c564b", "#e377c2", "#17becf", "#7f7f7f", "#bcbd22"};

struct Axis {
    double lo = 0, hi = 1;
    bool log = false;
    double map(double v, double pixelLo, double pixelHi) const {
        const double a = log ? std::log10(lo) : lo, b = log ? std::log10(hi) : hi;
        const double t = ((log ? std::log10(v) : v) - a) / (b - a > 0 ? b - a : 1);
        return pixelLo + t * (pixelHi - pixelLo);
    }
    std::vector<double> ticks() const {
        std::vector<double> t;
        if (log) {
            for (double p = std::floor(std::log10(lo)); p <= std::ceil(std::log10(hi)); ++p)
                if (std::pow(10.0, p) >= lo * 0.999 && std::pow(10.0, p) <= hi * 1.001) t.push_back(std::pow(10.0, p));
            if (t.size() < 2) t = {lo, hi};
            return t;
        }
        for (int k = 0; k <= 5; ++k) t.push_back(lo + (hi - lo) * k / 5.0);
        return t;
    }
};

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0); }

Axis fitAxis(const std::vector<PlotSeries>& series, bool useX, bool log) {
    Axis axis{1e300, -1e300, log};
    for (const PlotSeries& s : series)
        for (size_t k = 0; k < s.x.size(); ++k) {
            const double v = useX ? s.x[k] : s.y[k];
            if (usable(s.x[k], false) && usable(s.y[k], false) && usable(v, log)) {
                axis.lo = std::min(axis.lo, v);
                axis.hi = std::max(axis.hi, v);
            }
        }
    if (axis.lo > axis.hi) axis = {log ? 1.0 : 0.0, log ? 10.0 : 1.0, log};
    if (axis.lo == axis.hi) {
        axis.lo = log ? axis.lo / 2 : axis.lo - 1;
        axis.hi = log ? axis.hi * 2 : axis.hi + 1;
    }
    if (!log && axis.lo > 0 && axis.lo < 0.5 * axis.hi) axis.lo = 0;
    return axis;
}

}  // namespace

std::string svgLinePlot(const PlotSpec& spec, const std::vector<PlotSeries>& series) {
    const double left = 70, right = spec.width - 170, top = 30, bottom = spec.height - 50;
    const Axis ax = fitAxis(series, true, spec.logX), ay = fitAxis(series, false, spec.logY);
    std::string svg = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" "
        "font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" "
        "fill=\"white\"/>\n<text x=\"{}\" y=\"18\" font-size=\"13\" text-anchor=\"middle\">{}</text>\n",
        spec.width, spec.height, (left + right) / 2, spec.title);
    svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#444\"/>\n",
                       left, top, right - left, bottom - top);
    for (double t : ax.ticks())
        svg += fmt::format("<text x=\"{:.1f}\" y=\"{}\" text-anchor=\"middle\">{:.3g}</text>\n",
                           ax.map(t, left, right), bottom + 15, t);
    for (double t : ay.ticks())
        svg += fmt::format("<line x1=\"{}\" x2=\"{}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"#ddd\"/>"
                           "<text x=\"{}\" y=\"{:.1f}\" text-anchor=\"end\">{:.3g}</text>\n",
                           left, right, ay.map(t, bottom, top), ay.map(t, bottom, top), left - 5,
                           ay.map(t, bottom, top) + 4, t);
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", (left + right) / 2,
                       spec.height - 12, spec.xLabel);
    svg += fmt::format("<text transform=\"translate(16,{}) rotate(-90)\" text-anchor=\"middle\">{}</text>\n",
                       (top + bottom) / 2, spec.yLabel);
    for (size_t s = 0; s < series.size(); ++s) {
        const char* colour = kColours[s % std::size(kColours)];
        std::string points;
        for (size_t k = 0; k < series[s].x.size(); ++k) {
            const double x = series[s].x[k], y = series[s].y[k];
            if (!usable(x, spec.logX) || !usable(y, spec.logY)) continue;
            const double px = ax.map(x, left, right), py = ay.map(y, bottom, top);
            points += fmt::format("{:.1f},{:.1f} ", px, py);
            svg += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"2.5\" fill=\"{}\"/>\n", px, py, colour);
        }
        svg += fmt::format("<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>\n",
                           points, colour);
        svg += fmt::format("<text x=\"{}\" y=\"{}\" fill=\"{}\">{}</text>\n", right + 10,
                           top + 14 * (s + 1), colour, series[s].label);
    }
    return svg + "</svg>\n";
}

std::string svgSideBySide(const std::vector<std::pair<PlotSpec, std::vector<PlotSeries>>>& panels) {
    int width = 0, height = 0;
    std::string inner;
    for (const auto& [spec, series] : panels) {
        // A nested <svg> placed at x = the panels before it.
        inner += fmt::format("<svg x=\"{}\"", width) + svgLinePlot(spec, series).substr(4);
        width += spec.width;
        height = std::max(height, spec.height);
    }
    return fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\">\n", width, height) +
           inner + "</svg>\n";
}

}  // namespace relief::bench
