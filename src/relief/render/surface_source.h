#pragma once
// A surface from a source string (a file or gen:NAME:WxH, optionally @crop=X,Y,W,H) and the
// DESIGN §3 surface options, and baked maps checked against it: the one path that the CLI
// commands and the bench share.
#include <relief/core/error.h>
#include <relief/io/heightfield_crop.h>
#include <relief/io/heightfield_io.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>

#include <memory>
#include <optional>
#include <string>

namespace relief {

// A source string split into the file or generator and its window: "FILE@crop=X,Y,W,H" takes the
// W×H samples from corner (X, Y); "FILE@centre=X,Y,W,H" the W×H samples around (X, Y), moved
// inside the map; heights renormalized to [0,1] over the window.
struct SourceSpec {
    std::string base;    // the file or gen:NAME:WxH[:seed]
    std::string suffix;  // "@crop=X,Y,W,H" or "@centre=X,Y,W,H" as written, or empty
    std::optional<CropWindow> crop;
};
// BadArgument when the window is not four integers X,Y,W,H.
Result<SourceSpec> parseSourceSpec(const std::string& source);

struct SurfaceOptions {
    std::string source;
    std::optional<float> depth;
    float depthRatio = 0.1f;
    std::string edge = "clamp";
    bool invert = false;
    std::string heightRange;  // "LO:HI"
    std::string raw;          // "WxH:u8|u16|f32"
    std::string channel = "luminance";
    int64_t maxSamples = kDefaultMaxSamples;
};

Result<std::shared_ptr<const Heightfield>> loadHeightfield(const SurfaceOptions& options);
Result<std::shared_ptr<const Surface>> makeSurface(const SurfaceOptions& options,
                                                   std::shared_ptr<const Heightfield> hf);
// The map file at `path`, read once per process (render -t all and the bench ask for it once per
// technique and heightfield), checked against `surface`.
Result<std::shared_ptr<const MapFile>> loadCheckedMaps(const std::string& path, const Surface& surface);

}  // namespace relief
