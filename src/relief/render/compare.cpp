#include <relief/render/compare.h>

#include <fmt/format.h>
#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>

namespace relief {

ErrorStats compareHits(const Image<Hit>& hits, const Image<Hit>& reference) {
    ErrorStats stats;
    std::vector<double> errors, steps, coveredSteps, fetches;
    for (size_t k = 0; k < hits.pixels.size(); ++k) {
        const Hit& h = hits.pixels[k];
        const Hit& r = reference.pixels[k];
        ++stats.pixels;
        stats.hits += h.hit;
        steps.push_back(h.steps);
        fetches.push_back(h.fetches);
        if (h.hit || r.hit) {
            ++stats.covered;
            coveredSteps.push_back(h.steps);
        }
        stats.bothHit += h.hit && r.hit;
        if (h.hit != r.hit) {
            ++stats.wrong;
            stats.pastFirstHit += r.hit;  // stepped over every hit the reference finds
            continue;
        }
        if (!h.hit) continue;
        const double e = std::abs(double(h.t) - double(r.t));
        errors.push_back(e);
        if (e > kWrongHitDistance) ++stats.wrong;
        if (double(h.t) - double(r.t) > kWrongHitDistance) ++stats.pastFirstHit;
    }
    stats.error = summarize(std::move(errors));
    stats.steps = summarize(std::move(steps));
    stats.coveredSteps = summarize(std::move(coveredSteps));
    stats.fetches = summarize(std::move(fetches));
    return stats;
}

ImageF errorValues(const Image<Hit>& hits, const Image<Hit>& reference) {
    ImageF out(hits.width, hits.height, NAN);
    for (size_t k = 0; k < hits.pixels.size(); ++k) {
        const Hit& h = hits.pixels[k];
        const Hit& r = reference.pixels[k];
        if (h.hit != r.hit) out.pixels[k] = kInfinity;
        else if (h.hit) {
            const float e = std::abs(h.t - r.t);
            out.pixels[k] = e > kWrongHitDistance ? kInfinity : e;
        }
    }
    return out;
}

ImageF stepValues(const Image<Hit>& hits) {
    ImageF out(hits.width, hits.height, NAN);
    for (size_t k = 0; k < hits.pixels.size(); ++k)
        if (hits.pixels[k].steps > 0) out.pixels[k] = float(hits.pixels[k].steps);
    return out;
}

ImageF depthValues(const Image<Hit>& hits) {
    ImageF out(hits.width, hits.height, kInfinity);
    for (size_t k = 0; k < hits.pixels.size(); ++k)
        if (hits.pixels[k].hit) out.pixels[k] = hits.pixels[k].t;
    return out;
}

namespace {

// A perceptual ramp (dark blue → teal → yellow), close to viridis.
vec3 ramp(float x) {
    static const vec3 stops[] = {{0.267f, 0.005f, 0.329f}, {0.230f, 0.322f, 0.546f},
                                 {0.128f, 0.567f, 0.551f}, {0.369f, 0.789f, 0.383f},
                                 {0.993f, 0.906f, 0.144f}};
    x = std::clamp(x, 0.0f, 1.0f) * 4.0f;
    const int i = std::min(3, int(x));
    return glm::mix(stops[i], stops[i + 1], x - float(i));
}

Rgb8 rgb(const vec3& c) { return Rgb8(glm::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f); }

void drawText(ImageRgb8& image, int x, int y, const std::string& text, Rgb8 colour) {
    static thread_local char buffer[64 * 1024];
    const int quads = stb_easy_font_print(float(x), float(y), const_cast<char*>(text.c_str()),
                                          nullptr, buffer, sizeof buffer);
    struct Vertex {
        float x, y, z;
        unsigned char c[4];
    };
    const auto* v = reinterpret_cast<const Vertex*>(buffer);
    for (int q = 0; q < quads; ++q) {
        const Vertex* quad = v + 4 * q;
        for (int py = int(quad[0].y); py < int(quad[2].y); ++py)
            for (int px = int(quad[0].x); px < int(quad[2].x); ++px)
                if (px >= 0 && py >= 0 && px < image.width && py < image.height)
                    image.at(px, py) = colour;
    }
}

}  // namespace

ImageRgb8 heatmap(const ImageF& values, float scaleMax, std::string_view title) {
    const int barWidth = 90;
    const Rgb8 background(26, 28, 33), flagged(255, 0, 255), text(230, 230, 230);
    ImageRgb8 out(values.width + barWidth, std::max(values.height, 80), background);
    const float scale = scaleMax > 0.0f ? scaleMax : 1.0f;
    for (int y = 0; y < values.height; ++y)
        for (int x = 0; x < values.width; ++x) {
            const float v = values.at(x, y);
            if (std::isnan(v)) continue;
            out.at(x, y) = std::isinf(v) ? flagged : rgb(ramp(v / scale));
        }
    const int barX = values.width + 10, barTop = 24, barBottom = out.height - 24;
    for (int y = barTop; y < barBottom; ++y)
        for (int x = barX; x < barX + 14; ++x)
            out.at(x, y) = rgb(ramp(float(barBottom - 1 - y) / float(barBottom - barTop - 1)));
    drawText(out, values.width + 4, 4, std::string(title), text);
    drawText(out, barX + 18, barTop, fmt::format("{:.3g}", scale), text);
    drawText(out, barX + 18, (barTop + barBottom) / 2, fmt::format("{:.3g}", 0.5f * scale), text);
    drawText(out, barX + 18, barBottom - 8, "0", text);
    return out;
}

ImageRgb8 stepsHeatmap(const Image<Hit>& hits, const ErrorStats& stats, std::string_view name) {
    return heatmap(stepValues(hits), float(stats.steps.max), fmt::format("{} steps", name));
}

ImageRgb8 errorHeatmap(const Image<Hit>& hits, const Image<Hit>& reference,
                       const ErrorStats& stats, std::string_view name) {
    return heatmap(errorValues(hits, reference), std::max(1e-3f, float(stats.error.p99)),
                   fmt::format("{} |t-t_ref|", name));
}

}  // namespace relief
