#include <relief/curves/curves_command.h>

#include <relief/core/parallel.h>
#include <relief/curves/sphere_reference.h>
#include <relief/io/image_write.h>
#include <relief/techniques/registry.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <numbers>

namespace relief::curves {

namespace {

std::shared_ptr<const SphereSurface> makeSphere(const CurvesRenderRequest& r) {
    const double radius = r.radius > 0.0 ? r.radius
                                         : double(r.surface->width()) / (2.0 * std::numbers::pi);
    return std::make_shared<const SphereSurface>(r.surface->heightfieldPtr(), radius,
                                                  double(r.surface->depth()));
}

ViewFrame viewOf(const CurvesRenderRequest& r, const SphereSurface* sphere) {
    if (!sphere) return ViewFrame::fromCamera(Camera(r.view, *r.surface, r.width, r.height));
    // Distances in units of the enclosing sphere's diameter, as the plane's are in box diagonals.
    return ViewFrame::orbit(r.view, dvec3(0.0), 2.0 * sphere->maxRadius(), r.width, r.height);
}

// The reference hit of every sample's ray, in parallel.
Image<Hit> referenceHits(const Tracer& reference, const ViewFrame& view,
                         const std::vector<CurveSample>& samples) {
    Image<Hit> out(int(samples.size()), 1);
    parallelRanges(int64_t(samples.size()), 1024, [&](int64_t begin, int64_t end) {
        std::vector<Ray> rays;
        for (int64_t k = begin; k < end; ++k) rays.push_back(view.ray(dvec2(samples[size_t(k)].pixel)));
        reference.traceBatch(rays, std::span<Hit>(out.pixels).subspan(size_t(begin), rays.size()));
    });
    return out;
}

// Per pixel: the largest |t − t_ref| of its samples; +inf where one is wrong.
ImageF pixelErrors(int width, int height, const std::vector<CurveSample>& samples,
                   const Image<Hit>& reference) {
    Image<Hit> hits(int(samples.size()), 1);
    for (size_t k = 0; k < samples.size(); ++k) hits.pixels[k] = samples[k].hit;
    const ImageF perSample = errorValues(hits, reference);
    ImageF out(width, height, std::nanf(""));
    for (size_t k = 0; k < samples.size(); ++k) {
        const float e = perSample.pixels[k];
        if (std::isnan(e)) continue;
        float& p = out.at(int(samples[k].pixel.x), int(samples[k].pixel.y));
        p = std::isnan(p) ? e : std::max(p, e);
    }
    return out;
}

std::string summaryText(const CurvesRenderRequest& r, const CurvesRun& run) {
    const StepCounts& c = run.result.counts;
    const double samples = double(std::max<int64_t>(1, c.samples()));
    const bool curves = r.technique == "curves";
    const std::string base = r.base == BaseSurface::Sphere ? "sphere" : "plane";
    if (r.json) {
        nlohmann::json row = {
            {"technique", r.technique}, {"surface", base},
            {"samples_per_pixel", r.options.samplesPerPixel}, {"epsilon", r.options.step.epsilon},
            {"visibility_curves", c.curves}, {"inside_samples", c.insideSamples},
            {"extra_samples", c.extraSamples}, {"advance_steps", c.advanceSteps},
            {"reverse_steps", c.reverseSteps}, {"binary_cuts", c.binaryCuts},
            {"wall_hits", c.wallHits}, {"capped_samples", c.cappedSamples},
            {"empty_pixels", run.result.emptyPixels},
            {"measured", run.stats.pixels}, {"wrong", run.stats.wrong},
            {"error_mean", run.stats.error.mean}, {"error_p95", run.stats.error.p95},
            {"error_max", run.stats.error.max}, {"steps_mean", run.stats.steps.mean}};
        if (!r.deterministic) row["seconds"] = run.result.seconds;
        return nlohmann::json::array({row}).dump(2) + "\n";
    }
    std::string text = fmt::format(
        "| technique | surface | samples/px | epsilon | curves | inside | extra | advance | "
        "reverse | cuts | evals/sample | mean |err| | p95 |err| | max |err| | wrong | ms |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    text += fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.2f} | {:.3g} | {:.3g} | {:.3g} | "
        "{:.3f}% | {} |\n",
        r.technique, base, curves ? fmt::format("{}", r.options.samplesPerPixel) : "1",
        curves ? fmt::format("{}", r.options.step.epsilon) : "-", c.curves, c.insideSamples,
        c.extraSamples, c.advanceSteps, c.reverseSteps, c.binaryCuts,
        curves ? double(c.evaluations()) / samples : run.stats.steps.mean, run.stats.error.mean,
        run.stats.error.p95, run.stats.error.max, 100.0 * run.stats.wrongRate(),
        r.deterministic ? std::string("-") : fmt::format("{:.1f}", 1000.0 * run.result.seconds));
    if (curves)
        text += fmt::format("\nerrors per sample against the {} reference on the same ray; {} "
                            "pixels had no sample (filled from neighbours)\n",
                            r.base == BaseSurface::Sphere ? "sphere" : "exact",
                            run.result.emptyPixels);
    return text;
}

}  // namespace

Result<CurvesRun> renderAndMeasure(const CurvesRenderRequest& r) {
    if (r.technique != "curves" && !(r.technique == "exact" && r.base == BaseSurface::Sphere))
        return makeError(ErrorKind::Unsupported,
                         "technique '{}' runs on the plane only; the sphere takes 'curves' or "
                         "'exact'", r.technique);
    CurvesRun run;
    std::shared_ptr<const SphereSurface> sphere;
    if (r.base == BaseSurface::Sphere) sphere = makeSphere(r);
    const ViewFrame view = viewOf(r, sphere.get());
    if (r.technique == "exact") {
        run.result = renderSphereExact(sphere, view, r.shading);
        run.stats = compareHits(run.result.hits, run.result.hits);
        return run;
    }
    auto result = sphere ? renderCurvesSphere(*sphere, view, r.shading, r.options)
                         : renderCurvesPlane(*r.surface, view, r.shading, r.options);
    if (!result) return result.error();
    run.result = std::move(*result);
    std::unique_ptr<Tracer> reference;
    if (sphere) {
        reference = makeSphereReferenceTracer(sphere);
    } else {
        auto exact = createTracer("exact", r.surface);
        if (!exact) return exact.error();
        reference = std::move(*exact);
    }
    const auto start = std::chrono::steady_clock::now();
    run.reference = referenceHits(*reference, view, run.result.samples);
    run.referenceSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    Image<Hit> hits(int(run.result.samples.size()), 1);
    for (size_t k = 0; k < hits.pixels.size(); ++k) hits.pixels[k] = run.result.samples[k].hit;
    run.stats = compareHits(hits, run.reference);
    return run;
}

Result<std::string> runCurvesRender(const CurvesRenderRequest& r) {
    auto run = renderAndMeasure(r);
    if (!run) return run.error();
    const std::string prefix = r.outDir.empty() ? "" : r.outDir + "/" + r.technique;
    const std::string colorPath = !r.output.empty() ? r.output : prefix + ".png";
    const std::string stepsPath = !r.stepsOut.empty() ? r.stepsOut : (prefix.empty() ? "" : prefix + "-steps.png");
    const std::string errorPath = !r.errorOut.empty() ? r.errorOut : (prefix.empty() ? "" : prefix + "-error.png");
    const CurvesResult& res = run->result;
    if (Status s = writePng(colorPath, res.color); !s) return s.error();
    if (!stepsPath.empty()) {
        double top = 1.0;
        for (float v : res.evaluationsPerSample.pixels)
            if (std::isfinite(v)) top = std::max(top, double(v));
        const std::string title = r.technique == "curves" ? "curves evaluations/sample" : "exact marching steps";
        if (Status s = writePng(stepsPath, heatmap(res.evaluationsPerSample, float(top), title)); !s)
            return s.error();
    }
    if (!errorPath.empty() && r.technique == "curves") {
        const ImageF errors = pixelErrors(r.width, r.height, res.samples, run->reference);
        const float scale = std::max(1e-3f, float(run->stats.error.p99));
        if (Status s = writePng(errorPath, heatmap(errors, scale, "curves |t-t_ref|")); !s)
            return s.error();
    }
    return summaryText(r, *run);
}

}  // namespace relief::curves
