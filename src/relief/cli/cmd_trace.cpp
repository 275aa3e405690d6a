// relief trace HEIGHTFIELD -t TECH --rays rays.csv|rays.npy|- -o hits.csv|hits.npy|-
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
        "trace", "trace rays from a ray file (CSV or .npy) and write one hit per ray (CSV or .npy)");
    cmd->footer(
        "Rays, in texel space: CSV lines ox,oy,oz,dx,dy,dz[,tmax] (a header line allowed), or .npy "
        "float32/float64 of shape (N,6) or (N,7) in that order. tmax (+inf: none) is the ray's "
        "length from its origin as given: the tracers stop there, and a hit beyond it is reported "
        "as a miss.\nHits: CSV hit,t,x,y,z,steps,fetches (a miss: 0,inf,nan,nan,nan,steps,fetches), "
        "or .npy, a structured array of shape (N,) with dtype [('hit','?'), ('t','<f4'), "
        "('x','<f4'), ('y','<f4'), ('z','<f4'), ('steps','<i4'), ('fetches','<i4')] (a miss: t "
        "inf, x,y,z nan).\nThe format comes from the extension: .npy, else CSV; '-' is CSV.");
    addSurfaceOptions(*cmd, o->surface);
    addTechniqueOptions(*cmd, o->technique);
    cmd->add_option("--rays", o->rays,
                    "ray file: .csv/.txt or .npy ('-' = CSV on stdin, read as it streams in)")
        ->required();
    cmd->add_option("--max-rays", o->maxRays, "refuse ray files with more rays (checked while reading)")
        ->check(CLI::Range(size_t(1), kMaxRaysPerFile))->capture_default_str();
    cmd->add_option("-o,--output", o->output, "hit file: .csv or .npy ('-' = CSV on stdout)")
        ->capture_default_str();
    addThreadsOption(*cmd, o->threads);
    addIsaOption(*cmd);
    cmd->callback([o] { runTrace(*o); });
}

}  // namespace relief::cli
