#include <relief/gl/gl_tracer.h>

#include <relief/gl/egl_context.h>
#include <relief/gl/program.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

namespace relief {

namespace {

using namespace gl;

// Rays per dispatch of a batch (32 MiB of records each way); larger batches loop.
constexpr size_t kMaxRaysPerDispatch = size_t(1) << 20;

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

int groupsFor(int count, int groupSize) { return (count + groupSize - 1) / groupSize; }

// Frames timed one by one with glFinish, after untimed warm-up frames.
template <class DrawFrame>
GlFrameTiming timedFrames(const GlTimingOptions& options, DrawFrame&& drawFrame) {
    for (int k = 0; k < options.warmupFrames; ++k) {
        drawFrame();
        glFinish();
    }
    GlFrameTiming timing;
    timing.frames = std::max(options.frames, 1);
    double total = 0.0, fastest = 1e300;
    for (int k = 0; k < timing.frames; ++k) {
        const Clock::time_point start = Clock::now();
        drawFrame();
        glFinish();
        const double ms = millisecondsSince(start);
        total += ms;
        fastest = std::min(fastest, ms);
    }
    timing.msPerFrame = total / timing.frames;
    timing.msMin = fastest;
    return timing;
}

// One program: main_rays.glsl (ray batches, the Tracer) or main_camera.glsl (camera frames).
enum class Entry { Rays, Camera };

class GlTracer final : public Tracer, public GlCameraTracer {
public:
    bool prefersOneBatch() const override { return true; }
    static Result<std::unique_ptr<GlTracer>> create(const TechniqueInfo& info,
                                                    const TechniqueInput& input, Entry entry) {
        if (info.glsl.empty())
            return makeError(ErrorKind::Unsupported,
                             "technique '{}' has no GLSL tracer (its registry row has no glsl)",
                             info.name);
        if (!input.surface) return makeError(ErrorKind::BadArgument, "GL backend: no surface");
        if (const VariantSpec* variant = variantOf(info, input.params); variant && variant->cpuOnly)
            return makeError(ErrorKind::Unsupported,
                             "technique '{}': variant {} ({}) runs on the CPU only (its GLSL "
                             "has no such form)",
                             info.name, variant->label, variant->params);
        // What the row's create would refuse (input.params are resolved already).
        if (info.check)
            if (Status status = info.check(input); !status) return status.error();
        // Maps: the baked ones, else built now; read only here (uploaded, and their layout
        // compiled into the program).
        const TechniqueMaps* maps = input.maps;
        TechniqueMaps built;
        if (!maps && info.buildMaps) {
            auto made = info.buildMaps(input);
            if (!made) return made.error();
            built = std::move(*made);
            maps = &built;
        }
        auto tracer = std::unique_ptr<GlTracer>(new GlTracer());
        auto uniforms = traceUniforms(info, input.params);
        if (!uniforms) return uniforms.error();
        auto context = EglContext::shared();
        if (!context) return context.error();

        tracer->m_context = *context;
        tracer->m_hasMaps = maps != nullptr;
        tracer->m_surface = input.surface;
        tracer->m_info = &info;
        tracer->m_traceUniforms = *uniforms;
        EglContext::Scope scope(*tracer->m_context);
        const std::span<const float> heights = input.surface->paddedHeights();
        GLint64 maxBlock = 0;
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
        if (int64_t(heights.size_bytes()) > maxBlock)
            return makeError(ErrorKind::Unsupported,
                             "GL backend: the padded heightfield is {} bytes, over this GL's "
                             "storage block limit of {} bytes",
                             heights.size_bytes(), maxBlock);
        tracer->m_heights.upload(heights.data(), heights.size_bytes(), GL_STATIC_DRAW);
        if (maps) {
            const std::vector<float> packed = packMaps(*maps);
            if (int64_t(packed.size() * sizeof(float)) > maxBlock)
                return makeError(ErrorKind::Unsupported,
                                 "GL backend: the maps of '{}' are {} bytes, over this GL's "
                                 "storage block limit of {} bytes",
                                 info.name, packed.size() * sizeof(float), maxBlock);
            tracer->m_mapData.upload(packed.data(), packed.size() * sizeof(float),
                                     GL_STATIC_DRAW);
        }
        uploadBlock(tracer->m_surfaceUbo, surfaceUniforms(*input.surface));
        auto program = tracer->compile(
            entry == Entry::Rays ? "main_rays.glsl" : "main_camera.glsl", maps);
        if (!program) return program.error();
        tracer->m_program = std::move(*program);
        if (std::string error = takeGlError(); !error.empty())
            return makeError(ErrorKind::Runtime, "GL backend: setting up '{}' failed: {}",
                             info.name, error);
        return tracer;
    }

