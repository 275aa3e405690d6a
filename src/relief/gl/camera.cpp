#include <relief/gl/camera.h>

#include <cmath>
#include <numbers>

namespace relief::gl {

CameraUniforms orbitCamera(const Surface& surface, const OrbitView& view, int width, int height) {
    const vec3 size(float(surface.width()), float(surface.height()), surface.depth());
    const vec3 centre = 0.5f * size;
    const float diagonal = glm::length(size);
    const float toRadians = std::numbers::pi_v<float> / 180.0f;
    const float elevation = view.elevationDeg * toRadians, azimuth = view.azimuthDeg * toRadians;
    const vec3 toEye(std::cos(elevation) * std::cos(azimuth),
                     std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    CameraUniforms c;
    c.eye = centre + view.distance * diagonal * toEye;
    c.forward = -glm::normalize(toEye);
    // Looking straight down, "up" on screen is the azimuth direction instead of +z.
    const vec3 worldUp = std::abs(c.forward.z) > 0.999f
                             ? vec3(std::cos(azimuth), std::sin(azimuth), 0.0f)
                             : vec3(0.0f, 0.0f, 1.0f);
    c.right = glm::normalize(glm::cross(c.forward, worldUp));
    c.up = glm::cross(c.right, c.forward);
    c.tanHalfFovY = std::tan(0.5f * view.fovYDeg * toRadians);
    c.aspect = float(width) / float(height);
    c.width = width;
    c.height = height;
    return c;
}

glm::mat4 clipFromTexel(const CameraUniforms& c, float near, float far) {
    glm::mat4 view(1.0f);  // rows: right, up, -forward (column-major storage)
    for (int k = 0; k < 3; ++k) {
        view[k][0] = c.right[k];
        view[k][1] = c.up[k];
        view[k][2] = -c.forward[k];
    }
    view[3][0] = -glm::dot(c.right, c.eye);
    view[3][1] = -glm::dot(c.up, c.eye);
    view[3][2] = glm::dot(c.forward, c.eye);
    glm::mat4 projection(0.0f);
    projection[0][0] = 1.0f / (c.tanHalfFovY * c.aspect);
    projection[1][1] = 1.0f / c.tanHalfFovY;
    projection[2][2] = -(far + near) / (far - near);
    projection[2][3] = -1.0f;
    projection[3][2] = -2.0f * far * near / (far - near);
    return projection * view;
}

}  // namespace relief::gl
