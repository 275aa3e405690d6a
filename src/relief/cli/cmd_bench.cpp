// relief bench: techniques × heightfields × views × iteration caps × backends, with the Embree
// peer in the same run; writes results.csv, results.json, images, SVG plots and index.html.
#include <relief/cli/bench_presets.h>
#include <relief/cli/bench_report.h>
#include <relief/cli/common.h>
#include <relief/core/parallel.h>
#include <relief/core/progress.h>
#include <relief/embree/embree_scene.h>
#include <relief/gl/camera.h>
#include <relief/gl/gl_tracer.h>
#include <relief/io/image_write.h>
#include <relief/render/compare.h>
#include <relief/render/renderer.h>
#include <relief/report/svg_plot.h>
#include <relief/techniques/registry.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

namespace relief::cli {

namespace {

struct BenchOptions {
    std::string preset = "default";
    std::string techniques, maps, elevations, caps, backends, size;
    std::string outDir = "bench-out";
    std::string markdownPath;  // also write the Markdown report here (links relative to it)
    int threads = 0;
    int repeats = 0;
    bool noImages = false;
    bool deterministic = false;
};

using Row = BenchRow;

Row newRow(std::string technique, std::string contract, std::string map, std::string backend, float elevation, int cap) {
    Row row;
    row.technique = std::move(technique);
    row.contract = std::move(contract);
    row.map = std::move(map);
    row.backend = std::move(backend);
    row.elevation = elevation;
    row.cap = cap;
    return row;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class Fn>
double bestOf(int repeats, Fn&& fn) {
    double best = 1e300;
    for (int r = 0; r < std::max(1, repeats); ++r) {
        const auto start = std::chrono::steady_clock::now();
        fn();
        best = std::min(best, secondsSince(start));
    }
    return best;
}

std::string slug(std::string text) {
    for (char& c : text)
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '.') c = '_';
    return text;
}

bool hasCap(const TechniqueInfo& info) {
    for (const ParamSpec& p : info.params)
        if (p.name == "max-steps" && p.defaultValue != 0) return true;
    return false;
}

// A built tracer plus what building it cost, kept per (map, technique, cap).
struct BuiltTracer {
    std::unique_ptr<Tracer> tracer;
    double buildSeconds = 0, bytesPerTexel = 0;
};

BuiltTracer buildTracer(const TechniqueInfo& info, std::shared_ptr<const Surface> surface, int cap) {
    std::vector<std::pair<std::string, double>> overrides;
    if (cap > 0) overrides.emplace_back("max-steps", double(cap));
    TechniqueInput input{surface, orFail(resolveParams(info, overrides)), nullptr};
    BuiltTracer built;
    const auto start = std::chrono::steady_clock::now();
    std::optional<TechniqueMaps> maps;
    if (info.buildMaps) {
        maps = orFail(info.buildMaps(input));
        size_t bytes = 0;
        for (const MapArray& a : maps->arrays) bytes += a.data.size() * sizeof(float);
        built.bytesPerTexel = double(bytes) / double(surface->heightfield().sampleCount());
        input.maps = &*maps;
    }
    built.tracer = orFail(info.create(input));
    built.buildSeconds = secondsSince(start);
    return built;
}

// A technique's input for the GL rows, with its maps built once per heightfield (on the CPU).
struct GlInput {
    std::optional<TechniqueMaps> maps;
    TechniqueInput input;
    double buildSeconds = 0, bytesPerTexel = 0;

    GlInput(const TechniqueInfo& info, std::shared_ptr<const Surface> surface, int cap) {
        std::vector<std::pair<std::string, double>> overrides;
        if (cap > 0) overrides.emplace_back("max-steps", double(cap));
        input = TechniqueInput{surface, orFail(resolveParams(info, overrides)), nullptr};
        if (!info.buildMaps) return;
        const auto start = std::chrono::steady_clock::now();
        maps = orFail(info.buildMaps(input));
        buildSeconds = secondsSince(start);
        size_t bytes = 0;
        for (const MapArray& a : maps->arrays) bytes += a.data.size() * sizeof(float);
        bytesPerTexel = double(bytes) / double(surface->heightfield().sampleCount());
        input.maps = &*maps;
    }
    GlInput(GlInput&&) = delete;  // input.maps points into this object
};

// The command that reproduces this run, for the report's first line.
std::string commandLine(const BenchOptions& o) {
    std::string s = "relief bench --preset " + o.preset;
    for (const auto& [flag, value] : {std::pair{"-t", o.techniques}, {"--heightfields", o.maps}, {"--elevations", o.elevations},
                                      {"--caps", o.caps}, {"--backend", o.backends}, {"--size", o.size}})
        if (!value.empty()) s += fmt::format(" {} {}", flag, value);
    if (o.repeats) s += fmt::format(" --repeats {}", o.repeats);
    if (o.threads) s += fmt::format(" --threads {}", o.threads);
    return s;
}

class Bench {
public:
    Bench(const BenchOptions& o, BenchConfig config) : m_o(o), m_config(std::move(config)) {}

