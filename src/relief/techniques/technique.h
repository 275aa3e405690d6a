#pragma once
// What every technique provides to the registry: a contract, parameters, and a tracer that the
// renderer, CLI, bench and tests call one batch at a time (one virtual call per batch; the loop
// over rays inside is a template instantiation of the technique's inline `trace`).
#include <relief/core/error.h>
#include <relief/core/isa.h>
#include <relief/core/math.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>
#include <relief/techniques/build_share.h>

#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace relief {

// DESIGN §3.
enum class Contract { Exact, Conservative, Approximate };
std::string_view toString(Contract contract);

// What a parameter does, so that consumers (CLI options, bench, GL, exports) act on roles and
// never on parameter names.
enum class ParamRole : uint8_t {
    Tuning,        // changes the tracer's work only (e.g. binary refinement steps)
    IterationCap,  // the iteration cap of DESIGN §3 (`--max-steps`); never changes the maps
    Variant,       // picks a form of the method; TechniqueInfo::variants gives its contract
    Encoding,      // how the maps are stored (bits per value, sqrt coding)
    MapShape,      // a builder option: changes what the maps hold
    PhiMax,        // viewing-angle restriction in degrees (`--phi-max`)
    Visibility,    // 0 = maps for all rays, 1 = exterior rays only (`--visibility`)
    ImageSampling, // samples per pixel of the row's whole-image method (`image`); tracers ignore it
    RayWalk,       // read by the per-ray tracer only, not by the row's whole-image method
};
std::string_view toString(ParamRole role);

struct ParamSpec {
    std::string_view name;  // kebab-case
    double defaultValue;
    double minValue;
    double maxValue;
    bool integer;
    std::string_view help;
    ParamRole role = ParamRole::Tuning;
};

// A named form of a technique: the parameter values that select it ("variant=1", several
// comma-separated) and the contract that form keeps. Parameters not named keep any value.
struct VariantSpec {
    std::string_view label;   // e.g. "faithful"
    std::string_view params;  // NAME=VALUE[,NAME=VALUE...]
    Contract contract;
    std::string_view summary;
    bool clampOnly = false;  // exists in clamp mode only (e.g. exterior rays: a finite box)
    bool cpuOnly = false;    // the row's GLSL lacks this form: the GL backend refuses it
    // The surface it is exact on when that is not S (`contract` is its contract against S).
    std::string_view exactOn = {};
};

// A parameter set that takes the tracer down another path (an encoding, a policy, a variant):
// the GL differential test and the contract harness run each one.
struct PathCase {
    std::string_view params;  // NAME=VALUE[,NAME=VALUE...]; empty = the defaults
    bool clampOnly = false;   // only meaningful in clamp mode (e.g. exterior rays)
};

// A constant the technique's GLSL reads, defined once in C++ (emitted as `const int/float`).
struct GlslConstant {
    std::string_view name;
    double value;
    bool integer;
};

