#pragma once
// The orbit camera of DESIGN §4: looks at the centre of the relief's box from an elevation angle
// above the base plane and an azimuth, at a distance measured in box diagonals.
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/surface/surface.h>

#include <vector>

namespace relief {

struct OrbitView {
    float elevationDeg = 40.2f;
    float azimuthDeg = 30.0f;
    float distance = 1.2f;  // in units of the box diagonal
    float fovDeg = 45.0f;   // vertical field of view
};

// The ranges the CLI's camera options and the Python module's views accept; azimuths are taken
// in one turn either way. The viewer narrows them.
inline constexpr double kMaxAzimuth = 360.0;
struct CameraLimits {
    float minDistance = 0.01f, maxDistance = 1000.0f;
    float minFov = 1.0f, maxFov = 170.0f;
};
// BadArgument naming the first value out of its range (angles, distance, fov; image size 1 to
// 16384 each way), for callers that do not parse options (the Python module).
Status checkOrbitView(const OrbitView& view, int width, int height,
                      const CameraLimits& limits = {});

// DESIGN §4 standard sets.
inline constexpr float kStandardElevations[] = {2.9f, 15.3f, 27.8f, 40.2f, 52.7f, 65.1f, 77.6f, 90.0f};
inline constexpr int kStandardCaps[] = {4, 6, 8, 12, 24, 48, 200};

class Camera {
public:
    Camera(const OrbitView& view, const Surface& surface, int width, int height);
    // The same orbit around `target`, the distance in units of `diameter` (the mesh preview).
    Camera(const OrbitView& view, vec3 target, float diameter, int width, int height);

    // Primary ray through the image point (px, py) in pixels, (0,0) = top-left corner.
    Ray primaryRay(float px, float py) const {
        const float sx = (2.0f * px / float(m_width) - 1.0f) * m_halfWidth;
        const float sy = (1.0f - 2.0f * py / float(m_height)) * m_halfHeight;
        return Ray{m_eye, glm::normalize(m_forward + sx * m_right + sy * m_up), kInfinity};
    }
    const vec3& eye() const { return m_eye; }
    const vec3& forward() const { return m_forward; }
    const vec3& right() const { return m_right; }
    const vec3& up() const { return m_up; }
    float halfWidth() const { return m_halfWidth; }
    float halfHeight() const { return m_halfHeight; }
    int width() const { return m_width; }
    int height() const { return m_height; }

private:
    vec3 m_eye, m_forward, m_right, m_up;
    float m_halfWidth, m_halfHeight;
    int m_width, m_height;
};

// Unit vector towards a directional light (or from the target to an orbit eye).
vec3 directionFromAngles(float elevationDeg, float azimuthDeg);

// All primary rays of a width×height image, row-major.
std::vector<Ray> primaryRays(const Camera& camera);

}  // namespace relief