    void run() {
        namespace fs = std::filesystem;
        std::error_code ec;
        fs::create_directories(fs::path(m_o.outDir) / "images", ec);
        if (ec) throw CommandFailed{makeError(ErrorKind::Io, "{}: cannot create folder: {}", m_o.outDir, ec.message())};
        Progress progress("bench", int64_t(m_config.maps.size() * m_config.elevations.size()));
        for (const std::string& source : m_config.maps) {
            SurfaceOptions so;
            so.source = source.rfind("gen:", 0) == 0 || fs::path(source).is_absolute()
                            ? source : resolveDataPath(source);
            so.depthRatio = m_config.depthRatio;
            auto hf = orFail(loadHeightfield(so));
            auto surface = orFail(makeSurface(so, hf));
            runMap(mapLabel(source), surface, progress);
        }
        writeResults();
    }

private:
    static std::string mapLabel(const std::string& source) {
        return source.rfind("gen:", 0) == 0 ? source.substr(4) : std::filesystem::path(source).stem().string();
    }
    static std::string resolveDataPath(const std::string& relative) {
        for (const std::string& base : {std::string("."), std::string(RELIEF_SOURCE_DIR)})
            if (std::filesystem::exists(base + "/" + relative)) return base + "/" + relative;
        return relative;
    }

    void runMap(const std::string& label, std::shared_ptr<const Surface> surface, Progress& progress) {
        std::map<std::pair<std::string, int>, BuiltTracer> built;
        std::map<std::pair<std::string, int>, GlInput> glInputs;
        auto exact = buildTracer(*findTechnique("exact"), surface, 0);
        std::unique_ptr<EmbreeScene> embree;
        double embreeBuild = 0;
        if (m_config.embree && surface->edge() == EdgeMode::Clamp) {
            const auto start = std::chrono::steady_clock::now();
            embree = orFail(EmbreeScene::create(*surface));
            embreeBuild = secondsSince(start);
        }
        for (float elevation : m_config.elevations) {
            OrbitView view{elevation, m_config.azimuth, m_config.distance, 45.0f};
            const Camera camera(view, *surface, m_config.size.x, m_config.size.y);
            const Image<Hit> reference = tracePrimary(camera, *exact.tracer);
            if (embree) runEmbree(label, elevation, camera, *embree, embreeBuild, reference);
            for (const std::string& name : m_config.techniques) {
                const TechniqueInfo& info = *findTechnique(name);
                const std::vector<int> caps = hasCap(info) && !m_config.caps.empty() ? m_config.caps : std::vector<int>{0};
                for (int cap : caps) {
                    if (wants("cpu")) {
                        auto key = std::make_pair(name, cap);
                        if (!built.count(key)) built[key] = buildTracer(info, surface, cap);
                        const bool images = !m_o.noImages && cap == caps.back();
                        runTechnique(info, label, elevation, cap, *surface, camera, built[key], reference, images);
                    }
                    if (wants("gl") && !info.glsl.empty()) {
                        auto key = std::make_pair(name, cap);
                        if (!glInputs.count(key))
                            glInputs.emplace(std::piecewise_construct, std::forward_as_tuple(key),
                                             std::forward_as_tuple(info, surface, cap));
                        runGl(info, label, elevation, cap, glInputs.at(key), camera, reference);
                    }
                }
            }
            if (wants("gl")) runMesh(label, elevation, *surface, camera);
            progress.advance();
        }
    }