// A bench study a row contributes (a paper's experiment): `relief bench --preset NAME`.
enum class StudyKind : uint8_t {
    Views,   // techniques × heightfields × views × caps, against the reference and the peers
    Builds,  // map build time (wall and process CPU) and size per technique and map size
    Scaling, // steps per ray (mean, p99) against map size, every hit checked by the reference
    Paper,   // a paper's page: runs its parts (other studies) and judges its claims (docs/papers/)
};
// What a paper claim is measured with, per view of a part's rows (bench/runner.h BenchRow).
enum class ClaimMetric : uint8_t {
    Speed,          // rays per second (fps on GL): as a ratio, > 1 means the numerator is faster
    Steps,          // mean steps per pixel
    MeanError,      // mean |t - t_ref| in texels over the pixels both hit
    WrongPercent,   // % of the pixels with a wrong hit (hit/miss difference or |dt| over the tolerance)
    PastFirstHitPercent,  // % of the pixels whose hit lies past the reference's first hit, or that miss it
    BuildSeconds,   // map build, wall seconds
    // % of the pixels whose shadow (lit or not, toward StudySpec::shadowElevation's light, from the
    // reference's primary hit, traced from the light toward the point) differs from the reference's
    ShadowWrongPercent,
    // The visibility-curve renderer's Table 1 counters (rows drawn with ImageMethod::VisibilityCurves):
    ExtraSamplesPercent,   // extra samples (outside the mapped region) as % of the inside samples
    AdvancePerSample,      // advance steps per sample
    ReversePerSample,      // reverse steps per sample
    BinaryCutsPerReverse,  // binary cuts per reverse step
    EvaluationsPerSample,  // advance + reverse + binary per sample
};
// One side of a claim: row `numerator` (a row label of the part) over row `denominator` on the
// same views (geometric mean of the per-view ratios); an empty denominator: the numerator's
// value itself (arithmetic mean over the views). Map labels as the bench names them ("fbm:512x512");
// empty: every map, the same one on both sides.
struct ClaimMeasure {
    std::string_view numerator = {}, denominator = {};
    std::string_view numeratorMap = {}, denominatorMap = {};
};
// A paper's headline claim, judged from a run: its value with the paper's own variant (the
// verdict) and, beside it, with our safe variant.
struct ClaimSpec {
    std::string_view source = {};  // where the paper says it: "Fig. 9", "Table 1", "§8"
    std::string_view claim = {};   // its wording, short
    std::string_view paper = {};   // the paper's number
    std::string_view part = {};    // the study (preset name) of the page that measures it
    ClaimMetric metric = ClaimMetric::Speed;
    ClaimMeasure paperVariant = {};
    ClaimMeasure safeVariant = {};  // empty numerator: no safe variant to show
    float minElevation = -90.0f, maxElevation = 90.0f;  // the views it is judged on
    int cap = -1;  // the rows' iteration cap: -1 the largest the part runs, 0 the row's default
    double low = -1e300, high = 1e300;  // agrees when the paper variant's value lies in [low, high]
    std::string_view whyAgrees = {}, whyDisagrees = {};  // the reason the page shows with the verdict
};
struct PaperRatioSpec {
    std::string_view what = {}, paper = {};
    std::string_view numeratorTechnique = {}, numeratorMap = {}, denominatorTechnique = {},
                     denominatorMap = {};
    std::string_view backend = "cpu";
};
inline constexpr float kShadowLightAzimuth = 135.0f;  // degrees: StudySpec::shadowElevation's light
struct StudySpec {
    std::string_view name = {}, description = {};
    StudyKind kind = StudyKind::Views;
    std::span<const std::string_view> maps = {};        // gen:NAME:WxH or repository paths ({N}: each size)
    std::span<const std::string_view> techniques = {};  // NAME or NAME:PARAM=V[:PARAM=V]
    std::span<const float> elevations = {};             // empty = the standard elevations
    std::span<const int> caps = {};                     // iteration caps, for rows that have one
    std::span<const int> sizes = {};                    // map sizes N (N×N) for Builds and Scaling
    int width = 640, height = 512;                      // primary rays per view
    float depthRatio = 0.1f;
    float distance = 1.0f;   // camera distance in box diagonals
    bool peerTable = false;  // the report adds the reference-vs-peers table per view
    std::string_view compare = {};  // "A/B" (row labels): the report adds A-vs-B tables by view and cap
    std::string_view paperNotes = {};
    std::span<const PaperRatioSpec> paperRatios = {};
    bool imageMethod = false;  // rows draw with their own TechniqueInfo::image, not one ray per pixel
    // > 0: every row also traces shadow rays toward a light at this elevation (degrees; azimuth
    // kShadowLightAzimuth) from the reference's primary hits, from the light toward the point as
    // a relaxed-cone tracer must (it forbids upward rays), and counts where it differs (bench).
    float shadowElevation = 0.0f;
    // StudyKind::Paper: the studies it runs (preset names, any row's), the claims it judges, and
    // the paper (a file name in ../shared/papers).
    std::span<const std::string_view> parts = {};
    std::span<const ClaimSpec> claims = {};
    std::string_view paperFile = {};
};

