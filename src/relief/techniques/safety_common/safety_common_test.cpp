// Map invariants of the safety shapes against brute force on small maps: dense ray sampling from
// the texel's centerline segment (incl. rays aimed just under vertices: the limit rays), exact
// crossing counts along each ray, and the N-buffer cone slope against reading vertices one by one.
#include <support/safety_test_support.h>

#include <relief/techniques/safety_common/safety_maps.h>

namespace relief::safety {
namespace {

using testing::makeSurface;
using testing::transitions;

struct InvariantCase {
    const char* generator;
    int width, height;
    EdgeMode edge;
    float depthRatio;
};

const InvariantCase kInvariantCases[] = {
    {"fig11", 16, 16, EdgeMode::Clamp, 0.5f},  {"fig11", 16, 16, EdgeMode::Repeat, 0.5f},
    {"walls", 16, 12, EdgeMode::Clamp, 0.25f}, {"spikes", 14, 14, EdgeMode::Repeat, 0.5f},
    {"fbm", 16, 16, EdgeMode::Clamp, 0.25f},   {"sine", 12, 12, EdgeMode::Repeat, 0.25f},
    {"terraces", 16, 16, EdgeMode::Clamp, 0.25f},
};

// Local class direction (1, m) and rise per centerline → world direction.
dvec3 worldDirection(int cls, double m, double rise) {
    switch (cls) {
        case kXPlus: return {1.0, m, rise};
        case kXMinus: return {-1.0, m, rise};
        case kYPlus: return {m, 1.0, rise};
        default: return {m, -1.0, rise};
    }
}

struct Sampler {
    const Surface& s;
    std::mt19937 rng{5};
    double uniform(double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng); }
};

// Rays of class `cls` through points strictly above S on s_τ of texel (i, j), with slopes
// allowed by tanPhi; `within(origin, dir)` returns the number of centerlines the shape
// promises (t ∈ [0, n], t in centerlines). Counts rays that cross S twice inside it.
template <class Within>
size_t violationsAt(const Surface& s, int cls, int i, int j, double tanPhi, Within within,
                    size_t& rays, std::mt19937& rng) {
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<>(lo, hi)(rng); };
    const Frame f{cls};
    const SegmentHeights seg = segmentHeights(s, f, i, j);
    const double D = std::max(1.0, double(s.depth()));
    size_t bad = 0;
    auto tryRay = [&](double b, double lift, double m, double rise) {
        if (std::abs(m) > 1.0) return;
        if (std::isfinite(tanPhi) && rise > tanPhi * std::sqrt(1.0 + m * m) - 1e-6) return;
        double X, Y;
        f.world(seg.a0, b, X, Y);
        const dvec3 o(X + 0.5, Y + 0.5, seg.at(b) + lift);
        const dvec3 d = worldDirection(cls, m, rise);
        const double n = within(vec3(o), vec3(glm::normalize(d)), rise);
        ++rays;
        if (transitions(s, o, d, n, 1e-6 * D) > 1) ++bad;
    };
    const double bs[] = {seg.b0 - 0.5, seg.b0 - 0.2, double(seg.b0), seg.b0 + 0.3, seg.b0 + 0.5};
    const double lifts[] = {1e-4, 1e-2, 0.2, 1.0, 0.5 * D};
    const double ms[] = {-1.0, -0.5, 0.0, 0.4, 1.0};
    const double rises[] = {-3.0 * D, -D, -2.0, -0.5, -0.1, -0.01, 0.0, 0.02, 0.3, 1.5, D};
    for (double b : bs)
        for (double lift : lifts)
            for (double m : ms)
                for (double rise : rises) tryRay(b, lift, m, rise);
    // Limit rays: from a random point of s_τ just above S to just under a vertex ahead.
    for (int k = 0; k < 300; ++k) {
        const double b = uniform(seg.b0 - 0.5, seg.b0 + 0.5);
        const double lift = k % 2 ? 1e-3 : uniform(0.0, 0.3 * D);
        const int da = 1 + int(uniform(0.0, 12.0)), db = int(std::floor(uniform(-da - 1.0, da + 1.0)));
        double X, Y;
        f.world(seg.a0 + da, seg.b0 + db, X, Y);
        const double vz = s.sampleZ(int(X), int(Y));
        const double m = (seg.b0 + db - b) / double(da);
        const double rise = (vz - (k % 3 ? 1e-3 : 0.05) - seg.at(b) - lift) / double(da);
        tryRay(b, lift, m, rise);
    }
    return bad;
}

