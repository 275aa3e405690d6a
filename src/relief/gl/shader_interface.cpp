#include <relief/gl/shader_interface.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

namespace relief::gl {

SurfaceUniforms surfaceUniforms(const Surface& surface) {
    SurfaceUniforms u;
    u.size = ivec2(surface.width(), surface.height());
    u.depth = surface.depth();
    u.maxZ = surface.maxZ();
    u.edge = int32_t(surface.edge());
    return u;
}

Result<TraceUniforms> traceUniforms(const TechniqueInfo& info, const ParamValues& params) {
    if (info.params.size() > size_t(kMaxParams))
        return makeError(ErrorKind::Unsupported, "GL backend: technique '{}' has {} parameters, "
                         "the GL interface holds {}", info.name, info.params.size(), kMaxParams);
    TraceUniforms u;
    for (size_t k = 0; k < info.params.size(); ++k)
        u.params[k / 4][int(k % 4)] = float(params.get(info.params[k].name));
    return u;
}

std::string glslParamName(std::string_view paramName) {
    std::string name = "kParam";
    bool upper = true;
    for (char c : paramName) {
        if (c == '-' || c == '_') {
            upper = true;
            continue;
        }
        name += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
        upper = false;
    }
    return name;
}

namespace {

std::string constant(std::string_view name, int value) {
    return fmt::format("const int {} = {};\n", name, value);
}
std::string constant(std::string_view name, float value) {
    return fmt::format("const float {} = {:#.9g};\n", name, value);
}

// Natural order: runs of digits compare as numbers ("level2" < "level10").
bool naturalLess(std::string_view a, std::string_view b) {
    size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        const bool da = std::isdigit(static_cast<unsigned char>(a[i])) != 0;
        const bool db = std::isdigit(static_cast<unsigned char>(b[j])) != 0;
        if (da && db) {
            size_t ei = i, ej = j;
            while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
            while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
            std::string_view na = a.substr(i, ei - i), nb = b.substr(j, ej - j);
            while (na.size() > 1 && na[0] == '0') na.remove_prefix(1);
            while (nb.size() > 1 && nb[0] == '0') nb.remove_prefix(1);
            if (na.size() != nb.size()) return na.size() < nb.size();
            if (na != nb) return na < nb;
            i = ei;
            j = ej;
            continue;
        }
        if (a[i] != b[j]) return a[i] < b[j];
        ++i;
        ++j;
    }
    return a.size() - i < b.size() - j;
}

template <class T, class Get>
std::string constantArray(std::string_view type, std::string_view name,
                          const std::vector<const MapArray*>& arrays, Get&& get) {
    std::string text = fmt::format("const {} {}[kMapCount] = {}[](", type, name, type);
    for (size_t k = 0; k < arrays.size(); ++k)
        text += fmt::format("{}{}", k ? ", " : "", T(get(*arrays[k])));
    return text + ");\n";
}

}  // namespace

std::string glslMapName(std::string_view name) {
    std::string out;
    bool upper = true;
    for (char c : name) {
        if (c == '+' || c == '-') {
            out += c == '+' ? "Plus" : "Minus";
            upper = true;
        } else if (std::isalnum(static_cast<unsigned char>(c))) {
            out += upper ? char(std::toupper(static_cast<unsigned char>(c))) : c;
            upper = false;
        } else {
            upper = true;
        }
    }
    return out;
}

std::vector<const MapArray*> mapOrder(const TechniqueMaps& maps) {
    std::vector<const MapArray*> arrays;
    for (const MapArray& a : maps.arrays) arrays.push_back(&a);
    std::stable_sort(arrays.begin(), arrays.end(), [](const MapArray* a, const MapArray* b) {
        return naturalLess(a->name, b->name);
    });
    return arrays;
}

std::vector<float> packMaps(const TechniqueMaps& maps) {
    std::vector<float> data;
    for (const MapArray* a : mapOrder(maps)) data.insert(data.end(), a->data.begin(), a->data.end());
    return data;
}

