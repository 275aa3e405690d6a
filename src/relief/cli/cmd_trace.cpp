// relief trace HEIGHTFIELD -t TECH --rays rays.csv -o hits.csv
#include <relief/cli/common.h>
#include <relief/core/parallel.h>
#include <relief/io/ray_io.h>

namespace relief::cli {

namespace {

struct TraceOptions {
    SurfaceOptions surface;
    TechniqueOptions technique;
    std::string rays;
    size_t maxRays = kDefaultMaxRays;
    std::string output = "-";
    int threads = 0;
};

void runTrace(const TraceOptions& o) {
    ThreadLimit limit(o.threads);
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    auto tracer = orFail(makeTracer(o.technique, surface));
    std::vector<Ray> rays = orFail(readRays(o.rays, o.maxRays));
    std::vector<Hit> hits(rays.size());
    traceFromAnywhere(*tracer, *surface, rays, hits);
    orFail(writeHits(o.output, hits));
}

}  // namespace

void addTraceCommand(CLI::App& app) {
    auto o = std::make_shared<TraceOptions>();
    CLI::App* cmd = app.add_subcommand(
        "trace",
        "trace rays from a CSV file (ox,oy,oz,dx,dy,dz per line, texel space) and write "
        "hit,t,x,y,z,steps per ray");
    addSurfaceOptions(*cmd, o->surface);
    addTechniqueOptions(*cmd, o->technique);
    cmd->add_option("--rays", o->rays, "ray file ('-' = stdin)")->required();
    cmd->add_option("--max-rays", o->maxRays, "refuse ray files with more rays (checked while reading)")
        ->check(CLI::Range(size_t(1), kMaxRaysPerFile))->capture_default_str();
    cmd->add_option("-o,--output", o->output, "hit file ('-' = stdout)")->capture_default_str();
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o] { runTrace(*o); });
}

}  // namespace relief::cli
