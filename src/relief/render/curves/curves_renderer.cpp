#include <relief/render/curves/curves_renderer.h>

#include <relief/core/parallel.h>
#include <relief/render/curves/plane_mapping.h>
#include <relief/render/curves/sampling.h>
#include <relief/render/curves/sphere_mapping.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace relief::curves {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Extra samples past the trailing edge per line, at most (the curve normally ends long before).
constexpr int kMaxExtraSamples = 1 << 16;

// ==== plane ====================================================================================

struct PlaneCurve {
    const Surface* surface;
    dvec2 origin, dir;  // CoP_s and the line's direction on the base plane
    double sLead, sTrail;
    bool leadIsWall;
    double height(double s) const {
        return double(surface->heightAt(float(origin.x + s * dir.x), float(origin.y + s * dir.y)));
    }
};

// An eye ray of a vertical cutting plane: its height above the base at horizontal distance s
// from CoP_s is eyeZ − k·s.
struct PlaneRay {
    double eyeZ, k, horizontal;
    double level(double s) const { return eyeZ - k * s; }
    double stepTo(double z) const { return k > 0.0 ? (eyeZ - z) / k : kNaN; }
    double lowest() const { return kNaN; }
    // Where it meets the plane z = zRef (NaN if it does not descend).
    double at(double zRef) const { return k > 0.0 ? (eyeZ - zRef) / k : kNaN; }
    double tOf(double s) const { return s / horizontal; }
};

class PlaneScene {
public:
    using Curve = PlaneCurve;
    using EyeRay = PlaneRay;
    struct Line {
        PlaneCurve curve;
        dvec2 unit;
        double rLead, rTrail;
    };

    PlaneScene(const Surface& surface, const ViewFrame& view, const Shading& shading)
        : m_surface(surface), m_view(view), m_shading(shading), m_mapping(view) {}

    Status prepare();
    dvec2 cop() const { return m_mapping.copView(); }
    double angleStart() const { return m_angle0; }
    double angleEnd() const { return m_angle1; }
    double farthest() const { return m_farthest; }
    std::optional<Line> line(double angle) const;

    PlaneRay eyeRay(const Line&, const dvec3& d) const {
        const double h = std::hypot(d.x, d.y);
        return {m_view.eye.z, -d.z / h, h};
    }
    PlaneRay leadRay(const Line& line) const {
        const double k = line.curve.sLead > 0.0 ? m_view.eye.z / line.curve.sLead
                                                : std::numeric_limits<double>::infinity();
        return {m_view.eye.z, k, 0.0};
    }
    double spacing(const PlaneRay& a, const PlaneRay& b) const {
        const double ground = std::abs(b.at(0.0) - a.at(0.0));
        return std::isfinite(ground) ? ground : std::abs(b.at(m_surface.maxZ()) - a.at(m_surface.maxZ()));
    }
    vec3 shade(const Line&, const Hit& hit) const {
        const vec3 n = shadeNormal(m_surface, m_shading, hit.position, m_surface.normalAt(hit.position));
        const bool lit = glm::dot(n, m_shading.towardsLight) > 0.0f;
        return shadeLambert(m_shading, shadeAlbedo(m_surface, m_shading, hit.position), n, lit);
    }

private:
    const Surface& m_surface;
    const ViewFrame& m_view;
    const Shading& m_shading;
    PlaneMapping m_mapping;
    double m_angle0 = 0.0, m_angle1 = kTwoPi, m_farthest = 1.0;
};

Status PlaneScene::prepare() {
    if (m_surface.edge() != EdgeMode::Clamp)
        return makeError(ErrorKind::Unsupported,
                         "curves: the plane's mapped region must be finite (--edge clamp)");
    if (!(m_view.eye.z > 0.0))
        return makeError(ErrorKind::Unsupported, "curves: the eye must be above the base plane");
    const double w = m_surface.width(), h = m_surface.height();
    const dvec2 corners[] = {{0, 0}, {w, 0}, {w, h}, {0, h}};
    const dvec2 cop = m_mapping.copView(), copS = m_mapping.copSurface();
    const double centreAngle = [&] {
        const dvec2 c = m_mapping.toView({0.5 * w, 0.5 * h}) - cop;
        return std::atan2(c.y, c.x);
    }();
    double lo = 0.0, hi = 0.0;
    for (const dvec2& c : corners) {
        if (!(m_mapping.weight(c) > 0.0))
            return makeError(ErrorKind::Unsupported,
                             "curves: part of the relief is behind the eye; move the camera back");
        const dvec2 p = m_mapping.toView(c) - cop;
        m_farthest = std::max(m_farthest, glm::length(p));
        const double a = std::remainder(std::atan2(p.y, p.x) - centreAngle, kTwoPi);
        lo = std::min(lo, a);
        hi = std::max(hi, a);
    }
    const bool copInside = copS.x >= 0.0 && copS.x <= w && copS.y >= 0.0 && copS.y <= h;
    if (copInside) {
        m_angle0 = 0.0;
        m_angle1 = kTwoPi;
    } else {
        m_angle0 = centreAngle + lo;
        m_angle1 = centreAngle + hi;
    }
    return {};
}

