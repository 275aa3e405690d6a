#include <relief/techniques/quadtree_oriented/quadtree_oriented.h>

namespace relief {

OrientedMaps::OrientedMaps(const Surface& surface)
    : OrientedMaps(VertexGrid(surface), PyramidLayout::of(surface)) {}

OrientedMaps::OrientedMaps(const VertexGrid& vertices, const PyramidLayout& layout)
    : maxima(vertices, layout), planes(vertices, maxima) {}

Result<std::unique_ptr<Tracer>> createQuadtreeOriented(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"), false};
    return makeBatchTracer(QuadtreeOrientedTracer(
        input.surface, std::make_shared<const OrientedMaps>(*input.surface), limits));
}

}  // namespace relief
