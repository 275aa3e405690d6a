#include <relief/io/map_file.h>

#include <relief/core/heightfield.h>
#include <relief/io/exr_stream.h>
#include <relief/io/map_container.h>
#include <relief/io/image_write.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputPart.h>
#include <ImfIntAttribute.h>
#include <ImfMultiPartInputFile.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>
#include <ImfStringVectorAttribute.h>
#include <zlib.h>

#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>
#include <functional>
#include <set>

namespace relief {

namespace {

const char* const kChannelNames[] = {"c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7"};
constexpr int kMaxChannels = 8;

std::string encodeParameters(const std::map<std::string, std::string>& parameters) {
    std::string text;
    for (const auto& [k, v] : parameters) text += (text.empty() ? "" : ";") + k + "=" + v;
    return text;
}

bool isNumber(const std::string& text, double& value) {
    const char* end = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), end, value);
    return !text.empty() && ec == std::errc() && ptr == end && std::isfinite(value);
}

// Every item NAME=NUMBER with a name of [a-z0-9-] (what the builders write), else nullopt.
std::optional<std::map<std::string, std::string>> decodeParameters(const std::string& text) {
    std::map<std::string, std::string> parameters;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find(';', start);
        if (end == std::string::npos) end = text.size();
        const std::string item = text.substr(start, end - start);
        const size_t eq = item.find('=');
        double value = 0;
        if (eq == 0 || eq == std::string::npos || !isNumber(item.substr(eq + 1), value) ||
            item.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-") < eq ||
            !parameters.emplace(item.substr(0, eq), item.substr(eq + 1)).second)
            return std::nullopt;
        start = end + 1;
    }
    return parameters;
}

PartAttributes attributesOf(const MapFile& file, const TechniqueMaps& t, const MapArray& a,
                            int index, int parts) {
    return {t.technique,
            a.name,
            encodeParameters(t.parameters),
            fmt::format("{:016x}", file.source.heightfieldHash),
            fmt::format("{}x{}", file.source.width, file.source.height),
            file.source.edge,
            fmt::format("{:.9g}", file.source.depth),
            index,
            parts,
            {}};  // the checksum: partAttributes fills it in
}

// CRC-32 (zlib's, which libpng already links) over the part's relief attributes, its size and
// its floats as little-endian bytes. It is a guard against damage (a flipped byte, a truncated
// or edited block), not against forgery: a CRC detects every error burst up to 32 bits and all
// but 2^-32 of the others, which is what a map read back from disk needs.
uint32_t partChecksum(const PartAttributes& p, const MapArray& a) {
    uLong crc = crc32(0L, Z_NULL, 0);
    const std::string text =
        fmt::format("relief-map {}\n{}/{}\n{}\n{}\n{}\n{}\n{}\n{}x{}x{}\n{}/{}\n",
                    kMapFormatVersion, p.technique, p.array, p.parameters, p.hash, p.size, p.edge,
                    p.depth, a.width, a.height, a.channels, p.index, p.parts);
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(text.data()), text.size());
    if constexpr (std::endian::native == std::endian::little) {
        crc = crc32_z(crc, reinterpret_cast<const Bytef*>(a.data.data()),
                      a.data.size() * sizeof(float));
    } else {
        for (float v : a.data) {
            const uint32_t bits = std::bit_cast<uint32_t>(v);
            const Bytef bytes[4] = {Bytef(bits), Bytef(bits >> 8), Bytef(bits >> 16),
                                    Bytef(bits >> 24)};
            crc = crc32_z(crc, bytes, 4);
        }
    }
    return uint32_t(crc);
}

std::string checksumText(uint32_t crc) { return fmt::format("crc32:{:08x}", crc); }

Imf::Header partHeader(const MapFile& file, const PartAttributes& p, const MapArray& a) {
    // Multi-part files need one display window for all parts: the heightfield's.
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(std::max(1, file.source.width) - 1,
                                                            std::max(1, file.source.height) - 1));
    const Imath::Box2i data(Imath::V2i(0, 0), Imath::V2i(a.width - 1, a.height - 1));
    Imf::Header h(display, data);
    h.setName(p.technique + "/" + p.array);
    h.setType(Imf::SCANLINEIMAGE);
    for (int c = 0; c < a.channels; ++c) h.channels().insert(kChannelNames[c], Imf::Channel(Imf::FLOAT));
    h.insert("relief.version", Imf::IntAttribute(kMapFormatVersion));
    h.insert("relief.technique", Imf::StringAttribute(p.technique));
    h.insert("relief.array", Imf::StringAttribute(p.array));
    h.insert("relief.parameters", Imf::StringAttribute(p.parameters));
    h.insert("relief.source.hash", Imf::StringAttribute(p.hash));
    h.insert("relief.source.size", Imf::StringAttribute(p.size));
    h.insert("relief.source.edge", Imf::StringAttribute(p.edge));
    h.insert("relief.source.depth", Imf::StringAttribute(p.depth));
    h.insert("relief.parts", Imf::IntAttribute(p.parts));
    h.insert("relief.checksum", Imf::StringAttribute(checksumText(partChecksum(p, a))));
    return h;
}

