// The rasterized peer: flat Lambert shading from the screen-space derivatives of the position.

in vec3 texelPosition;
layout(location = 0) out vec4 color;

void main() {
    const vec3 normal = normalize(cross(dFdx(texelPosition), dFdy(texelPosition)));
    const float shade = 0.15 + 0.85 * abs(dot(normal, mesh.lightDirection));
    color = vec4(vec3(shade), 1.0);
}