// The part s ≥ 0 of the line origin + s·dir inside [0,W]×[0,H].
bool clipToRegion(const dvec2& origin, const dvec2& dir, double w, double h, double& s0,
                  double& s1) {
    s0 = 0.0;
    s1 = std::numeric_limits<double>::infinity();
    const double lo[] = {0.0, 0.0}, hi[] = {w, h};
    for (int a = 0; a < 2; ++a) {
        if (std::abs(dir[a]) < 1e-15) {
            if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
            continue;
        }
        double t0 = (lo[a] - origin[a]) / dir[a], t1 = (hi[a] - origin[a]) / dir[a];
        if (t0 > t1) std::swap(t0, t1);
        s0 = std::max(s0, t0);
        s1 = std::min(s1, t1);
    }
    return s0 < s1;
}

std::optional<PlaneScene::Line> PlaneScene::line(double angle) const {
    const dvec2 unit(std::cos(angle), std::sin(angle));
    const dvec2 cop = m_mapping.copView();
    // Every image point of the half-line from CoP_v looks in the same horizontal direction.
    const dvec3 d = m_view.direction(cop + m_farthest * unit);
    const double h = std::hypot(d.x, d.y);
    if (h < 1e-12) return std::nullopt;
    const dvec2 dir(d.x / h, d.y / h), copS = m_mapping.copSurface();
    double s0, s1;
    if (!clipToRegion(copS, dir, m_surface.width(), m_surface.height(), s0, s1))
        return std::nullopt;
    Line line{{&m_surface, copS, dir, s0, s1, s0 > 0.0}, unit, 0.0, 0.0};
    if (s0 > 0.0) line.rLead = glm::length(m_mapping.toView(copS + s0 * dir) - cop);
    line.rTrail = glm::length(m_mapping.toView(copS + s1 * dir) - cop);
    return line;
}

// ==== sphere ===================================================================================

struct SphereCurve {
    const SphereSurface* sphere;
    dvec3 axis, side;  // the great circle: cos θ·axis + sin θ·side
    double sLead = 0.0, sTrail = std::numbers::pi;
    bool leadIsWall = false;
    dvec3 direction(double theta) const {
        return std::cos(theta) * axis + std::sin(theta) * side;
    }
    double height(double theta) const { return sphere->heightAt(direction(theta)); }
};

// An eye ray at angle δ from the direction of the centre: at angle θ from CoP_s (seen from the
// centre) it is ρ·sin δ / sin(δ + θ) from the centre (law of sines).
struct SphereRay {
    double rho, radius, delta, sinDelta;
    double level(double theta) const {
        const double a = delta + theta;
        return a < std::numbers::pi ? rho * sinDelta / std::sin(a) - radius
                                    : std::numeric_limits<double>::infinity();
    }
    // The front intersection with the sphere of radius R + z (the paper's θ formula); NaN where
    // the ray passes above it.
    double stepTo(double z) const { return thetaAtRadius(radius + z); }
    double lowest() const { return 0.5 * std::numbers::pi - delta; }  // closest to the centre
    double thetaAtRadius(double r) const {
        const double x = rho * sinDelta / r;
        return x <= 1.0 ? std::asin(x) - delta : kNaN;
    }
    double tOf(double theta) const {
        return delta > 0.0 ? rho * std::sin(theta) / std::sin(delta + theta) : rho - radius;
    }
};

class SphereScene {
public:
    using Curve = SphereCurve;
    using EyeRay = SphereRay;
    struct Line {
        SphereCurve curve;
        dvec2 unit;
        double rLead, rTrail;
    };

    SphereScene(const SphereSurface& sphere, const ViewFrame& view, const Shading& shading)
        : m_sphere(sphere), m_view(view), m_shading(shading),
          m_mapping(view, dvec3(0.0), sphere.radius()) {}

