#include <relief/bench/runner.h>

#include <relief/bench/paper_page.h>
#include <relief/bench/peers.h>
#include <relief/bench/report.h>
#include <relief/bench/timing.h>
#include <relief/core/parallel.h>
#include <relief/core/progress.h>
#include <relief/gl/camera.h>
#include <relief/gl/gl_tracer.h>
#include <relief/io/image_write.h>
#include <relief/render/compare.h>
#include <relief/render/curves/curves_image.h>
#include <relief/render/renderer.h>
#include <relief/render/surface_source.h>
#include <relief/techniques/registry.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>

namespace relief::bench {

namespace {

namespace fs = std::filesystem;

// Inside the run, errors unwind to run() as this; run() returns them.
struct Failure {
    Error error;
};
template <class T>
T orFail(Result<T> result) {
    if (!result) throw Failure{result.error()};
    return std::move(*result);
}
void orFail(Status status) {
    if (!status) throw Failure{status.error()};
}

using Overrides = std::vector<std::pair<std::string, double>>;

std::string slug(std::string text) {
    for (char& c : text)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.') c = '_';
    return text;
}

// The row's iteration cap parameter, when it has a real one (0 = "none" defaults do not count).
const ParamSpec* capParam(const TechniqueInfo& info) {
    const ParamSpec* cap = paramWithRole(info, ParamRole::IterationCap);
    return cap && cap->defaultValue != 0 ? cap : nullptr;
}

// Against the reference: the pixels in the exact contract's agreement (same hit/miss and
// |Δt| <= 1e-3 texel), and steps over the rays that enter the relief's box.
void agreement(BenchRow& row, const Image<Hit>& hits, const Image<Hit>& reference, const std::vector<char>& inBox) {
    size_t agree = 0;
    std::vector<double> steps;
    for (size_t k = 0; k < hits.pixels.size(); ++k) {
        const Hit& a = hits.pixels[k];
        const Hit& b = reference.pixels[k];
        agree += a.hit == b.hit && (!a.hit || std::abs(a.t - b.t) <= 1e-3f);
        if (inBox[k]) steps.push_back(double(a.steps));
    }
    row.agreeRate = hits.pixels.empty() ? 0.0 : double(agree) / double(hits.pixels.size());
    row.boxSteps = relief::summarize(std::move(steps));
}

size_t mapBytes(const TechniqueMaps& maps) {
    size_t bytes = 0;
    for (const MapArray& a : maps.arrays) bytes += a.data.size() * sizeof(float);
    return bytes;
}

// A crop keeps its window in the label, as WxH+X+Y or "WxH centre X+Y" (no commas: the label is
// a CSV field): two windows of one file are two maps.
std::string mapLabel(const std::string& source) {
    auto spec = parseSourceSpec(source);
    const std::string base = spec ? spec->base : source;
    std::string label = base.rfind("gen:", 0) == 0 ? base.substr(4) : fs::path(base).stem().string();
    if (spec && spec->crop)
        label += fmt::format(fmt::runtime(spec->crop->centred ? "@{}x{} centre {}+{}" : "@{}x{}+{}+{}"),
                             spec->crop->width, spec->crop->height, spec->crop->x, spec->crop->y);
    return label;
}

std::string resolveDataPath(const std::string& source) {
    auto spec = parseSourceSpec(source);
    if (!spec) return source;  // the loader reports the syntax
    const std::string& file = spec->base;
    if (file.rfind("gen:", 0) == 0 || fs::path(file).is_absolute()) return source;
    for (const std::string& base : {std::string("."), std::string(RELIEF_SOURCE_DIR)})
        if (fs::exists(base + "/" + file)) return base + "/" + file + spec->suffix;
    return source;
}

// The heightfields of the run: in a Builds or Scaling study, a map with {N} in it stands for one
// map per size N (gen:fbm:{N}x{N}:1); the others are taken once.
std::vector<std::string> runMaps(const BenchConfig& c) {
    std::vector<std::string> maps;
    for (const std::string& m : c.maps)
        if (c.sizes.empty() || m.find("{N}") == std::string::npos) maps.push_back(m);
    std::vector<std::string> sized;
    for (int n : c.sizes)
        for (std::string m : c.maps) {
            if (m.find("{N}") == std::string::npos) continue;
            for (size_t at; (at = m.find("{N}")) != std::string::npos;) m.replace(at, 3, std::to_string(n));
            sized.push_back(m);
        }
    sized.insert(sized.end(), maps.begin(), maps.end());
    return sized;
}

// A row's parameters from the global options: --param NAME=V where the row has NAME, and the
// --visibility / --phi-max roles where it has them; an option that no row takes is an error.
Result<std::vector<Overrides>> globalOverrides(const RunOptions& o, const std::vector<RowSpec>& rows) {
    struct Global {
        std::string option;
        std::optional<ParamRole> role;
        std::string name;
        double value;
    };
    std::vector<Global> globals;
    for (const std::string& p : o.params) {
        auto parsed = parseParamList(p);
        if (!parsed || parsed->size() != 1)
            return makeError(ErrorKind::BadArgument, "--param '{}': expected NAME=NUMBER", p);
        globals.push_back({"--param " + p, std::nullopt, parsed->front().first, parsed->front().second});
    }
    if (!o.visibility.empty()) {
        if (o.visibility != "all" && o.visibility != "exterior")
            return makeError(ErrorKind::BadArgument, "--visibility '{}': all or exterior", o.visibility);
        globals.push_back({"--visibility " + o.visibility, ParamRole::Visibility, "", o.visibility == "exterior" ? 1.0 : 0.0});
    }
    if (o.phiMax) globals.push_back({fmt::format("--phi-max {}", *o.phiMax), ParamRole::PhiMax, "", *o.phiMax});
    std::vector<Overrides> perRow(rows.size());
    for (const Global& g : globals) {
        bool taken = false;
        for (size_t k = 0; k < rows.size(); ++k) {
            const ParamSpec* spec = nullptr;
            if (g.role) spec = paramWithRole(*rows[k].info, *g.role);
            for (const ParamSpec& s : rows[k].info->params)
                if (!g.role && s.name == g.name) spec = &s;
            if (!spec) continue;
            perRow[k].emplace_back(std::string(spec->name), g.value);
            taken = true;
        }
        if (!taken) return makeError(ErrorKind::BadArgument, "{}: none of the selected techniques takes it", g.option);
    }
    // The row's own variant parameters are the more specific: they come last and win.
    for (size_t k = 0; k < rows.size(); ++k) {
        perRow[k].insert(perRow[k].end(), rows[k].params.begin(), rows[k].params.end());
        if (auto check = resolveParams(*rows[k].info, perRow[k]); !check) return check.error();
    }
    return perRow;
}

// One row on one heightfield: its maps, built once (or taken from --maps) and shared by its caps
// and backends.
struct PreparedRow {
    const RowSpec* spec = nullptr;
    bool skipped = false;  // BenchConfig::rowMaxSamples: not run on this heightfield
    Overrides overrides;
    std::optional<TechniqueMaps> built;
    const TechniqueMaps* maps = nullptr;
    Elapsed build;
    double bytesPerTexel = 0;
    std::map<int, std::pair<std::unique_ptr<Tracer>, double>> cpu;  // per cap: tracer, create seconds
    // Uploaded and compiled once, for every view and cap (the cap is a uniform: setParams).
    std::unique_ptr<GlCameraTracer> gl;
    // Per cap: the row's tracer as an Embree user geometry (BenchConfig::userGeometry). After
    // `built`: destroyed first, as the tracer reads those maps.
    std::map<int, std::unique_ptr<EmbreePeer>> user;

