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

// A running-bond brick wall that tiles: courses of bricks twice as wide as high, every other course
// offset by half a brick, separated by mortar joints; each stone has its own height, tilt and
// colour, a bevelled rim and a little grain. Heights and colours come from the same layout.
class BrickWall {
public:
    BrickWall(int w, int h, Rng& rng) : m_w(w) {
        // An even number of courses so the half-brick offset tiles vertically.
        m_courses = std::max(2, 2 * int(std::lround(double(h) / 48.0)));
        m_courseHeight = double(h) / m_courses;
        m_perCourse = std::max(1, int(std::lround(double(w) / (2.0 * m_courseHeight))));
        m_brickWidth = double(w) / m_perCourse;
        m_mortar = std::max(1.0, 0.1 * m_courseHeight);
        m_bevel = std::max(1.0, 0.2 * m_courseHeight);
        m_stones.resize(size_t(m_courses) * size_t(m_perCourse));
        for (Stone& s : m_stones)
            s = {rng.uniform(0.8, 1.0), rng.uniform(-0.08, 0.08), rng.uniform(-0.08, 0.08),
                 rng.uniform(0.75, 1.15), rng.uniform(-0.06, 0.06)};
        m_grain.resize(size_t(w) * size_t(h));
        for (double& g : m_grain) g = rng.uniform(-1.0, 1.0);
    }

    // Height in [0, 1] and colour (sRGB, [0, 1]) of sample (i, j).
    double height(int i, int j) const {
        const Place p = place(i, j);
        const double grain = 0.02 * m_grain[size_t(j) * size_t(m_w) + size_t(i)];
        if (p.rim <= 0.0) return 0.1 + grain;
        const Stone& s = m_stones[p.stone];
        const double bevel = std::min(1.0, p.rim / m_bevel);
        const double top = s.top + s.tiltX * p.u + s.tiltY * p.v;
        return 0.1 + (top - 0.1) * std::sqrt(bevel * (2.0 - bevel)) + grain;
    }
    void colour(int i, int j, double rgb[3]) const {
        const Place p = place(i, j);
        const double grain = 0.05 * m_grain[size_t(j) * size_t(m_w) + size_t(i)];
        if (p.rim <= 0.0) {
            for (int c = 0; c < 3; ++c) rgb[c] = 0.72 + grain;
            return;
        }
        const Stone& s = m_stones[p.stone];
        const double base[3] = {0.62, 0.30, 0.22};
        const double edge = 0.8 + 0.2 * std::min(1.0, p.rim / m_bevel);
        for (int c = 0; c < 3; ++c)
            rgb[c] = std::clamp(base[c] * s.shade * edge + s.hue * (1 - c) + grain, 0.0, 1.0);
    }

private:
    struct Stone {
        double top, tiltX, tiltY, shade, hue;
    };
    struct Place {
        size_t stone;
        double rim;   // texels from the stone's outline inwards (≤ 0: mortar)
        double u, v;  // position in the stone, [-1, 1] each
    };
    Place place(int i, int j) const {
        const double y = j + 0.5;
        const int course = std::min(m_courses - 1, int(y / m_courseHeight));
        const double x = std::fmod(i + 0.5 + (course % 2) * 0.5 * m_brickWidth, double(m_w));
        const int column = std::min(m_perCourse - 1, int(x / m_brickWidth));
        const double lx = x - column * m_brickWidth, ly = y - course * m_courseHeight;
        const double rim = std::min({lx, m_brickWidth - lx, ly, m_courseHeight - ly}) - 0.5 * m_mortar;
        return {size_t(course) * size_t(m_perCourse) + size_t(column), rim,
                2.0 * lx / m_brickWidth - 1.0, 2.0 * ly / m_courseHeight - 1.0};
    }

    int m_w, m_courses = 2, m_perCourse = 1;
    double m_courseHeight = 1, m_brickWidth = 1, m_mortar = 1, m_bevel = 1;
    std::vector<Stone> m_stones;
    std::vector<double> m_grain;
};

Heightfield bricks(int w, int h, Rng& rng) {
    const BrickWall wall(w, h, rng);
    Heightfield hf = blank(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) hf.at(i, j) = float(std::clamp(wall.height(i, j), 0.0, 1.0));
    return hf;
}

ImageRgb8 bricksColor(int w, int h, Rng& rng) {
    const BrickWall wall(w, h, rng);
    ImageRgb8 image(w, h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            double rgb[3];
            wall.colour(i, j, rgb);
            image.at(i, j) = Rgb8(uint8_t(rgb[0] * 255.0 + 0.5), uint8_t(rgb[1] * 255.0 + 0.5),
                                  uint8_t(rgb[2] * 255.0 + 0.5));
        }
    return image;
}

struct Generator {
    std::string_view name;
    Heightfield (*make)(int, int, Rng&);
    ImageRgb8 (*makeColor)(int, int, Rng&) = nullptr;  // a matching colour map, where it has one
};

constexpr Generator kGenerators[] = {
    {"sine", sine},         {"peaks6", peaks6},     {"fbm", fbm},   {"walls", walls},
    {"spikes", spikes},     {"terraces", terraces}, {"ramp", ramp}, {"flat", flat},
    {"bricks", bricks, bricksColor},
};

Rng seeded(uint64_t seed) { return Rng{seed * 0x2545F4914F6CDD1Dull + 1}; }

std::string knownNames(bool (*keep)(const Generator&)) {
    std::string known;
    for (const Generator& g : kGenerators)
        if (keep(g)) known += (known.empty() ? "" : ", ") + std::string(g.name);
    return known;
}

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
        Rng rng = seeded(seed);
        return g.make(width, height, rng);
    }
    return makeError(ErrorKind::BadArgument, "unknown generator '{}' (known: {})", name,
                     knownNames([](const Generator&) { return true; }));
}

Result<ImageRgb8> generateColorMap(std::string_view name, int width, int height, uint64_t seed) {
    for (const Generator& g : kGenerators) {
        if (g.name != name || !g.makeColor) continue;
        Rng rng = seeded(seed);
        return g.makeColor(width, height, rng);
    }
    return makeError(ErrorKind::BadArgument,
                     "generator '{}' has no colour map (generators with one: {})", name,
                     knownNames([](const Generator& g) { return g.makeColor != nullptr; }));
}

}  // namespace relief