    void runTechnique(const TechniqueInfo& info, const std::string& map, float elevation, int cap,
                      const Surface& surface, const Camera& camera, const BuiltTracer& built,
                      const Image<Hit>& reference, bool images) {
        Row row = newRow(std::string(info.name), std::string(toString(info.contract)), map, "cpu", elevation, cap);
        Image<Hit> hits;
        const double seconds = bestOf(m_config.repeats, [&] { hits = tracePrimary(camera, *built.tracer); });
        row.stats = compareHits(hits, reference);
        row.mraysPerSecond = double(hits.pixels.size()) / seconds / 1e6;
        row.msPerFrame = 1000.0 * seconds;
        row.buildSeconds = built.buildSeconds;
        row.bytesPerTexel = built.bytesPerTexel;
        if (images) {
            row.images = fmt::format("images/{}_{}_e{:.1f}", slug(map), slug(row.technique), elevation);
            const std::string base = m_o.outDir + "/" + row.images;
            Shading shading;
            orFail(writePng(base + ".png", render(surface, camera, *built.tracer, shading).color));
            orFail(writePng(base + "-steps.png", stepsHeatmap(hits, row.stats, row.technique)));
            orFail(writePng(base + "-error.png", errorHeatmap(hits, reference, row.stats, row.technique)));
        }
        m_rows.push_back(std::move(row));
    }

    bool wants(const std::string& backend) const {
        return std::find(m_config.backends.begin(), m_config.backends.end(), backend) != m_config.backends.end();
    }

    // GPU rows: rays made on the GPU from the camera, ms per frame with glFinish (DESIGN §8);
    // accuracy from one frame read back and compared with CPU exact on the same rays.
    void runGl(const TechniqueInfo& info, const std::string& map, float elevation, int cap,
               const GlInput& gl, const Camera& camera, const Image<Hit>& reference) {
        const TechniqueInput& input = gl.input;
        const gl::CameraUniforms uniforms = gl::cameraUniforms(camera);
        const GlFrameTiming timing = orFail(timeGlFrame(info, input, uniforms, {m_config.glFrames, 2}));
        Image<Hit> hits(camera.width(), camera.height());
        hits.pixels = orFail(traceGlCamera(info, input, uniforms));
        Row row = newRow(std::string(info.name), std::string(toString(info.contract)), map, "gl", elevation, cap);
        row.stats = compareHits(hits, reference);
        row.msPerFrame = timing.msPerFrame;
        row.mraysPerSecond = double(hits.pixels.size()) / (timing.msPerFrame * 1e-3) / 1e6;
        row.buildSeconds = gl.buildSeconds;
        row.bytesPerTexel = gl.bytesPerTexel;
        m_glDevice = timing.device;
        m_rows.push_back(std::move(row));
    }

    void runMesh(const std::string& map, float elevation, const Surface& surface, const Camera& camera) {
        const GlFrameTiming timing = orFail(timeRasterizedMesh(surface, gl::cameraUniforms(camera), {m_config.glFrames, 2}));
        Row row = newRow("mesh", "peer", map, "gl", elevation, 0);
        row.msPerFrame = timing.msPerFrame;
        row.mraysPerSecond = double(camera.width()) * camera.height() / (timing.msPerFrame * 1e-3) / 1e6;
        m_rows.push_back(std::move(row));
    }

    void runEmbree(const std::string& map, float elevation, const Camera& camera,
                   const EmbreeScene& scene, double buildSeconds, const Image<Hit>& reference) {
        const std::vector<Ray> rays = primaryRays(camera);
        const std::vector<size_t> order = packetOrder(camera.width(), camera.height());
        std::vector<Ray> packed(rays.size());
        for (size_t k = 0; k < order.size(); ++k) packed[k] = rays[order[k]];
        for (int packet : {1, 16}) {
            std::vector<Hit> hits(rays.size());
            const std::vector<Ray>& input = packet == 1 ? rays : packed;
            const double seconds = bestOf(m_config.repeats, [&] {
                parallelRanges(int64_t(input.size() / 256), 1, [&](int64_t begin, int64_t end) {
                    const size_t first = size_t(begin) * 256, count = size_t(end - begin) * 256;
                    auto in = std::span(input).subspan(first, count);
                    auto out = std::span(hits).subspan(first, count);
                    packet == 1 ? scene.intersect1(in, out) : scene.intersect16(in, out);
                });
            });
            Image<Hit> image(camera.width(), camera.height());
            for (size_t k = 0; k < hits.size(); ++k) image.pixels[packet == 1 ? k : order[k]] = hits[k];
            Row row = newRow(packet == 1 ? "embree-1" : "embree-16", "peer", map, "cpu", elevation, 0);
            row.stats = compareHits(image, reference);
            row.mraysPerSecond = double(hits.size()) / seconds / 1e6;
            row.msPerFrame = 1000.0 * seconds;
            row.buildSeconds = buildSeconds;
            m_rows.push_back(std::move(row));
        }
    }

