// Primary rays of a pinhole camera. Mirrors relief::gl::cameraRay (src/relief/gl/camera.h).

Ray cameraRay(int px, int py) {
    const float sx = (2.0 * (float(px) + 0.5) / float(camera.width) - 1.0) * camera.tanHalfFovY *
                     camera.aspect;
    const float sy = (1.0 - 2.0 * (float(py) + 0.5) / float(camera.height)) * camera.tanHalfFovY;
    return Ray(camera.eye, normalize(camera.forward + sx * camera.right + sy * camera.up),
               kInfinity);
}