Imf::FrameBuffer frameBuffer(const MapArray& a, float* data) {
    Imf::FrameBuffer fb;
    const size_t pixel = sizeof(float) * size_t(a.channels);
    for (int c = 0; c < a.channels; ++c)
        fb.insert(kChannelNames[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(data + c), pixel,
                                               pixel * size_t(a.width)));
    return fb;
}

template <class A>
const A* attribute(const Imf::Header& h, const char* name) {
    return h.findTypedAttribute<A>(name);
}

bool isName(const std::string& text) {
    return !text.empty() && text.size() <= 64 &&
           text.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-_+") == std::string::npos;
}

// The source attributes, each checked: 16 hex digits, WxH within the dimension limit, an edge
// mode relief knows and a finite depth in the range makeSurface accepts (a `nan` depth would
// otherwise pass every comparison in checkMapSource).
Result<MapSource> parseSource(const std::string& path, const PartAttributes& p) {
    MapSource s;
    auto bad = [&](const char* what, const std::string& value) {
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: relief.source.{} '{}' is not {}; "
                         "bake it again",
                         path, what, value,
                         std::string_view(what) == "hash"   ? "16 hex digits"
                         : std::string_view(what) == "size" ? "WxH within the size limit"
                         : std::string_view(what) == "edge" ? "clamp or repeat"
                                                            : "a depth from 0 to 1e6");
    };
    const char* hashEnd = p.hash.data() + p.hash.size();
    if (p.hash.size() != 16 ||
        std::from_chars(p.hash.data(), hashEnd, s.heightfieldHash, 16).ptr != hashEnd)
        return bad("hash", p.hash);
    char tail = 0;
    if (std::sscanf(p.size.c_str(), "%dx%d%c", &s.width, &s.height, &tail) != 2 || s.width < 1 ||
        s.height < 1 || s.width > kMaxDimension || s.height > kMaxDimension ||
        p.size != fmt::format("{}x{}", s.width, s.height))
        return bad("size", p.size);
    if (p.edge != "clamp" && p.edge != "repeat") return bad("edge", p.edge);
    s.edge = p.edge;
    double depth = 0;
    if (!isNumber(p.depth, depth) || depth < 0 || depth > 1e6) return bad("depth", p.depth);
    s.depth = float(depth);
    return s;
}

// A part's relief attributes; null when one is missing or has the wrong type.
std::optional<PartAttributes> readAttributes(const Imf::Header& h, int index) {
    const char* names[] = {"relief.technique",   "relief.array",       "relief.parameters",
                           "relief.source.hash", "relief.source.size", "relief.source.edge",
                           "relief.source.depth"};
    PartAttributes p;
    std::string* fields[] = {&p.technique, &p.array, &p.parameters, &p.hash,
                             &p.size,      &p.edge,  &p.depth};
    for (size_t k = 0; k < std::size(names); ++k) {
        const auto* a = attribute<Imf::StringAttribute>(h, names[k]);
        if (!a) return std::nullopt;
        *fields[k] = a->value();
    }
    const auto* parts = attribute<Imf::IntAttribute>(h, "relief.parts");
    if (!parts) return std::nullopt;
    p.parts = parts->value();
    p.index = index;
    return p;
}

Result<MapArray> readArray(const std::string& path, Imf::MultiPartInputFile& file, int part,
                           const std::string& name) {
    const Imf::Header& h = file.header(part);
    MapArray a;
    a.name = name;
    const Imath::Box2i window = h.dataWindow();
    const int64_t w = int64_t(window.max.x) - window.min.x + 1, ht = int64_t(window.max.y) - window.min.y + 1;
    a.channels = 0;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
        if (a.channels >= kMaxChannels || std::string(it.name()) != kChannelNames[a.channels] ||
            it.channel().type != Imf::FLOAT)
            return makeError(ErrorKind::InvalidInput, "{}: part '{}' has unexpected channels", path, h.name());
        ++a.channels;
    }
    if (a.channels == 0)
        return makeError(ErrorKind::InvalidInput, "{}: part '{}' has no channels", path, h.name());
    // The sample limit counts floats, so a part's channels count too (8 channels: 8 GiB otherwise).
    if (Status s = checkDimensions(path, w, ht, kDefaultMaxSamples / a.channels); !s) return s.error();
    a.width = int(w);
    a.height = int(ht);
    a.data.resize(size_t(w) * size_t(ht) * size_t(a.channels));
    Imf::InputPart in(file, part);
    // The frame buffer is addressed from the data window's origin.
    float* origin = a.data.data() - (int64_t(window.min.y) * w + window.min.x) * a.channels;
    in.setFrameBuffer(frameBuffer(a, origin));
    in.readPixels(window.min.y, window.max.y);
    for (float v : a.data)
        if (!std::isfinite(v))
            return makeError(ErrorKind::InvalidInput, "{}: part '{}' holds non-finite values", path, h.name());
    return a;
}

}  // namespace

