#pragma once
// A window of a heightfield, renormalized to [0,1] over the window: the real maps the benches
// take a crop of (an SRTM region, a continent of a world map) span little of the world's range.
#include <relief/core/heightfield.h>

namespace relief {

struct CropWindow {
    int x = 0, y = 0;           // the window's corner (column, row), or its centre if `centred`
    int width = 0, height = 0;  // its size in samples
    // Centred on (x, y) and moved inside the map where it would leave it: a region kept at every
    // window size (a bench study's {N}×{N} windows of one place).
    bool centred = false;
};

// The W×H samples from the corner (or around the centre), rescaled by the window's own min/max
// (a constant window becomes all zeros). InvalidInput when the window is empty, larger than the
// map, or (a corner) leaves it; `what` names the source.
Result<Heightfield> cropHeightfield(const Heightfield& hf, const CropWindow& window, const std::string& what);

}  // namespace relief