    Overrides at(int cap) const {
        Overrides o = overrides;
        if (cap > 0) o.emplace_back(std::string(capParam(*spec->info)->name), double(cap));
        return o;
    }
};

class Runner {
public:
    Runner(const RunOptions& o, BenchConfig config, std::vector<RowSpec> rows, std::vector<Overrides> overrides)
        : m_o(o), m_config(std::move(config)), m_specs(std::move(rows)), m_overrides(std::move(overrides)) {}

    const std::vector<BenchRow>& rows() const { return m_rows; }

    void run() {
        std::error_code ec;
        fs::create_directories(fs::path(m_o.outDir) / "images", ec);
        if (ec) throw Failure{makeError(ErrorKind::Io, "{}: cannot create folder: {}", m_o.outDir, ec.message())};
        m_loadBefore = loadAverage();
        const std::vector<std::string> maps = runMaps(m_config);
        const bool views = m_config.kind != StudyKind::Builds;
        Progress progress("bench", int64_t(maps.size() * (views ? m_config.elevations.size() : 1)));
        for (const std::string& source : maps) {
            SurfaceOptions so;
            so.source = resolveDataPath(source);
            so.depth = m_config.depth;
            so.depthRatio = m_config.depthRatio;
            so.edge = m_config.edge;
            auto surface = orFail(makeSurface(so, orFail(loadHeightfield(so))));
            m_mapSamples = surface->heightfield().sampleCount();
            std::shared_ptr<const MapFile> mapFile;
            if (!m_o.mapsPath.empty()) mapFile = orFail(loadCheckedMaps(m_o.mapsPath, *surface));
            std::vector<PreparedRow> rows = prepare(surface, mapFile.get());
            if (views)
                runViews(mapLabel(source), surface, rows, progress);
            else
                recordBuilds(mapLabel(source), rows, progress);
        }
        writeResults();
        if (m_o.judge) judge();
    }

private:
    // Maps once per (row, heightfield): parameters with role IterationCap do not shape them.
    std::vector<PreparedRow> prepare(std::shared_ptr<const Surface> surface, const MapFile* mapFile) {
        std::vector<PreparedRow> rows(m_specs.size());
        for (size_t k = 0; k < m_specs.size(); ++k) {
            PreparedRow& row = rows[k];
            row.spec = &m_specs[k];
            row.overrides = m_overrides[k];
            const TechniqueInfo& info = *row.spec->info;
            for (const auto& [label, samples] : m_config.rowMaxSamples)
                row.skipped |= label == row.spec->label && int64_t(surface->heightfield().sampleCount()) > samples;
            if (!info.buildMaps || row.skipped) continue;
            if (mapFile) {
                row.maps = orFail(techniqueInput(info, surface, row.overrides, mapFile, m_o.mapsPath)).maps;
            } else {
                const TechniqueInput input = orFail(techniqueInput(info, surface, row.overrides));
                Result<TechniqueMaps> maps = makeError(ErrorKind::Runtime, "not built");
                row.build = timeOnce([&] { maps = info.buildMaps(input); });
                row.built = orFail(std::move(maps));
                row.maps = &*row.built;
            }
            row.bytesPerTexel = double(mapBytes(*row.maps)) / double(surface->heightfield().sampleCount());
        }
        return rows;
    }