double rayLimit(const Surface& s) { return 3.0 * double(std::max(s.width(), s.height())); }

void checkDistanceInvariant(double phiMaxDeg) {
    size_t rays = 0, bad = 0, texels = 0, tight = 0;
    std::mt19937 rng(11);
    for (const InvariantCase& c : kInvariantCases) {
        auto s = makeSurface(c.generator, c.width, c.height, c.edge, c.depthRatio);
        BuildOptions o;
        o.phiMaxDeg = phiMaxDeg;
        const DistanceMap map = buildDistanceMap(*s, o);
        const double tanPhi = tanPhiMax(phiMaxDeg);
        for (int cls = 0; cls < kClassCount; ++cls)
            for (int j = 0; j < s->height(); ++j)
                for (int i = 0; i < s->width(); ++i) {
                    const int r = map.at(cls, i, j);
                    EXPECT_EQ(r, safetyDistanceDirect(*s, cls, i, j, tanPhi, kMaxDistance))
                        << c.generator << " texel " << i << "," << j << " class " << cls;
                    const double n = std::min(double(r), rayLimit(*s));
                    const size_t v = violationsAt(*s, cls, i, j, tanPhi,
                                                  [&](vec3, vec3, double) { return n; }, rays, rng);
                    if (v) ADD_FAILURE() << c.generator << " " << toString(c.edge) << " texel " << i
                                         << "," << j << " class " << cls << " r " << r << ": " << v
                                         << " rays cross S twice";
                    bad += v;
                    ++texels;
                    if (r < kMaxDistance && r + 1.0 <= rayLimit(*s)) {  // the scan is tight
                        size_t unused = 0;
                        tight += violationsAt(*s, cls, i, j, tanPhi,
                                              [&](vec3, vec3, double) { return r + 1.0; }, unused,
                                              rng) > 0;
                    }
                }
    }
    std::printf("[ safety   ] SD with r + 1: %zu of %zu texel-classes show a double crossing\n",
                tight, texels);
    EXPECT_GT(tight, texels / 10);
    std::printf("[ safety   ] SD invariant (phi-max %g): %zu texel-classes, %zu rays, %zu "
                "crossing S twice within r\n", phiMaxDeg, texels, rays, bad);
    EXPECT_EQ(bad, 0u);
}

TEST(SafetyMaps, DistanceInvariantAllRays) { checkDistanceInvariant(90.0); }
TEST(SafetyMaps, DistanceInvariantPhiMax) {
    checkDistanceInvariant(-45.0);
    checkDistanceInvariant(30.0);
}

TEST(SafetyMaps, RestrictionOnlyLengthensDistances) {
    auto s = makeSurface("fbm", 32, 32, EdgeMode::Clamp, 0.25f);
    BuildOptions all, restricted, iso;
    restricted.phiMaxDeg = -45.0;
    iso.isotropic = true;
    const DistanceMap a = buildDistanceMap(*s, all), b = buildDistanceMap(*s, restricted);
    const DistanceMap m = buildDistanceMap(*s, iso);
    double sumA = 0, sumB = 0;
    for (int c = 0; c < kClassCount; ++c)
        for (int j = 0; j < 32; ++j)
            for (int i = 0; i < 32; ++i) {
                EXPECT_LE(a.at(c, i, j), b.at(c, i, j));
                EXPECT_LE(m.at(0, i, j), a.at(c, i, j));
                sumA += a.at(c, i, j), sumB += b.at(c, i, j);
            }
    std::printf("[ safety   ] mean r fbm 32x32: all rays %.2f, phi-max -45 %.2f\n",
                sumA / (4 * 1024), sumB / (4 * 1024));
    EXPECT_GT(sumB, sumA);
}

