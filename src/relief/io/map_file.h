#pragma once
// Baked maps on disk (DESIGN §7): one multi-part OpenEXR file per heightfield. Each part is one
// float array (a map level or channel group) named "<technique>/<array>", with header attributes
// saying which technique and parameters made it, the format version, and the source heightfield's
// hash, size, edge mode and depth so a stale map is refused instead of silently misused.
#include <relief/core/error.h>

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace relief {

// 2: every part carries "relief.checksum" (CRC-32 over its attributes and data) and
// "relief.parts"; version 1 maps (no checksum) are refused with a message to bake them again.
inline constexpr int kMapFormatVersion = 2;

struct MapArray {
    std::string name;  // e.g. "level0", "cones"
    int width = 0, height = 0, channels = 1;
    std::vector<float> data;  // row-major, channels interleaved
};

// What a map was built from; all of it must match when the map is used.
struct MapSource {
    uint64_t heightfieldHash = 0;
    int width = 0, height = 0;
    std::string edge;
    float depth = 0.0f;
};

struct TechniqueMaps {
    std::string technique;
    std::map<std::string, std::string> parameters;  // as baked (e.g. "phi-max" → "45")
    std::vector<MapArray> arrays;

    const MapArray* find(const std::string& name) const;
};

struct MapFile {
    MapSource source;
    std::vector<TechniqueMaps> techniques;

    const TechniqueMaps* find(const std::string& technique) const;
};

Status writeMapFile(const std::string& path, const MapFile& maps);
// Reads OpenEXR, PNG and KTX2 map files alike (by their first bytes), with the same checks.
Result<MapFile> readMapFile(const std::string& path);
// The same reader on a map file's bytes in memory (`name` stands for the path in messages).
Result<MapFile> readMapFile(std::span<const unsigned char> bytes, const std::string& name);

// ---- Engine containers (docs/maps.md) ---------------------------------------------------------
// A PNG holds one array, a KTX2 file one texture: one array, several arrays of one size as
// layers, or a max pyramid's levels as mip levels. Both carry the EXR part's attributes and
// checksum (PNG tEXt chunks, KTX2 key/value data), so a reader refuses them as it refuses an EXR.
enum class MapFormat : uint8_t { Exr, Png, Ktx2 };
std::string_view toString(MapFormat format);
// "exr", "png", "ktx2"; nullopt for anything else.
std::optional<MapFormat> mapFormatFromName(std::string_view name);
// The format an output path's extension names (.exr, .png, .ktx2), else nullopt.
std::optional<MapFormat> mapFormatFromPath(std::string_view path);

// What an array's values are, as far as 8/16-bit codes go (MapChannelSpec::kind):
enum class MapValueKind : uint8_t {
    Unit,     // in [0, 1]; on the code grid k / (2^b − 1) when the bake quantized them (bits=b)
    Integer,  // whole numbers 0..65535 (stored as the codes themselves)
    Float,    // any float (texel units): 32-bit float storage only
};
// How one array is stored in a PNG / KTX2: UNORM codes decoding to code / (2^b − 1), integer
// codes decoding to the code itself (PNG only), or 32-bit floats (KTX2 only).
enum class MapStorage : uint8_t { Unit8, Unit16, Int8, Int16, Float32 };
// The smallest storage of `format` that gives back every value of `array` bit for bit for its
// kind (8 bits before 16), else nullopt. The exporter never rounds a value itself: rounding is the
// bake's (`--param bits=N`), in the conservative direction its encoding documents. A KTX2 texture
// holds the array's values as they are: Unit arrays as UNORM when exact, everything else as float.
std::optional<MapStorage> exactStorage(const MapArray& array, MapValueKind kind, MapFormat format);
// Writes `maps` as `format`, each array in the storage given (techniques in order, then arrays;
// ignored for EXR, which stores floats). Refuses (BadArgument) what one PNG / KTX2 cannot hold,
// naming the format that can.
Status writeMapFile(const std::string& path, const MapFile& maps, MapFormat format,
                    std::span<const MapStorage> storages);
// Refuses maps built from another heightfield, size, edge mode or depth, naming the difference.
Status checkMapSource(const std::string& path, const MapSource& stored, const MapSource& current);

}  // namespace relief