    TechniqueInput inputAt(const PreparedRow& row, std::shared_ptr<const Surface> surface, int cap) const {
        TechniqueInput input = orFail(techniqueInput(*row.spec->info, std::move(surface), row.at(cap)));
        input.maps = row.maps;
        return input;
    }

    std::vector<int> capsOf(const TechniqueInfo& info) const {
        return capParam(info) && !m_config.caps.empty() ? m_config.caps : std::vector<int>{0};
    }

    BenchRow newRow(const PreparedRow& row, const std::string& map, std::string backend, float elevation, int cap,
                    const ParamValues& params) const {
        BenchRow r;
        r.technique = row.spec->label;
        r.contract = std::string(toString(contractOf(*row.spec->info, params)));
        r.map = map;
        r.backend = std::move(backend);
        r.elevation = elevation;
        r.cap = cap;
        r.buildSeconds = row.build.wall;
        r.buildCpuSeconds = row.build.cpu;
        r.bytesPerTexel = row.bytesPerTexel;
        r.mapSamples = m_mapSamples;
        return r;
    }

    void recordBuilds(const std::string& map, const std::vector<PreparedRow>& rows, Progress& progress) {
        for (const PreparedRow& row : rows) {
            if (!row.maps || row.skipped) continue;
            const ParamValues params = orFail(resolveParams(*row.spec->info, row.overrides));
            m_rows.push_back(newRow(row, map, "cpu", 0.0f, 0, params));
            if (auto summary = row.spec->info->mapSummary) m_rows.back().mapSummary = summary(*row.maps);
        }
        progress.advance();
    }

    void runViews(const std::string& label, std::shared_ptr<const Surface> surface, std::vector<PreparedRow>& rows,
                  Progress& progress) {
        const std::unique_ptr<Tracer> reference = orFail(referenceTechnique().create(
            orFail(techniqueInput(referenceTechnique(), surface, {}))));
        std::unique_ptr<EmbreePeer> embree;
        if (m_config.embree && surface->edge() == EdgeMode::Clamp) embree = orFail(EmbreePeer::create(*surface));
        m_embree = embree.get();
        for (float elevation : m_config.elevations) {
            OrbitView view{elevation, m_config.azimuth, m_config.distance, 45.0f};
            const Camera camera(view, *surface, m_config.size.x, m_config.size.y);
            const Image<Hit> referenceHits = tracePrimary(camera, *reference);
            if (m_config.shadowElevation > 0.0f) prepareShadows(*surface, camera, referenceHits, *reference);
            m_inBox.clear();
            const std::vector<Ray> rays = primaryRays(camera);
            for (const Ray& ray : rays) m_inBox.push_back(!surface->clip(ray).empty());
            m_packetOrder = packetOrder(camera.width(), camera.height());
            m_packetRays = inPacketOrder(rays, m_packetOrder);
            if (embree) runEmbree(label, elevation, camera, *embree, referenceHits);
            for (PreparedRow& row : rows) {
                if (row.skipped) continue;
                const std::vector<int> caps = capsOf(*row.spec->info);
                for (int cap : caps) {
                    const bool images = !m_o.noImages && cap == caps.back();
                    if (wants("cpu") && drawsCurves(*row.spec->info))
                        runCurves(row, label, elevation, cap, surface, view, images);
                    else if (wants("cpu"))
                        runCpu(row, label, elevation, cap, surface, camera, referenceHits, images);
                    if (wants("gl") && !row.spec->info->glsl.empty())
                        runGl(row, label, elevation, cap, inputAt(row, surface, cap), camera, referenceHits);
                }
            }
            if (wants("gl")) runMesh(label, elevation, *surface, camera);
            progress.advance();
        }
        m_embree = nullptr;  // `embree` ends here
    }

