#include <relief/render/curves/view_frame.h>

#include <cmath>

namespace relief::curves {

ViewFrame ViewFrame::fromCamera(const Camera& camera) {
    ViewFrame f;
    f.eye = dvec3(camera.eye());
    f.forward = dvec3(camera.forward());
    f.right = dvec3(camera.right());
    f.up = dvec3(camera.up());
    f.halfWidth = camera.halfWidth();
    f.halfHeight = camera.halfHeight();
    f.width = camera.width();
    f.height = camera.height();
    return f;
}

ViewFrame ViewFrame::orbit(const OrbitView& view, const dvec3& target, double scale, int width,
                           int height) {
    // Mirrors Camera's constructor (render/camera.cpp) with an explicit target and scale.
    ViewFrame f;
    f.width = width;
    f.height = height;
    f.eye = target + view.distance * scale * dvec3(directionFromAngles(view.elevationDeg,
                                                                       view.azimuthDeg));
    f.forward = glm::normalize(target - f.eye);
    const dvec3 worldUp = std::abs(f.forward.z) > 0.9999
                              ? -dvec3(directionFromAngles(0.0f, view.azimuthDeg))
                              : dvec3(0.0, 0.0, 1.0);
    f.right = glm::normalize(glm::cross(f.forward, worldUp));
    f.up = glm::cross(f.right, f.forward);
    f.halfHeight = std::tan(0.5 * glm::radians(double(view.fovDeg)));
    f.halfWidth = f.halfHeight * double(width) / double(height);
    return f;
}

dvec2 ViewFrame::project(const dvec3& world, double* depth) const {
    const dvec3 d = world - eye;
    const double z = glm::dot(d, forward);
    if (depth) *depth = z;
    const double sx = glm::dot(d, right) / z, sy = glm::dot(d, up) / z;
    return {(sx / halfWidth + 1.0) * 0.5 * double(width),
            (1.0 - sy / halfHeight) * 0.5 * double(height)};
}

}  // namespace relief::curves