// How the renderer draws a row's image.
enum class ImageMethod : uint8_t {
    PerPixel,          // one primary ray per pixel through the row's tracer (render/renderer.h)
    VisibilityCurves,  // the paper's own whole-image method (render/curves/curves_renderer.h)
};

// One channel of a baked map array, as exports and docs/maps.md (`relief help maps`) describe it.
enum class MapRounding : uint8_t {
    Exact,  // stored as built (floats, integers, maxima of exact values)
    Up,     // quantized upwards: a higher apex / maximum only shrinks what the map promises free
    Down,   // quantized downwards: a narrower cone / shorter distance, likewise
};
std::string_view toString(MapRounding rounding);
enum class MapFilter : uint8_t { Nearest, Bilinear };
std::string_view toString(MapFilter filter);
struct MapChannelSpec {
    std::string_view array;  // array name; a trailing '*' names a family ("level*": level0, ...)
    std::string_view name;   // the channel, e.g. "apex"
    std::string_view meaning;
    std::string_view range;  // value range and scale as stored
    MapValueKind kind;       // what 8/16-bit storage can hold it (io/map_file.h)
    MapRounding rounding;    // how the bake rounds it when it quantizes
    MapFilter filter;        // what a shader must sample it with
    std::string_view depth;  // how the depth D is baked in
    std::string_view quantize = {};  // how to bake it as 8/16-bit codes ("--param bits=16"), if any
};

class SphereSurface;  // sphere/sphere_surface.h

// A sampler of a row's engine shader-library function (shaders/relief/, docs/engine.md), in
// parameter order: its name there and the map array it holds, one texture per array with the
// array's floats ("" = the heightfield itself, h in [0, 1]). mipChain: `array` is "<stem><k>"
// and "<stem><k>", "<stem><k+1>", ... are its mip levels 0, 1, ... (a pyramid). fallback: the array
// it holds when the bake has no `array` (safety-cc's isotropic "cc" for each ray class).
struct ShaderSampler {
    std::string_view name;
    std::string_view array;
    bool mipChain = false;
    std::string_view fallback = {};
};

// Parameter values by name, complete (defaults filled in) once validated by the registry.
class ParamValues {
public:
    void set(std::string name, double value) { m_values[std::move(name)] = value; }
    bool has(std::string_view name) const { return m_values.count(std::string(name)) != 0; }
    double get(std::string_view name) const;
    int getInt(std::string_view name) const { return int(get(name)); }
    const std::map<std::string, double, std::less<>>& all() const { return m_values; }

private:
    std::map<std::string, double, std::less<>> m_values;
};

class Tracer {
public:
    virtual ~Tracer() = default;
    virtual void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const = 0;
    // True when one large batch beats many small parallel ones (a GPU behind one context).
    virtual bool prefersOneBatch() const { return false; }
};

// Traces all rays: one batch if the tracer prefers it, else 256-ray batches in parallel.
void traceAll(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits);
// traceAll for rays from anywhere (`relief trace`, the Python module): far origins are brought to
// the box first, in place (Surface::nearBox, in double), and their hits get the distance back; a
// hit beyond its ray's tMax (a tracer that overshoots it) is reported as a miss.
void traceFromAnywhere(const Tracer& tracer, const Surface& surface, std::span<Ray> rays,
                       std::span<Hit> hits);

