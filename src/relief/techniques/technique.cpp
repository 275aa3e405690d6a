#include <relief/techniques/technique.h>

#include <relief/core/check.h>
#include <relief/core/parallel.h>

#include <algorithm>
#include <charconv>

namespace relief {

std::string_view toString(Contract contract) {
    switch (contract) {
        case Contract::Exact: return "exact";
        case Contract::Conservative: return "conservative";
        case Contract::Approximate: return "approximate";
    }
    return "?";
}

void traceAll(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    RELIEF_CHECK(rays.size() == hits.size());
    if (tracer.prefersOneBatch()) {
        tracer.traceBatch(rays, hits);
        return;
    }
    parallelRanges(int64_t(rays.size()), 256, [&](int64_t begin, int64_t end) {
        tracer.traceBatch(rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
    });
}

void traceFromAnywhere(const Tracer& tracer, const Surface& surface, std::span<Ray> rays,
                       std::span<Hit> hits) {
    RELIEF_CHECK(rays.size() == hits.size());
    std::vector<double> offsets(rays.size());
    for (size_t k = 0; k < rays.size(); ++k) rays[k] = surface.nearBox(rays[k], offsets[k]);
    traceAll(tracer, rays, hits);
    for (size_t k = 0; k < hits.size(); ++k) {
        if (!hits[k].hit) continue;
        if (hits[k].t > rays[k].tMax) {
            hits[k].hit = false;
            hits[k].t = kInfinity;
            continue;
        }
        hits[k].t = float(double(hits[k].t) + offsets[k]);
    }
}

double ParamValues::get(std::string_view name) const {
    auto it = m_values.find(name);
    RELIEF_CHECK(it != m_values.end());
    return it->second;
}

}  // namespace relief

namespace relief {

std::string_view toString(ParamRole role) {
    switch (role) {
        case ParamRole::Tuning: return "tuning";
        case ParamRole::IterationCap: return "iteration cap";
        case ParamRole::Variant: return "variant";
        case ParamRole::Encoding: return "encoding";
        case ParamRole::MapShape: return "map shape";
        case ParamRole::PhiMax: return "phi-max";
        case ParamRole::Visibility: return "visibility";
        case ParamRole::ImageSampling: return "image sampling";
        case ParamRole::RayWalk: return "ray walk";
    }
    return "?";
}

std::string_view toString(MapRounding rounding) {
    switch (rounding) {
        case MapRounding::Exact: return "exact";
        case MapRounding::Up: return "up";
        case MapRounding::Down: return "down";
    }
    return "?";
}

std::string_view toString(MapFilter filter) {
    return filter == MapFilter::Nearest ? "nearest" : "bilinear";
}

namespace {
bool arrayMatches(std::string_view pattern, std::string_view name) {
    if (!pattern.empty() && pattern.back() == '*')
        return name.substr(0, pattern.size() - 1) == pattern.substr(0, pattern.size() - 1);
    return pattern == name;
}

std::string vkFormatName(int bits, int channels, bool isFloat) {
    std::string name;
    const char* letters = channels == 1 ? "R" : channels == 2 ? "RG" : "RGBA";
    for (const char* c = letters; *c; ++c) name += fmt::format("{}{}", *c, bits);
    return name + (isFloat ? "_SFLOAT" : "_UNORM");
}
}  // namespace

std::vector<const MapChannelSpec*> channelsOf(const TechniqueInfo& info, std::string_view name) {
    std::vector<const MapChannelSpec*> specs;
    for (const MapChannelSpec& c : info.mapChannels)
        if (arrayMatches(c.array, name)) specs.push_back(&c);
    return specs;
}

MapValueKind arrayKind(const TechniqueInfo& info, std::string_view name) {
    const auto specs = channelsOf(info, name);
    if (specs.empty()) return MapValueKind::Float;
    for (const MapChannelSpec* c : specs)
        if (c->kind != specs.front()->kind) return MapValueKind::Float;
    return specs.front()->kind;
}

std::string exportFormats(const TechniqueInfo& info) {
    if (info.mapChannels.empty()) return {};
    std::vector<std::string_view> arrays;
    for (const MapChannelSpec& c : info.mapChannels)
        if (std::find(arrays.begin(), arrays.end(), c.array) == arrays.end())
            arrays.push_back(c.array);
    std::string formats = "exr";
    if (arrays.size() != 1)
        return formats + " only (its arrays differ in channels: no one PNG or KTX2 texture)";
    const auto specs = channelsOf(info, arrays.front());
    const int channels = int(specs.size()), padded = channels == 3 ? 4 : channels;
    const MapValueKind kind = arrayKind(info, arrays.front());
    const bool family = arrays.front().back() == '*';
    const std::string_view quantize = specs.front()->quantize;
    formats += ", ktx2 (";
    if (kind == MapValueKind::Unit && !quantize.empty())
        formats += fmt::format("{} / {} baked with {}, else {}", vkFormatName(8, padded, false),
                               vkFormatName(16, padded, false), quantize,
                               vkFormatName(32, padded, true));
    else
        formats += vkFormatName(32, padded, true);
    formats += family ? "; a max pyramid's levels as mip levels, same-size arrays as layers)" : ")";
    if (!family && kind == MapValueKind::Unit && !quantize.empty())
        formats += fmt::format(", png (8/16-bit, baked with {})", quantize);
    else if (!family && kind == MapValueKind::Integer)
        formats += ", png (8/16-bit integer codes)";
    return formats;
}

MapSource mapSourceOf(const Surface& surface) {
    return {surface.heightfield().contentHash(), surface.width(), surface.height(),
            std::string(toString(surface.edge())), surface.depth()};
}

const ParamSpec* paramWithRole(const TechniqueInfo& info, ParamRole role) {
    for (const ParamSpec& spec : info.params)
        if (spec.role == role) return &spec;
    return nullptr;
}

Result<std::vector<std::pair<std::string, double>>> parseParamList(std::string_view text) {
    std::vector<std::pair<std::string, double>> values;
    if (text.empty()) return values;
    for (size_t start = 0; start <= text.size();) {
        const size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view item = text.substr(start, comma - start);
        start = comma + 1;
        const size_t eq = item.find('=');
        double value = 0;
        const char* end = item.data() + item.size();
        std::from_chars_result parsed{item.data(), std::errc::invalid_argument};
        if (eq != std::string_view::npos && eq > 0)
            parsed = std::from_chars(item.data() + eq + 1, end, value);
        if (parsed.ec != std::errc() || parsed.ptr != end)
            return makeError(ErrorKind::BadArgument, "parameter '{}' in '{}': expected NAME=NUMBER",
                             item, text);
        values.emplace_back(std::string(item.substr(0, eq)), value);
    }
    return values;
}

const VariantSpec* variantOf(const TechniqueInfo& info, const ParamValues& params) {
    for (const VariantSpec& variant : info.variants) {
        const auto wanted = parseParamList(variant.params);
        RELIEF_CHECK(wanted.ok());  // rows are checked by RegistryTest
        bool matches = true;
        for (const auto& [name, value] : *wanted)
            matches = matches && params.has(name) && params.get(name) == value;
        if (matches) return &variant;
    }
    return nullptr;
}

Contract contractOf(const TechniqueInfo& info, const ParamValues& params) {
    const VariantSpec* variant = variantOf(info, params);
    const Contract contract = variant ? variant->contract : info.contract;
    // An exact walk stopped after N iterations (where 0 means no cap) promises nothing.
    const ParamSpec* cap = paramWithRole(info, ParamRole::IterationCap);
    if (contract == Contract::Exact && cap && cap->defaultValue == 0 && params.has(cap->name) &&
        params.get(cap->name) > 0)
        return Contract::Approximate;
    return contract;
}

}  // namespace relief
