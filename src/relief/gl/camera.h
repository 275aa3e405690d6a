#pragma once
// The renderer's orbit camera (render/camera.h, DESIGN §4) in the form the GL backend takes it
// (CameraUniforms: eye and an orthonormal basis), and its primary rays. cameraRay is mirrored by common_camera.glsl, so the
// CPU can trace exactly the rays a GL frame makes on the GPU.
#include <relief/gl/shader_interface.h>
#include <relief/render/camera.h>

#include <glm/glm.hpp>

namespace relief::gl {

CameraUniforms cameraUniforms(const Camera& camera);

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
