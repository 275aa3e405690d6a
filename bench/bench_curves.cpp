// bench_curves: the visibility-curve renderer (issue 8) in one run: the paper's Table 1 counts
// for the sine map at 2 samples per pixel, ε ∈ {0.25, 0.001}, unslanted and slanted views, and
// its cost beside the per-pixel `exact` tracer on the very same sample rays (same view, same
// sample count, all cores).
//   bench_curves [SIZE=512] [IMAGE=640x480] [REPEATS=3] [DEPTH_RATIO=0.1]
#include <relief/core/generators.h>
#include <relief/core/parallel.h>
#include <relief/render/curves/curves_renderer.h>
#include <relief/render/compare.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <thread>

using namespace relief;
using namespace relief::curves;

namespace {

double bestSeconds(int repeats, const std::function<void()>& fn) {
    double best = 1e300;
    for (int r = 0; r < repeats; ++r) {
        const auto start = std::chrono::steady_clock::now();
        fn();
        best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    return best;
}

struct Row {
    std::string view;
    double epsilon;
    StepCounts counts;
    double curvesSeconds, exactSeconds;
    double exactStepsPerRay;
    ErrorStats error;
};

Row measure(const std::shared_ptr<const Surface>& surface, const Tracer& exact,
            const std::string& name, float elevation, double epsilon, int w, int h, int repeats) {
    OrbitView view;
    view.elevationDeg = elevation;
    view.azimuthDeg = 30.0f;
    const ViewFrame frame = ViewFrame::fromCamera(Camera(view, *surface, w, h));
    CurvesOptions options;
    options.samplesPerPixel = 2.0;
    options.step.epsilon = epsilon;
    Shading shading;
    CurvesResult result;
    Row row{name, epsilon, {}, 0, 0, 0, {}};
    row.curvesSeconds = bestSeconds(repeats, [&] {
        result = *renderCurvesPlane(*surface, frame, shading, options);
    });
    row.counts = result.counts;
    std::vector<Ray> rays;
    for (const CurveSample& s : result.samples) rays.push_back(frame.ray(dvec2(s.pixel)));
    // Every sample counts, including those outside the image, which the curves also solved; the
    // exact tracer gets the in-image ones (the same rays the image is made of).
    Image<Hit> reference(int(rays.size()), 1);
    row.exactSeconds = bestSeconds(repeats, [&] {
        parallelRanges(int64_t(rays.size()), 1024, [&](int64_t b, int64_t e) {
            exact.traceBatch(std::span<const Ray>(rays).subspan(size_t(b), size_t(e - b)),
                             std::span<Hit>(reference.pixels).subspan(size_t(b), size_t(e - b)));
        });
    });
    double steps = 0.0;
    for (const Hit& hit : reference.pixels) steps += hit.steps;
    row.exactStepsPerRay = steps / double(std::max<size_t>(1, rays.size()));
    Image<Hit> hits(int(rays.size()), 1);
    for (size_t k = 0; k < rays.size(); ++k) hits.pixels[k] = result.samples[k].hit;
    row.error = compareHits(hits, reference);
    row.exactSeconds *= double(result.counts.samples()) / double(std::max<size_t>(1, rays.size()));
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    const int size = argc > 1 ? std::atoi(argv[1]) : 512;
    int w = 640, h = 480;
    if (argc > 2) std::sscanf(argv[2], "%dx%d", &w, &h);
    const int repeats = argc > 3 ? std::atoi(argv[3]) : 3;
    const float depthRatio = argc > 4 ? float(std::atof(argv[4])) : 0.1f;
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("sine", size, size, 1));
    auto surface = std::make_shared<const Surface>(hf, depthRatio * float(size), EdgeMode::Clamp);
    auto exact = std::move(*createTracer("exact", surface));
    std::vector<Row> rows;
    for (auto [name, elevation] : {std::pair{"unslanted (65.1 deg)", 65.1f}, {"slanted (15.3 deg)", 15.3f}})
        for (double epsilon : {0.25, 0.001})
            rows.push_back(measure(surface, *exact, name, elevation, epsilon, w, h, repeats));
    fmt::print("sine {0}x{0}, depth {1}, image {2}x{3}, 2 samples/pixel, azimuth 30, distance 1.2, "
               "fov 45; {4} threads; best of {5}\n\n", size, depthRatio * size, w, h,
               std::thread::hardware_concurrency(), repeats);
    fmt::print("| quantity |");
    for (const Row& r : rows) fmt::print(" {} eps={} |", r.view, r.epsilon);
    fmt::print("\n|---|---|---|---|---|\n");
    auto line = [&](const char* label, auto get) {
        fmt::print("| {} |", label);
        for (const Row& r : rows) fmt::print(" {} |", get(r));
        fmt::print("\n");
    };
    line("visibility curves", [](const Row& r) { return fmt::format("{}", r.counts.curves); });
    line("inside samples", [](const Row& r) { return fmt::format("{}", r.counts.insideSamples); });
    line("extra samples", [](const Row& r) { return fmt::format("{}", r.counts.extraSamples); });
    line("total samples", [](const Row& r) { return fmt::format("{}", r.counts.samples()); });
    line("advance steps", [](const Row& r) { return fmt::format("{}", r.counts.advanceSteps); });
    line("reverse steps", [](const Row& r) { return fmt::format("{}", r.counts.reverseSteps); });
    line("binary cuts", [](const Row& r) { return fmt::format("{}", r.counts.binaryCuts); });
    line("wall hits (leading edge)", [](const Row& r) { return fmt::format("{}", r.counts.wallHits); });
    line("curves evaluations / sample", [](const Row& r) {
        return fmt::format("{:.2f}", double(r.counts.evaluations()) / double(r.counts.samples()));
    });
    line("exact cells / ray", [](const Row& r) { return fmt::format("{:.2f}", r.exactStepsPerRay); });
    line("curves Msamples/s", [](const Row& r) {
        return fmt::format("{:.2f}", 1e-6 * double(r.counts.samples()) / r.curvesSeconds);
    });
    line("exact Mrays/s (same rays)", [](const Row& r) {
        return fmt::format("{:.2f}", 1e-6 * double(r.counts.samples()) / r.exactSeconds);
    });
    line("mean abs dt (texels)", [](const Row& r) { return fmt::format("{:.3g}", r.error.error.mean); });
    line("wrong samples", [](const Row& r) { return fmt::format("{:.3f}%", 100.0 * r.error.wrongRate()); });
    return 0;
}
