#include <relief/io/heightfield_crop.h>

#include <algorithm>
#include <cstdint>

namespace relief {

Result<Heightfield> cropHeightfield(const Heightfield& hf, const CropWindow& window, const std::string& what) {
    CropWindow w = window;
    if (w.centred && w.width <= hf.width && w.height <= hf.height) {
        w.x = int(std::clamp(int64_t(w.x) - w.width / 2, int64_t(0), int64_t(hf.width - w.width)));
        w.y = int(std::clamp(int64_t(w.y) - w.height / 2, int64_t(0), int64_t(hf.height - w.height)));
    }
    // 64-bit sums: a corner near INT_MAX must not wrap into the map.
    if (w.width < 1 || w.height < 1 || w.x < 0 || w.y < 0 || int64_t(w.x) + w.width > hf.width ||
        int64_t(w.y) + w.height > hf.height)
        return makeError(ErrorKind::InvalidInput, "{}: crop {}x{} {} ({}, {}) is not inside the {}x{} map", what,
                         w.width, w.height, w.centred ? "around" : "at", window.x, window.y, hf.width, hf.height);
    Heightfield out{w.width, w.height, {}};
    out.samples.reserve(out.sampleCount());
    for (int j = w.y; j < w.y + w.height; ++j)
        for (int i = w.x; i < w.x + w.width; ++i) out.samples.push_back(hf.at(i, j));
    if (Status s = normalizeSamples(what, out.samples, out.width, 0.0, 0.0); !s) return s.error();
    return out;
}

}  // namespace relief
