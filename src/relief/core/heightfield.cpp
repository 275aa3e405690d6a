#include <relief/core/heightfield.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace relief {

uint64_t Heightfield::contentHash() const {
    uint64_t hash = 1469598103934665603ull;
    auto mix = [&hash](const void* data, size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t k = 0; k < bytes; ++k) {
            hash ^= p[k];
            hash *= 1099511628211ull;
        }
    };
    mix(&width, sizeof width);
    mix(&height, sizeof height);
    mix(samples.data(), samples.size() * sizeof(float));
    return hash;
}

Status checkDimensions(const std::string& what, int64_t width, int64_t height,
                       int64_t maxSamples) {
    if (width <= 0 || height <= 0)
        return makeError(ErrorKind::InvalidInput, "{}: invalid size {}x{} (both must be >= 1)",
                         what, width, height);
    if (width > kMaxDimension || height > kMaxDimension)
        return makeError(ErrorKind::InvalidInput,
                         "{}: size {}x{} exceeds the limit of {} per side", what, width, height,
                         kMaxDimension);
    if (width * height > maxSamples)
        return makeError(ErrorKind::InvalidInput,
                         "{}: {}x{} = {} samples exceeds the limit of {} (raise it with "
                         "--max-samples N)",
                         what, width, height, width * height, maxSamples);
    return {};
}

Status normalizeSamples(const std::string& what, std::vector<float>& raw, int width, double lo,
                        double hi) {
    for (size_t k = 0; k < raw.size(); ++k) {
        if (!std::isfinite(raw[k]))
            return makeError(ErrorKind::InvalidInput,
                             "{}: non-finite sample {} at column {}, row {}", what, raw[k],
                             k % size_t(width), k / size_t(width));
    }
    if (!(lo < hi)) {
        auto [mn, mx] = std::minmax_element(raw.begin(), raw.end());
        lo = raw.empty() ? 0.0 : *mn;
        hi = raw.empty() ? 1.0 : *mx;
    }
    const double range = hi - lo;
    for (float& v : raw) {
        const double n = range > 0.0 ? (double(v) - lo) / range : 0.0;
        v = float(std::clamp(n, 0.0, 1.0));
    }
    return {};
}

}  // namespace relief
