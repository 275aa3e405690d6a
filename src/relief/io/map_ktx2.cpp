// Maps as KTX2 (Khronos KTX File Format 2.0; docs/maps.md), written and read by hand: Debian 12
// packages no KTX library. One file is one texture: one array, several arrays of one size as array
// layers, or a max pyramid's levels as mip levels (level 0 first in the level index, the data laid
// out smallest level first, each level aligned to lcm(texel size, 4); the base is padded to powers
// of two so that every level fits the mip chain, padding texels 0). VkFormats R8/R8G8/R8G8B8A8 and
// R16/R16G16/R16G16B16A16 UNORM, R32/R32G32/R32G32B32A32 SFLOAT, a 3-channel array padded to 4
// with 0; a basic Data Format Descriptor for the format; key/value data KTXorientation "rd",
// KTXwriter and the relief keys of map_container.h. No supercompression.
#include <relief/io/map_container.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <numeric>

namespace relief {

namespace {

constexpr unsigned char kIdentifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0',
                                           0xBB, '\r', '\n', 0x1A, '\n'};
constexpr size_t kHeaderBytes = 80;  // identifier, header, index
constexpr size_t kLevelEntryBytes = 24;
constexpr uint32_t kMaxLevels = 20, kMaxLayers = 64;

struct VkFormatInfo {
    uint32_t vkFormat;
    int bits, components;
    bool isFloat;
};
constexpr VkFormatInfo kFormats[] = {
    {9, 8, 1, false},   {16, 8, 2, false},   {37, 8, 4, false},    // R8, R8G8, R8G8B8A8 UNORM
    {70, 16, 1, false}, {77, 16, 2, false},  {91, 16, 4, false},   // R16 .. R16G16B16A16 UNORM
    {100, 32, 1, true}, {103, 32, 2, true},  {109, 32, 4, true},   // R32 .. R32G32B32A32 SFLOAT
};

const VkFormatInfo* formatOf(int bits, int components, bool isFloat) {
    for (const VkFormatInfo& f : kFormats)
        if (f.bits == bits && f.components == components && f.isFloat == isFloat) return &f;
    return nullptr;
}
const VkFormatInfo* formatOf(uint32_t vkFormat) {
    for (const VkFormatInfo& f : kFormats)
        if (f.vkFormat == vkFormat) return &f;
    return nullptr;
}
int texelBytes(const VkFormatInfo& f) { return f.bits / 8 * f.components; }
size_t levelAlignment(const VkFormatInfo& f) { return std::lcm(size_t(texelBytes(f)), size_t(4)); }

void put32(std::vector<unsigned char>& out, uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back((unsigned char)(v >> (8 * k)));
}
void set32(std::vector<unsigned char>& out, size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) out[at + size_t(k)] = (unsigned char)(v >> (8 * k));
}
void set64(std::vector<unsigned char>& out, size_t at, uint64_t v) {
    set32(out, at, uint32_t(v));
    set32(out, at + 4, uint32_t(v >> 32));
}
uint32_t get32(std::span<const unsigned char> in, size_t at) {
    return uint32_t(in[at]) | uint32_t(in[at + 1]) << 8 | uint32_t(in[at + 2]) << 16 |
           uint32_t(in[at + 3]) << 24;
}
uint64_t get64(std::span<const unsigned char> in, size_t at) {
    return uint64_t(get32(in, at)) | uint64_t(get32(in, at + 4)) << 32;
}

