#include <relief/techniques/safety_common/safety_sampled.h>

#include <relief/core/parallel.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace relief::safety {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// One sampled ray from s_τ: the first column (centerlines from τ) where it leaves S after
// entering it, if below `limit`; else `limit`. Walks the cells along the ray: in a cell S is
// the max of two planes, so ray − S is concave there and its sign pattern is decided at the
// segment's ends and at the kink of the two planes.
int exitColumn(const Surface& s, const Frame& f, int a0, const Ray& ray, int limit, float minZ) {
    const RayInterval span = s.clip(ray);
    if (span.empty()) return limit;
    const vec3& o = ray.origin;
    const vec3& d = ray.direction;
    float t = std::max(span.tEnter, 0.0f);
    const vec3 start = ray.at(t);
    int ci = s.cellOfX(start.x), cj = s.cellOfY(start.y);
    const int stepX = d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0);
    const int stepY = d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0);
    bool below = false;
    while (t < span.tExit) {
        const float tx = stepX == 0 ? kInfinity : (float(ci) + (stepX > 0 ? 1.5f : 0.5f) - o.x) / d.x;
        const float ty = stepY == 0 ? kInfinity : (float(cj) + (stepY > 0 ? 1.5f : 0.5f) - o.y) / d.y;
        const float tc = std::max(t, std::min({tx, ty, span.tExit}));
        // The column of this cell: local a of the segment's midpoint.
        const vec3 mid = ray.at(0.5f * (t + tc));
        double a, b;
        f.local(double(mid.x) - 0.5, double(mid.y) - 0.5, a, b);
        const int column = int(std::floor(a - double(a0)));
        if (column >= limit) return limit;
        const CellPlanes planes = s.cellPlanes(ci, cj);
        const float u0 = float(ci) + 0.5f, v0 = float(cj) + 0.5f;
        auto gap = [&](const CellPlane& p, float tt) {
            const vec3 q = ray.at(tt);
            return double(q.z) - double(p.at(q.x - u0, q.y - v0));
        };
        // ray − P1 and ray − P2 are linear in t; S's kink is where they are equal.
        const double g1a = gap(planes.first, t), g1b = gap(planes.first, tc);
        const double g2a = gap(planes.second, t), g2b = gap(planes.second, tc);
        double samples[3] = {std::min(g1a, g2a), 0.0, std::min(g1b, g2b)};
        int count = 1;
        const double da = g1a - g2a, db = g1b - g2b;
        if ((da < 0.0) != (db < 0.0) && da != db) {
            const double w = da / (da - db);
            samples[count++] = g1a + w * (g1b - g1a);
        }
        samples[count++] = samples[2];
        for (int k = 0; k < count; ++k) {
            if (samples[k] <= 0.0) below = true;
            else if (below) return column;
        }
        if (tc >= span.tExit) break;
        // Below S and under the lowest sample while not rising: it never comes out.
        if (below && d.z <= 0.0f && ray.at(tc).z < minZ) break;
        if (tx <= ty) ci += stepX;
        if (ty <= tx) cj += stepY;
        t = tc;
    }
    return limit;
}

int sampledTexel(const Surface& s, int cls, int i, int j, double phiMaxDeg, int maxDistance,
                 const SamplingOptions& sampling, float margin, float minZ) {
    const Frame f{cls};
    const SegmentHeights seg = segmentHeights(s, f, i, j);
    const double top = std::min(phiMaxDeg, 90.0);
    int best = maxDistance;
    // Steepest descents first: they meet nearby relief, and a low bound shortens later walks.
    for (int e = 0; e < sampling.elevations; ++e) {
        const double phi = (-90.0 + (e + 0.5) * (top + 90.0) / sampling.elevations) * kDegree;
        for (int q = 0; q < sampling.azimuths; ++q) {
            const double theta = (-45.0 + (q + 0.5) * 90.0 / sampling.azimuths) * kDegree;
            double dX, dY, oX, oY;
            f.world(std::cos(theta), std::sin(theta), dX, dY);  // linear: a direction maps as is
            for (int p = 0; p < sampling.positions; ++p) {
                const double b = seg.b0 - 0.5 + (p + 0.5) / sampling.positions;
                f.world(seg.a0, b, oX, oY);
                Ray ray;
                ray.origin = vec3(float(oX + 0.5), float(oY + 0.5), float(seg.at(b)) + margin);
                ray.direction = vec3(float(dX), float(dY), float(std::tan(phi)));
                best = std::min(best, exitColumn(s, f, seg.a0, ray, best, minZ));
                if (best == 0) return 0;
            }
        }
    }
    return best;
}

}  // namespace

