#include <relief/techniques/quadtree/quadtree.h>

namespace relief {

Result<std::unique_ptr<Tracer>> createQuadtree(const TechniqueInput& input) {
    const WalkLimits limits{input.params.getInt("max-steps"),
                            input.params.getInt("box-surface") != 0};
    const Ascent ascent = input.params.getInt("ascend") == 0 ? Ascent::None : Ascent::Parent;
    auto pyramid = maxPyramidFor(input);  // baked (input.maps) or built now
    if (!pyramid) return pyramid.error();
    return makeBatchTracer(QuadtreeTracer(input.surface, std::move(*pyramid), ascent, limits));
}

Result<TechniqueMaps> buildQuadtreeMaps(const TechniqueInput& input) {
    return maxPyramidMaps(input, "quadtree");
}

}  // namespace relief