// The basic descriptor block of Khronos Data Format 1.3 for an uncompressed RGBA-ordered format:
// RGBSDA model, BT.709 primaries, linear transfer, one sample per channel (R, G, B, A = ids 0, 1,
// 2, 15); UNORM samples span 0 .. 2^bits − 1, float samples are signed floats spanning −1 .. 1.
std::vector<unsigned char> dataFormatDescriptor(const VkFormatInfo& f) {
    std::vector<unsigned char> d;
    const uint32_t blockSize = 24 + 16 * uint32_t(f.components);
    put32(d, 4 + blockSize);          // dfdTotalSize
    put32(d, 0);                      // vendorId KHRONOS, descriptorType BASICFORMAT
    put32(d, 2u | blockSize << 16);   // versionNumber 2 (1.3), descriptorBlockSize
    put32(d, 1u | 1u << 8 | 1u << 16);  // model RGBSDA, primaries BT709, transfer LINEAR, flags 0
    put32(d, 0);                      // texel block 1×1×1×1
    put32(d, uint32_t(texelBytes(f)));  // bytesPlane0
    put32(d, 0);                      // bytesPlane4..7
    constexpr uint32_t kChannelIds[] = {0, 1, 2, 15};
    for (int c = 0; c < f.components; ++c) {
        const uint32_t qualifiers = f.isFloat ? 0x80u | 0x40u : 0u;  // FLOAT | SIGNED
        put32(d, uint32_t(c * f.bits) | uint32_t(f.bits - 1) << 16 |
                     (kChannelIds[c] | qualifiers) << 24);
        put32(d, 0);  // sample position
        put32(d, f.isFloat ? 0xBF800000u : 0u);
        put32(d, f.isFloat ? 0x3F800000u : uint32_t((1ull << f.bits) - 1));
    }
    return d;
}

// What one file's arrays form: the base size, layers (0: not an array texture) and levels.
struct Texture {
    int width = 0, height = 0;
    uint32_t layers = 0, levels = 1;
    bool mips = false;
    int levelWidth(uint32_t level) const { return std::max(1, width >> level); }
    int levelHeight(uint32_t level) const { return std::max(1, height >> level); }
};

// A max pyramid: level L is ceil(w0 / 2^L) × ceil(h0 / 2^L) and the last is 1×1.
bool isPyramid(std::span<const MapArray> arrays) {
    const int w0 = arrays.front().width, h0 = arrays.front().height;
    for (size_t level = 0; level < arrays.size(); ++level) {
        const int w = ((w0 - 1) >> level) + 1, h = ((h0 - 1) >> level) + 1;
        if (arrays[level].width != w || arrays[level].height != h) return false;
    }
    return arrays.back().width == 1 && arrays.back().height == 1 &&
           (arrays.size() == 1 || arrays[arrays.size() - 2].width * arrays[arrays.size() - 2].height > 1);
}

Result<Texture> textureOf(const std::string& path, const TechniqueMaps& t) {
    const std::vector<MapArray>& a = t.arrays;
    Texture tex{a.front().width, a.front().height};
    for (const MapArray& x : a)
        if (x.channels != a.front().channels)
            return makeError(ErrorKind::BadArgument,
                             "{}: {} arrays have different channel counts and a KTX2 file holds "
                             "one texture: write --format exr",
                             path, t.technique);
    if (a.size() == 1) return tex;
    const bool sameSize = std::all_of(a.begin(), a.end(), [&](const MapArray& x) {
        return x.width == tex.width && x.height == tex.height;
    });
    if (sameSize && a.size() <= kMaxLayers) {
        tex.layers = uint32_t(a.size());
        return tex;
    }
    if (isPyramid(a) && a.size() <= kMaxLevels) {
        tex.mips = true;
        tex.levels = uint32_t(a.size());
        tex.width = int(std::bit_ceil(unsigned(tex.width)));
        tex.height = int(std::bit_ceil(unsigned(tex.height)));
        return tex;
    }
    return makeError(ErrorKind::BadArgument,
                     "{}: {} arrays are neither one size (layers) nor a max pyramid (mip levels), "
                     "and a KTX2 file holds one texture: write --format exr",
                     path, t.technique);
}

// The widest storage of the arrays (8-bit codes are exact at 16 bits as well: k/255 = 257k/65535).
MapStorage unified(std::span<const MapStorage> storages) {
    MapStorage s = storages.front();
    for (MapStorage x : storages)
        if (storageBits(x) > storageBits(s) || x == MapStorage::Float32) s = x;
    return s;
}

