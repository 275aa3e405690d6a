#include <relief/render/curves/curves_image.h>

#include <relief/core/parallel.h>
#include <relief/sphere/sphere_reference.h>
#include <relief/techniques/registry.h>

#include <chrono>
#include <cmath>
#include <numbers>

namespace relief::curves {

namespace {

ViewFrame viewOf(const CurvesScene& scene) {
    if (!scene.sphere)
        return ViewFrame::fromCamera(Camera(scene.view, *scene.surface, scene.width, scene.height));
    // Distances in units of the enclosing sphere's diameter, as the plane's are in box diagonals.
    return ViewFrame::orbit(scene.view, dvec3(0.0), 2.0 * scene.sphere->maxRadius(), scene.width,
                            scene.height);
}

// The reference hit of every sample's ray, in parallel.
Image<Hit> referenceHits(const Tracer& reference, const ViewFrame& view,
                         const std::vector<CurveSample>& samples) {
    Image<Hit> out(int(samples.size()), 1);
    parallelRanges(int64_t(samples.size()), 1024, [&](int64_t begin, int64_t end) {
        std::vector<Ray> rays;
        for (int64_t k = begin; k < end; ++k)
            rays.push_back(view.ray(dvec2(samples[size_t(k)].pixel)));
        reference.traceBatch(rays, std::span<Hit>(out.pixels).subspan(size_t(begin), rays.size()));
    });
    return out;
}

Image<Hit> sampleHits(const std::vector<CurveSample>& samples) {
    Image<Hit> hits(int(samples.size()), 1);
    for (size_t k = 0; k < samples.size(); ++k) hits.pixels[k] = samples[k].hit;
    return hits;
}

// Traces the reference on every sample's ray and measures the samples against it.
void measure(CurvesRun& run, const Tracer& reference, const ViewFrame& view) {
    const auto start = std::chrono::steady_clock::now();
    run.reference = referenceHits(reference, view, run.result.samples);
    run.referenceSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    run.stats = compareHits(sampleHits(run.result.samples), run.reference);
}

}  // namespace

std::shared_ptr<const SphereSurface> makeSphere(const Surface& surface, double radius) {
    if (!(radius > 0.0)) radius = double(surface.width()) / (2.0 * std::numbers::pi);
    return std::make_shared<const SphereSurface>(surface.heightfieldPtr(), radius,
                                                 double(surface.depth()));
}

CurvesOptions curvesOptions(const TechniqueInfo& info, const ParamValues& params) {
    CurvesOptions options;
    options.step.epsilon = params.get("epsilon");
    if (const ParamSpec* samples = paramWithRole(info, ParamRole::ImageSampling))
        options.samplesPerPixel = params.get(samples->name);
    if (const ParamSpec* cap = paramWithRole(info, ParamRole::IterationCap))
        options.step.maxEvaluations = params.getInt(cap->name);
    return options;
}

Result<CurvesRun> renderAndMeasure(const CurvesScene& scene, const CurvesOptions& options) {
    const ViewFrame view = viewOf(scene);
    auto result = scene.sphere ? renderCurvesSphere(*scene.sphere, view, scene.shading, options)
                               : renderCurvesPlane(*scene.surface, view, scene.shading, options);
    if (!result) return result.error();
    CurvesRun run;
    run.result = std::move(*result);
    std::unique_ptr<Tracer> reference;
    if (scene.sphere) {
        reference = makeBatchTracer(SphereReference(scene.sphere));
    } else {
        auto exact = createTracer(referenceTechnique().name, scene.surface);
        if (!exact) return exact.error();
        reference = std::move(*exact);
    }
    measure(run, *reference, view);
    return run;
}

Result<CurvesRun> renderSphere(const CurvesScene& scene, const Tracer& tracer,
                               const Tracer* reference) {
    if (!scene.sphere) return makeError(ErrorKind::BadArgument, "renderSphere: no sphere");
    const ViewFrame view = viewOf(scene);
    CurvesRun run;
    run.result = renderSpherePixels(*scene.sphere, view, tracer, scene.shading);
    if (reference) {
        measure(run, *reference, view);
    } else {
        run.reference = sampleHits(run.result.samples);
        run.stats = compareHits(run.reference, run.reference);
    }
    return run;
}

ImageRgb8 stepsImage(const CurvesRun& run, std::string_view title) {
    double top = 1.0;
    for (float v : run.result.evaluationsPerSample.pixels)
        if (std::isfinite(v)) top = std::max(top, double(v));
    return heatmap(run.result.evaluationsPerSample, float(top), title);
}

ImageRgb8 errorImage(const CurvesRun& run, std::string_view title) {
    // Per pixel: the largest |t − t_ref| of its samples; +inf where one is wrong.
    const std::vector<CurveSample>& samples = run.result.samples;
    const ImageF perSample = errorValues(sampleHits(samples), run.reference);
    ImageF errors(run.result.color.width, run.result.color.height, std::nanf(""));
    for (size_t k = 0; k < samples.size(); ++k) {
        const float e = perSample.pixels[k];
        if (std::isnan(e)) continue;
        float& p = errors.at(int(samples[k].pixel.x), int(samples[k].pixel.y));
        p = std::isnan(p) ? e : std::max(p, e);
    }
    return heatmap(errors, std::max(1e-3f, float(run.stats.error.p99)), title);
}

}  // namespace relief::curves
