// What the PNG and KTX2 map containers share: format names, storages and their exact codes, the
// relief keys both write (the EXR part attributes, plus the array list, checksums and storage),
// and the one way both readers turn those keys and decoded arrays into a checked MapFile.
#include <relief/io/map_container.h>

#include <cmath>
#include <cstdio>

namespace relief {

std::string_view toString(MapFormat format) {
    switch (format) {
        case MapFormat::Exr: return "exr";
        case MapFormat::Png: return "png";
        case MapFormat::Ktx2: return "ktx2";
    }
    return "?";
}

std::optional<MapFormat> mapFormatFromName(std::string_view name) {
    for (MapFormat f : {MapFormat::Exr, MapFormat::Png, MapFormat::Ktx2})
        if (toString(f) == name) return f;
    return std::nullopt;
}

std::optional<MapFormat> mapFormatFromPath(std::string_view path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot == std::string_view::npos || (slash != std::string_view::npos && dot < slash))
        return std::nullopt;
    std::string extension(path.substr(dot + 1));
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    return mapFormatFromName(extension);
}

int storageBits(MapStorage storage) {
    switch (storage) {
        case MapStorage::Unit8:
        case MapStorage::Int8: return 8;
        case MapStorage::Unit16:
        case MapStorage::Int16: return 16;
        case MapStorage::Float32: return 32;
    }
    return 32;
}

bool storageIsInteger(MapStorage storage) {
    return storage == MapStorage::Int8 || storage == MapStorage::Int16;
}

namespace {
constexpr std::pair<MapStorage, std::string_view> kStorageNames[] = {
    {MapStorage::Unit8, "unit8"},   {MapStorage::Unit16, "unit16"}, {MapStorage::Int8, "int8"},
    {MapStorage::Int16, "int16"},   {MapStorage::Float32, "float32"},
};

uint32_t codeMax(MapStorage storage) { return (1u << storageBits(storage)) - 1u; }
}  // namespace

std::string_view storageName(MapStorage storage) {
    for (const auto& [s, name] : kStorageNames)
        if (s == storage) return name;
    return "?";
}

std::optional<MapStorage> storageFromName(std::string_view name) {
    for (const auto& [s, n] : kStorageNames)
        if (n == name) return s;
    return std::nullopt;
}

float decodeCode(MapStorage storage, uint32_t code) {
    return storageIsInteger(storage) ? float(code) : float(code) / float(codeMax(storage));
}

uint32_t encodeCode(MapStorage storage, float value) {
    const float scaled = storageIsInteger(storage) ? value : value * float(codeMax(storage));
    return uint32_t(std::lrint(std::clamp(scaled, 0.0f, float(codeMax(storage)))));
}

namespace {
bool exactIn(const MapArray& array, MapStorage storage) {
    const float top = float(codeMax(storage));
    for (float v : array.data) {
        if (!(v >= 0.0f && v <= (storageIsInteger(storage) ? top : 1.0f))) return false;
        // Bit for bit, so that the texture decodes to the float the CPU tracer reads.
        if (std::bit_cast<uint32_t>(decodeCode(storage, encodeCode(storage, v))) !=
            std::bit_cast<uint32_t>(v))
            return false;
    }
    return true;
}
}  // namespace

std::optional<MapStorage> exactStorage(const MapArray& array, MapValueKind kind, MapFormat format) {
    if (format == MapFormat::Exr) return MapStorage::Float32;
    if (kind == MapValueKind::Unit)
        for (MapStorage s : {MapStorage::Unit8, MapStorage::Unit16})
            if (exactIn(array, s)) return s;
    if (format == MapFormat::Ktx2) return MapStorage::Float32;
    if (kind == MapValueKind::Integer)
        for (MapStorage s : {MapStorage::Int8, MapStorage::Int16})
            if (exactIn(array, s)) return s;
    return std::nullopt;
}

Status writeMapFile(const std::string& path, const MapFile& maps, MapFormat format,
                    std::span<const MapStorage> storages) {
    if (format == MapFormat::Exr) return writeMapFile(path, maps);
    size_t arrays = 0;
    for (const TechniqueMaps& t : maps.techniques) arrays += t.arrays.size();
    if (maps.techniques.size() != 1 || arrays == 0)
        return makeError(ErrorKind::BadArgument,
                         "{}: a {} map file holds the maps of one technique ({} given); bake one "
                         "technique per file, or write --format exr",
                         path, toString(format), maps.techniques.size());
    if (storages.size() != arrays)
        return makeError(ErrorKind::Runtime, "{}: {} storages for {} arrays", path,
                         storages.size(), arrays);
    return format == MapFormat::Png ? writePngMaps(path, maps, storages)
                                    : writeKtx2Maps(path, maps, storages);
}

// ---- The relief keys -------------------------------------------------------------------------

