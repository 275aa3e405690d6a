#pragma once
// A W×H grid of samples normalized to [0,1] (DESIGN §1): sample (i,j) is column i, row j.
#include <relief/core/error.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace relief {

// Size limits, checked before any allocation. Raise them with --max-samples on the CLI.
inline constexpr int kMaxDimension = 1 << 16;
inline constexpr int64_t kDefaultMaxSamples = int64_t(1) << 28;  // 1 GiB of float samples

struct Heightfield {
    int width = 0;
    int height = 0;
    std::vector<float> samples;  // row-major, width*height, each in [0,1]

    float at(int i, int j) const { return samples[size_t(j) * size_t(width) + size_t(i)]; }
    float& at(int i, int j) { return samples[size_t(j) * size_t(width) + size_t(i)]; }
    size_t sampleCount() const { return size_t(width) * size_t(height); }

    // FNV-1a over the size and the sample bits: identifies the source of a baked map.
    uint64_t contentHash() const;
};

// Checks a requested size against the limits; the message names `what` (a path or generator).
Status checkDimensions(const std::string& what, int64_t width, int64_t height,
                       int64_t maxSamples = kDefaultMaxSamples);

// Rescales raw values to [0,1]: by [lo,hi] if given (lo < hi), else by the data's own min/max
// (a constant field becomes all zeros). Fails on non-finite samples, naming the first one.
Status normalizeSamples(const std::string& what, std::vector<float>& raw, int width, double lo,
                        double hi);

}  // namespace relief
