// The visibility-curve renderer (issue 8): mappings, sampling, stepping on plane and sphere
// against the exact references (sphere/sphere_test.cpp checks the sphere's).
#include <relief/core/generators.h>
#include <relief/render/curves/curves_image.h>
#include <relief/render/curves/plane_mapping.h>
#include <relief/render/curves/sampling.h>
#include <relief/render/curves/sphere_mapping.h>
#include <relief/techniques/registry.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>

namespace relief::curves {
namespace {

std::shared_ptr<const Surface> makePlane(const char* generator, int w, int h, float depth) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield(generator, w, h, 1));
    return std::make_shared<const Surface>(hf, depth, EdgeMode::Clamp);
}

OrbitView orbit(float elevation, float azimuth, float distance = 1.2f) {
    OrbitView v;
    v.elevationDeg = elevation;
    v.azimuthDeg = azimuth;
    v.distance = distance;
    return v;
}

TEST(CurvesPlaneMapping, RoundTripsAndMatchesTheCamera) {
    auto surface = makePlane("sine", 64, 48, 6.0f);
    for (float elevation : {15.3f, 40.2f, 90.0f}) {
        const ViewFrame view = ViewFrame::fromCamera(Camera(orbit(elevation, 30.0f), *surface, 200, 150));
        const PlaneMapping m(view);
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(0.0, 64.0);
        for (int k = 0; k < 200; ++k) {
            const dvec2 st(u(rng), 0.75 * u(rng));
            const dvec2 uv = m.toView(st);
            EXPECT_NEAR(glm::length(m.toSurface(uv) - st), 0.0, 1e-9);
            // The camera basis comes from float: orthonormal to ~1e-7, hence ~1e-5 px.
            EXPECT_NEAR(glm::length(uv - view.project(dvec3(st, 0.0))), 0.0, 1e-4);
        }
        // CoP_v is the image of the vertical through the eye: its ray points straight down.
        const dvec3 d = glm::normalize(view.direction(m.copView()));
        EXPECT_NEAR(d.z, -1.0, 1e-9) << elevation;
    }
}

TEST(CurvesSampling, RecurrenceSpacingAndInverse) {
    const double n = 4.0, r0 = 300.0;
    const LineRadii radii = insideRadii(n, r0, 20.0);
    ASSERT_GT(radii.radii.size(), 10u);
    EXPECT_EQ(radii.radii.front(), r0);
    for (size_t j = 1; j < radii.radii.size(); ++j) {
        const double prev = radii.radii[j - 1], r = radii.radii[j];
        EXPECT_NEAR(prev - r, r0 / (prev * std::sqrt(n)), 1e-9);  // r_j = r_{j-1} − r_0/(r_{j-1}√n)
        EXPECT_NEAR(nextOuterRadius(n, r0, r), prev, 1e-9);       // the inverse recurrence
        EXPECT_GE(r, 20.0);
    }
    EXPECT_LT(radii.innerEnd, 20.0);
    // Lines 1/√n pixels apart at the farthest radius.
    EXPECT_NEAR(lineAngleStep(n, r0) * r0, 0.5, 1e-12);
    LineJitter jitter(7);
    for (int k = 0; k < 1000; ++k) {
        const double p = jitter.place(10.0, 11.0);
        EXPECT_TRUE(p >= 10.0 && p <= 11.0);
    }
}

CurvesScene planeScene(std::shared_ptr<const Surface> surface, float elevation, int w = 96,
                       int h = 72) {
    CurvesScene scene;
    scene.surface = std::move(surface);
    scene.view = orbit(elevation, 30.0f);
    scene.width = w;
    scene.height = h;
    return scene;
}

CurvesOptions withEpsilon(double epsilon) {
    CurvesOptions options;
    options.step.epsilon = epsilon;
    return options;
}

