#include <relief/gl/camera.h>


namespace relief::gl {

CameraUniforms cameraUniforms(const Camera& camera) {
    CameraUniforms c;
    c.eye = camera.eye();
    c.forward = camera.forward();
    c.right = camera.right();
    c.up = camera.up();
    c.tanHalfFovY = camera.halfHeight();
    c.aspect = camera.halfWidth() / camera.halfHeight();
    c.width = camera.width();
    c.height = camera.height();
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
