#pragma once
// Baked maps on disk (DESIGN §7): one multi-part OpenEXR file per heightfield. Each part is one
// float array (a map level or channel group) named "<technique>/<array>", with header attributes
// saying which technique and parameters made it, the format version, and the source heightfield's
// hash, size, edge mode and depth so a stale map is refused instead of silently misused.
#include <relief/core/error.h>

#include <cstdint>
#include <map>
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
Result<MapFile> readMapFile(const std::string& path);
// The same reader on a map file's bytes in memory (`name` stands for the path in messages).
Result<MapFile> readMapFile(std::span<const unsigned char> bytes, const std::string& name);

// Refuses maps built from another heightfield, size, edge mode or depth, naming the difference.
Status checkMapSource(const std::string& path, const MapSource& stored, const MapSource& current);

}  // namespace relief
