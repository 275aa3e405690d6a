#pragma once
// What the map containers share (internal to src/relief/io): the relief attributes of one part
// (an EXR part, a PNG file, one array of a KTX2 file) as text, their checksum, and the checks
// every reader makes before it hands out a part (map_file.cpp), so that a PNG or KTX2 export is
// refused when stale or damaged exactly as the EXR bake is.
#include <relief/io/map_file.h>
#include <relief/io/read_common.h>

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace relief {

// The relief attributes of one part as stored (strings as written), and what its checksum covers.
struct PartAttributes {
    std::string technique, array, parameters, hash, size, edge, depth;
    int index = 0, parts = 0;
    std::string checksum;  // "crc32:XXXXXXXX", filled by partAttributes()
};

// Every array's attributes and checksum, techniques in order, then arrays.
std::vector<PartAttributes> partAttributes(const MapFile& maps);

// Validates one part (version, names, parameters, part count, source, then its data through
// `readData` and the checksum) and adds its array to `maps`. `first` and `seen` carry over between
// the parts of one file. Missing attributes are nullopt / null.
Status addMapPart(const std::string& path, MapFile& maps, std::optional<int> version,
                  const std::optional<PartAttributes>& attributes, const std::string* checksum,
                  const std::string& partName, int partsInFile,
                  const std::function<Result<MapArray>()>& readData,
                  std::optional<PartAttributes>& first, std::set<std::string>& seen);

// Storages (map_export.cpp).
int storageBits(MapStorage storage);       // 8, 16 or 32
bool storageIsInteger(MapStorage storage);  // codes are the values (else code / (2^bits − 1))
std::string_view storageName(MapStorage storage);
std::optional<MapStorage> storageFromName(std::string_view name);
// Code → value and value → code for the UNORM storages (exact for values exactStorage accepted).
float decodeCode(MapStorage storage, uint32_t code);
uint32_t encodeCode(MapStorage storage, float value);

// The relief keys a PNG (tEXt chunks) or KTX2 file (key/value data) carries: the part attributes
// shared by all its arrays, "relief.arrays" (NAME:WxHxC,...), "relief.checksums" (one per array,
// the checksum its EXR part would have) and "relief.storage".
std::vector<std::pair<std::string, std::string>> containerKeys(const MapFile& maps,
                                                               MapStorage storage);
struct ContainerArray {
    std::string name;
    int width = 0, height = 0, channels = 0;
    std::string checksum;
};
struct ContainerKeys {
    std::optional<int> version;
    std::optional<PartAttributes> common;  // null: relief keys missing
    MapStorage storage = MapStorage::Float32;
    std::vector<ContainerArray> arrays;
};
Result<ContainerKeys> parseContainerKeys(const std::string& path,
                                         const std::map<std::string, std::string>& keys);
// The checked MapFile: each array decoded by `decode(k)`, then checked by addMapPart.
Result<MapFile> assembleMaps(const std::string& path, const ContainerKeys& keys,
                             const std::function<Result<MapArray>(size_t index)>& decode);

// Writes `bytes` to `path` through the one output mechanism (output.h).
Status writeBytes(const std::string& path, const std::vector<unsigned char>& bytes);

bool isKtx2(std::span<const unsigned char> head);
Result<MapFile> readPngMaps(FileReader& file);
Result<MapFile> readKtx2Maps(FileReader& file);
Status writePngMaps(const std::string& path, const MapFile& maps, std::span<const MapStorage> storages);
Status writeKtx2Maps(const std::string& path, const MapFile& maps, std::span<const MapStorage> storages);

}  // namespace relief
