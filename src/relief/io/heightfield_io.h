#pragma once
// Loading heightfields from files or generators (DESIGN §1, §5).
#include <relief/core/heightfield.h>
#include <relief/core/image.h>

#include <optional>
#include <span>
#include <string>

namespace relief {

enum class ChannelSelect { Luminance, Red, Green, Blue, Alpha };

struct RawLayout {
    int width = 0;
    int height = 0;
    enum class Type { U8, U16, F32 } type = Type::U8;
};

struct LoadOptions {
    bool invert = false;                     // depth map → height map (h → 1 − h)
    std::optional<double> rangeLo, rangeHi;  // --height-range LO:HI for float formats
    ChannelSelect channel = ChannelSelect::Luminance;  // for RGB/RGBA images
    std::optional<RawLayout> raw;            // --raw WxH:u8|u16|f32
    int64_t maxSamples = kDefaultMaxSamples;
};

// `source` is a path (format from its content: PNG, JPEG, OpenEXR, PFM; raw with options.raw) or
// a generator spec `gen:NAME:WxH[:seed]`. Errors name the source and the problem.
Result<Heightfield> loadHeightfield(const std::string& source, const LoadOptions& options = {});

// Parses "WxH:u8|u16|f32" (the --raw option).
Result<RawLayout> parseRawLayout(const std::string& text);

// Colour images (for --color, --normal): 8-bit RGB from PNG/JPEG.
Result<ImageRgb8> loadColorImage(const std::string& path);
// The colour map of a generator source `gen:NAME:WxH[:seed]` (generateColorMap: bricks has one).
Result<ImageRgb8> loadGeneratorColor(const std::string& source);

// The same readers on bytes in memory (a file's content; `name` stands for the path in messages).
// options.raw and options.maxSamples apply as for files; there are no generators here.
Result<Heightfield> decodeHeightfield(std::span<const unsigned char> bytes,
                                      const std::string& name, const LoadOptions& options = {});
Result<ImageRgb8> decodeColorImage(std::span<const unsigned char> bytes, const std::string& name,
                                   int64_t maxSamples = kDefaultMaxSamples);

}  // namespace relief
