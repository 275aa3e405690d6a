#include <relief/render/renderer.h>

#include <relief/core/parallel.h>
#include <relief/core/progress.h>

#include <chrono>

namespace relief {

namespace {

constexpr int kTile = 16;

struct TileGrid {
    int columns, rows;
    TileGrid(int w, int h) : columns((w + kTile - 1) / kTile), rows((h + kTile - 1) / kTile) {}
    int count() const { return columns * rows; }
};

// Rays of one tile, row-major; fills pixel coordinates alongside.
void tileRays(const Camera& camera, int tile, const TileGrid& grid, std::vector<Ray>& rays,
              std::vector<ivec2>& pixels) {
    rays.clear();
    pixels.clear();
    const int x0 = (tile % grid.columns) * kTile, y0 = (tile / grid.columns) * kTile;
    for (int y = y0; y < std::min(y0 + kTile, camera.height()); ++y)
        for (int x = x0; x < std::min(x0 + kTile, camera.width()); ++x) {
            rays.push_back(camera.primaryRay(float(x) + 0.5f, float(y) + 0.5f));
            pixels.emplace_back(x, y);
        }
}

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

class TileShader {
public:
    TileShader(const Surface& s, const Tracer& tracer, const Shading& shading)
        : m_surface(s), m_tracer(tracer), m_shading(shading) {}

    void shade(std::span<const Hit> hits, std::span<const ivec2> pixels, ImageRgb8& out) {
        std::vector<vec3> normals(hits.size());
        m_shadowRays.clear();
        for (size_t k = 0; k < hits.size(); ++k) {
            if (!hits[k].hit) continue;
            normals[k] = shadingNormal(hits[k].position);
            if (m_shading.shadows && glm::dot(normals[k], m_shading.towardsLight) > 0.0f)
                m_shadowRays.push_back(shadowRay(hits[k].position));
        }
        m_shadowHits.resize(m_shadowRays.size());
        if (!m_shadowRays.empty()) m_tracer.traceBatch(m_shadowRays, m_shadowHits);
        size_t nextShadow = 0;
        for (size_t k = 0; k < hits.size(); ++k) {
            vec3 c = m_shading.background;
            if (hits[k].hit) {
                bool lit = glm::dot(normals[k], m_shading.towardsLight) > 0.0f;
                if (m_shading.shadows && lit) lit = !m_shadowHits[nextShadow++].hit;
                c = shadeLambert(m_shading, shadeAlbedo(m_surface, m_shading, hits[k].position),
                                 normals[k], lit);
            }
            out.at(pixels[k].x, pixels[k].y) = toRgb8(c);
        }
    }

private:
    vec3 shadingNormal(const vec3& p) const {
        return shadeNormal(m_surface, m_shading, p, m_surface.normalAt(p));
    }
    // Starts just above S: the geometric normal is used even with a normal map, so the origin
    // really is above the surface the tracer sees.
    Ray shadowRay(const vec3& p) const {
        const float offset = 1e-3f * std::max(1.0f, m_surface.depth());
        return Ray{p + offset * m_surface.normalAt(p) + offset * vec3(0, 0, 1),
                   m_shading.towardsLight, kInfinity};
    }

    const Surface& m_surface;
    const Tracer& m_tracer;
    const Shading& m_shading;
    std::vector<Ray> m_shadowRays;
    std::vector<Hit> m_shadowHits;
};

template <class PerTile>
double forEachTile(const Camera& camera, const Tracer& tracer, Image<Hit>& hits, PerTile&& perTile) {
    const TileGrid grid(camera.width(), camera.height());
    Progress progress("render", grid.count());
    const auto start = std::chrono::steady_clock::now();
    parallelRanges(grid.count(), 1, [&](int64_t begin, int64_t end) {
        std::vector<Ray> rays;
        std::vector<ivec2> pixels;
        std::vector<Hit> tileHits;
        for (int64_t tile = begin; tile < end; ++tile) {
            tileRays(camera, int(tile), grid, rays, pixels);
            tileHits.resize(rays.size());
            tracer.traceBatch(rays, tileHits);
            for (size_t k = 0; k < pixels.size(); ++k) hits.at(pixels[k].x, pixels[k].y) = tileHits[k];
            perTile(std::span<const Hit>(tileHits), std::span<const ivec2>(pixels));
            progress.advance();
        }
    });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

Rgb8 toRgb8(const vec3& c) { return Rgb8(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

vec3 shadeAlbedo(const Surface& s, const Shading& shading, const vec3& texel) {
    if (shading.color) return sampleTexture(*shading.color, s, texel);
    const float depth = std::max(s.depth(), 1e-6f);
    return heightTint(texel.z / depth);
}

vec3 shadeNormal(const Surface& s, const Shading& shading, const vec3& texel,
                 const vec3& geometricNormal) {
    if (!shading.normalMap || geometricNormal.z <= 0.5f) return geometricNormal;
    return glm::normalize(sampleTexture(*shading.normalMap, s, texel) * 2.0f - 1.0f);
}

vec3 shadeLambert(const Shading& shading, const vec3& albedo, const vec3& normal, bool lit) {
    const float lambert = std::max(0.0f, glm::dot(normal, shading.towardsLight));
    return albedo * (shading.ambient + (1.0f - shading.ambient) * (lit ? lambert : 0.0f));
}

Image<Hit> tracePrimary(const Camera& camera, const Tracer& tracer, double* seconds) {
    Image<Hit> hits(camera.width(), camera.height());
    const double s = forEachTile(camera, tracer, hits, [](auto, auto) {});
    if (seconds) *seconds = s;
    return hits;
}

RenderResult render(const Surface& surface, const Camera& camera, const Tracer& tracer,
                    const Shading& shading) {
    RenderResult result;
    result.hits = Image<Hit>(camera.width(), camera.height());
    result.color = ImageRgb8(camera.width(), camera.height());
    result.seconds = forEachTile(camera, tracer, result.hits,
                                 [&](std::span<const Hit> hits, std::span<const ivec2> pixels) {
                                     TileShader(surface, tracer, shading)
                                         .shade(hits, pixels, result.color);
                                 });
    return result;
}

}  // namespace relief
