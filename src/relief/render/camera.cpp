#include <relief/render/camera.h>

#include <cmath>

namespace relief {

vec3 directionFromAngles(float elevationDeg, float azimuthDeg) {
    const float el = glm::radians(elevationDeg), az = glm::radians(azimuthDeg);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
}

namespace {
vec3 boxSize(const Surface& surface) {
    return vec3(float(surface.width()), float(surface.height()), surface.depth());
}
}  // namespace

Camera::Camera(const OrbitView& view, const Surface& surface, int width, int height)
    : Camera(view, 0.5f * boxSize(surface), glm::length(boxSize(surface)), width, height) {}

Camera::Camera(const OrbitView& view, vec3 target, float diameter, int width, int height)
    : m_width(width), m_height(height) {
    m_eye = target + view.distance * diameter *
                         directionFromAngles(view.elevationDeg, view.azimuthDeg);
    m_forward = glm::normalize(target - m_eye);
    // Straight down, "up" on screen is the azimuth direction projected on the base plane.
    const vec3 worldUp = std::abs(m_forward.z) > 0.9999f
                             ? -directionFromAngles(0.0f, view.azimuthDeg)
                             : vec3(0.0f, 0.0f, 1.0f);
    m_right = glm::normalize(glm::cross(m_forward, worldUp));
    m_up = glm::cross(m_right, m_forward);
    m_halfHeight = std::tan(0.5f * glm::radians(view.fovDeg));
    m_halfWidth = m_halfHeight * float(width) / float(height);
}

Status checkOrbitView(const OrbitView& view, int width, int height, const CameraLimits& limits) {
    const struct {
        const char* name;
        double value, lo, hi;
    } checks[] = {{"elevation", view.elevationDeg, -90.0, 90.0},
                  {"azimuth", view.azimuthDeg, -kMaxAzimuth, kMaxAzimuth},
                  {"distance", view.distance, limits.minDistance, limits.maxDistance},
                  {"fov", view.fovDeg, limits.minFov, limits.maxFov},
                  {"width", double(width), 1.0, 16384.0},
                  {"height", double(height), 1.0, 16384.0}};
    for (const auto& c : checks)
        if (!(c.value >= c.lo && c.value <= c.hi))  // NaN fails too
            return makeError(ErrorKind::BadArgument,
                             "{} {:g} is not a finite number from {:g} to {:g}", c.name, c.value,
                             c.lo, c.hi);
    return {};
}

std::vector<Ray> primaryRays(const Camera& camera) {
    std::vector<Ray> rays;
    rays.reserve(size_t(camera.width()) * size_t(camera.height()));
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x)
            rays.push_back(camera.primaryRay(float(x) + 0.5f, float(y) + 0.5f));
    return rays;
}

}  // namespace relief