DistanceMap buildSampledDistanceMap(const Surface& s, const BuildOptions& options,
                                    const SamplingOptions& sampling) {
    const int w = s.width(), h = s.height();
    int maxDistance = std::clamp(options.maxDistance, 1, 65535);
    if (s.edge() == EdgeMode::Repeat) maxDistance = std::min(maxDistance, std::max(w, h));
    // As the march's classification margin: a start this far above S counts as above.
    const float margin = 1e-4f * (1.0f + s.maxZ());
    float minZ = s.maxZ();
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) minZ = std::min(minZ, s.sampleZ(i, j));
    DistanceMap map{w, h, kClassCount, {}};
    map.r.resize(size_t(kClassCount) * size_t(w) * size_t(h));
    parallelRanges(int64_t(kClassCount) * h, 1, [&](int64_t begin, int64_t end) {
        for (int64_t row = begin; row < end; ++row) {
            const int cls = int(row / h), j = int(row % h);
            for (int i = 0; i < w; ++i)
                map.r[size_t(row) * size_t(w) + size_t(i)] = uint16_t(sampledTexel(
                    s, cls, i, j, options.phiMaxDeg, maxDistance, sampling, margin, minZ));
        }
    });
    if (!options.isotropic) return map;
    return isotropicMinimum(map);
}

bool sampledPrecompute(const ParamValues& params) {
    return params.has("precompute") && params.getInt("precompute") != 0;
}

DistanceMap buildDistanceMapFor(const Surface& surface, const BuildOptions& options, bool sampled) {
    return sampled ? buildSampledDistanceMap(surface, options) : buildDistanceMap(surface, options);
}

std::shared_ptr<const DistanceMap> sharedDistanceMap(const TechniqueInput& input,
                                                     const BuildOptions& options, bool sampled,
                                                     const std::string& row) {
    auto build = [&] { return buildDistanceMapFor(*input.surface, options, sampled); };
    if (!input.share) return std::make_shared<const DistanceMap>(build());
    // Everything the distances depend on besides the surface (one share per surface).
    const std::string key = fmt::format("safety-distances phi-max={} isotropic={} max-distance={} "
                                        "exterior={} sampled={}",
                                        options.phiMaxDeg, options.isotropic, options.maxDistance,
                                        options.exterior, sampled);
    return input.share->get<DistanceMap>(key, "safety distances", row, build);
}

Status checkSampledPrecompute(const ParamValues& params, const TechniqueMaps* maps) {
    const bool sampled = sampledPrecompute(params);
    if (sampled && params.getInt("exterior") != 0)
        return makeError(ErrorKind::Unsupported,
                         "precompute=1 (sampled) builds all-ray or phi-max maps only, not exterior=1");
    if (!maps) return {};
    const auto it = maps->parameters.find("precompute");
    const bool bakedSampled = it != maps->parameters.end() && it->second != "0";
    if (bakedSampled != sampled)
        return makeError(ErrorKind::InvalidInput,
                         "{} maps were baked with precompute={}; asked for precompute={}",
                         maps->technique, bakedSampled ? 1 : 0, sampled ? 1 : 0);
    return {};
}

void recordPrecompute(TechniqueMaps& maps, bool sampled) {
    if (sampled) maps.parameters["precompute"] = "1";
}

}  // namespace relief::safety