    // StudySpec::shadowElevation: the reference's primary hits that face the light, in the 4×4
    // tiles of the Embree packets (coherent shadow rays for every row and peer), and whether the
    // reference finds each lit (traced from the light, as every row's shadow test is). With
    // shadowTiming, the rays themselves: segments that end before their points, searched whole
    // by the rows (first hit) and by Embree's occlusion queries (any hit; litFromHits' verdict).
    void prepareShadows(const Surface& surface, const Camera& camera,
                        const Image<Hit>& referenceHits, const Tracer& reference) {
        m_towardsLight = towardsLight(m_config.shadowElevation);
        m_shadowPoints = shadowPoints(surface, referenceHits.pixels, camera.width(),
                                      camera.height(), m_towardsLight);
        m_referenceLit = litFromTheLight(surface, m_shadowPoints, reference, m_towardsLight);
        if (!m_config.shadowTiming) return;
        m_lightRays = raysFromTheLight(surface, m_shadowPoints, m_towardsLight);
    }

    double shadowWrongRate(std::span<const uint8_t> lit, size_t pixels) const {
        size_t wrong = 0;
        for (size_t k = 0; k < lit.size(); ++k) wrong += lit[k] != m_referenceLit[k];
        return double(wrong) / double(std::max<size_t>(1, pixels));
    }

    bool wants(const std::string& backend) const {
        return std::find(m_config.backends.begin(), m_config.backends.end(), backend) != m_config.backends.end();
    }

    // Rows with an image method of their own, in a preset that asks for it (BenchConfig::imageMethod).
    bool drawsCurves(const TechniqueInfo& info) const {
        return m_config.imageMethod && info.image == ImageMethod::VisibilityCurves;
    }

    // The visibility-curve renderer as `relief render` runs it (render/curves/curves_image.h): every
    // sample measured against the reference on its own ray, the reference timed on those rays.
    void runCurves(const PreparedRow& row, const std::string& map, float elevation, int cap,
                   std::shared_ptr<const Surface> surface, const OrbitView& view, bool images) {
        const TechniqueInfo& info = *row.spec->info;
        const ParamValues params = orFail(resolveParams(info, row.at(cap)));
        const curves::CurvesScene scene{surface, nullptr, view, m_config.size.x, m_config.size.y, Shading{}};
        const curves::CurvesOptions options = curves::curvesOptions(info, params);
        curves::CurvesRun run;
        double seconds = 1e300, referenceSeconds = 1e300;
        for (int k = 0; k < std::max(1, m_config.repeats); ++k) {
            run = orFail(curves::renderAndMeasure(scene, options));
            seconds = std::min(seconds, run.result.seconds);
            referenceSeconds = std::min(referenceSeconds, run.referenceSeconds);
        }
        BenchRow r = newRow(row, map, "cpu", elevation, cap, params);
        r.stats = run.stats;
        Image<Hit> hits(int(run.result.samples.size()), 1);
        for (size_t k = 0; k < run.result.samples.size(); ++k) hits.pixels[k] = run.result.samples[k].hit;
        agreement(r, hits, run.reference, std::vector<char>(hits.pixels.size(), 1));
        CurvesFigures figures{run.result.counts};
        double cells = 0;
        for (const Hit& hit : run.reference.pixels) cells += hit.steps;
        const double rays = double(std::max<size_t>(1, run.reference.pixels.size()));
        figures.referenceCellsPerRay = cells / rays;
        figures.msamplesPerSecond = 1e-6 * double(figures.counts.samples()) / seconds;
        figures.referenceMraysPerSecond = 1e-6 * rays / referenceSeconds;
        r.curves = figures;
        r.mraysPerSecond = figures.msamplesPerSecond;
        r.msPerFrame = 1000.0 * seconds;
        if (images) {
            r.images = fmt::format("images/{}_{}_e{:.1f}", slug(map), slug(r.technique), elevation);
            const std::string base = m_o.outDir + "/" + r.images;
            orFail(writePng(base + ".png", run.result.color));
            orFail(writePng(base + "-steps.png", curves::stepsImage(run, r.technique + " evaluations/sample")));
            orFail(writePng(base + "-error.png", curves::errorImage(run, r.technique + " |t-t_ref|")));
        }
        m_rows.push_back(std::move(r));
    }

