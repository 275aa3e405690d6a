// The sphere's exact reference (DESIGN §6) against brute-force marching.
#include <relief/core/generators.h>
#include <relief/sphere/sphere_reference.h>

#include <gtest/gtest.h>

#include <random>

namespace relief {
namespace {

std::shared_ptr<const SphereSurface> makeSphere(const char* generator, double radius, double depth) {
    auto hf = std::make_shared<const Heightfield>(*generateHeightfield(generator, 64, 32, 1));
    return std::make_shared<const SphereSurface>(hf, radius, depth);
}

// Brute force: fixed tiny steps along the ray from the enclosing sphere, then bisection.
Hit bruteForceSphere(const SphereSurface& s, const Ray& ray, double step) {
    const dvec3 o(ray.origin), d(ray.direction);
    auto f = [&](double t) {
        const dvec3 p = o + t * d;
        return glm::length(p) - s.radius() - s.heightAt(glm::normalize(p));
    };
    const double far = glm::length(o) + s.maxRadius();
    double prev = 0.0;
    for (double t = 0.0; t < far; t += step) {
        if (f(t) <= 0.0) {
            double lo = prev, hi = t;
            for (int k = 0; k < 60; ++k) (f(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
            Hit h;
            h.hit = true;
            h.t = float(hi);
            return h;
        }
        prev = t;
    }
    return Hit{};
}

TEST(CurvesSphereReference, AgreesWithBruteForceMarching) {
    for (const char* generator : {"sine", "peaks6"}) {
        auto sphere = makeSphere(generator, 12.0, 3.0);
        const SphereReference reference(sphere);
        std::mt19937 rng(11);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        int hits = 0;
        for (int k = 0; k < 40; ++k) {
            const dvec3 o = 40.0 * glm::normalize(dvec3(u(rng), u(rng), u(rng)));
            const dvec3 target = 14.0 * dvec3(u(rng), u(rng), u(rng));
            const Ray ray{vec3(o), vec3(glm::normalize(target - o)), kInfinity};
            const Hit a = reference.trace(ray), b = bruteForceSphere(*sphere, ray, 2e-3);
            ASSERT_EQ(a.hit, b.hit) << generator << " ray " << k;
            if (a.hit) {
                ++hits;
                EXPECT_NEAR(a.t, b.t, 1e-3) << generator << " ray " << k;
            }
        }
        EXPECT_GT(hits, 10);
    }
}

}  // namespace
}  // namespace relief