    Status prepare();
    dvec2 cop() const { return m_mapping.copView(); }
    double angleStart() const { return 0.0; }
    double angleEnd() const { return kTwoPi; }
    double farthest() const { return m_farthest; }
    std::optional<Line> line(double angle) const;

    SphereRay eyeRay(const Line&, const dvec3& d) const {
        const double c = std::clamp(glm::dot(d, m_toCentre), -1.0, 1.0);
        return {m_mapping.rho(), m_sphere.radius(), std::acos(c), std::sqrt(1.0 - c * c)};
    }
    SphereRay leadRay(const Line&) const {
        return {m_mapping.rho(), m_sphere.radius(), 0.0, 0.0};
    }
    double spacing(const SphereRay& a, const SphereRay& b) const {
        for (double r : {m_sphere.radius(), m_sphere.maxRadius()}) {
            const double d = std::abs(b.thetaAtRadius(r) - a.thetaAtRadius(r));
            if (std::isfinite(d)) return d;
        }
        return std::abs(b.delta - a.delta);
    }
    vec3 shade(const Line& line, const Hit& hit) const;

private:
    const SphereSurface& m_sphere;
    const ViewFrame& m_view;
    const Shading& m_shading;
    SphereMapping m_mapping;
    dvec3 m_toCentre{0.0};
    double m_thetaTrail = 0.0, m_farthest = 1.0;
};

Status SphereScene::prepare() {
    const double rho = m_mapping.rho();
    if (!(rho > m_sphere.maxRadius()))
        return makeError(ErrorKind::Unsupported,
                         "curves: the eye must be outside the displaced sphere (distance {} <= {})",
                         rho, m_sphere.maxRadius());
    if (!(rho * std::cos(m_mapping.psi()) > m_sphere.maxRadius()))
        return makeError(ErrorKind::Unsupported,
                         "curves: part of the sphere is behind the eye; move the camera back");
    m_toCentre = glm::normalize(-m_view.eye);
    m_thetaTrail = std::acos(m_mapping.beta());  // the base sphere's silhouette
    for (int k = 0; k < 256; ++k) {
        const double phi = kTwoPi * k / 256.0;
        m_farthest = std::max(m_farthest,
                              glm::length(m_mapping.toView({m_thetaTrail, phi}) - cop()));
    }
    return {};
}

std::optional<SphereScene::Line> SphereScene::line(double angle) const {
    const dvec2 unit(std::cos(angle), std::sin(angle));
    const double phi = m_mapping.longitudeOf(cop() + m_farthest * unit);
    const dvec3 axis = glm::normalize(m_view.eye);
    const dvec3 side = glm::normalize(m_mapping.worldPoint({0.5 * std::numbers::pi, phi}));
    Line line{{&m_sphere, axis, side}, unit, 0.0, 0.0};
    line.rTrail = glm::length(m_mapping.toView({m_thetaTrail, phi}) - cop());
    return line;
}

vec3 SphereScene::shade(const Line&, const Hit& hit) const {
    return shadeSphere(m_sphere, m_shading, hit.position);
}

// ==== one visibility line ======================================================================

struct ShadedSample {
    CurveSample sample;
    vec3 color;
};

template <class Scene>
class LineTracer {
public:
    LineTracer(const Scene& scene, const typename Scene::Line& line, const ViewFrame& view,
               const Shading& shading, const CurvesOptions& options, StepCounts& counts,
               std::vector<ShadedSample>& out)
        : m_scene(scene), m_line(line), m_view(view), m_shading(shading), m_options(options),
          m_counts(counts), m_out(out), m_state(startCurve(line.curve)),
          m_previous(scene.leadRay(line)) {}

