#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>

namespace relief {

namespace {
OrientedMaps buildMaps(const Surface& surface) {
    const VertexGrid vertices(surface);
    return OrientedMaps(vertices,
                        std::make_shared<const MaxPyramid>(vertices, PyramidLayout::of(surface)));
}
}  // namespace

OrientedMaps::OrientedMaps(const Surface& surface) : OrientedMaps(buildMaps(surface)) {}

OrientedMaps::OrientedMaps(const VertexGrid& vertices, std::shared_ptr<const MaxPyramid> maxima)
    : maxima(std::move(maxima)), planes(vertices, *this->maxima) {}

Result<std::unique_ptr<Tracer>> createQuadtreeOriented(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"), false};
    auto maps = orientedMapsFor(input);  // baked (input.maps) or built now
    if (!maps) return maps.error();
    return makeBatchTracer(QuadtreeOrientedTracer(input.surface, std::move(*maps), limits));
}

}  // namespace relief
