#include <relief/bench/presets.h>

#include <relief/render/camera.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <type_traits>

namespace relief::bench {

namespace {

struct GlobalPreset {
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

// Issue 9's GPU comparison: 1920×1080, 1024² maps, the standard elevations, plus the mesh.
BenchConfig gpu() {
    BenchConfig c;
    c.maps = {"gen:fbm:1024x1024", "gen:peaks6:1024x1024"};
    c.techniques = allTechniques();
    c.elevations.assign(std::begin(kStandardElevations), std::end(kStandardElevations));
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

// Issue 20: the heightfield as an Embree user geometry over exact and maxmip against its
// triangles in the same scene type, at 1024² and 4096² (--map-sizes), on the same rays.
BenchConfig embreeUser() {
    BenchConfig c;
    c.maps = {"gen:fbm:{N}x{N}:1"};
    c.sizes = {1024, 4096};
    c.techniques = {"exact", "maxmip"};
    c.elevations = {27.8f, 65.1f};
    c.size = {256, 256};
    c.repeats = 2;
    c.userGeometry = true;
    return c;
}

// Issue 21: the CPU tracers against Embree on the same primary and shadow rays (light at 30°),
// fbm and an SRTM window (the Himalaya, as cones-quality) at 1024² and 4096². safety-cc and qdm
// only at 1024²: their 4096² bakes take minutes.
BenchConfig cpuPeers() {
    constexpr int64_t k1024 = 1024 * 1024;
    BenchConfig c;
    c.maps = {"gen:fbm:1024x1024:1", "../shared/data/earth-srtm-10800x5400.png@centre=7980,1860,1024,1024",
              "gen:fbm:4096x4096:1", "../shared/data/earth-srtm-10800x5400.png@centre=7980,1860,4096,4096"};
    c.techniques = {"quadtree", "maxmip", "cone", "safety-cc", "exact", "qdm"};
    c.elevations = {15.3f, 40.2f, 65.1f};
    c.shadowElevation = 30.0f;
    c.shadowTiming = true;
    c.pairedPeers = true;
    c.repeats = 5;  // pairs per row and view: their median is the ratio
    c.rowMaxSamples = {{"safety-cc", k1024}, {"qdm", k1024}};
    // The shadow targets are "the same ratios against rtcOccluded16", exact's included.
    for (bool shadow : {false, true}) {
        c.targets.push_back({"quadtree", "embree-16", 2.0, shadow, 0, true});
        c.targets.push_back({"safety-cc", "embree-16", 1.5, shadow, k1024, false});
        c.targets.push_back({"cone", "embree-16", 1.5, shadow, 0, false});
        c.targets.push_back({"exact", shadow ? "embree-16" : "embree-1", 1.0, shadow, 0, false});
    }
    return c;
}

const GlobalPreset kGlobalPresets[] = {
    {"quick", "tiny maps, for CI", quick},
    {"default", "fbm 512² and the Colorado DEM, four elevations", standard},
    {"gpu", "GL backend: 1920×1088, 1024² maps, standard elevations, with the rasterized mesh", gpu},
    {"embree-user", "exact and maxmip as Embree user geometries vs the triangles: Mrays/s and bytes/texel, 1024², 4096²",
     embreeUser},
    {"cpu-peers", "CPU rows vs Embree rtcIntersect1/16 and rtcOccluded1/16 (shadows), fbm and SRTM 1024², 4096²: issue 21's targets",
     cpuPeers},
};

std::vector<std::string> strings(std::span<const std::string_view> views) {
    return std::vector<std::string>(views.begin(), views.end());
}

BenchConfig fromStudy(const StudySpec& s) {
    BenchConfig c;
    c.kind = s.kind;
    c.maps = strings(s.maps);
    c.techniques = strings(s.techniques);
    if (s.elevations.empty())
        c.elevations.assign(std::begin(kStandardElevations), std::end(kStandardElevations));
    else
        c.elevations.assign(s.elevations.begin(), s.elevations.end());
    c.caps.assign(s.caps.begin(), s.caps.end());
    c.sizes.assign(s.sizes.begin(), s.sizes.end());
    c.size = {s.width, s.height};
    c.depthRatio = s.depthRatio;
    c.distance = s.distance;
    c.peerTable = s.peerTable;
    c.compare = std::string(s.compare);
    c.paperNotes = std::string(s.paperNotes);
    c.imageMethod = s.imageMethod;
    c.shadowElevation = s.shadowElevation;
    c.parts = strings(s.parts);
    c.claims = s.claims;
    c.paperFile = std::string(s.paperFile);
    for (const PaperRatioSpec& r : s.paperRatios)
        c.paperRatios.push_back({std::string(r.what), std::string(r.paper), std::string(r.numeratorTechnique),
                                 std::string(r.numeratorMap), std::string(r.denominatorTechnique),
                                 std::string(r.denominatorMap), std::string(r.backend)});
    return c;
}

// Numbers, comma-separated, each finite and in [lo, hi] (integral for an integer T).
template <class T>
Result<std::vector<T>> parseList(const std::string& text, const char* what, double lo, double hi) {
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
        if (!std::isfinite(v) || v < lo || v > hi || (std::is_integral_v<T> && v != std::floor(v)))
            return makeError(ErrorKind::BadArgument, "{}: '{}' is not {} from {:g} to {:g}", what, item,
                             std::is_integral_v<T> ? "an integer" : "a finite number", lo, hi);
        values.push_back(T(v));
        start = comma + 1;
    }
    return values;
}

// "WxH" with both sides integers (no overflow, no trailing text).
bool parseImageSize(const std::string& text, int& w, int& h) {
    const size_t x = text.find('x');
    if (x == std::string::npos) return false;
    const char* end = text.data() + text.size();
    const auto a = std::from_chars(text.data(), text.data() + x, w);
    const auto b = std::from_chars(text.data() + x + 1, end, h);
    return a.ec == std::errc() && a.ptr == text.data() + x && b.ec == std::errc() && b.ptr == end;
}

std::vector<std::string> split(const std::string& text, char separator) {
    std::vector<std::string> parts;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find(separator, start);
        if (end == std::string::npos) end = text.size();
        parts.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return parts;
}

bool hasWindow(const std::string& source) {
    return source.find("@crop=") != std::string::npos || source.find("@centre=") != std::string::npos;
}

// --heightfields: comma-separated sources, where the commas of a suffix @crop=X,Y,W,H (or
// @centre=) stay in it.
std::vector<std::string> splitSources(const std::string& text) {
    std::vector<std::string> sources;
    for (const std::string& part : split(text, ',')) {
        const bool inCrop = !sources.empty() && hasWindow(sources.back()) &&
                            std::count(sources.back().begin(), sources.back().end(), ',') < 3;
        if (inCrop)
            sources.back() += "," + part;
        else
            sources.push_back(part);
    }
    return sources;
}

// gen:NAME:WxH[:seed] → gen:NAME:64x64.
std::string smokeMap(const std::string& map) {
    if (map.rfind("gen:", 0) != 0 || hasWindow(map)) return map;  // a window needs its size
    std::vector<std::string> parts = split(map, ':');
    return "gen:" + parts[1] + ":64x64";
}

constexpr int kQuickMapSize = 256;

// gen:NAME:WxH[:seed] → at most 256² (aspect kept); a window @crop=/@centre=X,Y,W,H → at most
// 256² about the same centre.
std::string quickMap(const std::string& map) {
    auto shrink = [](int& w, int& h) {
        const int longest = std::max(w, h);
        if (longest <= kQuickMapSize) return false;
        w = std::max(2, int(int64_t(w) * kQuickMapSize / longest));
        h = std::max(2, int(int64_t(h) * kQuickMapSize / longest));
        return true;
    };
    for (const char* tag : {"@crop=", "@centre="}) {
        const size_t at = map.find(tag);
        if (at == std::string::npos) continue;
        const std::vector<std::string> v = split(map.substr(at + std::strlen(tag)), ',');
        int x = 0, y = 0, w = 0, h = 0;
        if (v.size() != 4 || std::sscanf(v[0].c_str(), "%d", &x) != 1 || std::sscanf(v[1].c_str(), "%d", &y) != 1 ||
            std::sscanf(v[2].c_str(), "%d", &w) != 1 || std::sscanf(v[3].c_str(), "%d", &h) != 1)
            return map;  // {N} or malformed: the loader reports it
        const int w0 = w, h0 = h;
        if (!shrink(w, h)) return map;
        if (std::string(tag) == "@crop=") {  // keep the window's centre
            x += (w0 - w) / 2;
            y += (h0 - h) / 2;
        }
        return fmt::format("{}{}{},{},{},{}", map.substr(0, at), tag, x, y, w, h);
    }
    if (map.rfind("gen:", 0) != 0) return map;
    std::vector<std::string> parts = split(map, ':');
    int w = 0, h = 0;
    if (parts.size() < 3 || !parseImageSize(parts[2], w, h) || !shrink(w, h)) return map;
    parts[2] = fmt::format("{}x{}", w, h);
    std::string out = parts[0];
    for (size_t k = 1; k < parts.size(); ++k) out += ":" + parts[k];
    return out;
}

}  // namespace

std::vector<PresetEntry> presetList() {
    std::vector<PresetEntry> list;
    for (const GlobalPreset& p : kGlobalPresets) list.push_back({p.name, p.description, ""});
    for (const TechniqueInfo& info : techniques())
        for (const StudySpec& s : info.studies)
            list.push_back({std::string(s.name), std::string(s.description), std::string(info.name)});
    return list;
}

std::string presetNames() {
    std::string names;
    for (const PresetEntry& p : presetList()) names += (names.empty() ? "" : ", ") + p.name;
    return names;
}

Result<BenchConfig> presetConfig(const std::string& name) {
    std::optional<BenchConfig> found;
    for (const GlobalPreset& p : kGlobalPresets)
        if (name == p.name) found = p.make();
    for (const TechniqueInfo& info : techniques())
        for (const StudySpec& s : info.studies)
            if (name == s.name) found = fromStudy(s);
    if (!found) return makeError(ErrorKind::BadArgument, "unknown preset '{}' (known: {})", name, presetNames());
    found->name = name;
    std::erase_if(found->techniques, [](const std::string& t) { return !parseRowSpec(t); });
    return *found;
}

Result<RowSpec> parseRowSpec(const std::string& text) {
    const size_t colon = text.find(':');
    RowSpec row;
    row.label = text;
    auto info = lookupTechnique(text.substr(0, colon));
    if (!info) return info.error();
    row.info = *info;
    if (colon == std::string::npos) return row;
    std::string params = text.substr(colon + 1);
    std::replace(params.begin(), params.end(), ':', ',');
    auto parsed = parseParamList(params);
    if (!parsed) return makeError(ErrorKind::BadArgument, "-t '{}': {}", text, parsed.error().message);
    if (auto check = resolveParams(*row.info, *parsed); !check) return check.error();
    row.params = std::move(*parsed);
    return row;
}

Status applyOverrides(BenchConfig& c, const BenchOverrides& o) {
    if (!o.techniques.empty()) {
        c.techniques = o.techniques == "all" ? allTechniques() : split(o.techniques, ',');
        for (const std::string& t : c.techniques)
            if (auto row = parseRowSpec(t); !row) return row.error();
    }
    if (!o.maps.empty()) c.maps = splitSources(o.maps);
    if (!o.elevations.empty()) {
        auto v = parseList<float>(o.elevations, "--elevations", -90.0, 90.0);
        if (!v) return v.error();
        c.elevations = *v;
    }
    if (!o.caps.empty()) {
        auto v = parseList<int>(o.caps, "--caps", 1, 1e9);
        if (!v) return v.error();
        c.caps = *v;
    }
    if (!o.sizes.empty()) {
        auto v = parseList<int>(o.sizes, "--map-sizes", 2, 16384);
        if (!v) return v.error();
        c.sizes = *v;
    }
    if (!o.backends.empty()) {
        c.backends = split(o.backends, ',');
        for (const std::string& b : c.backends)
            if (b != "cpu" && b != "gl") return makeError(ErrorKind::BadArgument, "--backend '{}': cpu or gl", b);
    }
    if (!o.size.empty()) {
        int w = 0, h = 0;
        if (!parseImageSize(o.size, w, h) || w < 16 || h < 16 || w % 16 || h % 16 || w > 8192 || h > 8192)
            return makeError(ErrorKind::BadArgument, "--size '{}': WxH, multiples of 16 from 16 to 8192", o.size);
        c.size = {w, h};
    }
    if (!o.edge.empty()) {
        if (o.edge != "clamp" && o.edge != "repeat")
            return makeError(ErrorKind::BadArgument, "--edge '{}': clamp or repeat", o.edge);
        c.edge = o.edge;
    }
    auto finite = [](const auto& value, const char* what, double lo, double hi) -> Status {
        if (value && !(std::isfinite(double(*value)) && *value >= lo && *value <= hi))
            return makeError(ErrorKind::BadArgument, "{} {}: expected a finite number from {:g} to {:g}",
                             what, *value, lo, hi);
        return {};
    };
    for (Status s : {finite(o.depth, "--depth", 0.0, 1e6), finite(o.depthRatio, "--depth-ratio", 0.0, 1e6),
                     finite(o.azimuth, "--azimuth", -360.0, 360.0), finite(o.distance, "--distance", 0.01, 1000.0)})
        if (!s) return s.error();
    if (o.depth) c.depth = *o.depth;
    if (o.depthRatio) c.depthRatio = *o.depthRatio;
    if (o.azimuth) c.azimuth = *o.azimuth;
    if (o.distance) c.distance = *o.distance;
    if (o.repeats < 0) return makeError(ErrorKind::BadArgument, "--repeats must be >= 1");
    if (o.repeats > 0) c.repeats = o.repeats;
    if (o.smoke) {
        // Generated maps shrink to 64²; files (which cannot) stay only when there is no generated one.
        std::vector<std::string> maps;
        for (const std::string& m : c.maps)
            if (m.rfind("gen:", 0) == 0 && std::find(maps.begin(), maps.end(), smokeMap(m)) == maps.end())
                maps.push_back(smokeMap(m));
        if (maps.empty()) maps = c.maps;
        c.maps = maps;
        if (!c.sizes.empty()) c.sizes = {64};
        if (c.elevations.size() > 1) c.elevations = {c.elevations.front()};
        c.size = {32, 32};
        c.repeats = 1;
        c.glFrames = 1;
    }
    if (o.quick && o.smoke) return makeError(ErrorKind::BadArgument, "--quick and --smoke: choose one");
    if (o.quick) {
        // Maps that shrink to the same one (fbm 1024² and 4096²) are run once.
        std::vector<std::string> maps;
        for (const std::string& m : c.maps)
            if (std::find(maps.begin(), maps.end(), quickMap(m)) == maps.end()) maps.push_back(quickMap(m));
        c.maps = maps;
        if (!c.sizes.empty()) {
            std::vector<int> sizes;
            for (int n : c.sizes)
                if (n <= 2 * kQuickMapSize) sizes.push_back(n);
            c.sizes = sizes.empty() ? std::vector<int>{*std::min_element(c.sizes.begin(), c.sizes.end())} : sizes;
        }
        c.size = {std::min(c.size.x, 160), std::min(c.size.y, 128)};
        c.repeats = 1;
        c.glFrames = 2;
    }
    if (c.kind == StudyKind::Paper) return {};  // its parts name their own techniques
    if (c.techniques.empty()) return makeError(ErrorKind::BadArgument, "no techniques to run");
    return {};
}

}  // namespace relief::bench