    void runCpu(PreparedRow& row, const std::string& map, float elevation, int cap,
                std::shared_ptr<const Surface> surface, const Camera& camera, const Image<Hit>& reference,
                bool images) {
        const TechniqueInput input = inputAt(row, surface, cap);
        // References, not a structured binding: lambdas capture them (clang 14).
        auto& built = row.cpu[cap];
        std::unique_ptr<Tracer>& tracer = built.first;
        double& createSeconds = built.second;
        if (!tracer) createSeconds = timeOnce([&] { tracer = orFail(row.spec->info->create(input)); }).wall;
        BenchRow r = newRow(row, map, "cpu", elevation, cap, input.params);
        r.buildSeconds += createSeconds;
        // Timed as Embree's packets are (EmbreePeer::run): on rays made beforehand, in its order.
        std::vector<Hit> packed(m_packetRays.size());
        const double seconds = timeRow([&] { traceAll(*tracer, m_packetRays, packed); }, false, camera, r);
        Image<Hit> hits(camera.width(), camera.height());
        for (size_t k = 0; k < packed.size(); ++k) hits.pixels[m_packetOrder[k]] = packed[k];
        r.stats = compareHits(hits, reference);
        agreement(r, hits, reference, m_inBox);
        r.mraysPerSecond = double(hits.pixels.size()) / seconds / 1e6;
        r.msPerFrame = 1000.0 * seconds;
        if (m_config.shadowElevation > 0.0f && m_config.shadowTiming) {
            std::vector<Hit> shadowHits(m_lightRays.rays.size());
            const double shadowSeconds =
                timeRow([&] { traceAll(*tracer, m_lightRays.rays, shadowHits); }, true, camera, r);
            r.shadowMraysPerSecond = double(shadowHits.size()) / shadowSeconds / 1e6;
            r.shadowWrongRate = shadowWrongRate(litFromHits(m_lightRays, shadowHits), hits.pixels.size());
        } else if (m_config.shadowElevation > 0.0f) {
            r.shadowWrongRate = shadowWrongRate(litFromTheLight(*surface, m_shadowPoints, *tracer, m_towardsLight),
                                                hits.pixels.size());
        }
        if (images) {
            r.images = fmt::format("images/{}_{}_e{:.1f}", slug(map), slug(r.technique), elevation);
            const std::string base = m_o.outDir + "/" + r.images;
            Shading shading;
            orFail(writePng(base + ".png", render(*surface, camera, *tracer, shading).color));
            orFail(writePng(base + "-steps.png", stepsHeatmap(hits, r.stats, r.technique)));
            orFail(writePng(base + "-error.png", errorHeatmap(hits, reference, r.stats, r.technique)));
        }
        m_rows.push_back(std::move(r));
        if (m_config.userGeometry && surface->edge() == EdgeMode::Clamp)
            runUserGeometry(row, map, elevation, cap, surface, camera, reference, input);
    }

    // A CPU row's best time over the repeats on the view's primary or shadow rays. With
    // BenchConfig::pairedPeers each repeat is followed by one run of each Embree peer on the same
    // rays, and r.pairedRatios gets the median of the per-repeat ratios.
    template <class Trace>
    double timeRow(Trace&& trace, bool shadow, const Camera& camera, BenchRow& r) const {
        if (!m_config.pairedPeers || !m_embree) return bestOf(m_config.repeats, trace);
        constexpr PeerKind kKinds[] = {PeerKind::Embree1, PeerKind::Embree16};
        std::vector<double> ratios[std::size(kKinds)];
        double best = 1e300;
        for (int k = 0; k < std::max(1, m_config.repeats); ++k) {
            const auto start = std::chrono::steady_clock::now();
            trace();
            const double seconds = secondsSince(start);
            best = std::min(best, seconds);
            for (size_t p = 0; p < std::size(kKinds); ++p) {
                const double peerSeconds = shadow ? m_embree->occluded(kKinds[p], m_lightRays.rays, 1).seconds
                                                  : m_embree->run(kKinds[p], camera, 1).seconds;
                ratios[p].push_back(peerSeconds / seconds);  // row speed ÷ peer speed
            }
        }
        for (size_t p = 0; p < std::size(kKinds); ++p)
            r.pairedRatios[embreeQuery(kKinds[p], shadow)] = median(ratios[p]);
        return best;
    }

    // The row's tracer behind an Embree user geometry: the triangle peers' Embree calls on the same
    // rays. Memory: the heightfield and the surface's padded heights (what the callbacks read),
    // the row's maps, and the Embree scene (a BVH over one box).
    void runUserGeometry(PreparedRow& row, const std::string& map, float elevation, int cap,
                         std::shared_ptr<const Surface> surface, const Camera& camera, const Image<Hit>& reference,
                         const TechniqueInput& input) {
        std::unique_ptr<EmbreePeer>& peer = row.user[cap];
        if (!peer) {
            std::shared_ptr<const Tracer> tracer = orFail(row.spec->info->create(input));
            peer = orFail(EmbreePeer::createUserGeometry(surface, std::move(tracer)));
        }
        const double heights =
            double(surface->heightfield().sampleCount() + surface->paddedHeights().size()) * sizeof(float);
        for (PeerKind kind : {PeerKind::Embree1, PeerKind::Embree16}) {
            BenchRow r = newRow(row, map, "cpu", elevation, cap, input.params);
            r.technique = userGeometryLabel(row.spec->label, kind);
            measurePeer(r, peer->run(kind, camera, m_config.repeats), reference);
            r.buildSeconds += peer->buildSeconds();
            r.bytesPerTexel += (heights + double(peer->embreeBytes())) / double(m_mapSamples);
            m_rows.push_back(std::move(r));
        }
    }

    void measurePeer(BenchRow& r, const PeerResult& result, const Image<Hit>& reference) const {
        r.stats = compareHits(result.hits, reference);
        agreement(r, result.hits, reference, m_inBox);
        r.mraysPerSecond = double(result.hits.pixels.size()) / result.seconds / 1e6;
        r.msPerFrame = 1000.0 * result.seconds;
    }

