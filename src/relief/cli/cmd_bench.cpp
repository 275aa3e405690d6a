// relief bench: the options of the one bench (src/relief/bench/) → bench::run.
#include <relief/bench/runner.h>
#include <relief/cli/common.h>

#include <iostream>

namespace relief::cli {

void addBenchCommand(CLI::App& app) {
    auto o = std::make_shared<bench::RunOptions>();
    auto list = std::make_shared<bool>(false);
    bench::BenchOverrides& v = o->overrides;
    CLI::App* cmd = app.add_subcommand("bench", "compare techniques on heightfields × views × caps, "
                                                "with Embree in the same run; writes an HTML report");
    cmd->add_option("--preset", o->preset, "preset (--list-presets): " + bench::presetNames())->capture_default_str();
    cmd->add_flag("--list-presets", *list, "list the presets (bench-wide and the rows' studies) and exit");
    cmd->add_option("-t,--technique", v.techniques,
                    "rows, comma-separated, each NAME[:PARAM=V[:PARAM=V]] (default: the preset's; all)");
    cmd->add_option("--param", o->params, "parameter NAME=V of every row that has it (repeatable)");
    cmd->add_option("--maps", o->mapsPath, "baked maps (relief bake), checked against each heightfield");
    cmd->add_option("--visibility", o->visibility, "maps for all rays or exterior rays only (rows that have it)")
        ->check(CLI::IsMember({"all", "exterior"}));
    cmd->add_option("--phi-max", o->phiMax, "viewing-angle restriction in degrees (rows that have it)");
    cmd->add_option("--heightfields", v.maps, "heightfields, comma-separated (files or gen:NAME:WxH, each may end in @crop= or @centre=X,Y,W,H)");
    cmd->add_option("--depth", v.depth, "relief depth D in texels (overrides --depth-ratio)");
    cmd->add_option("--depth-ratio", v.depthRatio, "relief depth as a fraction of max(W,H)");
    cmd->add_option("--edge", v.edge, "edge mode")->check(CLI::IsMember({"clamp", "repeat"}));
    cmd->add_option("--elevations", v.elevations, "camera elevations in degrees, comma-separated");
    cmd->add_option("--azimuth", v.azimuth, "camera azimuth (degrees)");
    cmd->add_option("--distance", v.distance, "camera distance in box diagonals");
    cmd->add_option("--caps", v.caps, "iteration caps for rows that have one, comma-separated");
    cmd->add_option("--map-sizes", v.sizes, "map sizes N of a builds or scaling study, comma-separated");
    cmd->add_option("--backend", v.backends, "backends, comma-separated: cpu, gl");
    cmd->add_option("--size", v.size, "image size WxH (multiples of 16)");
    cmd->add_option("--repeats", v.repeats, "timed runs per row (the best counts)")
        ->check(CLI::Range(1, 1000));
    cmd->add_flag("--smoke", v.smoke, "a seconds-long run of the preset: maps 64², one view, 32×32 rays, one repeat");
    cmd->add_flag("--quick", v.quick,
                  "a minutes-long run of the preset with every view: maps at most 256², map sizes at most 512, "
                  "160×128 rays, one repeat");
    cmd->add_option("--out-dir", o->outDir, "output folder")->capture_default_str();
    cmd->add_option("--markdown", o->markdownPath, "also write the Markdown report to this file");
    cmd->add_flag("--no-images", o->noImages, "skip the per-run images");
    cmd->add_flag("--deterministic", o->deterministic, "leave timings out of the outputs");
    cmd->add_flag("--judge", o->judge, "fail (exit 4) when an exact row or a CPU peer disagrees with the reference");
    addThreadsOption(*cmd, o->threads);
    addIsaOption(*cmd);
    cmd->callback([o, list] {
        if (*list) {
            std::cout << bench::presetTable();
            return;
        }
        orFail(bench::run(*o));
    });
}

}  // namespace relief::cli
