// Entry point of GlTracer::traceBatch (src/relief/gl/gl_tracer.cpp): one invocation per ray,
// `trace` being the technique's tracer.

layout(local_size_x = kLocalSize) in;

layout(std430, binding = kRaysBinding) readonly buffer Rays { RayRecord rays[]; };
layout(std430, binding = kHitsBinding) writeonly buffer Hits { HitRecord hits[]; };

void main() {
    const uint k = gl_GlobalInvocationID.x;
    if (k >= uint(traceUniforms.rayCount)) return;
    hits[k] = toRecord(trace(fromRecord(rays[k])));
}