    // Solves the sample at distance r from CoP_v.
    void sample(double r, bool inside) {
        const dvec2 exact = m_scene.cop() + r * m_line.unit;
        const vec2 pixel(exact);  // the stored position; the ray is rebuilt from it
        const dvec3 d = glm::normalize(m_view.direction(dvec2(pixel)));
        const typename Scene::EyeRay ray = m_scene.eyeRay(m_line, d);
        ShadedSample s{{pixel, Hit{}, inside}, m_shading.background};
        if (!m_ended) {
            const SampleSolution sol = solveSample(m_line.curve, ray, m_scene.spacing(m_previous, ray),
                                                   m_options.step, m_state, m_counts);
            s.sample.hit.steps = sol.evaluations;
            s.sample.hit.fetches = 4 * sol.evaluations;
            if (sol.outcome == SampleOutcome::CurveEnd) m_ended = true;
            if (sol.outcome == SampleOutcome::Hit || sol.outcome == SampleOutcome::Wall) {
                Hit& h = s.sample.hit;
                h.hit = true;
                h.t = float(ray.tOf(sol.s));
                h.position = vec3(m_view.eye + double(h.t) * d);
                s.color = m_scene.shade(m_line, h);
            }
        }
        m_previous = ray;
        if (pixel.x >= 0.0f && pixel.y >= 0.0f && pixel.x < float(m_view.width) &&
            pixel.y < float(m_view.height))
            m_out.push_back(s);
    }
    bool ended() const { return m_ended; }

private:
    const Scene& m_scene;
    const typename Scene::Line& m_line;
    const ViewFrame& m_view;
    const Shading& m_shading;
    const CurvesOptions& m_options;
    StepCounts& m_counts;
    std::vector<ShadedSample>& m_out;
    CurveState m_state;
    typename Scene::EyeRay m_previous;
    bool m_ended = false;
};

template <class Scene>
void traceLine(const Scene& scene, const typename Scene::Line& line, const ViewFrame& view,
               const Shading& shading, const CurvesOptions& options, uint64_t seed,
               StepCounts& counts, std::vector<ShadedSample>& out) {
    const double n = options.samplesPerPixel;
    const LineRadii radii = insideRadii(n, line.rTrail, line.rLead);
    if (radii.radii.empty()) return;
    ++counts.curves;
    LineJitter jitter(seed);
    LineTracer<Scene> tracer(scene, line, view, shading, options, counts, out);
    const std::vector<double>& r = radii.radii;
    // Inside samples, from the leading edge outwards: sample j lies in [r_{j+1}, r_j].
    for (size_t j = r.size(); j-- > 0;) {
        const double inner = j + 1 < r.size() ? r[j + 1] : std::max(radii.innerEnd, 0.0);
        ++counts.insideSamples;
        tracer.sample(jitter.place(inner, r[j]), true);
    }
    // Extra samples past the trailing edge until a step leaves the mapped region.
    double inner = r[0];
    for (int k = 0; k < kMaxExtraSamples && !tracer.ended(); ++k) {
        const double outer = nextOuterRadius(n, r[0], inner);
        ++counts.extraSamples;
        tracer.sample(jitter.place(inner, outer), false);
        inner = outer;
    }
}

// ==== splatting ================================================================================

void fillEmptyPixels(Image<vec3>& sum, Image<int>& count, Image<Hit>& nearest, int64_t& empty) {
    const Image<int> before = count;
    for (int y = 0; y < sum.height; ++y)
        for (int x = 0; x < sum.width; ++x) {
            if (before.at(x, y) > 0) continue;
            vec3 c(0.0f);
            int used = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= sum.width || ny >= sum.height) continue;
                    if (before.at(nx, ny) == 0) continue;
                    c += sum.at(nx, ny) / float(before.at(nx, ny));
                    if (used++ == 0) nearest.at(x, y) = nearest.at(nx, ny);
                }
            if (used > 0) {  // a hole among sampled pixels (outside the lines: background)
                ++empty;
                sum.at(x, y) = c / float(used);
                count.at(x, y) = -1;  // filled: the sum is already a mean
            }
        }
}

