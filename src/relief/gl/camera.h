#pragma once
// The orbit camera of DESIGN §4 in the form the GL backend takes it (CameraUniforms: eye and an
// orthonormal basis), and its primary rays. cameraRay is mirrored by common_camera.glsl, so the
// CPU can trace exactly the rays a GL frame makes on the GPU.
#include <relief/gl/shader_interface.h>

#include <glm/glm.hpp>

namespace relief::gl {

struct OrbitView {
    float elevationDeg = 40.2f;  // above the base plane
    float azimuthDeg = 30.0f;    // from +x towards +y
    float distance = 1.5f;       // from the box centre, in box diagonals
    float fovYDeg = 45.0f;       // vertical field of view
};

// Looks at the centre of the surface's box [0,W]×[0,H]×[0,D] from `view`, image width×height.
CameraUniforms orbitCamera(const Surface& surface, const OrbitView& view, int width, int height);

// The primary ray through the centre of pixel (px, py), row 0 at the top.
inline Ray cameraRay(const CameraUniforms& camera, int px, int py) {
    const float sx = (2.0f * (float(px) + 0.5f) / float(camera.width) - 1.0f) *
                     camera.tanHalfFovY * camera.aspect;
    const float sy = (1.0f - 2.0f * (float(py) + 0.5f) / float(camera.height)) * camera.tanHalfFovY;
    Ray ray;
    ray.origin = camera.eye;
    ray.direction = glm::normalize(camera.forward + sx * camera.right + sy * camera.up);
    return ray;
}

// The rasterizer's matrix for the same camera: a pixel centre of the framebuffer (row 0 at the
// bottom, as GL has it) sees along cameraRay(px, height - 1 - row). near/far in texel units.
glm::mat4 clipFromTexel(const CameraUniforms& camera, float near, float far);

}  // namespace relief::gl
