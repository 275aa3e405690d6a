#include <relief/cli/bench_presets.h>

#include <relief/render/camera.h>
#include <relief/techniques/registry.h>

#include <cstdio>
#include <cstdlib>

namespace relief::cli {

namespace {

const std::vector<float> kAllElevations(std::begin(kStandardElevations), std::end(kStandardElevations));

struct Preset {
    const char* name;
    const char* description;
    BenchConfig (*make)();
};

std::vector<std::string> allTechniques() {
    std::vector<std::string> names;
    for (const TechniqueInfo& info : techniques()) names.emplace_back(info.name);
    return names;
}

BenchConfig quick() {
    BenchConfig c;
    c.maps = {"gen:fbm:64x64", "gen:walls:48x48"};
    c.techniques = allTechniques();
    c.elevations = {27.8f, 65.1f};
    c.caps = {8, 32};
    c.size = {96, 64};
    c.repeats = 1;
    return c;
}

BenchConfig standard() {
    BenchConfig c;
    c.maps = {"gen:fbm:512x512", "data/colorado-elevation-400.png"};
    c.techniques = allTechniques();
    c.elevations = {15.3f, 40.2f, 65.1f, 90.0f};
    c.caps = {8, 24, 200};
    return c;
}

BenchConfig qdmPaper() {
    BenchConfig c;
    c.maps = {"gen:sine:1024x1024", "gen:peaks6:1024x1024", "gen:fbm:1024x1024",
              "gen:terraces:1024x1024", "data/colorado-elevation-400.png",
              "data/finland-topography-400-16bit.png"};
    c.techniques = {"qdm", "cone", "exact"};
    c.elevations = kAllElevations;
    c.caps = {4, 6, 8, 12, 24, 48, 200};
    c.paperNotes = "Quadratic displacement maps (Fig. 9-11, Table 1): QDM reaches a given error with fewer "
                   "iterations than cone step mapping; the time difference per frame grows with the cap.";
    return c;
}

BenchConfig safetyPaper() {
    BenchConfig c;
    c.maps = {"gen:fbm:256x256", "gen:fbm:512x512", "gen:fbm:1024x1024"};
    c.techniques = {"exact", "linear", "relaxed-cone", "safety-sd", "safety-cc"};
    c.elevations = {15.3f, 40.2f, 65.1f};
    c.caps = {16, 32, 64};
    c.size = {1280, 1024};
    c.paperNotes = "Precomputed safety shapes (Fig. 29, 512² map covering a 1280×1024 screen, GTX 285): "
                   "NA is accurate but slow; LS and RC are faster but show artefacts; SD and CC are exact "
                   "and fastest, CC with φ_max = 45° best. Table 1 gives frame rates without φ_max; NA "
                   "(our `exact`) is only drawn as a bar in Fig. 29, so it has no ratio here.";
    c.paperRatios = {
        {"CC / SD, 256²", "548 / 304 Hz = 1.80× (Table 1)", "safety-cc", "fbm:256x256", "safety-sd", "fbm:256x256"},
        {"CC / SD, 512²", "444 / 190 Hz = 2.34× (Table 1)", "safety-cc", "fbm:512x512", "safety-sd", "fbm:512x512"},
        {"CC / SD, 1024²", "313 / 85 Hz = 3.68× (Table 1)", "safety-cc", "fbm:1024x1024", "safety-sd", "fbm:1024x1024"},
        {"CC 1024² / CC 256²", "313 / 548 Hz = 0.57× (Table 1)", "safety-cc", "fbm:1024x1024", "safety-cc", "fbm:256x256"},
    };
    return c;
}

BenchConfig quadtreePaper() {
    BenchConfig c;
    c.maps = {"gen:fbm:256x256", "gen:fbm:512x512", "gen:fbm:1024x1024", "gen:fbm:2048x2048"};
    c.techniques = {"quadtree", "maxmip", "quadtree-oriented", "linear", "parallax", "exact"};
    c.elevations = {15.3f, 52.7f};
    c.paperNotes = "Quadtree relief mapping: steps grow like log p for steep views and toward sqrt p for "
                   "grazing ones; the frame rate falls slowly from 256² to 2048² maps (Table 1, average fps "
                   "over view angles, GeForce 6600GT SLI). The paper's relief mapping doubles its linear "
                   "steps per doubling of the map; our `linear` keeps its default step count, so its ratio "
                   "is not comparable.";
    c.paperRatios = {
        {"quadtree 2048² / 256²", "63 / 95 fps = 0.66× (Table 1)", "quadtree", "fbm:2048x2048", "quadtree", "fbm:256x256"},
        {"quadtree 1024² / 256²", "71 / 95 fps = 0.75× (Table 1)", "quadtree", "fbm:1024x1024", "quadtree", "fbm:256x256"},
        {"parallax 2048² / 256²", "354 / 360 fps = 0.98× (Table 1)", "parallax", "fbm:2048x2048", "parallax", "fbm:256x256"},
        {"quadtree / relief mapping, 256²", "95 / 188 fps = 0.51× (Table 1)", "quadtree", "fbm:256x256", "linear", "fbm:256x256"},
    };
    return c;
}

BenchConfig curvesPaper() {
    BenchConfig c;
    c.maps = {"gen:sine:512x512"};
    c.techniques = {"curves", "exact"};
    c.elevations = {20.0f, 60.0f};
    c.paperNotes = "Geometric displacement on plane and sphere, Table 1 (sine map, 2 samples per pixel).";
    return c;
}

// Issue 9's GPU comparison: 1920×1080, 1024² maps, the standard elevations, plus the mesh.
BenchConfig gpu() {
    BenchConfig c;
    c.maps = {"gen:fbm:1024x1024", "gen:peaks6:1024x1024"};
    c.techniques = allTechniques();
    c.elevations = kAllElevations;
    c.size = {1920, 1088};
    c.backends = {"gl"};
    c.embree = false;
    c.repeats = 1;
    c.glFrames = 20;
    c.paperNotes = "Safety shapes §8: cylinder-cone 395 fps vs 170 fps for the rasterized mesh (GTX 285, "
                   "1024² map, 1280×1024).";
    c.paperRatios = {{"CC / rasterized mesh, 1024²", "395 / 170 fps = 2.32× (safety shapes §8)", "safety-cc", "",
                      "mesh", "", "gl"}};
    return c;
}

const Preset kPresets[] = {
    {"quick", "tiny maps, for CI", quick},
    {"default", "fbm 512² and the Colorado DEM, four elevations", standard},
    {"qdm-paper", "quadratic displacement maps vs cone stepping", qdmPaper},
    {"safety-paper", "safety shapes Fig. 29 / Table 1", safetyPaper},
    {"quadtree-paper", "quadtree scaling 256²-2048²", quadtreePaper},
    {"curves-paper", "visibility curves Table 1", curvesPaper},
    {"gpu", "GL backend: 1920×1088, 1024² maps, standard elevations, with the rasterized mesh", gpu},
};

template <class T>
Result<std::vector<T>> parseList(const std::string& text, const char* what) {
    std::vector<T> values;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        const std::string item = text.substr(start, comma - start);
        char* end = nullptr;
        const double v = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0')
            return makeError(ErrorKind::BadArgument, "{} '{}': expected a comma-separated list of numbers", what, text);
        values.push_back(T(v));
        start = comma + 1;
    }
    return values;
}

std::vector<std::string> splitNames(const std::string& text) {
    std::vector<std::string> names;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        names.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return names;
}

}  // namespace