// The per-ray loop of a batch, compiled once per ISA (core/isa.h): the SSE4 and AVX2 copies
// inline the whole walk (flatten) and compile it for their target; the baseline one is today's.
template <class Impl>
void traceRays(const Impl& impl, std::span<const Ray> rays, std::span<Hit> hits) {
    for (size_t k = 0; k < rays.size(); ++k) hits[k] = impl.trace(rays[k]);
}
#if RELIEF_ISA_DISPATCH
template <class Impl>
RELIEF_TARGET_SSE4 void traceRaysSse4(const Impl& impl, std::span<const Ray> rays,
                                      std::span<Hit> hits) {
    traceRays(impl, rays, hits);
}
template <class Impl>
RELIEF_TARGET_AVX2 void traceRaysAvx2(const Impl& impl, std::span<const Ray> rays,
                                      std::span<Hit> hits) {
    traceRays(impl, rays, hits);
}
#endif

// Adapts a technique's concrete tracer (anything with `Hit trace(const Ray&) const`).
template <class Impl>
class BatchTracer final : public Tracer {
public:
    explicit BatchTracer(Impl impl) : m_impl(std::move(impl)) {}
    void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const override {
#if RELIEF_ISA_DISPATCH
        switch (activeIsa()) {
            case Isa::Avx2: return traceRaysAvx2(m_impl, rays, hits);
            case Isa::Sse4: return traceRaysSse4(m_impl, rays, hits);
            case Isa::Baseline: break;
        }
#endif
        traceRays(m_impl, rays, hits);
    }
    const Impl& impl() const { return m_impl; }

private:
    Impl m_impl;
};

template <class Impl>
std::unique_ptr<Tracer> makeBatchTracer(Impl impl) {
    return std::make_unique<BatchTracer<Impl>>(std::move(impl));
}

// A row whose default traces each batch in SIMD packets (Highway; quadtree, maxmip, exact): the
// packet path, and its scalar BatchTracer, which gives the same hits bit for bit. Baseline ISA
// (--isa / RELIEF_ISA=baseline: the portable code as a whole) takes the scalar path; so does
// RELIEF_PACKETS=0, when the row is created (packetsEnabled, core/isa.h).
class PacketTracer : public Tracer {
public:
    // The same row, ray by ray (BatchTracer): the A/B peer of the packet path.
    virtual const Tracer& scalarPath() const = 0;
};

template <class Impl, void (*kTracePackets)(const Impl&, std::span<const Ray>, std::span<Hit>)>
class PacketBatchTracer final : public PacketTracer {
public:
    explicit PacketBatchTracer(Impl impl) : m_scalar(std::move(impl)) {}
    void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const override {
        if (activeIsa() == Isa::Baseline) return m_scalar.traceBatch(rays, hits);
        kTracePackets(m_scalar.impl(), rays, hits);
    }
    const Tracer& scalarPath() const override { return m_scalar; }

private:
    BatchTracer<Impl> m_scalar;
};

// What maps baked for this surface record, and must match when they are used.
MapSource mapSourceOf(const Surface& surface);

// Everything a technique needs to build its maps and its tracer. The surface outlives the tracer.
struct TechniqueInput {
    std::shared_ptr<const Surface> surface;
    ParamValues params;
    // Baked maps for this technique (`--maps FILE`), already checked against the surface's
    // heightfield; null means "build them now".
    const TechniqueMaps* maps = nullptr;
    // Products of other rows' builds in the same bake of this surface; null: nothing shared.
    BuildShare* share = nullptr;
};

