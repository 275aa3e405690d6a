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

Result<Heightfield> loadGenerator(const std::string& spec, const LoadOptions& options) {
    // gen:NAME:WxH[:seed]
    std::vector<std::string_view> parts;
    std::string_view rest(spec);
    for (size_t pos; (pos = rest.find(':')) != std::string_view::npos; rest = rest.substr(pos + 1))
        parts.push_back(rest.substr(0, pos));
    parts.push_back(rest);
    int64_t w = 0, h = 0, seed = 1;
    if (parts.size() < 3 || parts.size() > 4 || !parseSize(parts[2], w, h) ||
        (parts.size() == 4 && !parseInt(parts[3], seed)))
        return makeError(ErrorKind::BadArgument,
                         "'{}': a generator is written gen:NAME:WxH[:seed], e.g. gen:fbm:512x512:7",
                         spec);
    if (Status s = checkDimensions(spec, w, h, options.maxSamples); !s) return s.error();
    if (Status s = reserveMemory(w * h * int64_t(sizeof(float)), fmt::format("{}: generating", spec)); !s)
        return s.error();
    return generateHeightfield(parts[1], int(w), int(h), uint64_t(seed));
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

Result<Heightfield> loadHeightfield(const std::string& source, const LoadOptions& options) {
    auto loaded = source.rfind("gen:", 0) == 0 ? loadGenerator(source, options)
                                                : loadHeightfieldFile(source, options);
    if (!loaded) return loaded;
    if (options.invert)
        for (float& v : loaded->samples) v = 1.0f - v;
    return loaded;
}

}  // namespace relief