const MapArray* TechniqueMaps::find(const std::string& name) const {
    for (const MapArray& a : arrays)
        if (a.name == name) return &a;
    return nullptr;
}

const TechniqueMaps* MapFile::find(const std::string& technique) const {
    for (const TechniqueMaps& t : techniques)
        if (t.technique == technique) return &t;
    return nullptr;
}

Status writeMapFile(const std::string& path, const MapFile& maps) {
    std::vector<Imf::Header> headers;
    std::vector<const MapArray*> arrays;
    int parts = 0;
    for (const TechniqueMaps& t : maps.techniques) parts += int(t.arrays.size());
    std::set<std::string> names;
    for (const TechniqueMaps& t : maps.techniques)
        for (const MapArray& a : t.arrays) {
            if (a.channels < 1 || a.channels > kMaxChannels || a.width < 1 || a.height < 1 ||
                a.data.size() != size_t(a.width) * size_t(a.height) * size_t(a.channels))
                return makeError(ErrorKind::Runtime, "{}: map array {}/{} is malformed", path, t.technique, a.name);
            // OpenEXR's own refusal of twin part names would reach the user as its message.
            if (!names.insert(t.technique + "/" + a.name).second)
                return makeError(ErrorKind::BadArgument, "{}: maps {}/{} given twice", path,
                                 t.technique, a.name);
            headers.push_back(
                partHeader(maps, attributesOf(maps, t, a, int(headers.size()), parts), a));
            arrays.push_back(&a);
        }
    if (headers.empty()) return makeError(ErrorKind::BadArgument, "{}: no maps to write", path);
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        try {
            Imf::MultiPartOutputFile file(temp.c_str(), headers.data(), int(headers.size()), false,
                                         exrThreads());
            for (size_t p = 0; p < arrays.size(); ++p) {
                Imf::OutputPart part(file, int(p));
                part.setFrameBuffer(frameBuffer(*arrays[p], const_cast<float*>(arrays[p]->data.data())));
                part.writePixels(arrays[p]->height);
            }
        } catch (const std::exception& e) {
            return makeError(ErrorKind::Io, "{}: writing maps failed: {}", path, e.what());
        }
        return {};
    });
}

Status addMapPart(const std::string& path, MapFile& maps, std::optional<int> version,
                  const std::optional<PartAttributes>& attributes, const std::string* checksum,
                  const std::string& partName, int partsInFile,
                  const std::function<Result<MapArray>()>& readData,
                  std::optional<PartAttributes>& first, std::set<std::string>& seen) {
    const int p = attributes ? attributes->index : int(seen.size());
    if (!version)
        return makeError(ErrorKind::InvalidInput, "{}: not a relief map file (part {} lacks relief attributes)", path, p);
    if (*version < kMapFormatVersion)
        return makeError(ErrorKind::Unsupported,
                         "{}: map format version {} has no checksum (this relief "
                         "reads version {} only); bake the maps again with relief bake",
                         path, *version, kMapFormatVersion);
    if (*version != kMapFormatVersion)
        return makeError(ErrorKind::Unsupported, "{}: map format version {} (this relief reads {}); bake it again",
                         path, *version, kMapFormatVersion);
    if (!attributes)
        return makeError(ErrorKind::InvalidInput,
                         "{}: not a relief map file (part {} lacks relief attributes)", path,
                         p);
    if (!checksum)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: part {} has no checksum; bake it again", path,
                         p);
    const std::string part = attributes->technique + "/" + attributes->array;
    auto parameters = decodeParameters(attributes->parameters);
    if (!isName(attributes->technique) || !isName(attributes->array) || partName != part ||
        !parameters)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: part {} ('{}') has malformed "
                         "names or parameters; bake it again",
                         path, p, partName);
    if (attributes->parts != partsInFile)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: it says {} parts but holds {}; "
                         "bake it again",
                         path, attributes->parts, partsInFile);
    if (!seen.insert(part).second)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: part '{}' appears twice", path, part);
    auto source = parseSource(path, *attributes);
    if (!source) return source.error();
    if (!first) {
        maps.source = *source;
        first = *attributes;
    } else if (attributes->hash != first->hash || attributes->size != first->size ||
               attributes->edge != first->edge || attributes->depth != first->depth)
        return makeError(ErrorKind::InvalidInput, "{}: parts come from different heightfields", path);
    auto array = readData();
    if (!array) return array.error();
    array->name = attributes->array;
    const std::string computed = checksumText(partChecksum(*attributes, *array));
    if (*checksum != computed)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: part '{}' has checksum {} but "
                         "its data and attributes give {}; bake it again",
                         path, part, *checksum, computed);
    TechniqueMaps* t = const_cast<TechniqueMaps*>(maps.find(attributes->technique));
    if (!t) {
        maps.techniques.push_back({attributes->technique, std::move(*parameters), {}});
        t = &maps.techniques.back();
    } else if (t->parameters != *parameters)
        return makeError(ErrorKind::InvalidInput,
                         "{}: map file damaged: the parts of '{}' disagree on "
                         "its parameters",
                         path, attributes->technique);
    t->arrays.push_back(std::move(*array));
    return {};
}

