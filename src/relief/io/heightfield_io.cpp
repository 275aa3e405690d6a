#include <relief/io/heightfield_io.h>

#include <relief/core/generators.h>
#include <relief/core/memory_budget.h>

#include <charconv>

namespace relief {

namespace {

bool parseInt(std::string_view text, int64_t& value) {
    auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && ptr == text.data() + text.size();
}

// "WxH" → width, height.
bool parseSize(std::string_view text, int64_t& w, int64_t& h) {
    const size_t x = text.find('x');
    return x != std::string_view::npos && parseInt(text.substr(0, x), w) &&
           parseInt(text.substr(x + 1), h);
}

struct GeneratorSpec {
    std::string_view name;
    int64_t width = 0, height = 0, seed = 1;
};

// gen:NAME:WxH[:seed]
Result<GeneratorSpec> parseGenerator(const std::string& spec, const LoadOptions& options) {
    std::vector<std::string_view> parts;
    std::string_view rest(spec);
    for (size_t pos; (pos = rest.find(':')) != std::string_view::npos; rest = rest.substr(pos + 1))
        parts.push_back(rest.substr(0, pos));
    parts.push_back(rest);
    GeneratorSpec g;
    if (parts.size() < 3 || parts.size() > 4 || !parseSize(parts[2], g.width, g.height) ||
        (parts.size() == 4 && !parseInt(parts[3], g.seed)))
        return makeError(ErrorKind::BadArgument,
                         "'{}': a generator is written gen:NAME:WxH[:seed], e.g. gen:fbm:512x512:7",
                         spec);
    g.name = parts[1];
    if (Status s = checkDimensions(spec, g.width, g.height, options.maxSamples); !s) return s.error();
    return g;
}

Result<Heightfield> loadGenerator(const std::string& spec, const LoadOptions& options) {
    auto g = parseGenerator(spec, options);
    if (!g) return g.error();
    if (Status s = reserveMemory(g->width * g->height * int64_t(sizeof(float)),
                                 fmt::format("{}: generating", spec));
        !s)
        return s.error();
    return generateHeightfield(g->name, int(g->width), int(g->height), uint64_t(g->seed));
}

}  // namespace

Result<RawLayout> parseRawLayout(const std::string& text) {
    RawLayout layout;
    const size_t colon = text.find(':');
    int64_t w = 0, h = 0;
    if (colon == std::string::npos || !parseSize(std::string_view(text).substr(0, colon), w, h))
        return makeError(ErrorKind::BadArgument, "--raw '{}': expected WxH:u8|u16|f32", text);
    const std::string type = text.substr(colon + 1);
    if (type == "u8") layout.type = RawLayout::Type::U8;
    else if (type == "u16") layout.type = RawLayout::Type::U16;
    else if (type == "f32") layout.type = RawLayout::Type::F32;
    else return makeError(ErrorKind::BadArgument, "--raw '{}': type must be u8, u16 or f32", text);
    if (Status s = checkDimensions("--raw", w, h); !s) return s.error();
    layout.width = int(w);
    layout.height = int(h);
    return layout;
}

Result<Heightfield> loadHeightfieldFile(const std::string& path, const LoadOptions& options);

Result<ImageRgb8> loadGeneratorColor(const std::string& source) {
    if (source.rfind("gen:", 0) != 0)
        return makeError(ErrorKind::BadArgument,
                         "{}: a generated colour map needs a generator source gen:NAME:WxH[:seed]",
                         source);
    auto g = parseGenerator(source, {});
    if (!g) return g.error();
    if (Status s = reserveMemory(g->width * g->height * int64_t(sizeof(Rgb8) + sizeof(double)),
                                 fmt::format("{}: generating its colour map", source));
        !s)
        return s.error();
    return generateColorMap(g->name, int(g->width), int(g->height), uint64_t(g->seed));
}

Result<Heightfield> loadHeightfield(const std::string& source, const LoadOptions& options) {
    auto loaded = source.rfind("gen:", 0) == 0 ? loadGenerator(source, options)
                                                : loadHeightfieldFile(source, options);
    if (!loaded) return loaded;
    if (options.invert)
        for (float& v : loaded->samples) v = 1.0f - v;
    return loaded;
}

}  // namespace relief