std::string presetNames() {
    std::string names;
    for (const Preset& p : kPresets) names += (names.empty() ? "" : ", ") + std::string(p.name);
    return names;
}

Result<BenchConfig> presetConfig(const std::string& name) {
    for (const Preset& p : kPresets) {
        if (name != p.name) continue;
        BenchConfig c = p.make();
        std::erase_if(c.techniques, [](const std::string& t) { return !findTechnique(t); });
        return c;
    }
    return makeError(ErrorKind::BadArgument, "unknown preset '{}' (known: {})", name, presetNames());
}

Status applyOverrides(BenchConfig& c, const std::string& techniques, const std::string& maps,
                      const std::string& elevations, const std::string& caps,
                      const std::string& backends, const std::string& size, int repeats) {
    if (!techniques.empty()) {
        c.techniques = techniques == "all" ? allTechniques() : splitNames(techniques);
        for (const std::string& t : c.techniques)
            if (!findTechnique(t))
                return makeError(ErrorKind::BadArgument, "unknown technique '{}' (known: {})", t, techniqueNames());
    }
    if (!maps.empty()) c.maps = splitNames(maps);
    if (!elevations.empty()) {
        auto v = parseList<float>(elevations, "--elevations");
        if (!v) return v.error();
        c.elevations = *v;
    }
    if (!caps.empty()) {
        auto v = parseList<int>(caps, "--caps");
        if (!v) return v.error();
        for (int cap : *v)
            if (cap < 1) return makeError(ErrorKind::BadArgument, "--caps: {} is not a positive cap", cap);
        c.caps = *v;
    }
    if (!backends.empty()) {
        c.backends = splitNames(backends);
        for (const std::string& b : c.backends)
            if (b != "cpu" && b != "gl") return makeError(ErrorKind::BadArgument, "--backend '{}': cpu or gl", b);
    }
    if (!size.empty()) {
        int w = 0, h = 0;
        if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w % 16 || h % 16 || w > 8192 || h > 8192)
            return makeError(ErrorKind::BadArgument, "--size '{}': WxH, multiples of 16 from 16 to 8192", size);
        c.size = {w, h};
    }
    if (repeats < 0) return makeError(ErrorKind::BadArgument, "--repeats must be >= 1");
    if (repeats > 0) c.repeats = repeats;
    if (c.techniques.empty()) return makeError(ErrorKind::BadArgument, "no techniques to run");
    return {};
}

}  // namespace relief::cli