// Jitter moves samples along their visibility line only: all samples of a render lie on as many
// directions from CoP_v as there are curves, and the density is about n per pixel.
TEST(CurvesSampling, SamplesStayOnTheirLinesAtTheRequestedDensity) {
    auto surface = makePlane("sine", 64, 64, 6.4f);
    const CurvesScene r = planeScene(surface, 40.2f, 160, 120);
    auto run = renderAndMeasure(r, withEpsilon(0.25));
    ASSERT_TRUE(run.ok()) << run.error().message;
    const ViewFrame view = ViewFrame::fromCamera(Camera(r.view, *surface, r.width, r.height));
    const dvec2 cop = PlaneMapping(view).copView();
    std::set<int64_t> directions;
    std::set<int64_t> pixels;
    int64_t inside = 0;
    for (const CurveSample& s : run->result.samples) {
        // Samples are stored as float pixels: angles agree to ~1e-7 rad at these distances.
        const dvec2 p = dvec2(s.pixel) - cop;
        directions.insert(std::llround(std::atan2(p.y, p.x) * 2e5));
        if (!s.inside) continue;
        ++inside;
        pixels.insert(int64_t(s.pixel.y) * r.width + int64_t(s.pixel.x));
    }
    EXPECT_LE(int64_t(directions.size()), 2 * run->result.counts.curves);  // rounding splits a few
    const double density = double(inside) / double(pixels.size());
    EXPECT_GT(density, 1.6);
    EXPECT_LT(density, 2.6);
    std::printf("[ curves   ] %zu samples on %lld curves, %zu distinct directions; %.2f inside "
                "samples per covered pixel\n", run->result.samples.size(),
                (long long)run->result.counts.curves, directions.size(), density);
}

// Curves vs exact on small images, per sample (same ray): ε small.
TEST(CurvesPlane, CloseToExactForSmallEpsilon) {
    for (const char* generator : {"sine", "peaks6"}) {
        for (float elevation : {15.3f, 40.2f, 77.6f}) {
            auto surface = makePlane(generator, 64, 64, 6.4f);
            auto run = renderAndMeasure(planeScene(surface, elevation), withEpsilon(0.001));
            ASSERT_TRUE(run.ok()) << run.error().message;
            const ErrorStats& s = run->stats;
            std::printf("[ curves   ] %-7s el %5.1f: %zu samples, mean |dt| %.2e, max %.3g, "
                        "wrong %.3f%%\n", generator, elevation, s.pixels, s.error.mean, s.error.max,
                        100.0 * s.wrongRate());
            EXPECT_GT(s.hits, 1000u);
            // At grazing views consecutive eye rays are far apart on the surface and a step from
            // a valley can pass over the next crest or leave the region (the paper's termination):
            // those samples are wrong, mostly extra samples at the trailing silhouette.
            const bool grazing = elevation < 20.0f;
            EXPECT_LT(s.error.mean, grazing ? 0.15 : 0.002) << generator << " " << elevation;
            EXPECT_LT(s.wrongRate(), grazing ? 0.03 : 0.003) << generator << " " << elevation;
        }
    }
}

TEST(CurvesPlane, CountsAddUp) {
    auto surface = makePlane("sine", 64, 64, 6.4f);
    auto coarse = renderAndMeasure(planeScene(surface, 40.2f), withEpsilon(0.25));
    auto fine = renderAndMeasure(planeScene(surface, 40.2f), withEpsilon(0.001));
    ASSERT_TRUE(coarse.ok() && fine.ok());
    const StepCounts& c = coarse->result.counts;
    const StepCounts& f = fine->result.counts;
    EXPECT_EQ(c.curves, f.curves);                // lines and inside samples depend on the view
    EXPECT_EQ(c.insideSamples, f.insideSamples);  // and the sampling only
    EXPECT_GT(c.extraSamples, 0);
    EXPECT_GE(c.advanceSteps, c.samples() / 2);
    EXPECT_GT(f.evaluations(), c.evaluations());  // a stricter ε costs more
    EXPECT_LE(fine->stats.error.mean, coarse->stats.error.mean);
}

// The row's parameters are the image renderer's options (`relief render -t curves --param ...`).
TEST(CurvesPlane, OptionsComeFromTheRow) {
    const TechniqueInfo& row = *findTechnique("curves");
    EXPECT_EQ(row.image, ImageMethod::VisibilityCurves);
    auto params = resolveParams(row, {{"epsilon", 0.01}, {"samples", 4}, {"max-steps", 50}});
    ASSERT_TRUE(params.ok());
    const CurvesOptions o = curvesOptions(row, *params);
    EXPECT_EQ(o.step.epsilon, 0.01);
    EXPECT_EQ(o.samplesPerPixel, 4.0);
    EXPECT_EQ(o.step.maxEvaluations, 50);
    const CurvesOptions defaults = curvesOptions(row, *resolveParams(row, {}));
    EXPECT_EQ(defaults.step.epsilon, 0.05);
    EXPECT_EQ(defaults.samplesPerPixel, 2.0);
    EXPECT_EQ(defaults.step.maxEvaluations, 200);
}