void checkConeInvariant(bool isotropic, double phiMaxDeg) {
    size_t rays = 0, bad = 0;
    std::mt19937 rng(13);
    for (const InvariantCase& c : kInvariantCases) {
        auto s = makeSurface(c.generator, c.width, c.height, c.edge, c.depthRatio);
        BuildOptions o;
        o.isotropic = isotropic;
        o.phiMaxDeg = phiMaxDeg;
        const CylinderConeMap map = buildConeMap(*s, buildDistanceMap(*s, o), o);
        const ConeShape shape(std::make_shared<const CylinderConeMap>(map));
        const double tanPhi = tanPhiMax(phiMaxDeg);
        for (int cls = 0; cls < kClassCount; ++cls)
            for (int j = 0; j < s->height(); ++j)
                for (int i = 0; i < s->width(); ++i) {
                    auto within = [&](vec3 o3, vec3, double rise) {
                        const int n = shape.step(cls, i, j, o3.z, float(rise));
                        return std::min(double(n), rayLimit(*s));
                    };
                    const size_t v = violationsAt(*s, cls, i, j, tanPhi, within, rays, rng);
                    if (v) ADD_FAILURE() << c.generator << " " << toString(c.edge) << " texel "
                                         << i << "," << j << " class " << cls << ": " << v
                                         << " rays cross S twice inside the cylinder-cone";
                    bad += v;
                }
    }
    std::printf("[ safety   ] CC invariant (isotropic %d, phi-max %g): %zu rays, %zu crossing S "
                "twice within the shape\n", int(isotropic), phiMaxDeg, rays, bad);
    EXPECT_EQ(bad, 0u);
}

TEST(SafetyMaps, ConeInvariant) { checkConeInvariant(false, 90.0); }
TEST(SafetyMaps, ConeInvariantIsotropicAndPhiMax) {
    checkConeInvariant(true, 90.0);
    checkConeInvariant(false, -45.0);
}

// The N-buffer slope equals the slope from every reachable vertex read one by one (up to the
// plane's rounding margin), and is never below the paper's exact slope (limiting triangles only).
TEST(SafetyMaps, ConeSlopeMatchesDirectScan) {
    size_t texels = 0, equal = 0, tighter = 0;
    for (const InvariantCase& c : kInvariantCases) {
        auto s = makeSurface(c.generator, c.width, c.height, c.edge, c.depthRatio);
        const BuildOptions o;
        const CylinderConeMap map = buildConeMap(*s, buildDistanceMap(*s, o), o);
        const float slack = 1e-6f * (1.0f + s->maxZ());
        for (int cls = 0; cls < kClassCount; ++cls)
            for (int j = 0; j < s->height(); ++j)
                for (int i = 0; i < s->width(); ++i) {
                    const ConeTexel& t = map.at(cls, i, j);
                    const float zc = t.zc - slack;
                    const float all = coneSlopeDirect(*s, cls, i, j, t.r, zc, kInfinity, false);
                    const float lim = coneSlopeDirect(*s, cls, i, j, t.r, zc, kInfinity, true);
                    const float tol = 1e-4f * (1.0f + std::abs(all));
                    EXPECT_GE(t.slope + tol, all) << c.generator << " " << i << "," << j;
                    EXPECT_LE(lim, all + tol);
                    ++texels;
                    equal += std::abs(t.slope - all) <= tol;
                    tighter += lim < all - tol;
                }
    }
    std::printf("[ safety   ] cone slopes: %zu texel-classes, N-buffer = direct scan on %zu, "
                "limiting-only slope lower on %zu\n", texels, equal, tighter);
    EXPECT_GT(equal, texels * 9 / 10);
}

}  // namespace
}  // namespace relief::safety