    ~GlTracer() override {
        if (!m_context) return;  // failed before any GL object was made
        EglContext::Scope scope(*m_context);
        m_program.reset();
        m_heights = {};
        m_mapData = {};
        m_surfaceUbo = {};
        m_traceUbo = {};
        m_cameraUbo = {};
        m_rays = {};
        m_hits = {};
    }

    void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const override {
        RELIEF_CHECK(rays.size() == hits.size());
        if (rays.empty()) return;
        EglContext::Scope scope(*m_context);
        for (size_t first = 0; first < rays.size(); first += kMaxRaysPerDispatch) {
            const size_t count = std::min(kMaxRaysPerDispatch, rays.size() - first);
            m_rayRecords.resize(count);
            for (size_t k = 0; k < count; ++k) m_rayRecords[k] = toRecord(rays[first + k]);
            m_rays.upload(m_rayRecords.data(), count * sizeof(RayRecord));
            m_hits.ensure(count * sizeof(HitRecord));
            TraceUniforms uniforms = m_traceUniforms;
            uniforms.rayCount = int32_t(count);
            uploadBlock(m_traceUbo, uniforms);
            bindBuffers();
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kRaysBinding, m_rays.id());
            glUseProgram(m_program.id());
            glDispatchCompute(GLuint(groupsFor(int(count), kLocalSize)), 1, 1);
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            m_hitRecords.resize(count);
            m_hits.download(m_hitRecords.data(), count * sizeof(HitRecord));
            for (size_t k = 0; k < count; ++k) hits[first + k] = fromRecord(m_hitRecords[k]);
        }
        if (std::string error = takeGlError(); !error.empty()) {
            // The Tracer interface has no error channel; a GL error here is a driver failure.
            std::fprintf(stderr, "relief: error: GL backend: tracing a batch of %zu rays with "
                         "'%.*s' failed: %s\n", rays.size(), int(m_info->name.size()),
                         m_info->name.data(), error.c_str());
            std::abort();
        }
    }

    Result<GlFrameTiming> timeFrames(const GlCamera& camera,
                                     const GlTimingOptions& options) override {
        EglContext::Scope scope(*m_context);
        if (Status s = prepareCamera(camera); !s) return s.error();
        GlFrameTiming timing = timedFrames(options, [&] { dispatchCamera(camera); });
        const std::vector<HitRecord> records = readCameraHits(camera);
        double steps = 0.0, hitCount = 0.0;
        for (const HitRecord& r : records) {
            steps += r.steps;
            hitCount += r.hit != 0;
        }
        timing.meanSteps = steps / double(records.size());
        timing.hitFraction = hitCount / double(records.size());
        timing.device = m_context->description();
        if (std::string error = takeGlError(); !error.empty())
            return makeError(ErrorKind::Runtime, "GL backend: timing '{}' failed: {}",
                             m_info->name, error);
        return timing;
    }

    Result<std::vector<Hit>> traceFrame(const GlCamera& camera) override {
        EglContext::Scope scope(*m_context);
        if (Status s = prepareCamera(camera); !s) return s.error();
        dispatchCamera(camera);
        const std::vector<HitRecord> records = readCameraHits(camera);
        if (std::string error = takeGlError(); !error.empty())
            return makeError(ErrorKind::Runtime, "GL backend: a '{}' frame failed: {}",
                             m_info->name, error);
        std::vector<Hit> hits(records.size());
        for (size_t k = 0; k < records.size(); ++k) hits[k] = fromRecord(records[k]);
        return hits;
    }