std::vector<PartAttributes> partAttributes(const MapFile& maps) {
    std::vector<PartAttributes> parts;
    int count = 0;
    for (const TechniqueMaps& t : maps.techniques) count += int(t.arrays.size());
    for (const TechniqueMaps& t : maps.techniques)
        for (const MapArray& a : t.arrays) {
            parts.push_back(attributesOf(maps, t, a, int(parts.size()), count));
            parts.back().checksum = checksumText(partChecksum(parts.back(), a));
        }
    return parts;
}

namespace {

// Every part must carry relief's attributes (each validated), one source and a checksum that
// matches its data; parts of a technique are grouped.
Result<MapFile> readParts(const std::string& path, Imf::MultiPartInputFile& file) {
    MapFile maps;
    std::optional<PartAttributes> first;
    std::set<std::string> seen;
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        const auto* version = attribute<Imf::IntAttribute>(h, "relief.version");
        const auto* checksum = attribute<Imf::StringAttribute>(h, "relief.checksum");
        const std::optional<PartAttributes> attributes = readAttributes(h, p);
        if (Status s = addMapPart(
                path, maps, version ? std::optional<int>(version->value()) : std::nullopt,
                attributes, checksum ? &checksum->value() : nullptr, h.hasName() ? h.name() : "", file.parts(),
                [&] { return readArray(path, file, p, attributes->array); }, first, seen);
            !s)
            return s.error();
    }
    return maps;
}

// Files and bytes in memory alike: the header checks of exr_stream.h, then OpenEXR.
Result<MapFile> readMapFile(Result<FileReader> reader) {
    if (!reader) return reader.error();
    const std::string path = reader->path();
    // The engine containers (map_png.cpp, map_ktx2.cpp) carry the same attributes and checks.
    if (detectFormat(reader->head()) == FileFormat::Png) return readPngMaps(*reader);
    if (isKtx2(reader->head())) return readKtx2Maps(*reader);
    try {
        limitExrSizes();
        if (auto problem = exrHeaderProblem(*reader))
            return makeError(ErrorKind::InvalidInput, "{}: cannot read map file: {}", path,
                             *problem);
        ExrInputStream stream(*reader);
        Imf::MultiPartInputFile file(stream, exrThreads());
        return readParts(path, file);
    } catch (const std::exception& e) {
        return makeError(ErrorKind::InvalidInput, "{}: cannot read map file: {}", path, e.what());
    }
}

}  // namespace

Result<MapFile> readMapFile(const std::string& path) { return readMapFile(FileReader::open(path)); }

Result<MapFile> readMapFile(std::span<const unsigned char> bytes, const std::string& name) {
    return readMapFile(FileReader::fromMemory(bytes, name));
}

Status checkMapSource(const std::string& path, const MapSource& stored, const MapSource& current) {
    if (stored.width != current.width || stored.height != current.height)
        return makeError(ErrorKind::InvalidInput, "{}: maps were baked for a {}x{} heightfield, this one is {}x{}",
                         path, stored.width, stored.height, current.width, current.height);
    if (stored.heightfieldHash != current.heightfieldHash)
        return makeError(ErrorKind::InvalidInput, "{}: stale maps: baked from a different heightfield (hash {:016x}, "
                         "this one {:016x}); bake again", path, stored.heightfieldHash, current.heightfieldHash);
    if (stored.edge != current.edge)
        return makeError(ErrorKind::InvalidInput, "{}: maps were baked for --edge {}, not {}", path, stored.edge, current.edge);
    // Negated so that a NaN on either side is a mismatch, never a pass.
    if (!(std::abs(stored.depth - current.depth) <= 1e-6f * std::max(1.0f, current.depth)))
        return makeError(ErrorKind::InvalidInput, "{}: maps were baked for depth {}, not {}", path, stored.depth, current.depth);
    return {};
}

}  // namespace relief