void putTexel(std::vector<unsigned char>& out, size_t at, const VkFormatInfo& f, MapStorage storage,
              float value) {
    if (f.isFloat) {
        set32(out, at, std::bit_cast<uint32_t>(value));
        return;
    }
    const uint32_t code = encodeCode(storage, value);
    out[at] = (unsigned char)code;
    if (f.bits == 16) out[at + 1] = (unsigned char)(code >> 8);
}

float getTexel(std::span<const unsigned char> in, size_t at, const VkFormatInfo& f,
               MapStorage storage) {
    if (f.isFloat) return std::bit_cast<float>(get32(in, at));
    const uint32_t code = f.bits == 16 ? uint32_t(in[at]) | uint32_t(in[at + 1]) << 8 : in[at];
    return decodeCode(storage, code);
}

}  // namespace

bool isKtx2(std::span<const unsigned char> head) {
    return head.size() >= sizeof kIdentifier &&
           std::equal(std::begin(kIdentifier), std::end(kIdentifier), head.begin());
}

Status writeKtx2Maps(const std::string& path, const MapFile& maps,
                     std::span<const MapStorage> storages) {
    const TechniqueMaps& t = maps.techniques.front();
    auto tex = textureOf(path, t);
    if (!tex) return tex.error();
    const MapStorage storage = unified(storages);
    if (storageIsInteger(storage))
        return makeError(ErrorKind::Runtime, "{}: integer codes are for PNG only", path);
    const int channels = t.arrays.front().channels;
    const VkFormatInfo* f = formatOf(storageBits(storage), channels == 3 ? 4 : channels,
                                     storage == MapStorage::Float32);
    if (!f)
        return makeError(ErrorKind::BadArgument, "{}: {} channels fit no KTX2 format relief "
                         "writes: write --format exr", path, channels);

    std::vector<unsigned char> out(kIdentifier, kIdentifier + sizeof kIdentifier);
    for (uint32_t v : {f->vkFormat, uint32_t(f->bits / 8), uint32_t(tex->width),
                       uint32_t(tex->height), 0u, tex->layers, 1u, tex->levels, 0u})
        put32(out, v);
    const size_t index = out.size();
    out.resize(kHeaderBytes + kLevelEntryBytes * tex->levels, 0);
    const std::vector<unsigned char> dfd = dataFormatDescriptor(*f);
    set32(out, index, uint32_t(out.size()));
    set32(out, index + 4, uint32_t(dfd.size()));
    out.insert(out.end(), dfd.begin(), dfd.end());

    auto keys = containerKeys(maps, storage);
    keys.push_back({"KTXorientation", "rd"});
    keys.push_back({"KTXwriter", "relief (map export, hand-written KTX2)"});
    std::sort(keys.begin(), keys.end());  // the spec orders keys by their bytes
    const size_t kvd = out.size();
    for (const auto& [key, value] : keys) {
        put32(out, uint32_t(key.size() + 1 + value.size() + 1));
        out.insert(out.end(), key.begin(), key.end());
        out.push_back(0);
        out.insert(out.end(), value.begin(), value.end());
        out.push_back(0);
        while (out.size() % 4) out.push_back(0);
    }
    set32(out, index + 8, uint32_t(kvd));
    set32(out, index + 12, uint32_t(out.size() - kvd));
    // sgdByteOffset and sgdByteLength stay 0: no supercompression global data.

    const uint32_t layers = std::max(1u, tex->layers);
    for (uint32_t level = tex->levels; level-- > 0;) {
        while (out.size() % levelAlignment(*f)) out.push_back(0);
        const int w = tex->levelWidth(level), h = tex->levelHeight(level);
        const size_t start = out.size();
        const size_t bytes = size_t(w) * size_t(h) * size_t(texelBytes(*f)) * layers;
        out.resize(start + bytes, 0);
        for (uint32_t layer = 0; layer < layers; ++layer) {
            const MapArray& a = t.arrays[tex->mips ? level : layer];
            const size_t layerStart = start + size_t(layer) * size_t(w) * size_t(h) * size_t(texelBytes(*f));
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x)
                    for (int c = 0; c < a.channels; ++c)
                        putTexel(out,
                                 layerStart + (size_t(y) * size_t(w) + size_t(x)) * size_t(texelBytes(*f)) +
                                     size_t(c * f->bits / 8),
                                 *f, storage,
                                 a.data[(size_t(y) * size_t(a.width) + size_t(x)) * size_t(a.channels) + size_t(c)]);
        }
        const size_t entry = kHeaderBytes + kLevelEntryBytes * level;
        set64(out, entry, start);
        set64(out, entry + 8, bytes);
        set64(out, entry + 16, bytes);
    }
    return writeBytes(path, out);
}