struct TechniqueInfo {
    std::string_view name;
    std::string_view paper;    // citation of the method
    std::string_view summary;  // one line for --help and the report
    Contract contract;         // of the defaults; see variants and contractOf()
    std::span<const ParamSpec> params;
    // Builds whatever maps the technique needs (unless input.maps has them) and its tracer.
    Result<std::unique_ptr<Tracer>> (*create)(const TechniqueInput& input);
    // For `relief bake`: the technique's maps as named arrays; null when it has none.
    Result<TechniqueMaps> (*buildMaps)(const TechniqueInput& input) = nullptr;
    // Peak bytes per heightfield texel of building (or baking) its maps, measured with the
    // default parameters, for the memory budget (reserveMapMemory); 0: none counted.
    double mapBytesPerTexel = 0.0;
    // What `create` refuses beyond resolveParams (parameter combinations, and input.maps when
    // given: sizes, channels, what they were baked with), without building a tracer: the GL
    // backend traces with the row's GLSL and checks through this. Null: nothing more to check.
    Status (*check)(const TechniqueInput& input) = nullptr;
    // Optional view check for the renderer: a warning when these primary rays fall outside what
    // the technique's maps were built for (e.g. a viewing-angle restriction), else empty.
    std::string (*viewWarning)(const ParamValues& params, std::span<const Ray> rays) = nullptr;
    // Path of its GLSL tracer relative to src/relief/techniques (e.g. "exact/exact.glsl"); empty
    // when it has none.
    std::string_view glsl = {};
    // Constants its GLSL reads (from the C++ headers that define them).
    std::span<const GlslConstant> glslConstants = {};
    // Named forms whose contract differs from the row's (or that a paper's claim is judged with).
    std::span<const VariantSpec> variants = {};
    // Parameter sets that take the tracer down other paths (GL differential test).
    std::span<const PathCase> pathCases = {};
    // The paper's experiments, as bench presets.
    std::span<const StudySpec> studies = {};
    // True for the reference every other row is judged against (exactly one row).
    bool reference = false;
    // What `relief render` draws its image with.
    ImageMethod image = ImageMethod::PerPixel;
    // Its tracer on the displaced sphere (DESIGN §6, `--surface sphere`); null: the plane only
    // (unless its image method draws the sphere itself).
    Result<std::unique_ptr<Tracer>> (*createSphere)(std::shared_ptr<const SphereSurface> sphere,
                                                    const ParamValues& params) = nullptr;
    // Named statistics of its built maps (snake_case name, value), extra columns of the bench's
    // map-build tables (e.g. the mean safety distance); null: none.
    std::vector<std::pair<std::string, double>> (*mapSummary)(const TechniqueMaps& maps) = nullptr;
    // The channels of its baked arrays, in array then channel order (empty when it has no maps):
    // what `relief bake --format png|ktx2` stores and docs/maps.md lists.
    std::span<const MapChannelSpec> mapChannels = {};
    // Its function in the engine shader library: the file in shaders/relief/ (after common.glsl),
    // the function (`ReliefHit F(samplers, uv, viewDirTangent, params)`; its shadow query is
    // `float FShadow(samplers, hit, lightDirTangent, params)`) and the samplers both take, in
    // order. Empty: none.
    std::string_view shaderFile = {};
    std::string_view shaderFunction = {};
    std::span<const ShaderSampler> shaderSamplers = {};
};

// The channel specs of the array `name` (matching "level*" families), in channel order.
std::vector<const MapChannelSpec*> channelsOf(const TechniqueInfo& info, std::string_view name);
// What 8/16-bit storage an array can use: Unit or Integer when all its channels are, else Float.
MapValueKind arrayKind(const TechniqueInfo& info, std::string_view name);
// The formats a bake of this row can be written as, for `relief help maps` (e.g. "exr, ktx2
// (R32_SFLOAT mip levels), png (8/16-bit with --param bits=N)"); empty without maps.
std::string exportFormats(const TechniqueInfo& info);

// The parameter of `info` with this role (the first), or null.
const ParamSpec* paramWithRole(const TechniqueInfo& info, ParamRole role);
// "NAME=VALUE[,NAME=VALUE...]" as overrides; an error names the text.
Result<std::vector<std::pair<std::string, double>>> parseParamList(std::string_view text);
// The contract these (resolved) parameters keep: the first variant whose parameters they match,
// else the row's; an exact row with its iteration cap set (where 0 means none) is approximate.
Contract contractOf(const TechniqueInfo& info, const ParamValues& params);
// The first variant whose parameters these (resolved) parameters match, or null.
const VariantSpec* variantOf(const TechniqueInfo& info, const ParamValues& params);

}  // namespace relief
