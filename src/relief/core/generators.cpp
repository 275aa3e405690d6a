#include <relief/core/generators.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

namespace relief {

namespace {

// splitmix64: small, fast, good enough for placing features.
struct Rng {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    int below(int n) { return int(next() % uint64_t(n)); }
};

Heightfield blank(int w, int h, float value = 0.0f) {
    Heightfield hf;
    hf.width = w;
    hf.height = h;
    hf.samples.assign(size_t(w) * size_t(h), value);
    return hf;
}

void normalizeToUnit(Heightfield& hf) {
    auto [mn, mx] = std::minmax_element(hf.samples.begin(), hf.samples.end());
    const float lo = *mn, range = *mx - *mn;
    for (float& v : hf.samples) v = range > 0.0f ? (v - lo) / range : 0.0f;
}

Heightfield sine(int w, int h, Rng&) {
    Heightfield hf = blank(w, h);
    const double periods = 3.0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            hf.at(i, j) = float(0.5 + 0.5 * std::sin(2.0 * std::numbers::pi * periods * i / w));
    return hf;
}

Heightfield peaks6(int w, int h, Rng& rng) {
    Heightfield hf = blank(w, h);
    const double scale = std::min(w, h);
    for (int p = 0; p < 6; ++p) {
        const double cx = rng.uniform(0.15, 0.85) * w, cy = rng.uniform(0.15, 0.85) * h;
        const double amplitude = rng.uniform(0.3, 1.0), width = rng.uniform(0.03, 0.12) * scale;
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i)
                hf.at(i, j) += float(amplitude *
                                     std::exp(-std::hypot(i + 0.5 - cx, j + 0.5 - cy) / width));
    }
    normalizeToUnit(hf);
    return hf;
}

// Periodic value noise (lattice wraps at the map size) so the map tiles in repeat mode.
Heightfield fbm(int w, int h, Rng& rng) {
    Heightfield hf = blank(w, h);
    double amplitude = 1.0;
    for (int cells = 4; cells <= std::max(w, h) && cells <= 512; cells *= 2, amplitude *= 0.5) {
        const int gx = std::min(cells, w), gy = std::min(cells, h);
        std::vector<double> lattice(size_t(gx) * size_t(gy));
        for (double& v : lattice) v = rng.uniform();
        auto value = [&](int x, int y) { return lattice[size_t(y % gy) * gx + size_t(x % gx)]; };
        for (int j = 0; j < h; ++j) {
            const double fy = double(j) * gy / h;
            const int y0 = int(fy);
            const double ty = fy - y0, sy = ty * ty * (3 - 2 * ty);
            for (int i = 0; i < w; ++i) {
                const double fx = double(i) * gx / w;
                const int x0 = int(fx);
                const double tx = fx - x0, sx = tx * tx * (3 - 2 * tx);
                const double top = value(x0, y0) + sx * (value(x0 + 1, y0) - value(x0, y0));
                const double bottom =
                    value(x0, y0 + 1) + sx * (value(x0 + 1, y0 + 1) - value(x0, y0 + 1));
                hf.at(i, j) += float(amplitude * (top + sy * (bottom - top)));
            }
        }
    }
    normalizeToUnit(hf);
    return hf;
}

// One-texel-wide walls (full height) along rows and columns, plus isolated pillars.
Heightfield walls(int w, int h, Rng& rng) {
    Heightfield hf = blank(w, h, 0.0f);
    const int count = std::max(2, (w + h) / 16);
    for (int k = 0; k < count; ++k) {
        const bool horizontal = rng.below(2) == 0;
        const int length = 1 + rng.below(std::max(1, (horizontal ? w : h) / 2));
        const int x = rng.below(w), y = rng.below(h);
        const float top = float(rng.uniform(0.5, 1.0));
        for (int s = 0; s < length; ++s) {
            const int i = horizontal ? (x + s) % w : x, j = horizontal ? y : (y + s) % h;
            hf.at(i, j) = top;
        }
    }
    for (int k = 0; k < count; ++k) hf.at(rng.below(w), rng.below(h)) = float(rng.uniform(0.3, 1.0));
    return hf;
}

// Isolated one-texel spikes on a flat base.
Heightfield spikes(int w, int h, Rng& rng) {
    Heightfield hf = blank(w, h, 0.0f);
    const int count = std::max(1, int(size_t(w) * size_t(h) / 64));
    for (int k = 0; k < count; ++k) hf.at(rng.below(w), rng.below(h)) = float(rng.uniform(0.2, 1.0));
    return hf;
}

// Flat steps and vertical cliffs: fractal noise quantized to 6 levels.
Heightfield terraces(int w, int h, Rng& rng) {
    Heightfield hf = fbm(w, h, rng);
    for (float& v : hf.samples) v = std::min(5.0f, std::floor(v * 6.0f)) / 5.0f;
    return hf;
}

Heightfield ramp(int w, int h, Rng&) {
    Heightfield hf = blank(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) hf.at(i, j) = w > 1 ? float(i) / float(w - 1) : 0.0f;
    return hf;
}

Heightfield flat(int w, int h, Rng&) { return blank(w, h, 0.5f); }

struct Generator {
    std::string_view name;
    Heightfield (*make)(int, int, Rng&);
};

constexpr Generator kGenerators[] = {
    {"sine", sine},         {"peaks6", peaks6}, {"fbm", fbm},   {"walls", walls},
    {"spikes", spikes},     {"terraces", terraces}, {"ramp", ramp}, {"flat", flat},
};

}  // namespace

std::vector<std::string_view> generatorNames() {
    std::vector<std::string_view> names;
    for (const Generator& g : kGenerators) names.push_back(g.name);
    return names;
}

Result<Heightfield> generateHeightfield(std::string_view name, int width, int height,
                                        uint64_t seed) {
    for (const Generator& g : kGenerators) {
        if (g.name != name) continue;
        Rng rng{seed * 0x2545F4914F6CDD1Dull + 1};
        return g.make(width, height, rng);
    }
    std::string known;
    for (const Generator& g : kGenerators) known += (known.empty() ? "" : ", ") + std::string(g.name);
    return makeError(ErrorKind::BadArgument, "unknown generator '{}' (known: {})", name, known);
}

}  // namespace relief