std::vector<std::pair<std::string, std::string>> containerKeys(const MapFile& maps,
                                                               MapStorage storage) {
    const std::vector<PartAttributes> parts = partAttributes(maps);
    std::string arrays, checksums;
    const TechniqueMaps& t = maps.techniques.front();
    for (size_t k = 0; k < parts.size(); ++k) {
        const MapArray& a = t.arrays[k];
        arrays += fmt::format("{}{}:{}x{}x{}", k ? "," : "", a.name, a.width, a.height, a.channels);
        checksums += (k ? "," : "") + parts[k].checksum;
    }
    const PartAttributes& p = parts.front();
    return {{"relief.version", std::to_string(kMapFormatVersion)},
            {"relief.technique", p.technique},
            {"relief.parameters", p.parameters},
            {"relief.source.hash", p.hash},
            {"relief.source.size", p.size},
            {"relief.source.edge", p.edge},
            {"relief.source.depth", p.depth},
            {"relief.parts", std::to_string(p.parts)},
            {"relief.arrays", arrays},
            {"relief.checksums", checksums},
            {"relief.storage", std::string(storageName(storage))}};
}

namespace {
std::vector<std::string> splitList(const std::string& text) {
    std::vector<std::string> items;
    size_t start = 0;
    while (start <= text.size()) {
        size_t comma = text.find(',', start);
        if (comma == std::string::npos) comma = text.size();
        items.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    return items;
}
}  // namespace

Result<ContainerKeys> parseContainerKeys(const std::string& path,
                                         const std::map<std::string, std::string>& keys) {
    ContainerKeys out;
    auto get = [&](const char* name) -> const std::string* {
        auto it = keys.find(name);
        return it == keys.end() ? nullptr : &it->second;
    };
    auto damaged = [&](const std::string& what) {
        return makeError(ErrorKind::InvalidInput, "{}: map file damaged: {}; bake it again", path,
                         what);
    };
    if (const std::string* v = get("relief.version")) {
        int version = 0;
        char tail = 0;
        if (std::sscanf(v->c_str(), "%d%c", &version, &tail) != 1)
            return damaged("relief.version '" + *v + "' is not a number");
        out.version = version;
    }
    const char* names[] = {"relief.technique",   "relief.parameters",  "relief.source.hash",
                           "relief.source.size", "relief.source.edge", "relief.source.depth",
                           "relief.parts",       "relief.arrays",      "relief.checksums",
                           "relief.storage"};
    for (const char* name : names)
        if (!get(name)) return out;  // not a relief map: addMapPart says so (or the version)
    PartAttributes p;
    p.technique = *get("relief.technique");
    p.parameters = *get("relief.parameters");
    p.hash = *get("relief.source.hash");
    p.size = *get("relief.source.size");
    p.edge = *get("relief.source.edge");
    p.depth = *get("relief.source.depth");
    char tail = 0;
    if (std::sscanf(get("relief.parts")->c_str(), "%d%c", &p.parts, &tail) != 1)
        return damaged("relief.parts is not a number");
    const auto storage = storageFromName(*get("relief.storage"));
    if (!storage) return damaged("relief.storage '" + *get("relief.storage") + "' is unknown");
    out.storage = *storage;
    const std::vector<std::string> arrays = splitList(*get("relief.arrays"));
    const std::vector<std::string> checksums = splitList(*get("relief.checksums"));
    if (arrays.size() != checksums.size() || arrays.size() > 64)
        return damaged("relief.arrays and relief.checksums do not pair up");
    for (size_t k = 0; k < arrays.size(); ++k) {
        ContainerArray a;
        const size_t colon = arrays[k].find(':');
        if (colon == std::string::npos) return damaged("relief.arrays is malformed");
        a.name = arrays[k].substr(0, colon);
        const std::string dims = arrays[k].substr(colon + 1);
        if (std::sscanf(dims.c_str(), "%dx%dx%d%c", &a.width, &a.height, &a.channels, &tail) != 3 ||
            a.width < 1 || a.height < 1 || a.width > kMaxDimension || a.height > kMaxDimension ||
            a.channels < 1 || a.channels > 4 ||
            dims != fmt::format("{}x{}x{}", a.width, a.height, a.channels))
            return damaged("relief.arrays entry '" + arrays[k] + "' is malformed");
        a.checksum = checksums[k];
        out.arrays.push_back(std::move(a));
    }
    out.common = p;
    return out;
}

Result<MapFile> assembleMaps(const std::string& path, const ContainerKeys& keys,
                             const std::function<Result<MapArray>(size_t index)>& decode) {
    MapFile maps;
    std::optional<PartAttributes> first;
    std::set<std::string> seen;
    if (!keys.common || keys.arrays.empty()) {
        if (Status s = addMapPart(path, maps, keys.version, std::nullopt, nullptr, "", 0, {}, first,
                                  seen);
            !s)
            return s.error();
        return makeError(ErrorKind::InvalidInput, "{}: not a relief map file", path);
    }
    for (size_t k = 0; k < keys.arrays.size(); ++k) {
        PartAttributes p = *keys.common;
        p.array = keys.arrays[k].name;
        p.index = int(k);
        if (Status s = addMapPart(path, maps, keys.version, p, &keys.arrays[k].checksum,
                                  p.technique + "/" + p.array, int(keys.arrays.size()),
                                  [&] { return decode(k); }, first, seen);
            !s)
            return s.error();
    }
    return maps;
}

}  // namespace relief
