#include <relief/render/renderer.h>

#include <relief/core/parallel.h>
#include <relief/core/progress.h>
#include <relief/render/compare.h>
#include <relief/render/texture.h>

#include <chrono>
#include <optional>

namespace relief {

namespace {

// Nearest texel, wrapped in repeat mode (clamped in clamp mode, as the relief is).
vec3 sampleTexture(const ImageRgb8& image, const Surface& s, const vec3& p) {
    const int x = int(std::floor(p.x / float(s.width()) * float(image.width)));
    const int y = int(std::floor(p.y / float(s.height()) * float(image.height)));
    return vec3(image.at(texelIndex(x, image.width, s.edge()), texelIndex(y, image.height, s.edge()))) /
           255.0f;
}

// Height-tinted albedo when no colour map is given: low blue-green to high sand-white.
vec3 heightTint(float fraction) {
    const vec3 low(0.25f, 0.45f, 0.35f), mid(0.62f, 0.55f, 0.38f), high(0.95f, 0.94f, 0.90f);
    fraction = std::clamp(fraction, 0.0f, 1.0f);
    return fraction < 0.6f ? glm::mix(low, mid, fraction / 0.6f)
                           : glm::mix(mid, high, (fraction - 0.6f) / 0.4f);
}

}  // namespace

Rgb8 toRgb8(const vec3& c) { return Rgb8(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

vec3 shadeAlbedo(const Surface& s, const Shading& shading, const vec3& texel) {
    if (shading.color) return sampleTexture(*shading.color, s, texel);
    return heightTint(texel.z / std::max(s.depth(), 1e-6f));
}

vec3 shadeNormal(const Surface& s, const Shading& shading, const vec3& texel,
                 const vec3& geometricNormal) {
    if (!shading.normalMap || geometricNormal.z <= 0.5f) return geometricNormal;
    return glm::normalize(sampleTexture(*shading.normalMap, s, texel) * 2.0f - 1.0f);
}

vec3 shadeLambert(const Shading& shading, const vec3& albedo, const vec3& normal, bool lit) {
    const float lambert = lit ? std::max(0.0f, glm::dot(normal, shading.towardsLight)) : 0.0f;
    return albedo * (shading.ambient + (1.0f - shading.ambient) * lambert);
}

vec3 smoothNormalAt(const Surface& s, const vec3& p) {
    const float fx = p.x - 0.5f, fy = p.y - 0.5f;
    const int i = int(std::floor(fx)), j = int(std::floor(fy));
    const float tx = fx - float(i), ty = fy - float(j);
    auto vertex = [&](int a, int b) {
        return vec3(0.5f * (s.sampleZ(a - 1, b) - s.sampleZ(a + 1, b)),
                    0.5f * (s.sampleZ(a, b - 1) - s.sampleZ(a, b + 1)), 1.0f);
    };
    const vec3 top = glm::mix(vertex(i, j), vertex(i + 1, j), tx);
    const vec3 bottom = glm::mix(vertex(i, j + 1), vertex(i + 1, j + 1), tx);
    return glm::normalize(glm::mix(top, bottom, ty));
}

namespace {

// A shadow ray's start: just above S along the geometric normal (and up), so it really is above
// the surface the tracer sees even when a normal map bends the shading normal.
vec3 liftedOffS(const Surface& surface, const vec3& p) {
    const float offset = 1e-3f * std::max(1.0f, surface.depth());
    return p + offset * surface.normalAt(p) + offset * vec3(0, 0, 1);
}

class Shader {
public:
    Shader(const Surface& s, const Camera& camera, const Shading& shading)
        : m_surface(s), m_camera(camera), m_shading(shading),
          m_preview(shading.model == ShadingModel::Preview),
          m_pixelAngle(2.0f * camera.halfHeight() / float(camera.height())) {
        if (!m_preview) return;
        // Exposure 0: a flat face in full light shows the colour map's own colours.
        const float flat = shading.ambient + (1.0f - shading.ambient) *
                                                 std::max(shading.towardsLight.z, 0.1f);
        m_exposure = std::exp2(shading.exposure) / flat;
        if (shading.color) m_colorMips.emplace(*shading.color, true);
        if (shading.normalMap) m_normalMips.emplace(*shading.normalMap, false);
    }

    // Towards the eye from the hit of pixel k (row-major).
    vec3 toEye(size_t k) const {
        const int x = int(k % size_t(m_camera.width())), y = int(k / size_t(m_camera.width()));
        return -m_camera.primaryRay(float(x) + 0.5f, float(y) + 0.5f).direction;
    }
    // The width in texels of pixel k's footprint on the surface at its hit: the distance times the
    // pixel's angle, foreshortened by the facet's slant (at most 8 times).
    float footprint(const Hit& hit, size_t k) const {
        if (!m_preview) return 0.0f;
        const float facing = std::abs(glm::dot(toEye(k), m_surface.normalAt(hit.position)));
        return hit.t * m_pixelAngle / std::max(facing, 0.125f);
    }

    vec3 normal(const vec3& p, float footprint) const {
        vec3 geometric = m_surface.normalAt(p);
        // Box walls (z = 0) keep their facet normal.
        if (m_shading.smoothNormals && geometric.z > 0.0f) geometric = smoothNormalAt(m_surface, p);
        if (!m_normalMips || geometric.z <= 0.5f)
            return shadeNormal(m_surface, m_shading, p, geometric);
        return glm::normalize(sampleMap(*m_normalMips, *m_shading.normalMap, p, footprint) * 2.0f -
                              1.0f);
    }
    bool facesLight(const vec3& n) const { return glm::dot(n, m_shading.towardsLight) > 0.0f; }
    // Starts just above S along the geometric normal, so the origin really is above the surface
    // the tracer sees even when a normal map bends the shading normal.
    Ray shadowRay(const vec3& p) const { return Ray{liftedOffS(m_surface, p), m_shading.towardsLight, kInfinity}; }
    Rgb8 colour(const Hit& hit, const vec3& n, bool shadowed, size_t k) const {
        if (!hit.hit) return toRgb8(m_shading.background);
        if (!m_preview)
            return toRgb8(shadeLambert(m_shading, shadeAlbedo(m_surface, m_shading, hit.position),
                                       n, !shadowed));
        const vec3 eye = toEye(k);
        // Without a colour map the height tint is read as sRGB, so the preview keeps its palette.
        const vec3 albedo =
            m_colorMips ? sampleMap(*m_colorMips, *m_shading.color, hit.position, footprint(hit, k))
                        : decoded(shadeAlbedo(m_surface, m_shading, hit.position));
        const float lambert = glm::dot(n, m_shading.towardsLight);
        const bool lit = !shadowed && lambert > 0.0f;
        vec3 linear =
            albedo * (m_shading.ambient + (1.0f - m_shading.ambient) * (lit ? lambert : 0.0f));
        if (lit) {
            const vec3 half = glm::normalize(m_shading.towardsLight + eye);
            linear += vec3(m_shading.specular *
                           std::pow(std::max(0.0f, glm::dot(n, half)), m_shading.shininess));
        }
        linear *= m_exposure;
        return Rgb8(encodeSrgb8(linear.x), encodeSrgb8(linear.y), encodeSrgb8(linear.z));
    }

private:
    static vec3 decoded(const vec3& c) {
        return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
    }
    // The map over [0,W]×[0,H] at p, at the level of `footprint` relief texels.
    vec3 sampleMap(const MipTexture& mips, const ImageRgb8& image, const vec3& p,
                   float footprint) const {
        const float sx = float(image.width) / float(m_surface.width());
        const float sy = float(image.height) / float(m_surface.height());
        return mips.sample(p.x * sx, p.y * sy, mipLevel(footprint * std::max(sx, sy)),
                           m_surface.edge());
    }

    const Surface& m_surface;
    const Camera& m_camera;
    const Shading& m_shading;
    bool m_preview;
    float m_pixelAngle;
    float m_exposure = 1.0f;
    std::optional<MipTexture> m_colorMips, m_normalMips;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int64_t renderPeakBytes(int64_t pixels, bool shadows) {
    constexpr int64_t kTracing = sizeof(Ray) + sizeof(Hit);
    constexpr int64_t kShadows = sizeof(Ray) + sizeof(size_t) + sizeof(Hit);
    const int64_t shading = sizeof(Hit) + sizeof(vec3) + sizeof(uint8_t) + sizeof(Rgb8) +
                            (shadows ? kShadows : 0);
    return pixels * std::max(kTracing, shading);
}

Image<Hit> tracePrimary(const Camera& camera, const Tracer& tracer, double* seconds) {
    const std::vector<Ray> rays = primaryRays(camera);
    Image<Hit> hits(camera.width(), camera.height());
    Progress progress("trace", 1);
    const auto start = std::chrono::steady_clock::now();
    traceAll(tracer, rays, hits.pixels);
    if (seconds) *seconds = secondsSince(start);
    return hits;
}

RaysFromTheLight raysFromTheLight(const Surface& surface, std::span<const vec3> points, const vec3& towardsLight) {
    const float top = surface.depth() + 1.0f;  // above the relief's box
    RaysFromTheLight light;
    light.rays.reserve(points.size());
    light.lengths.reserve(points.size());
    for (const vec3& point : points) {
        const vec3 p = liftedOffS(surface, point);
        const float length = towardsLight.z > 0.0f ? std::max(0.0f, (top - p.z) / towardsLight.z) : 0.0f;
        light.rays.push_back(Ray{p + length * towardsLight, -towardsLight,
                                 std::max(0.0f, length - kWrongHitDistance)});
        light.lengths.push_back(length);
    }
    return light;
}

std::vector<uint8_t> litFromHits(const RaysFromTheLight& light, std::span<const Hit> hits) {
    std::vector<uint8_t> lit(light.rays.size());
    for (size_t k = 0; k < lit.size(); ++k)
        lit[k] = !hits[k].hit || hits[k].t >= light.lengths[k] - kWrongHitDistance;
    return lit;
}

std::vector<uint8_t> litFromTheLight(const Surface& surface, std::span<const vec3> points, const Tracer& tracer,
                                     const vec3& towardsLight) {
    const RaysFromTheLight light = raysFromTheLight(surface, points, towardsLight);
    std::vector<Hit> hits(light.rays.size());
    traceAll(tracer, light.rays, hits);
    return litFromHits(light, hits);
}

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading) {
    RenderResult result;
    const auto start = std::chrono::steady_clock::now();
    result.hits = tracePrimary(camera, tracer);
    const Shader shader(surface, camera, shading);
    const size_t n = result.hits.pixels.size();
    std::vector<vec3> normals(n);
    std::vector<uint8_t> shadowed(n, 0);
    std::vector<Ray> shadowRays;
    std::vector<size_t> shadowPixels;
    for (size_t k = 0; k < n; ++k) {
        const Hit& hit = result.hits.pixels[k];
        if (!hit.hit) continue;
        normals[k] = shader.normal(hit.position, shader.footprint(hit, k));
        if (shading.shadows && shader.facesLight(normals[k])) {
            shadowRays.push_back(shader.shadowRay(hit.position));
            shadowPixels.push_back(k);
        }
    }
    std::vector<Hit> shadowHits(shadowRays.size());
    traceAll(tracer, shadowRays, shadowHits);
    for (size_t s = 0; s < shadowHits.size(); ++s) shadowed[shadowPixels[s]] = shadowHits[s].hit;
    result.color = ImageRgb8(camera.width(), camera.height());
    parallelRanges(int64_t(n), 4096, [&](int64_t begin, int64_t end) {
        for (int64_t k = begin; k < end; ++k)
            result.color.pixels[k] = shader.colour(result.hits.pixels[k], normals[k], shadowed[k], size_t(k));
    });
    result.seconds = secondsSince(start);
    return result;
}

}  // namespace relief
