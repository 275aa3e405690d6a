// relief rays HEIGHTFIELD [view options] --size WxH -o rays.npy|rays.csv|-
// The primary rays `render` traces on the plane for that view (render/camera.h primaryRays), so
// that another method can be traced on exactly the same rays (relief trace --rays).
#include <relief/cli/common.h>
#include <relief/core/memory_budget.h>
#include <relief/io/ray_io.h>
#include <relief/render/camera.h>

namespace relief::cli {

namespace {

struct RaysOptions {
    SurfaceOptions surface;
    OrbitView view;
    std::string size = "800x600";
    std::string output = "-";
};

void runRays(const RaysOptions& o) {
    const ivec2 size = orFail(parseImageSize(o.size));
    // The rays, and their file text at up to ~100 bytes a ray.
    const int64_t pixels = int64_t(size.x) * size.y;
    orFail(reserveMemory(pixels * (int64_t(sizeof(Ray)) + 100),
                         fmt::format("rays --size {}x{}", size.x, size.y)));
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    orFail(writeRays(o.output, primaryRays(Camera(o.view, *surface, size.x, size.y))));
}

}  // namespace

void addRaysCommand(CLI::App& app) {
    auto o = std::make_shared<RaysOptions>();
    CLI::App* cmd = app.add_subcommand(
        "rays", "write the primary rays of a view, the ones `render` traces, for `relief trace`");
    cmd->footer(
        "The rays are exactly those `render` traces on the plane for the same view options: one "
        "per pixel through its centre, row-major from the top-left pixel, in texel space. Output: "
        ".npy float32 of shape (W*H, 6) [ox,oy,oz,dx,dy,dz], or CSV lines with a header (nine "
        "significant digits: the floats exactly); the format comes from the extension ('-' = CSV "
        "on stdout).");
    addSurfaceOptions(*cmd, o->surface);
    addViewOptions(*cmd, o->view);
    cmd->add_option("--size", o->size, "image size WxH")->capture_default_str();
    cmd->add_option("-o,--output", o->output, "ray file: .npy or .csv ('-' = CSV on stdout)")
        ->capture_default_str();
    cmd->callback([o] { runRays(*o); });
}

}  // namespace relief::cli