    // GPU rows: rays made on the GPU from the camera, ms per frame with glFinish (DESIGN §8);
    // accuracy from one frame read back and compared with the reference on the same rays. The
    // row's program is compiled once per heightfield; each cap only sets its uniforms.
    void runGl(PreparedRow& row, const std::string& map, float elevation, int cap, const TechniqueInput& input,
               const Camera& camera, const Image<Hit>& reference) {
        const TechniqueInfo& info = *row.spec->info;
        if (!row.gl) row.gl = orFail(createGlCameraTracer(info, input));
        else orFail(row.gl->setParams(input));
        const gl::CameraUniforms uniforms = gl::cameraUniforms(camera);
        const GlFrameTiming timing = orFail(row.gl->timeFrames(uniforms, {m_config.glFrames, 2}));
        Image<Hit> hits(camera.width(), camera.height());
        hits.pixels = orFail(row.gl->traceFrame(uniforms));
        BenchRow r = newRow(row, map, "gl", elevation, cap, input.params);
        r.stats = compareHits(hits, reference);
        agreement(r, hits, reference, m_inBox);
        r.msPerFrame = timing.msPerFrame;
        r.mraysPerSecond = double(hits.pixels.size()) / (timing.msPerFrame * 1e-3) / 1e6;
        m_glDevice = timing.device;
        m_rows.push_back(std::move(r));
    }

    BenchRow peerRow(const PeerInfo& peer, const std::string& map, float elevation) const {
        BenchRow r;
        r.technique = std::string(peer.name);
        r.contract = "peer";
        r.map = map;
        r.backend = std::string(peer.backend);
        r.elevation = elevation;
        r.mapSamples = m_mapSamples;
        return r;
    }

    void runMesh(const std::string& map, float elevation, const Surface& surface, const Camera& camera) {
        for (const PeerInfo& peer : peers()) {
            if (peer.kind != PeerKind::Mesh) continue;
            const PeerResult result = orFail(runMeshPeer(surface, camera, m_config.glFrames));
            BenchRow r = peerRow(peer, map, elevation);
            r.msPerFrame = 1000.0 * result.seconds;
            r.mraysPerSecond = double(camera.width()) * camera.height() / result.seconds / 1e6;
            m_rows.push_back(std::move(r));
        }
    }

    void runEmbree(const std::string& map, float elevation, const Camera& camera, const EmbreePeer& embree,
                   const Image<Hit>& reference) {
        for (const PeerInfo& peer : peers()) {
            if (peer.kind == PeerKind::Mesh) continue;
            BenchRow r = peerRow(peer, map, elevation);
            measurePeer(r, embree.run(peer.kind, camera, m_config.repeats), reference);
            r.buildSeconds = embree.buildSeconds();
            if (m_config.shadowElevation > 0.0f && m_config.shadowTiming) {
                const OcclusionResult shadows = embree.occluded(peer.kind, m_lightRays.rays, m_config.repeats);
                std::vector<uint8_t> lit(shadows.occluded.size());
                for (size_t k = 0; k < lit.size(); ++k) lit[k] = !shadows.occluded[k];
                r.shadowMraysPerSecond = double(lit.size()) / shadows.seconds / 1e6;
                r.shadowWrongRate = shadowWrongRate(lit, r.stats.pixels);
            }
            if (m_config.userGeometry) r.bytesPerTexel = double(embree.embreeBytes()) / double(m_mapSamples);
            m_rows.push_back(std::move(r));
        }
    }

    void writeResults() const {
        const bool timings = !m_o.deterministic;
        const nlohmann::json meta = {{"preset", m_o.preset}, {"threads", ThreadLimit::current()},
                                     {"image_size", fmt::format("{}x{}", m_config.size.x, m_config.size.y)},
                                     {"machine", cpuModelName()},
                                     {"gl_device", m_glDevice},
                                     {"date", timings ? todayUtc() : std::string("-")}};
        // The report's files are one transaction: a failure leaves the previous report whole.
        OutputSet outputs;
        writeFile(outputs, "results.json", resultsJson(m_rows, meta, timings));
        writeFile(outputs, "results.csv", resultsCsv(m_rows, timings));
        const auto [errorPlot, stepsPlot] = benchPlots(m_rows, m_config);
        writeFile(outputs, "error_vs_cap.svg", errorPlot);
        writeFile(outputs, "steps_vs_elevation.svg", stepsPlot);
        if (m_config.kind == StudyKind::Scaling)
            writeFile(outputs, kScalingPlotName, scalingPlot(m_rows, m_config));
        BenchMeta report{m_o.preset, meta["machine"], meta["image_size"], meta["date"], m_glDevice,
                         commandLine(m_o), "", "", ThreadLimit::current(), timings};
        if (timings) {
            report.loadBefore = m_loadBefore;
            report.loadAfter = loadAverage();
        }
        writeFile(outputs, "index.html", benchHtml(m_rows, m_config, report));
        writeFile(outputs, "report.md", benchMarkdown(m_rows, m_config, report, ""));
        if (!m_o.markdownPath.empty()) writeMarkdownCopy(outputs, report);
        orFail(outputs.commit());
        if (Progress::quiet()) return;  // -q: errors only
        if (!m_o.markdownPath.empty()) std::cout << "wrote " << m_o.markdownPath << "\n";
        if (!m_glDevice.empty()) std::cout << "GL: " << m_glDevice << "\n";
        std::cout << fmt::format("\nwrote {0}/index.html, {0}/report.md, results.csv, results.json\n", m_o.outDir);
    }

