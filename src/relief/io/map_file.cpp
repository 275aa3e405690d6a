#include <relief/io/map_file.h>

#include <relief/core/heightfield.h>
#include <relief/io/exr_stream.h>
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

#include <cmath>

namespace relief {

namespace {

const char* const kChannelNames[] = {"c0", "c1", "c2", "c3", "c4", "c5", "c6", "c7"};
constexpr int kMaxChannels = 8;

std::string encodeParameters(const std::map<std::string, std::string>& parameters) {
    std::string text;
    for (const auto& [k, v] : parameters) text += (text.empty() ? "" : ";") + k + "=" + v;
    return text;
}

std::map<std::string, std::string> decodeParameters(const std::string& text) {
    std::map<std::string, std::string> parameters;
    size_t start = 0;
    while (start < text.size()) {
        size_t end = text.find(';', start);
        if (end == std::string::npos) end = text.size();
        const std::string item = text.substr(start, end - start);
        const size_t eq = item.find('=');
        if (eq != std::string::npos) parameters[item.substr(0, eq)] = item.substr(eq + 1);
        start = end + 1;
    }
    return parameters;
}

Imf::Header partHeader(const MapFile& file, const TechniqueMaps& t, const MapArray& a) {
    // Multi-part files need one display window for all parts: the heightfield's.
    const Imath::Box2i display(Imath::V2i(0, 0), Imath::V2i(std::max(1, file.source.width) - 1,
                                                            std::max(1, file.source.height) - 1));
    const Imath::Box2i data(Imath::V2i(0, 0), Imath::V2i(a.width - 1, a.height - 1));
    Imf::Header h(display, data);
    h.setName(t.technique + "/" + a.name);
    h.setType(Imf::SCANLINEIMAGE);
    for (int c = 0; c < a.channels; ++c) h.channels().insert(kChannelNames[c], Imf::Channel(Imf::FLOAT));
    h.insert("relief.version", Imf::IntAttribute(kMapFormatVersion));
    h.insert("relief.technique", Imf::StringAttribute(t.technique));
    h.insert("relief.array", Imf::StringAttribute(a.name));
    h.insert("relief.parameters", Imf::StringAttribute(encodeParameters(t.parameters)));
    h.insert("relief.source.hash", Imf::StringAttribute(fmt::format("{:016x}", file.source.heightfieldHash)));
    h.insert("relief.source.size", Imf::StringAttribute(fmt::format("{}x{}", file.source.width, file.source.height)));
    h.insert("relief.source.edge", Imf::StringAttribute(file.source.edge));
    h.insert("relief.source.depth", Imf::StringAttribute(fmt::format("{:.9g}", file.source.depth)));
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

Result<MapSource> readSource(const std::string& path, const Imf::Header& h) {
    const auto* hash = attribute<Imf::StringAttribute>(h, "relief.source.hash");
    const auto* size = attribute<Imf::StringAttribute>(h, "relief.source.size");
    const auto* edge = attribute<Imf::StringAttribute>(h, "relief.source.edge");
    const auto* depth = attribute<Imf::StringAttribute>(h, "relief.source.depth");
    MapSource s;
    if (!hash || !size || !edge || !depth ||
        std::sscanf(size->value().c_str(), "%dx%d", &s.width, &s.height) != 2)
        return makeError(ErrorKind::InvalidInput, "{}: not a relief map file (source attributes missing)", path);
    s.heightfieldHash = std::strtoull(hash->value().c_str(), nullptr, 16);
    s.edge = edge->value();
    s.depth = std::strtof(depth->value().c_str(), nullptr);
    return s;
}

Result<MapArray> readArray(const std::string& path, Imf::MultiPartInputFile& file, int part) {
    const Imf::Header& h = file.header(part);
    MapArray a;
    const auto* name = attribute<Imf::StringAttribute>(h, "relief.array");
    a.name = name ? name->value() : "";
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
    for (const TechniqueMaps& t : maps.techniques)
        for (const MapArray& a : t.arrays) {
            if (a.channels < 1 || a.channels > kMaxChannels || a.width < 1 || a.height < 1 ||
                a.data.size() != size_t(a.width) * size_t(a.height) * size_t(a.channels))
                return makeError(ErrorKind::Runtime, "{}: map array {}/{} is malformed", path, t.technique, a.name);
            headers.push_back(partHeader(maps, t, a));
            arrays.push_back(&a);
        }
    if (headers.empty()) return makeError(ErrorKind::BadArgument, "{}: no maps to write", path);
    return writeAtomically(path, [&](const std::string& temp) -> Status {
        try {
            Imf::MultiPartOutputFile file(temp.c_str(), headers.data(), int(headers.size()));
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

namespace {

// Every part must carry relief's attributes and one source; parts of a technique are grouped.
Result<MapFile> readParts(const std::string& path, Imf::MultiPartInputFile& file) {
    MapFile maps;
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        const auto* version = attribute<Imf::IntAttribute>(h, "relief.version");
        const auto* technique = attribute<Imf::StringAttribute>(h, "relief.technique");
        const auto* parameters = attribute<Imf::StringAttribute>(h, "relief.parameters");
        if (!version || !technique || !parameters)
            return makeError(ErrorKind::InvalidInput, "{}: not a relief map file (part {} lacks relief attributes)", path, p);
        if (version->value() != kMapFormatVersion)
            return makeError(ErrorKind::Unsupported, "{}: map format version {} (this relief reads {}); bake it again",
                             path, version->value(), kMapFormatVersion);
        auto source = readSource(path, h);
        if (!source) return source.error();
        if (p == 0) maps.source = *source;
        else if (source->heightfieldHash != maps.source.heightfieldHash)
            return makeError(ErrorKind::InvalidInput, "{}: parts come from different heightfields", path);
        auto array = readArray(path, file, p);
        if (!array) return array.error();
        TechniqueMaps* t = const_cast<TechniqueMaps*>(maps.find(technique->value()));
        if (!t) {
            maps.techniques.push_back({technique->value(), decodeParameters(parameters->value()), {}});
            t = &maps.techniques.back();
        }
        t->arrays.push_back(std::move(*array));
    }
    return maps;
}

// Files and bytes in memory alike: the header checks of exr_stream.h, then OpenEXR.
Result<MapFile> readMapFile(Result<FileReader> reader) {
    if (!reader) return reader.error();
    const std::string path = reader->path();
    try {
        limitExrSizes();
        if (auto problem = exrHeaderProblem(*reader))
            return makeError(ErrorKind::InvalidInput, "{}: cannot read map file: {}", path,
                             *problem);
        ExrInputStream stream(*reader);
        Imf::MultiPartInputFile file(stream);
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
    if (std::abs(stored.depth - current.depth) > 1e-6f * std::max(1.0f, current.depth))
        return makeError(ErrorKind::InvalidInput, "{}: maps were baked for depth {}, not {}", path, stored.depth, current.depth);
    return {};
}

}  // namespace relief
