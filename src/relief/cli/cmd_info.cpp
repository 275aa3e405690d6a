// relief info HEIGHTFIELD: size, value range, histogram summary, a suggested depth.
#include <relief/cli/common.h>
#include <relief/core/isa.h>
#include <relief/core/memory_budget.h>
#include <relief/core/progress.h>
#include <relief/core/stats.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>

namespace relief::cli {

namespace {

struct InfoOptions {
    SurfaceOptions surface;
    std::string format = "text";
};

// The depth at which 95% of the texel-to-texel slopes stay below 45 degrees: deeper reliefs look
// spiky and make every marching method take more steps.
double slopeLimitedDepth(const Heightfield& hf) {
    std::vector<double> slopes;
    slopes.reserve(hf.sampleCount());
    Progress progress("info", hf.height);  // minutes on the largest maps
    for (int j = 0; j < hf.height; ++j, progress.advance())
        for (int i = 0; i < hf.width; ++i) {
            if (i + 1 < hf.width) slopes.push_back(std::abs(hf.at(i + 1, j) - hf.at(i, j)));
            if (j + 1 < hf.height) slopes.push_back(std::abs(hf.at(i, j + 1) - hf.at(i, j)));
        }
    const double p95 = summarize(std::move(slopes)).p95;
    return p95 > 0.0 ? 1.0 / p95 : double(std::max(hf.width, hf.height));
}

void runInfo(const InfoOptions& o) {
    const auto hf = orFail(loadHeightfield(o.surface));
    // The statistics hold every height as a double (and a copy while summarizing), then up to two
    // slopes per sample: the peak, next to the heightfield itself.
    orFail(reserveMemory(hf->sampleCount() * int64_t(sizeof(float) + 3 * sizeof(double)),
                         fmt::format("{}: statistics of {}x{} samples", o.surface.source, hf->width,
                                     hf->height)));
    const std::vector<double> values(hf->samples.begin(), hf->samples.end());
    const Summary s = summarize(values);
    double lo = 1.0;
    for (double v : values) lo = std::min(lo, v);
    constexpr int kBins = 10;
    std::vector<size_t> histogram(kBins, 0);
    for (double v : values) ++histogram[std::min(kBins - 1, int(v * kBins))];
    const double defaultDepth = 0.1 * std::max(hf->width, hf->height);
    const double slopeDepth = slopeLimitedDepth(*hf);
    if (o.format == "json") {
        std::cout << nlohmann::json{{"source", o.surface.source},
                                    {"width", hf->width},
                                    {"height", hf->height},
                                    {"min", lo},
                                    {"max", s.max},
                                    {"mean", s.mean},
                                    {"histogram", histogram},
                                    {"depth_default", defaultDepth},
                                    {"depth_slope_limited", slopeDepth},
                                    {"hash", fmt::format("{:016x}", hf->contentHash())},
                                    {"tracer_isa", tracerIsa()}}
                         .dump(2)
                  << "\n";
        return;
    }
    std::cout << fmt::format("{}: {}x{} samples ({:.1f} MB as float)\n", o.surface.source,
                             hf->width, hf->height, double(hf->sampleCount()) * 4.0 / 1e6);
    std::cout << fmt::format("normalized heights: min {:.4f}, max {:.4f}, mean {:.4f}\n", lo,
                             s.max, s.mean);
    std::cout << "histogram (10 bins over [0,1]):";
    for (size_t count : histogram)
        std::cout << fmt::format(" {:.1f}%", 100.0 * double(count) / double(values.size()));
    std::cout << fmt::format(
        "\nsuggested depth: --depth {:.1f} (default --depth-ratio 0.1); {:.1f} keeps 95% of "
        "texel slopes under 45 degrees\nsource hash: {:016x}\ntracer ISA: {} (RELIEF_ISA or --isa on trace and bench)\n",
        defaultDepth, slopeDepth, hf->contentHash(), tracerIsa());
}

}  // namespace

void addInfoCommand(CLI::App& app) {
    auto o = std::make_shared<InfoOptions>();
    CLI::App* cmd = app.add_subcommand("info", "size, value range, histogram and a suggested depth");
    addSurfaceOptions(*cmd, o->surface);
    cmd->add_option("--format", o->format, "output format")
        ->check(CLI::IsMember({"text", "json"}))
        ->capture_default_str();
    cmd->callback([o] { runInfo(*o); });
}

}  // namespace relief::cli