    // Pixel indices in 4×4 packets inside 16×16 tiles (the image size is a multiple of 16).
    static std::vector<size_t> packetOrder(int w, int h) {
        std::vector<size_t> order;
        for (int ty = 0; ty < h; ty += 16)
            for (int tx = 0; tx < w; tx += 16)
                for (int py = ty; py < ty + 16; py += 4)
                    for (int px = tx; px < tx + 16; px += 4)
                        for (int y = py; y < py + 4; ++y)
                            for (int x = px; x < px + 4; ++x) order.push_back(size_t(y) * size_t(w) + size_t(x));
        return order;
    }

    nlohmann::json rowJson(const Row& r) const {
        nlohmann::json j = {{"technique", r.technique}, {"contract", r.contract}, {"map", r.map},
                            {"backend", r.backend}, {"elevation", r.elevation}, {"cap", r.cap},
                            {"error_mean", r.stats.error.mean}, {"error_p95", r.stats.error.p95},
                            {"error_max", r.stats.error.max}, {"wrong_rate", r.stats.wrongRate()},
                            {"steps_mean", r.stats.steps.mean}, {"steps_max", r.stats.steps.max},
                            {"fetches_mean", r.stats.fetches.mean}, {"fetches_max", r.stats.fetches.max},
                            {"bytes_per_texel", r.bytesPerTexel}, {"images", r.images}};
        if (!m_o.deterministic) {
            j["mrays_per_s"] = r.mraysPerSecond;
            j["ms_per_frame"] = r.msPerFrame;
            j["build_seconds"] = r.buildSeconds;
        }
        return j;
    }

    void writeResults() const {
        nlohmann::json rows = nlohmann::json::array();
        for (const Row& r : m_rows) rows.push_back(rowJson(r));
        const nlohmann::json meta = {{"preset", m_o.preset}, {"threads", ThreadLimit::current()},
                                     {"image_size", fmt::format("{}x{}", m_config.size.x, m_config.size.y)},
                                     {"machine", machineName()},
                                     {"gl_device", m_glDevice},
                                     {"date", m_o.deterministic ? std::string("-") : today()}};
        writeFile("results.json", nlohmann::json{{"meta", meta}, {"rows", rows}}.dump(2) + "\n");
        std::string csv;
        const std::vector<std::string> columns = {"technique", "contract", "map", "backend", "elevation", "cap",
            "error_mean", "error_p95", "error_max", "wrong_rate", "steps_mean", "steps_max", "fetches_mean",
            "fetches_max", "mrays_per_s", "ms_per_frame", "build_seconds", "bytes_per_texel"};
        for (size_t c = 0; c < columns.size(); ++c) csv += (c ? "," : "") + columns[c];
        csv += "\n";
        for (const nlohmann::json& row : rows) {
            for (size_t c = 0; c < columns.size(); ++c) {
                const auto it = row.find(columns[c]);
                csv += c ? "," : "";
                if (it == row.end()) continue;
                csv += it->is_string() ? it->get<std::string>() : it->dump();
            }
            csv += "\n";
        }
        writeFile("results.csv", csv);
        writePlots();
        const BenchMeta report = reportMeta(meta);
        writeFile("index.html", benchHtml(m_rows, m_config, report));
        writeFile("report.md", benchMarkdown(m_rows, m_config, report, ""));
        if (!m_o.markdownPath.empty()) writeMarkdownCopy(report);
        if (!m_glDevice.empty()) std::cout << "GL: " << m_glDevice << "\n";
        std::cout << fmt::format("\nwrote {0}/index.html, {0}/report.md, results.csv, results.json\n", m_o.outDir);
    }

    void writePlots() const {
        std::map<std::string, PlotSeries> errorVsCap, stepsVsElevation;
        std::map<std::pair<std::string, double>, std::pair<double, int>> errorSum, stepsSum;
        for (const Row& r : m_rows) {
            if (r.cap > 0) {
                auto& acc = errorSum[{r.technique, r.cap}];
                acc.first += r.stats.error.mean;
                acc.second++;
            }
            if (r.cap == 0 || r.cap == m_config.caps.back()) {
                auto& acc = stepsSum[{r.technique, r.elevation}];
                acc.first += r.stats.steps.mean;
                acc.second++;
            }
        }
        for (const auto& [key, acc] : errorSum) {
            PlotSeries& s = errorVsCap[key.first];
            s.label = key.first;
            s.x.push_back(key.second);
            s.y.push_back(acc.first / acc.second);
        }
        for (const auto& [key, acc] : stepsSum) {
            PlotSeries& s = stepsVsElevation[key.first];
            s.label = key.first;
            s.x.push_back(key.second);
            s.y.push_back(acc.first / acc.second);
        }
        auto values = [](const std::map<std::string, PlotSeries>& m) {
            std::vector<PlotSeries> v;
            for (const auto& [k, s] : m) v.push_back(s);
            return v;
        };
        writeFile("error_vs_cap.svg", svgLinePlot({"mean |t - t_exact| vs iteration cap (all maps and views)",
                                                   "iteration cap", "mean |error| (texels)", true, true}, values(errorVsCap)));
        writeFile("steps_vs_elevation.svg", svgLinePlot({"mean steps per pixel vs camera elevation",
                                                         "elevation (degrees)", "mean steps", false, true}, values(stepsVsElevation)));
    }