std::string glslMapInterface(const TechniqueMaps* maps) {
    const std::vector<const MapArray*> arrays =
        maps ? mapOrder(*maps) : std::vector<const MapArray*>{};
    std::string text = constant("kMapsBinding", kMapsBinding);
    text += constant("kMapCount", int(arrays.size()));
    if (arrays.empty()) return text;
    for (size_t k = 0; k < arrays.size(); ++k) {
        const std::string name = glslMapName(arrays[k]->name);
        std::string upper;
        for (char c : name) upper += char(std::toupper(static_cast<unsigned char>(c)));
        text += constant("kMap" + name, int(k));
        text += fmt::format("#define RELIEF_MAP_{} 1\n", upper);
    }
    std::vector<uint32_t> offsets;
    uint32_t offset = 0;
    for (const MapArray* a : arrays) {
        offsets.push_back(offset);
        offset += uint32_t(a->data.size());
    }
    text += "const uint kMapOffset[kMapCount] = uint[](";
    for (size_t k = 0; k < offsets.size(); ++k) text += fmt::format("{}{}u", k ? ", " : "", offsets[k]);
    text += ");\n";
    text += constantArray<int>("int", "kMapWidth", arrays, [](const MapArray& a) { return a.width; });
    text += constantArray<int>("int", "kMapHeight", arrays, [](const MapArray& a) { return a.height; });
    text += constantArray<int>("int", "kMapChannels", arrays,
                               [](const MapArray& a) { return a.channels; });
    for (const auto& [key, value] : maps->parameters) {
        float number = 0.0f;
        const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
        if (ec == std::errc() && end == value.data() + value.size() && std::isfinite(number)) {
            // The #define lets a tracer accept maps baked before a parameter existed.
            const std::string name = "kMapParam" + glslParamName(key).substr(6);
            text += constant(name, number) + "#define HAS_" + name + "\n";
        }
    }
    text += "layout(std430, binding = kMapsBinding) readonly buffer Maps { float maps[]; };\n";
    text += "float mapTexel(int map, int x, int y, int channel) {\n"
            "    return maps[kMapOffset[map] +\n"
            "                uint((y * kMapWidth[map] + x) * kMapChannels[map] + channel)];\n"
            "}\n";
    return text;
}

std::string glslInterface(const TechniqueInfo* info, const TechniqueMaps* maps) {
    std::string text = "// Generated by relief::gl::glslInterface (shader_interface.h)\n";
    text += constant("kSurfaceBinding", kSurfaceBinding);
    text += constant("kTraceBinding", kTraceBinding);
    text += constant("kCameraBinding", kCameraBinding);
    text += constant("kMeshBinding", kMeshBinding);
    text += constant("kRaysBinding", kRaysBinding);
    text += constant("kHitsBinding", kHitsBinding);
    text += constant("kHeightsBinding", kHeightsBinding);
    text += constant("kLocalSize", kLocalSize);
    text += constant("kTileSize", kTileSize);
    text += constant("kMaxParams", kMaxParams);
    text += constant("kEdgeClamp", int(EdgeMode::Clamp));
    text += constant("kEdgeRepeat", int(EdgeMode::Repeat));
    text += constant("kRepeatTravelFactor", Surface::kRepeatTravelFactor);
    text += constant("kMaxOriginCoordinate", Surface::kMaxOriginCoordinate);
    text += constant("kFloatEpsilon", std::numeric_limits<float>::epsilon());
    text += constant("kIntMax", std::numeric_limits<int>::max());
    if (info) {
        // The row's own constants (TechniqueInfo::glslConstants), defined in its C++ headers.
        for (const GlslConstant& c : info->glslConstants)
            text += c.integer ? constant(c.name, int(c.value)) : constant(c.name, float(c.value));
        for (size_t k = 0; k < info->params.size(); ++k)
            text += constant(glslParamName(info->params[k].name), int(k));
    }
    text += glslMapInterface(maps);
    text += glslStruct<RayRecord>();
    text += glslStruct<HitRecord>();
    text += glslUniformBlock<SurfaceUniforms>("kSurfaceBinding", "surfaceUniforms");
    text += glslUniformBlock<TraceUniforms>("kTraceBinding", "traceUniforms");
    text += glslUniformBlock<CameraUniforms>("kCameraBinding", "camera");
    text += glslUniformBlock<MeshUniforms>("kMeshBinding", "mesh");
    return text;
}

}  // namespace relief::gl