Result<MapFile> readKtx2Maps(FileReader& file) {
    const std::string path = file.path();
    auto all = file.readAll();
    if (!all) return all.error();
    const std::span<const unsigned char> in = *all;
    auto bad = [&](const std::string& what) -> Error {
        return makeError(ErrorKind::InvalidInput, "{}: corrupt KTX2 map file: {}", path, what);
    };
    if (in.size() < kHeaderBytes || !isKtx2(in)) return bad("shorter than its header");
    const uint32_t vkFormat = get32(in, 12), typeSize = get32(in, 16), width = get32(in, 20),
                   height = get32(in, 24), depth = get32(in, 28), layers = get32(in, 32),
                   faces = get32(in, 36), levels = get32(in, 40), scheme = get32(in, 44);
    const VkFormatInfo* f = formatOf(vkFormat);
    if (!f) return bad(fmt::format("VkFormat {} is not one relief writes", vkFormat));
    if (typeSize != uint32_t(f->bits / 8) || depth != 0 || faces != 1 || scheme != 0 ||
        levels < 1 || levels > kMaxLevels || layers > kMaxLayers || width < 1 || height < 1 ||
        width > uint32_t(kMaxDimension) || height > uint32_t(kMaxDimension))
        return bad(fmt::format("header (type size {}, {}x{}x{}, {} layers, {} faces, {} levels, "
                               "supercompression {}) is not a 2D texture relief writes",
                               typeSize, width, height, depth, layers, faces, levels, scheme));
    const Texture tex{int(width), int(height), layers, levels, levels > 1};
    const size_t levelIndexEnd = kHeaderBytes + kLevelEntryBytes * levels;
    if (in.size() < levelIndexEnd) return bad("the level index runs past the end of the file");
    const uint32_t dfdOffset = get32(in, 48), dfdLength = get32(in, 52), kvdOffset = get32(in, 56),
                   kvdLength = get32(in, 60);
    const uint64_t sgdLength = get64(in, 72);
    const std::vector<unsigned char> dfd = dataFormatDescriptor(*f);
    if (dfdOffset != levelIndexEnd || dfdLength != dfd.size() ||
        uint64_t(dfdOffset) + dfdLength > in.size() ||
        !std::equal(dfd.begin(), dfd.end(), in.begin() + dfdOffset))
        return bad("its data format descriptor is not the one of its VkFormat");
    if (sgdLength != 0 || uint64_t(kvdOffset) + kvdLength > in.size())
        return bad("key/value or supercompression data out of place");

    std::map<std::string, std::string> keys;
    for (size_t at = kvdOffset; at < size_t(kvdOffset) + kvdLength;) {
        if (at + 4 > size_t(kvdOffset) + kvdLength) return bad("a key/value entry is cut short");
        const uint32_t length = get32(in, at);
        if (length < 2 || at + 4 + length > size_t(kvdOffset) + kvdLength)
            return bad("a key/value entry's length runs past the key/value data");
        const char* text = reinterpret_cast<const char*>(in.data() + at + 4);
        const size_t keyLength = strnlen(text, length);
        if (keyLength == 0 || keyLength == length) return bad("a key is not NUL-terminated");
        std::string value(text + keyLength + 1, length - keyLength - 1);
        if (!value.empty() && value.back() == '\0') value.pop_back();
        keys[std::string(text, keyLength)] = std::move(value);
        at += 4 + length;
        at = (at + 3) & ~size_t(3);
    }
    auto parsed = parseContainerKeys(path, keys);
    if (!parsed) return parsed.error();
    const ContainerKeys& k = *parsed;
    if (k.common) {
        const size_t n = k.arrays.size();
        const bool storageFits = k.storage == MapStorage::Float32
                                     ? f->isFloat
                                     : !f->isFloat && !storageIsInteger(k.storage) &&
                                           storageBits(k.storage) == f->bits;
        if (!storageFits)
            return bad(fmt::format("VkFormat {} cannot hold relief.storage {}", vkFormat,
                                   storageName(k.storage)));
        if (tex.mips ? (n != levels || layers != 0) : layers ? n != layers : n != 1)
            return bad(fmt::format("{} arrays in {} levels and {} layers", n, levels, layers));
        for (size_t a = 0; a < n; ++a) {
            const ContainerArray& x = k.arrays[a];
            const uint32_t level = tex.mips ? uint32_t(a) : 0;
            if ((x.channels == 3 ? 4 : x.channels) != f->components ||
                x.width > tex.levelWidth(level) || x.height > tex.levelHeight(level) ||
                (!tex.mips && (x.width != tex.width || x.height != tex.height)))
                return bad(fmt::format("array '{}' ({}x{}x{}) does not fit its level", x.name,
                                       x.width, x.height, x.channels));
        }
        const uint32_t layerCount = std::max(1u, layers);
        for (uint32_t level = 0; level < levels; ++level) {
            const size_t entry = kHeaderBytes + kLevelEntryBytes * level;
            const uint64_t offset = get64(in, entry), length = get64(in, entry + 8);
            const uint64_t expected = uint64_t(tex.levelWidth(level)) * uint64_t(tex.levelHeight(level)) *
                                      uint64_t(texelBytes(*f)) * layerCount;
            if (length != expected || get64(in, entry + 16) != expected || offset > in.size() ||
                length > in.size() - offset || offset % levelAlignment(*f) != 0 ||
                offset < uint64_t(kvdOffset) + kvdLength)
                return bad(fmt::format("level {} is not where and what its index says", level));
        }
    }
    return assembleMaps(path, k, [&](size_t a) -> Result<MapArray> {
        const ContainerArray& x = k.arrays[a];
        const uint32_t level = tex.mips ? uint32_t(a) : 0, layer = tex.mips ? 0 : uint32_t(a);
        const size_t w = size_t(tex.levelWidth(level)), h = size_t(tex.levelHeight(level));
        const size_t base = size_t(get64(in, kHeaderBytes + kLevelEntryBytes * level)) +
                            size_t(layer) * w * h * size_t(texelBytes(*f));
        MapArray out{x.name, x.width, x.height, x.channels, {}};
        out.data.resize(size_t(x.width) * size_t(x.height) * size_t(x.channels));
        for (int y = 0; y < x.height; ++y)
            for (int i = 0; i < x.width; ++i)
                for (int c = 0; c < x.channels; ++c)
                    out.data[(size_t(y) * size_t(x.width) + size_t(i)) * size_t(x.channels) + size_t(c)] =
                        getTexel(in, base + (size_t(y) * w + size_t(i)) * size_t(texelBytes(*f)) + size_t(c * f->bits / 8),
                                 *f, k.storage);
        for (float v : out.data)
            if (!std::isfinite(v))
                return makeError(ErrorKind::InvalidInput, "{}: array '{}' holds non-finite values",
                                 path, x.name);
        return out;
    });
}

}  // namespace relief
