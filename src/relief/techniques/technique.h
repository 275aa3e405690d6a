#pragma once
// What every technique provides to the registry: a contract, parameters, and a tracer that the
// renderer, CLI, bench and tests call one batch at a time (one virtual call per batch; the loop
// over rays inside is a template instantiation of the technique's inline `trace`).
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/io/map_file.h>
#include <relief/surface/surface.h>

#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace relief {

// DESIGN §3.
enum class Contract { Exact, Conservative, Approximate };
std::string_view toString(Contract contract);

struct ParamSpec {
    std::string_view name;  // kebab-case; "max-steps" is the iteration cap (DESIGN §3)
    double defaultValue;
    double minValue;
    double maxValue;
    bool integer;
    std::string_view help;
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

// Adapts a technique's concrete tracer (anything with `Hit trace(const Ray&) const`).
template <class Impl>
class BatchTracer final : public Tracer {
public:
    explicit BatchTracer(Impl impl) : m_impl(std::move(impl)) {}
    void traceBatch(std::span<const Ray> rays, std::span<Hit> hits) const override {
        for (size_t k = 0; k < rays.size(); ++k) hits[k] = m_impl.trace(rays[k]);
    }
    const Impl& impl() const { return m_impl; }

private:
    Impl m_impl;
};

template <class Impl>
std::unique_ptr<Tracer> makeBatchTracer(Impl impl) {
    return std::make_unique<BatchTracer<Impl>>(std::move(impl));
}

// Everything a technique needs to build its maps and its tracer. The surface outlives the tracer.
struct TechniqueInput {
    std::shared_ptr<const Surface> surface;
    ParamValues params;
    // Baked maps for this technique (`--maps FILE`), already checked against the surface's
    // heightfield; null means "build them now".
    const TechniqueMaps* maps = nullptr;
};

struct TechniqueInfo {
    std::string_view name;
    std::string_view paper;    // citation of the method
    std::string_view summary;  // one line for --help and the report
    Contract contract;
    std::span<const ParamSpec> params;
    // Builds whatever maps the technique needs (unless input.maps has them) and its tracer.
    Result<std::unique_ptr<Tracer>> (*create)(const TechniqueInput& input);
    // For `relief bake`: the technique's maps as named arrays; null when it has none.
    Result<TechniqueMaps> (*buildMaps)(const TechniqueInput& input) = nullptr;
    // Optional view check for the renderer: a warning when these primary rays fall outside what
    // the technique's maps were built for (e.g. a viewing-angle restriction), else empty.
    std::string (*viewWarning)(const ParamValues& params, std::span<const Ray> rays) = nullptr;
    // Path of its GLSL tracer relative to src/relief/techniques (e.g. "exact/exact.glsl"); empty
    // when it has none.
    std::string_view glsl = {};
};

}  // namespace relief