    Status setParams(const TechniqueInput& input) override {
        if (input.surface != m_surface)
            return makeError(ErrorKind::BadArgument, "GL backend: setParams of '{}' with another surface",
                             m_info->name);
        if (m_info->check)
            if (Status status = m_info->check(input); !status) return status.error();
        auto uniforms = traceUniforms(*m_info, input.params);
        if (!uniforms) return uniforms.error();
        m_traceUniforms = *uniforms;
        return {};
    }

private:
    GlTracer() = default;

    Result<GlProgram> compile(std::string_view entry, const TechniqueMaps* maps) const {
        return computeProgram(fmt::format("{} ({})", m_info->name, entry),
                              {"common_types.glsl", "common_surface.glsl",
                               "common_cell_intersect.glsl", "common_camera.glsl", m_info->glsl,
                               entry},
                              m_info, maps);
    }

    void bindBuffers() const {
        glBindBufferBase(GL_UNIFORM_BUFFER, kSurfaceBinding, m_surfaceUbo.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, kTraceBinding, m_traceUbo.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, kCameraBinding, m_cameraUbo.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHeightsBinding, m_heights.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kHitsBinding, m_hits.id());
        if (m_hasMaps) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kMapsBinding, m_mapData.id());
    }

    Status prepareCamera(const GlCamera& camera) {
        if (camera.width < 1 || camera.height < 1)
            return makeError(ErrorKind::BadArgument, "GL backend: camera image is {}×{}",
                             camera.width, camera.height);
        uploadBlock(m_cameraUbo, camera);
        TraceUniforms uniforms = m_traceUniforms;
        uniforms.rayCount = camera.width * camera.height;
        uploadBlock(m_traceUbo, uniforms);
        m_hits.ensure(size_t(camera.width) * size_t(camera.height) * sizeof(HitRecord));
        bindBuffers();
        glUseProgram(m_program.id());
        return {};
    }

    void dispatchCamera(const GlCamera& camera) const {
        glDispatchCompute(GLuint(groupsFor(camera.width, kTileSize)),
                          GLuint(groupsFor(camera.height, kTileSize)), 1);
    }

    std::vector<HitRecord> readCameraHits(const GlCamera& camera) const {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        std::vector<HitRecord> records(size_t(camera.width) * size_t(camera.height));
        m_hits.download(records.data(), records.size() * sizeof(HitRecord));
        return records;
    }

    std::shared_ptr<EglContext> m_context;
    std::shared_ptr<const Surface> m_surface;
    const TechniqueInfo* m_info = nullptr;
    TraceUniforms m_traceUniforms;
    bool m_hasMaps = false;  // m_mapData holds them
    GlProgram m_program;     // of the Entry it was created for
    // Mutable: traceBatch is const, and every use holds the context's Scope (its mutex).
    mutable GlBuffer m_heights, m_mapData, m_surfaceUbo, m_traceUbo, m_cameraUbo, m_rays, m_hits;
    mutable std::vector<RayRecord> m_rayRecords;
    mutable std::vector<HitRecord> m_hitRecords;
};

// The mesh of the rasterized peer: the padded sample grid as vertices (border vertices pulled in
// to the box faces), two triangles per cell split like S, and the side walls in clamp mode.
struct Mesh {
    std::vector<vec3> vertices;
    std::vector<uint32_t> indices;
};

