#pragma once
// How the packet walks (cell_walk_packet.cpp, cone/cone_packet.cpp,
// common/pyramid_walk_packet.cpp) hand a batch's rays to their lanes: in batch order, each ray
// that misses the box answered at once (an empty hit), the next one that enters it given with
// its clipped span.
#include <relief/surface/surface.h>

#include <span>

namespace relief {

// From rays[next] on: writes Hit{} for the rays that miss the box, and returns true with `index`
// and `span` of the first that enters it (next moves past it); false once the batch is done.
inline bool nextRayInBox(const Surface& s, std::span<const Ray> rays, std::span<Hit> hits,
                         size_t& next, size_t& index, RayInterval& span) {
    while (next < rays.size()) {
        const size_t i = next++;
        span = s.clip(rays[i]);
        if (!span.empty()) {
            index = i;
            return true;
        }
        hits[i] = Hit{};
    }
    return false;
}

}  // namespace relief
