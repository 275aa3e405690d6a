// Entry point of a camera frame (timeGlFrame, traceGlCamera in src/relief/gl/gl_tracer.cpp): the
// primary rays are made here from the camera block, one invocation per pixel, row 0 at the top.

layout(local_size_x = kTileSize, local_size_y = kTileSize) in;

layout(std430, binding = kHitsBinding) writeonly buffer Hits { HitRecord hits[]; };

void main() {
    const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (pixel.x >= camera.width || pixel.y >= camera.height) return;
    hits[pixel.y * camera.width + pixel.x] = toRecord(trace(cameraRay(pixel.x, pixel.y)));
}