Mesh buildMesh(const Surface& surface) {
    const int w = surface.width(), h = surface.height();
    const int stride = w + 2;
    const std::span<const float> z = surface.paddedHeights();
    Mesh mesh;
    mesh.vertices.reserve(size_t(stride) * size_t(h + 2));
    for (int j = -1; j <= h; ++j)
        for (int i = -1; i <= w; ++i)
            mesh.vertices.push_back({std::clamp(float(i) + 0.5f, 0.0f, float(w)),
                                     std::clamp(float(j) + 0.5f, 0.0f, float(h)),
                                     z[size_t(j + 1) * size_t(stride) + size_t(i + 1)]});
    auto vertex = [&](int i, int j) { return uint32_t((j + 1) * stride + (i + 1)); };
    mesh.indices.reserve(size_t(6) * size_t(w + 1) * size_t(h + 1));
    for (int cj = -1; cj < h; ++cj) {
        for (int ci = -1; ci < w; ++ci) {
            const uint32_t v00 = vertex(ci, cj), v10 = vertex(ci + 1, cj);
            const uint32_t v01 = vertex(ci, cj + 1), v11 = vertex(ci + 1, cj + 1);
            const float z00 = mesh.vertices[v00].z, z10 = mesh.vertices[v10].z;
            const float z01 = mesh.vertices[v01].z, z11 = mesh.vertices[v11].z;
            if (z00 + z11 <= z10 + z01)  // the lower diagonal, as planesFromCorners
                mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
            else
                mesh.indices.insert(mesh.indices.end(), {v00, v10, v01, v10, v11, v01});
        }
    }
    if (surface.edge() == EdgeMode::Clamp) {
        // Each wall quad joins two consecutive border vertices to their feet at z = 0.
        auto wall = [&](uint32_t a, uint32_t b) {
            const uint32_t base = uint32_t(mesh.vertices.size());
            mesh.vertices.push_back({mesh.vertices[a].x, mesh.vertices[a].y, 0.0f});
            mesh.vertices.push_back({mesh.vertices[b].x, mesh.vertices[b].y, 0.0f});
            mesh.indices.insert(mesh.indices.end(), {a, b, base + 1, a, base + 1, base});
        };
        for (int i = -1; i < w; ++i) {
            wall(vertex(i, -1), vertex(i + 1, -1));
            wall(vertex(i, h), vertex(i + 1, h));
        }
        for (int j = -1; j < h; ++j) {
            wall(vertex(-1, j), vertex(-1, j + 1));
            wall(vertex(w, j), vertex(w, j + 1));
        }
    }
    return mesh;
}

// Near and far planes that enclose the box as seen from the camera.
std::pair<float, float> depthRange(const Surface& surface, const GlCamera& camera) {
    float nearest = 1e30f, farthest = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        const vec3 p(corner & 1 ? float(surface.width()) : 0.0f,
                     corner & 2 ? float(surface.height()) : 0.0f,
                     corner & 4 ? surface.depth() : 0.0f);
        const float along = glm::dot(p - camera.eye, camera.forward);
        nearest = std::min(nearest, along);
        farthest = std::max(farthest, along);
    }
    const float diagonal = glm::length(
        vec3(float(surface.width()), float(surface.height()), std::max(surface.depth(), 1.0f)));
    return {std::max(0.9f * nearest, 1e-3f * diagonal), std::max(1.1f * farthest, diagonal)};
}

}  // namespace

Result<std::string> glBackendDescription() {
    auto context = gl::EglContext::shared();
    if (!context) return context.error();
    return (*context)->description();
}

Result<std::unique_ptr<Tracer>> createGlTracer(const TechniqueInfo& info,
                                               const TechniqueInput& input) {
    auto tracer = GlTracer::create(info, input, Entry::Rays);
    if (!tracer) return tracer.error();
    return std::unique_ptr<Tracer>(std::move(*tracer));
}

Result<std::unique_ptr<Tracer>> createTracer(Backend backend, const TechniqueInfo& info,
                                             const TechniqueInput& input) {
    return backend == Backend::Gl ? createGlTracer(info, input) : info.create(input);
}

Result<std::unique_ptr<GlCameraTracer>> createGlCameraTracer(const TechniqueInfo& info,
                                                             const TechniqueInput& input) {
    auto tracer = GlTracer::create(info, input, Entry::Camera);
    if (!tracer) return tracer.error();
    return std::unique_ptr<GlCameraTracer>(std::move(*tracer));
}

Result<GlFrameTiming> timeGlFrame(const TechniqueInfo& info, const TechniqueInput& input,
                                  const GlCamera& camera, const GlTimingOptions& options) {
    auto tracer = createGlCameraTracer(info, input);
    if (!tracer) return tracer.error();
    return (*tracer)->timeFrames(camera, options);
}

