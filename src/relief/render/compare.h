#pragma once
// Per-pixel error of a technique against the exact reference (DESIGN §8) and heatmap images.
#include <relief/core/image.h>
#include <relief/core/math.h>
#include <relief/core/stats.h>

#include <string_view>

namespace relief {

// A pixel is wrong when hit/miss differs or |Δt| > kWrongHitDistance texels.
inline constexpr float kWrongHitDistance = 0.5f;

// The bench's columns are over every pixel (kept as they were); the render summary is over the
// covered pixels, where the reference or the technique hits: in the default framing the relief
// fills about a third of the image, and background pixels would dilute every rate.
struct ErrorStats {
    size_t pixels = 0;
    size_t hits = 0;        // pixels the technique hit
    size_t covered = 0;     // pixels the technique or the reference hit
    size_t bothHit = 0;     // pixels both hit: the denominator of `error`
    size_t wrong = 0;       // wrong-hit pixels (all of them covered)
    // Wrong pixels whose hit lies past the reference's first hit, or that miss where it hits: what
    // a method that may step over a hit does (a subset of `wrong`).
    size_t pastFirstHit = 0;
    Summary error;          // |t − t_ref| over pixels where both hit
    Summary steps;          // per pixel (all pixels)
    Summary coveredSteps;   // per covered pixel
    Summary fetches;
    double wrongRate() const { return pixels ? double(wrong) / double(pixels) : 0.0; }
    double pastFirstHitRate() const { return pixels ? double(pastFirstHit) / double(pixels) : 0.0; }
    double coveredWrongRate() const { return covered ? double(wrong) / double(covered) : 0.0; }
};

ErrorStats compareHits(const Image<Hit>& hits, const Image<Hit>& reference);

// |t − t_ref| per pixel; NaN where both miss, +inf where the pixel is wrong.
ImageF errorValues(const Image<Hit>& hits, const Image<Hit>& reference);
ImageF stepValues(const Image<Hit>& hits);  // NaN where the ray missed the box entirely
ImageF depthValues(const Image<Hit>& hits);  // t, +inf where missed

// A colour heatmap of `values` scaled to [0, scaleMax], with a colour bar on the right labelled
// with `title` and its scale. NaN pixels are background, +inf pixels magenta (flagged).
ImageRgb8 heatmap(const ImageF& values, float scaleMax, std::string_view title);

// The two diagnostic images of a run: steps per pixel scaled to the run's maximum, and
// |t − t_ref| scaled to its 99th percentile (at least 1e-3 texel), wrong pixels magenta.
ImageRgb8 stepsHeatmap(const Image<Hit>& hits, const ErrorStats& stats, std::string_view name);
ImageRgb8 errorHeatmap(const Image<Hit>& hits, const Image<Hit>& reference,
                       const ErrorStats& stats, std::string_view name);

}  // namespace relief
