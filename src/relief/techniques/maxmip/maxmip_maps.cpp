// maxmip's baked maps: the max pyramid shared with `quadtree` (common/max_pyramid_maps.cpp).
#include <relief/techniques/maxmip/maxmip.h>

namespace relief {

Result<TechniqueMaps> buildMaxmipMaps(const TechniqueInput& input) {
    return maxPyramidMaps(input, "maxmip");
}

}  // namespace relief