Result<std::vector<Hit>> traceGlCamera(const TechniqueInfo& info, const TechniqueInput& input,
                                       const GlCamera& camera) {
    auto tracer = createGlCameraTracer(info, input);
    if (!tracer) return tracer.error();
    return (*tracer)->traceFrame(camera);
}

Result<GlFrameTiming> timeRasterizedMesh(const Surface& surface, const GlCamera& camera,
                                         const GlTimingOptions& options) {
    if (camera.width < 1 || camera.height < 1)
        return makeError(ErrorKind::BadArgument, "GL backend: camera image is {}×{}",
                         camera.width, camera.height);
    auto context = EglContext::shared();
    if (!context) return context.error();
    EglContext::Scope scope(**context);
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (camera.width > maxSize || camera.height > maxSize)
        return makeError(ErrorKind::Unsupported, "GL backend: {}×{} is over the renderbuffer "
                         "limit {}", camera.width, camera.height, maxSize);
    auto program = graphicsProgram("mesh", {"mesh_vertex.glsl"}, {"mesh_fragment.glsl"});
    if (!program) return program.error();

    const Mesh mesh = buildMesh(surface);
    GlBuffer vertices, indices, uniforms;
    vertices.upload(mesh.vertices.data(), mesh.vertices.size() * sizeof(vec3), GL_STATIC_DRAW);
    indices.upload(mesh.indices.data(), mesh.indices.size() * sizeof(uint32_t), GL_STATIC_DRAW);
    MeshUniforms meshUniforms;
    const auto [near, far] = depthRange(surface, camera);
    meshUniforms.clipFromTexel = clipFromTexel(camera, near, far);
    meshUniforms.lightDirection = glm::normalize(vec3(0.3f, 0.5f, 0.8f));
    uploadBlock(uniforms, meshUniforms);

    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    GlVertexArray vertexArray(id);
    glVertexArrayVertexBuffer(id, 0, vertices.id(), 0, sizeof(vec3));
    glVertexArrayAttribFormat(id, 0, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(id, 0, 0);
    glEnableVertexArrayAttrib(id, 0);
    glVertexArrayElementBuffer(id, indices.id());

    glCreateRenderbuffers(1, &id);
    GlRenderbuffer color(id);
    glNamedRenderbufferStorage(id, GL_RGBA8, camera.width, camera.height);
    glCreateRenderbuffers(1, &id);
    GlRenderbuffer depth(id);
    glNamedRenderbufferStorage(id, GL_DEPTH_COMPONENT24, camera.width, camera.height);
    glCreateFramebuffers(1, &id);
    GlFramebuffer framebuffer(id);
    glNamedFramebufferRenderbuffer(id, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color.id());
    glNamedFramebufferRenderbuffer(id, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth.id());
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return makeError(ErrorKind::Runtime, "GL backend: mesh framebuffer incomplete (0x{:04X})",
                         unsigned(status));

    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer.id());
    glViewport(0, 0, camera.width, camera.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClearDepth(1.0);
    glUseProgram(program->id());
    glBindVertexArray(vertexArray.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, kMeshBinding, uniforms.id());
    const GLsizei indexCount = GLsizei(mesh.indices.size());
    GlFrameTiming timing = timedFrames(options, [&] {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDrawElements(GL_TRIANGLES, indexCount, GL_UNSIGNED_INT, nullptr);
    });

    std::vector<float> depths(size_t(camera.width) * size_t(camera.height));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, camera.width, camera.height, GL_DEPTH_COMPONENT, GL_FLOAT, depths.data());
    timing.hitFraction = double(std::count_if(depths.begin(), depths.end(),
                                              [](float d) { return d < 1.0f; })) /
                         double(depths.size());
    timing.device = (*context)->description();
    glBindVertexArray(0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (std::string error = takeGlError(); !error.empty())
        return makeError(ErrorKind::Runtime, "GL backend: rasterizing the mesh failed: {}", error);
    return timing;
}

}  // namespace relief
