#include <relief/render/renderer.h>

#include <relief/core/parallel.h>
#include <relief/core/progress.h>

#include <chrono>

namespace relief {

namespace {

vec3 sampleTexture(const ImageRgb8& image, const Surface& s, const vec3& p) {
    const int x = std::clamp(int(p.x / float(s.width()) * float(image.width)), 0, image.width - 1);
    const int y = std::clamp(int(p.y / float(s.height()) * float(image.height)), 0, image.height - 1);
    return vec3(image.at(x, y)) / 255.0f;
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

namespace {

class Shader {
public:
    Shader(const Surface& s, const Shading& shading) : m_surface(s), m_shading(shading) {}

    vec3 normal(const vec3& p) const {
        return shadeNormal(m_surface, m_shading, p, m_surface.normalAt(p));
    }
    bool facesLight(const vec3& n) const { return glm::dot(n, m_shading.towardsLight) > 0.0f; }
    // Starts just above S along the geometric normal, so the origin really is above the surface
    // the tracer sees even when a normal map bends the shading normal.
    Ray shadowRay(const vec3& p) const {
        const float offset = 1e-3f * std::max(1.0f, m_surface.depth());
        return Ray{p + offset * m_surface.normalAt(p) + offset * vec3(0, 0, 1),
                   m_shading.towardsLight, kInfinity};
    }
    Rgb8 colour(const Hit& hit, const vec3& n, bool shadowed) const {
        if (!hit.hit) return toRgb8(m_shading.background);
        return toRgb8(shadeLambert(m_shading, shadeAlbedo(m_surface, m_shading, hit.position), n,
                                   !shadowed));
    }

private:
    const Surface& m_surface;
    const Shading& m_shading;
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

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading) {
    RenderResult result;
    const auto start = std::chrono::steady_clock::now();
    result.hits = tracePrimary(camera, tracer);
    const Shader shader(surface, shading);
    const size_t n = result.hits.pixels.size();
    std::vector<vec3> normals(n);
    std::vector<uint8_t> shadowed(n, 0);
    std::vector<Ray> shadowRays;
    std::vector<size_t> shadowPixels;
    for (size_t k = 0; k < n; ++k) {
        const Hit& hit = result.hits.pixels[k];
        if (!hit.hit) continue;
        normals[k] = shader.normal(hit.position);
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
            result.color.pixels[k] = shader.colour(result.hits.pixels[k], normals[k], shadowed[k]);
    });
    result.seconds = secondsSince(start);
    return result;
}

}  // namespace relief