    // The same report elsewhere (e.g. docs/benchmarks.md), its plot links rewritten to point
    // into the output folder.
    void writeMarkdownCopy(OutputSet& outputs, const BenchMeta& report) const {
        const fs::path target = fs::absolute(m_o.markdownPath);
        std::string prefix = fs::relative(fs::absolute(m_o.outDir), target.parent_path()).generic_string();
        prefix = prefix.empty() || prefix == "." ? "" : prefix + "/";
        orFail(outputs.addText(m_o.markdownPath, benchMarkdown(m_rows, m_config, report, prefix)));
    }

    void writeFile(OutputSet& outputs, const std::string& name, const std::string& text) const {
        orFail(outputs.addText(m_o.outDir + "/" + name, text));
    }

    // --judge: rows with the exact contract agree with the reference, and so do the CPU peers on
    // at least 99.9% of the rays of a view (same hit/miss, |Δt| <= 1e-3: Embree's watertight test
    // and ours differ on grazing edges).
    void judge() const {
        for (const BenchRow& r : m_rows) {
            const bool exact = r.contract == toString(Contract::Exact);
            const bool cpuPeer = isPeer(r.technique) && r.backend == "cpu";
            if ((exact && (r.stats.error.max > 1e-3 || r.stats.wrong > 0)) || (cpuPeer && r.agreeRate < 0.999))
                throw Failure{makeError(ErrorKind::Runtime,
                                        "--judge: {} on {} at elevation {:.1f} (cap {}) disagrees with {}: "
                                        "{:.3f}% wrong pixels, {:.4f}% agree, max error {:.3g} texels",
                                        r.technique, r.map, r.elevation, r.cap, referenceTechnique().name,
                                        100 * r.stats.wrongRate(), 100 * r.agreeRate, r.stats.error.max)};
        }
        std::cout << "judge: every exact row and CPU peer agrees with " << referenceTechnique().name << "\n";
    }

