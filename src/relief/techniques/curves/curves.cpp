#include <relief/techniques/curves/curves.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace relief::curves {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Curve {
    const Surface* surface;
    double ox, oy, dx, dy;
    double sLead, sTrail;
    bool leadIsWall;
    double height(double s) const {
        return double(surface->heightAt(float(ox + s * dx), float(oy + s * dy)));
    }
};

struct EyeRay {
    double eyeZ, k;
    double level(double s) const { return eyeZ - k * s; }
    double stepTo(double z) const { return k > 0.0 ? (eyeZ - z) / k : kNaN; }
    double lowest() const { return kNaN; }
    double ground() const { return k > 0.0 ? eyeZ / k : kNaN; }
};

// The part s ≥ 0 of the ray's horizontal line inside the region (clamp) or the repeat travel.
bool region(const Surface& s, const Ray& ray, double dx, double dy, double& s0, double& s1) {
    s0 = 0.0;
    s1 = double(Surface::kRepeatTravelFactor) * std::max(s.width(), s.height());
    if (s.edge() == EdgeMode::Repeat) return true;
    const double o[] = {ray.origin.x, ray.origin.y}, d[] = {dx, dy};
    const double hi[] = {double(s.width()), double(s.height())};
    s1 = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 2; ++a) {
        if (std::abs(d[a]) < 1e-15) {
            if (o[a] < 0.0 || o[a] > hi[a]) return false;
            continue;
        }
        double t0 = -o[a] / d[a], t1 = (hi[a] - o[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        s0 = std::max(s0, t0);
        s1 = std::min(s1, t1);
    }
    return s0 < s1;
}

Hit hitAt(const Ray& ray, double t, int evaluations) {
    Hit h;
    h.hit = true;
    h.t = float(t);
    h.position = ray.at(h.t);
    h.steps = evaluations;
    h.fetches = 4 * evaluations;
    return h;
}

}  // namespace

Hit CurvesTracer::trace(const Ray& ray) const {
    const Surface& s = *m_surface;
    if (s.clip(ray).empty()) return Hit{};  // misses the box, or not a ray (NaN, inf, zero)
    const vec3 d = glm::normalize(ray.direction);
    const double horizontal = std::hypot(double(d.x), double(d.y));
    const double eyeZ = ray.origin.z;
    if (horizontal < 1e-7) {  // the ray is its own CoP: the solution is straight below
        const bool inside = s.edge() == EdgeMode::Repeat ||
                            (ray.origin.x >= 0 && ray.origin.y >= 0 && ray.origin.x <= s.width() &&
                             ray.origin.y <= s.height());
        const double z = inside ? double(s.heightAt(ray.origin.x, ray.origin.y)) : 0.0;
        if (d.z >= 0.0f || !inside || eyeZ < z) return Hit{};
        return hitAt(ray, (eyeZ - z) / -double(d.z), 1);
    }
    const double dx = d.x / horizontal, dy = d.y / horizontal;
    double s0, s1;
    if (!region(s, ray, dx, dy, s0, s1)) return Hit{};
    const Curve curve{&s, ray.origin.x, ray.origin.y, dx, dy, s0, s1, s0 > 0.0};
    const double kTarget = -double(d.z) / horizontal;
    // Eye rays by their angle below the horizontal, from the first ray of the curve to the target.
    const double start = s0 > 0.0 ? std::atan2(eyeZ, s0) : 0.5 * std::numbers::pi;
    const double target = std::atan(kTarget);
    const int count = std::max(0, int(std::ceil((start - target) / m_angleStep)));
    CurveState state = startCurve(curve);
    StepCounts counts;
    EyeRay previous{eyeZ, s0 > 0.0 ? std::tan(start) : std::numeric_limits<double>::infinity()};
    SampleSolution sol;
    int evaluations = 0;
    for (int j = 1; j <= std::max(count, 1); ++j) {
        const double angle = start - (start - target) * double(j) / double(std::max(count, 1));
        const EyeRay eye{eyeZ, j >= count ? kTarget : std::tan(angle)};
        double spacing = std::abs(eye.ground() - previous.ground());
        if (!std::isfinite(spacing)) spacing = m_angleStep;
        sol = solveSample(curve, eye, spacing, m_params, state, counts);
        evaluations += sol.evaluations;
        if (sol.outcome == SampleOutcome::CurveEnd) break;  // this ray and all flatter ones miss
        previous = eye;
    }
    if (sol.outcome != SampleOutcome::Hit && sol.outcome != SampleOutcome::Wall) {
        Hit miss;
        miss.steps = evaluations;
        miss.fetches = 4 * evaluations;
        return miss;
    }
    return hitAt(ray, sol.s / horizontal, evaluations);
}

}  // namespace relief::curves

namespace relief {

Result<std::unique_ptr<Tracer>> createCurves(const TechniqueInput& input) {
    // Samples per pixel are the image renderer's (relief render); refused rather than ignored.
    for (const ParamSpec& spec : kCurvesParams)
        if (spec.role == ParamRole::ImageSampling && input.params.get(spec.name) != spec.defaultValue)
            return makeError(ErrorKind::BadArgument,
                             "curves: parameter '{}' is the image renderer's (relief render); the "
                             "per-ray tracer does not read it", spec.name);
    curves::StepParams params;
    params.epsilon = input.params.get("epsilon");
    params.maxEvaluations = input.params.getInt("max-steps");
    return makeBatchTracer(
        curves::CurvesTracer(input.surface, input.params.get("angle-step"), params));
}

}  // namespace relief