TEST(CurvesPlane, RejectsRepeatAndEyeBelowTheBase) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("sine", 32, 32));
    auto repeat = std::make_shared<const Surface>(hf, 3.0f, EdgeMode::Repeat);
    EXPECT_FALSE(renderAndMeasure(planeScene(repeat, 40.0f), withEpsilon(0.1)).ok());
    auto clamp = std::make_shared<const Surface>(hf, 3.0f, EdgeMode::Clamp);
    EXPECT_FALSE(renderAndMeasure(planeScene(clamp, -20.0f), withEpsilon(0.1)).ok());
}

TEST(CurvesSphereMapping, RoundTripsFrontAndBack) {
    const ViewFrame view = ViewFrame::orbit(orbit(25.0f, 40.0f, 2.0f), dvec3(3.0, -2.0, 1.0), 60.0, 200, 150);
    const SphereMapping m(view, dvec3(3.0, -2.0, 1.0), 20.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 300; ++k) {
        const double thetaMax = std::acos(m.beta());  // visible cap
        const SpherePoint p{0.98 * thetaMax * u(rng), 2.0 * std::numbers::pi * (u(rng) - 0.5)};
        const dvec2 uv = m.toView(p);
        EXPECT_NEAR(glm::length(uv - view.project(m.worldPoint(p))), 0.0, 1e-6);
        const auto front = m.toSphere(uv, true);
        ASSERT_TRUE(front.has_value());
        EXPECT_NEAR(front->theta, p.theta, 1e-7);
        if (p.theta > 1e-3) {
            EXPECT_NEAR(std::remainder(front->phi - p.phi, 2 * std::numbers::pi), 0.0, 1e-7);
        }
        // The back-facing intersection of the same eye ray projects to the same pixel.
        const auto back = m.toSphere(uv, false);
        ASSERT_TRUE(back.has_value());
        EXPECT_GT(back->theta, front->theta - 1e-12);
        EXPECT_NEAR(glm::length(view.project(m.worldPoint(*back)) - uv), 0.0, 1e-6);
        // The paper's θ formula equals the law-of-sines form used in the stepping.
        const double delta = std::acos(glm::dot(glm::normalize(view.direction(uv)),
                                                glm::normalize(dvec3(3.0, -2.0, 1.0) - view.eye)));
        const double b = std::tan(delta) * std::tan(delta);
        EXPECT_NEAR(*SphereMapping::thetaFromB(b, m.beta(), true),
                    std::asin(std::sin(delta) / m.beta()) - delta, 1e-7);
    }
}

TEST(CurvesSphere, CloseToTheReference) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield("sine", 64, 32, 1));
    CurvesScene r;
    r.surface = std::make_shared<const Surface>(hf, 2.0f, EdgeMode::Clamp);
    r.sphere = makeSphere(*r.surface, 12.0);
    r.view = orbit(20.0f, 10.0f, 2.0f);
    r.width = 96;
    r.height = 72;
    auto run = renderAndMeasure(r, withEpsilon(0.001));
    ASSERT_TRUE(run.ok()) << run.error().message;
    std::printf("[ curves   ] sphere: %zu samples, mean |dt| %.2e, wrong %.3f%%\n",
                run->stats.pixels, run->stats.error.mean, 100.0 * run->stats.wrongRate());
    EXPECT_GT(run->stats.hits, 1000u);
    EXPECT_LT(run->stats.error.mean, 0.02);
    // Wrong samples: silhouette rays whose hit lies past their closest approach to the centre,
    // where the stepping ends the curve (depth D/R = 1/6 here makes that band wide).
    EXPECT_LT(run->stats.wrongRate(), 0.015);
}

}  // namespace
}  // namespace relief::curves
