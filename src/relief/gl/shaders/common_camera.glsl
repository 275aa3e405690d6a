// Primary rays of a pinhole camera. Mirrors relief::gl::cameraRay (src/relief/gl/camera.h).

Ray cameraRay(int px, int py) {
    precise float sx = (divide(2.0 * (float(px) + 0.5), float(camera.width)) - 1.0) *
                       camera.tanHalfFovY * camera.aspect;
    precise float sy =
        (1.0 - divide(2.0 * (float(py) + 0.5), float(camera.height))) * camera.tanHalfFovY;
    precise vec3 direction = camera.forward + sx * camera.right + sy * camera.up;
    return Ray(camera.eye, normalizeLikeGlm(direction), kInfinity);
}
