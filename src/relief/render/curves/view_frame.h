#pragma once
// The view plane of the visibility-curve renderer: the orbit camera's pinhole (render/camera.h,
// same ray formula) in double precision, usable around any target (the sphere has no box).
// Image coordinates are pixels, (0,0) = top-left corner, as in Camera::primaryRay.
#include <relief/render/camera.h>

#include <glm/glm.hpp>

namespace relief::curves {

using glm::dvec2;
using glm::dvec3;

struct ViewFrame {
    dvec3 eye, forward, right, up;
    double halfWidth = 1, halfHeight = 1;
    int width = 1, height = 1;

    static ViewFrame fromCamera(const Camera& camera);
    // The orbit camera of DESIGN §4 looking at `target`, its distance in units of `scale`.
    static ViewFrame orbit(const OrbitView& view, const dvec3& target, double scale, int width,
                           int height);

    // Unnormalized direction through image point p.
    dvec3 direction(const dvec2& p) const {
        const double sx = (2.0 * p.x / double(width) - 1.0) * halfWidth;
        const double sy = (1.0 - 2.0 * p.y / double(height)) * halfHeight;
        return forward + sx * right + sy * up;
    }
    // The primary ray exactly as Camera::primaryRay builds it (float), so that the exact
    // reference traces the same ray.
    Ray ray(const dvec2& p) const {
        return Ray{vec3(eye), vec3(glm::normalize(direction(p))), kInfinity};
    }
    // Image point of a world point; depth ≤ 0 means behind the eye.
    dvec2 project(const dvec3& world, double* depth = nullptr) const;
    // Focal distance in pixels (square pixels).
    double focalPixels() const { return 0.5 * double(height) / halfHeight; }
};

}  // namespace relief::curves
