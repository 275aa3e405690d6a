#include <relief/render/surface_source.h>

#include <relief/techniques/technique.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>

namespace relief {

Result<SourceSpec> parseSourceSpec(const std::string& source) {
    SourceSpec spec;
    const size_t crop = source.rfind("@crop="), centre = source.rfind("@centre=");
    const bool centred = centre != std::string::npos && (crop == std::string::npos || centre > crop);
    const size_t at = centred ? centre : crop;
    spec.base = source.substr(0, at);
    if (at == std::string::npos) return spec;
    spec.suffix = source.substr(at);
    int values[4] = {};
    const char* p = source.data() + source.find('=', at) + 1;
    const char* end = source.data() + source.size();
    for (int k = 0; k < 4; ++k) {
        auto [next, ec] = std::from_chars(p, end, values[k]);
        const bool ok = ec == std::errc() && (k < 3 ? next != end && *next == ',' : next == end);
        if (!ok)
            return makeError(ErrorKind::BadArgument, "'{}': expected FILE@crop=X,Y,W,H (corner and size) or "
                             "FILE@centre=X,Y,W,H, integers", source);
        p = next + 1;
    }
    spec.crop = CropWindow{values[0], values[1], values[2], values[3], centred};
    return spec;
}

Result<std::shared_ptr<const Heightfield>> loadHeightfield(const SurfaceOptions& o) {
    auto spec = parseSourceSpec(o.source);
    if (!spec) return spec.error();
    // A generator reads no file: options that describe one would be ignored.
    if (o.source.rfind("gen:", 0) == 0)
        for (const auto& [given, option] : {std::pair{!o.raw.empty(), "--raw"},
                                            std::pair{!o.heightRange.empty(), "--height-range"},
                                            std::pair{o.channel != "luminance", "--channel"}})
            if (given)
                return makeError(ErrorKind::BadArgument,
                                 "{}: {} describes a file; a generator "
                                 "reads none",
                                 o.source, option);
    LoadOptions load;
    load.invert = o.invert;
    load.maxSamples = o.maxSamples;
    if (!o.heightRange.empty()) {
        double lo = 0, hi = 0;
        char extra = 0;  // "0:1:2" is not a range
        if (std::sscanf(o.heightRange.c_str(), "%lf:%lf%c", &lo, &hi, &extra) != 2 || !(lo < hi) ||
            !std::isfinite(lo) || !std::isfinite(hi))
            return makeError(ErrorKind::BadArgument, "--height-range '{}': expected LO:HI with LO < HI",
                             o.heightRange);
        load.rangeLo = lo;
        load.rangeHi = hi;
    }
    if (!o.raw.empty()) {
        auto layout = parseRawLayout(o.raw);
        if (!layout) return layout.error();
        load.raw = *layout;
    }
    const std::pair<const char*, ChannelSelect> channels[] = {
        {"luminance", ChannelSelect::Luminance}, {"r", ChannelSelect::Red},
        {"g", ChannelSelect::Green}, {"b", ChannelSelect::Blue}, {"a", ChannelSelect::Alpha}};
    for (auto& [name, value] : channels)
        if (o.channel == name) load.channel = value;
    auto hf = loadHeightfield(spec->base, load);
    if (!hf) return hf.error();
    if (spec->crop) hf = cropHeightfield(*hf, *spec->crop, o.source);
    if (!hf) return hf.error();
    return std::make_shared<const Heightfield>(std::move(*hf));
}

Result<std::shared_ptr<const Surface>> makeSurface(const SurfaceOptions& o,
                                                   std::shared_ptr<const Heightfield> hf) {
    const float depth = o.depth ? *o.depth : o.depthRatio * float(std::max(hf->width, hf->height));
    if (!std::isfinite(depth) || depth < 0.0f || depth > 1e6f)
        return makeError(ErrorKind::BadArgument, "depth {} is out of range (0 to 1e6 texels)", depth);
    if (!std::isfinite(o.depthRatio) || o.depthRatio < 0.0f)
        return makeError(ErrorKind::BadArgument, "--depth-ratio {} must be >= 0", o.depthRatio);
    if (o.edge != "clamp" && o.edge != "repeat")
        return makeError(ErrorKind::BadArgument, "--edge '{}': clamp or repeat", o.edge);
    const EdgeMode edge = o.edge == "repeat" ? EdgeMode::Repeat : EdgeMode::Clamp;
    return std::make_shared<const Surface>(std::move(hf), depth, edge);
}

Result<std::shared_ptr<const MapFile>> loadCheckedMaps(const std::string& path, const Surface& surface) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const MapFile>> cache;
    std::shared_ptr<const MapFile> file;
    {
        std::lock_guard lock(mutex);
        auto it = cache.find(path);
        if (it == cache.end()) {
            auto read = readMapFile(path);
            if (!read) return read.error();
            it = cache.emplace(path, std::make_shared<const MapFile>(std::move(*read))).first;
        }
        file = it->second;
    }
    if (Status s = checkMapSource(path, file->source, mapSourceOf(surface)); !s) return s.error();
    return file;
}

}  // namespace relief