    const RunOptions& m_o;
    BenchConfig m_config;
    std::vector<RowSpec> m_specs;
    std::vector<Overrides> m_overrides;
    std::vector<BenchRow> m_rows;
    std::string m_glDevice, m_loadBefore;
    std::vector<char> m_inBox;  // per pixel of the current view: its ray enters the box
    // The current view's primary rays in the Embree packets' order (4×4 pixel tiles), and the
    // pixel of each: the CPU rows are timed on them, as rtcIntersect16 is.
    std::vector<size_t> m_packetOrder;
    std::vector<Ray> m_packetRays;
    vec3 m_towardsLight{0, 0, 1};
    std::vector<vec3> m_shadowPoints;    // the current view's shadow test points
    std::vector<uint8_t> m_referenceLit;  // the reference's verdict on each
    RaysFromTheLight m_lightRays;          // shadowTiming: the rows' shadow rays
    int64_t m_mapSamples = 0;
    const EmbreePeer* m_embree = nullptr;  // runViews: the current heightfield's triangles, if any
};

// A paper's page (StudyKind::Paper): each part run as its own preset into <out-dir>/<part>/,
// then the claims judged from their rows (bench/paper_page.h) and the page written.
void runPaper(const RunOptions& o, const BenchConfig& paper) {
    const BenchOverrides& v = o.overrides;
    if (!v.techniques.empty() || !v.maps.empty() || !v.sizes.empty() || !v.elevations.empty() || !v.caps.empty() ||
        !v.edge.empty() || v.depth || v.depthRatio || v.azimuth || v.distance || !o.mapsPath.empty() ||
        !o.params.empty() || !o.visibility.empty() || o.phiMax)
        throw Failure{makeError(ErrorKind::BadArgument,
                                "--preset {} is a paper's page: it runs its parts ({}) as they are; to change "
                                "rows, maps or views run a part with --preset PART",
                                o.preset, fmt::join(paper.parts, ", "))};
    const auto loadBefore = loadAverage();
    PartRows parts;
    std::map<std::string, std::string> descriptions;
    for (const PresetEntry& p : presetList()) descriptions[p.name] = p.description;
    for (size_t k = 0; k < paper.parts.size(); ++k) {
        const std::string& part = paper.parts[k];
        RunOptions sub = o;
        sub.preset = part;
        sub.outDir = (fs::path(o.outDir) / part).string();
        sub.markdownPath.clear();
        BenchConfig config = orFail(presetConfig(part));
        if (config.kind == StudyKind::Paper)
            throw Failure{makeError(ErrorKind::Runtime, "paper {}: its part {} is a paper itself", o.preset, part)};
        orFail(applyOverrides(config, sub.overrides));
        if (!Progress::quiet())
            std::cerr << fmt::format("{}: part {}/{}: {}\n", o.preset, k + 1, paper.parts.size(), part);
        std::vector<RowSpec> rows;
        for (const std::string& t : config.techniques) rows.push_back(orFail(parseRowSpec(t)));
        std::vector<Overrides> overrides = orFail(globalOverrides(sub, rows));
        Runner runner(sub, std::move(config), std::move(rows), std::move(overrides));
        runner.run();
        parts[part] = runner.rows();
    }
    const bool timings = !o.deterministic;
    const std::vector<ClaimResult> claims = judgeClaims(paper, parts, timings);
    BenchMeta meta{o.preset, cpuModelName(), "", timings ? todayUtc() : std::string("-"), "",
                   commandLine(o), "", "", ThreadLimit::current(), timings};
    for (const auto& [part, rows] : parts)
        for (const BenchRow& r : rows)
            if (r.backend == "gl") meta.glDevice = "see the parts' reports";
    if (timings) {
        meta.loadBefore = loadBefore;
        meta.loadAfter = loadAverage();
    }
    auto pageWithLinksFrom = [&](const fs::path& pageFolder) {
        std::string prefix = fs::relative(fs::absolute(o.outDir), fs::absolute(pageFolder)).generic_string();
        prefix = prefix.empty() || prefix == "." ? "" : prefix + "/";
        std::map<std::string, std::string> links;  // part → its report, relative to this page
        for (const std::string& part : paper.parts) links[part] = prefix + part + "/report.md";
        return paperMarkdown(paper, claims, meta, links, descriptions);
    };
    OutputSet outputs;
    orFail(outputs.addText(o.outDir + "/report.md", pageWithLinksFrom(o.outDir)));
    orFail(outputs.addText(o.outDir + "/claims.json", claimsJson(claims)));
    if (!o.markdownPath.empty())
        orFail(outputs.addText(o.markdownPath, pageWithLinksFrom(fs::absolute(o.markdownPath).parent_path())));
    orFail(outputs.commit());
    if (Progress::quiet()) return;
    std::map<std::string, int> verdicts;
    for (const ClaimResult& c : claims) ++verdicts[c.verdict];
    std::string counts;
    for (const auto& [verdict, n] : verdicts) counts += fmt::format("{}{} {}", counts.empty() ? "" : ", ", n, verdict);
    std::cout << fmt::format("\n{}: {} claims: {}\nwrote {}/report.md, claims.json{}\n", o.preset, claims.size(),
                             counts, o.outDir, o.markdownPath.empty() ? "" : ", " + o.markdownPath);
}

}  // namespace

std::string commandLine(const RunOptions& o) {
    const BenchOverrides& v = o.overrides;
    std::string s = "relief bench --preset " + o.preset;
    for (const auto& [flag, value] : {std::pair{"-t", v.techniques}, {"--heightfields", v.maps}, {"--elevations", v.elevations},
                                      {"--caps", v.caps}, {"--map-sizes", v.sizes}, {"--backend", v.backends},
                                      {"--size", v.size}, {"--edge", v.edge}, {"--maps", o.mapsPath},
                                      {"--visibility", o.visibility}})
        if (!value.empty()) s += fmt::format(" {} {}", flag, value);
    for (const std::string& p : o.params) s += " --param " + p;
    for (const auto& [flag, value] : {std::pair{"--depth", v.depth}, {"--depth-ratio", v.depthRatio},
                                      {"--azimuth", v.azimuth}, {"--distance", v.distance}})
        if (value) s += fmt::format(" {} {}", flag, *value);
    if (o.phiMax) s += fmt::format(" --phi-max {}", *o.phiMax);
    if (v.smoke) s += " --smoke";
    if (v.quick) s += " --quick";
    if (v.repeats) s += fmt::format(" --repeats {}", v.repeats);
    if (o.threads) s += fmt::format(" --threads {}", o.threads);
    return s;
}

std::string presetTable() {
    std::string s;
    for (const PresetEntry& p : presetList())
        s += fmt::format("{:<16} {:<14} {}\n", p.name, p.owner.empty() ? "(bench)" : p.owner, p.description);
    return s;
}

Status run(const RunOptions& o) {
    try {
        // Checked before the run, not after an hour of it.
        if (!o.markdownPath.empty()) {
            const fs::path folder = fs::absolute(o.markdownPath).parent_path();
            if (!fs::is_directory(folder))
                return makeError(ErrorKind::BadArgument, "--markdown {}: folder '{}' does not exist", o.markdownPath,
                                 folder.string());
        }
        ThreadLimit limit(o.threads);
        BenchConfig config = orFail(presetConfig(o.preset));
        orFail(applyOverrides(config, o.overrides));
        if (config.kind == StudyKind::Paper) {
            runPaper(o, config);
            return {};
        }
        std::vector<RowSpec> rows;
        for (const std::string& t : config.techniques) rows.push_back(orFail(parseRowSpec(t)));
        std::vector<Overrides> overrides = orFail(globalOverrides(o, rows));
        Runner(o, std::move(config), std::move(rows), std::move(overrides)).run();
    } catch (const Failure& failure) {
        return failure.error;
    }
    return {};
}

}  // namespace relief::bench
