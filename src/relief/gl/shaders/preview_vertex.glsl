// The mesh preview's vertex shader (src/relief/preview/mesh_renderer.cpp): world-space mesh,
// uv scaled by the tiling, the tangent frame and its uv scale passed on. Its program text is
// "#version 330 core" + this file.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 uv;
layout(location = 3) in vec4 tangent;
layout(location = 4) in vec2 uvScale;
uniform mat4 clipFromWorld;
uniform float tiles;
out vec3 vWorld;
out vec3 vNormal;
out vec4 vTangent;
out vec2 vUv;
out vec2 vUvScale;
void main() {
    vWorld = position;
    vNormal = normal;
    vTangent = tangent;
    vUv = uv * tiles;
    vUvScale = uvScale / tiles;  // world length of one (tiled) uv unit along t and b
    gl_Position = clipFromWorld * vec4(position, 1.0);
}
