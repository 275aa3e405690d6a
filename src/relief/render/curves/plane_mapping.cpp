#include <relief/render/curves/plane_mapping.h>

namespace relief::curves {

PlaneMapping::PlaneMapping(const ViewFrame& view) {
    // glm matrices are column-major: dmat3(c0, c1, c2).
    const glm::dmat3 surface(dvec3(1, 0, 0), dvec3(0, 1, 0), -view.eye);
    const dvec3 iv = (2.0 * view.halfWidth / double(view.width)) * view.right;
    const dvec3 jv = -(2.0 * view.halfHeight / double(view.height)) * view.up;
    const dvec3 ov = view.forward - view.halfWidth * view.right + view.halfHeight * view.up;
    const glm::dmat3 viewPlane(iv, jv, ov);
    m_viewFromSurface = glm::inverse(viewPlane) * surface;
    m_surfaceFromView = glm::inverse(surface) * viewPlane;
    m_copSurface = dvec2(view.eye.x, view.eye.y);
    m_copView = toView(m_copSurface);
}

}  // namespace relief::curves