template <class Scene>
CurvesResult renderLines(const Scene& scene, const ViewFrame& view, const Shading& shading,
                         const CurvesOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const double step = lineAngleStep(options.samplesPerPixel, scene.farthest());
    const double span = scene.angleEnd() - scene.angleStart();
    const int64_t lineCount = std::max<int64_t>(1, int64_t(std::ceil(span / step)));
    std::vector<std::vector<ShadedSample>> perLine(static_cast<size_t>(lineCount));
    std::vector<StepCounts> counts(static_cast<size_t>(lineCount));
    parallelRanges(lineCount, 16, [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k) {
            const double angle = scene.angleStart() + (double(k) + 0.5) * span / double(lineCount);
            const auto line = scene.line(angle);
            if (!line) continue;
            traceLine(scene, *line, view, shading, options,
                      options.seed * 0x9E3779B97F4A7C15ull + uint64_t(k), counts[size_t(k)],
                      perLine[size_t(k)]);
        }
    });
    CurvesResult result;
    for (const StepCounts& c : counts) result.counts += c;
    Image<vec3> sum(view.width, view.height, vec3(0.0f));
    Image<int> count(view.width, view.height, 0);
    Image<float> evaluations(view.width, view.height, 0.0f);
    Image<float> nearestDistance(view.width, view.height, kInfinity);
    result.hits = Image<Hit>(view.width, view.height);
    for (const auto& line : perLine)
        for (const ShadedSample& s : line) {
            const int x = int(s.sample.pixel.x), y = int(s.sample.pixel.y);
            sum.at(x, y) += s.color;
            ++count.at(x, y);
            evaluations.at(x, y) += float(s.sample.hit.steps);
            const vec2 centre(float(x) + 0.5f, float(y) + 0.5f);
            const float distance = glm::length(s.sample.pixel - centre);
            if (distance < nearestDistance.at(x, y)) {
                nearestDistance.at(x, y) = distance;
                result.hits.at(x, y) = s.sample.hit;
            }
            if (options.keepSamples) result.samples.push_back(s.sample);
        }
    result.evaluationsPerSample = ImageF(view.width, view.height, std::nanf(""));
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x)
            if (count.at(x, y) > 0)
                result.evaluationsPerSample.at(x, y) = evaluations.at(x, y) / float(count.at(x, y));
    fillEmptyPixels(sum, count, result.hits, result.emptyPixels);
    result.color = ImageRgb8(view.width, view.height);
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x) {
            const int c = count.at(x, y);
            const vec3 mean = c > 0 ? sum.at(x, y) / float(c) : (c < 0 ? sum.at(x, y) : shading.background);
            result.color.at(x, y) = toRgb8(mean);
        }
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace

vec3 shadeSphere(const SphereSurface& sphere, const Shading& shading, const vec3& position) {
    const dvec3 n = glm::normalize(dvec3(position));
    const SphereSurface::Frame frame = sphere.frameAt(n);
    const vec3 texel = sphere.texelPoint(n);
    const vec3 nt = shadeNormal(sphere.grid(), shading, texel, vec3(frame.tangentNormal));
    const vec3 normal = glm::normalize(vec3(frame.tangentToWorld * dvec3(nt)));
    const bool lit = glm::dot(normal, shading.towardsLight) > 0.0f;
    return shadeLambert(shading, shadeAlbedo(sphere.grid(), shading, texel), normal, lit);
}

CurvesResult renderSpherePixels(const SphereSurface& sphere, const ViewFrame& view,
                                const Tracer& tracer, const Shading& shading) {
    const auto start = std::chrono::steady_clock::now();
    CurvesResult result;
    result.color = ImageRgb8(view.width, view.height);
    result.hits = Image<Hit>(view.width, view.height);
    result.evaluationsPerSample = ImageF(view.width, view.height);
    parallelRanges(view.height, 1, [&](int64_t begin, int64_t end) {
        std::vector<Ray> rays(size_t(view.width));
        for (int64_t y = begin; y < end; ++y) {
            for (int x = 0; x < view.width; ++x)
                rays[size_t(x)] = view.ray(dvec2(x + 0.5, double(y) + 0.5));
            const std::span<Hit> row(&result.hits.at(0, int(y)), size_t(view.width));
            tracer.traceBatch(rays, row);
            for (int x = 0; x < view.width; ++x) {
                const Hit& h = row[size_t(x)];
                result.evaluationsPerSample.at(x, int(y)) = float(h.steps);
                result.color.at(x, int(y)) =
                    toRgb8(h.hit ? shadeSphere(sphere, shading, h.position) : shading.background);
            }
        }
    });
    result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x)
            result.samples.push_back({vec2(float(x) + 0.5f, float(y) + 0.5f), result.hits.at(x, y)});
    return result;
}

Result<CurvesResult> renderCurvesPlane(const Surface& surface, const ViewFrame& view,
                                       const Shading& shading, const CurvesOptions& options) {
    PlaneScene scene(surface, view, shading);
    if (Status s = scene.prepare(); !s) return s.error();
    return renderLines(scene, view, shading, options);
}

Result<CurvesResult> renderCurvesSphere(const SphereSurface& sphere, const ViewFrame& view,
                                        const Shading& shading, const CurvesOptions& options) {
    SphereScene scene(sphere, view, shading);
    if (Status s = scene.prepare(); !s) return s.error();
    return renderLines(scene, view, shading, options);
}

}  // namespace relief::curves
