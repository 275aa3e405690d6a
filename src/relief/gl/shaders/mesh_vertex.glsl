// The rasterized peer (timeRasterizedMesh in src/relief/gl/gl_tracer.cpp): S as triangles.

layout(location = 0) in vec3 position;  // texel space
out vec3 texelPosition;

void main() {
    texelPosition = position;
    gl_Position = mesh.clipFromTexel * vec4(position, 1.0);
}