    BenchMeta reportMeta(const nlohmann::json& meta) const {
        return BenchMeta{m_o.preset, meta["machine"], meta["image_size"], meta["date"], m_glDevice,
                         commandLine(m_o), ThreadLimit::current(), !m_o.deterministic};
    }

    // The same report elsewhere (e.g. docs/benchmarks.md), its plot links rewritten to point
    // into the output folder.
    void writeMarkdownCopy(const BenchMeta& report) const {
        namespace fs = std::filesystem;
        const fs::path target = fs::absolute(m_o.markdownPath);
        std::string prefix = fs::relative(fs::absolute(m_o.outDir), target.parent_path()).generic_string();
        prefix = prefix.empty() || prefix == "." ? "" : prefix + "/";
        orFail(writeTextFile(m_o.markdownPath, benchMarkdown(m_rows, m_config, report, prefix)));
        std::cout << "wrote " << m_o.markdownPath << "\n";
    }

    void writeFile(const std::string& name, const std::string& text) const {
        orFail(writeTextFile(m_o.outDir + "/" + name, text));
    }

    static std::string machineName() {
        std::ifstream in("/proc/cpuinfo");
        for (std::string line; std::getline(in, line);)
            if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
        return "unknown CPU";
    }
    static std::string today() {
        const std::time_t now = std::time(nullptr);
        char buffer[32];
        std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
        return buffer;
    }

    const BenchOptions& m_o;
    BenchConfig m_config;
    std::vector<Row> m_rows;
    std::string m_glDevice;
};

void runBench(const BenchOptions& o) {
    // Checked before the run, not after an hour of it.
    if (!o.markdownPath.empty()) {
        const std::filesystem::path folder = std::filesystem::absolute(o.markdownPath).parent_path();
        if (!std::filesystem::is_directory(folder))
            throw CommandFailed{makeError(ErrorKind::BadArgument, "--markdown {}: folder '{}' does not exist",
                                          o.markdownPath, folder.string())};
    }
    ThreadLimit limit(o.threads);
    BenchConfig config = orFail(presetConfig(o.preset));
    orFail(applyOverrides(config, o.techniques, o.maps, o.elevations, o.caps, o.backends, o.size, o.repeats));
    Bench(o, std::move(config)).run();
}

}  // namespace

void addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<BenchOptions>();
    CLI::App* cmd = app.add_subcommand("bench", "compare techniques on heightfields × views × caps, "
                                                "with Embree in the same run; writes an HTML report");
    cmd->add_option("--preset", o->preset, "preset: " + presetNames())->capture_default_str();
    cmd->add_option("-t,--technique", o->techniques, "techniques, comma-separated (default: the preset's)");
    cmd->add_option("--heightfields", o->maps, "heightfields, comma-separated (files or gen:NAME:WxH)");
    cmd->add_option("--elevations", o->elevations, "camera elevations in degrees, comma-separated");
    cmd->add_option("--caps", o->caps, "iteration caps for techniques that have one, comma-separated");
    cmd->add_option("--backend", o->backends, "backends, comma-separated: cpu, gl");
    cmd->add_option("--size", o->size, "image size WxH (multiples of 16)");
    cmd->add_option("--repeats", o->repeats, "timed runs per row (the best counts)");
    cmd->add_option("--out-dir", o->outDir, "output folder")->capture_default_str();
    cmd->add_option("--markdown", o->markdownPath, "also write the Markdown report to this file");
    cmd->add_flag("--no-images", o->noImages, "skip the per-run images");
    cmd->add_flag("--deterministic", o->deterministic, "leave timings out of the outputs");
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o] { runBench(*o); });
}

}  // namespace relief::cli
