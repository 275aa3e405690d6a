// relief bake HEIGHTFIELD --maps TECH[,TECH...] -o maps.exr|maps.png|maps.ktx2 [--format F]
#include <relief/cli/common.h>
#include <relief/core/progress.h>
#include <relief/core/parallel.h>
#include <relief/techniques/registry.h>

#include <algorithm>
#include <chrono>
#include <iostream>

namespace relief::cli {

namespace {

struct BakeOptions {
    SurfaceOptions surface;
    TechniqueOptions technique;
    std::string techniques;
    std::string output;
    std::string format;  // empty: from the output's extension
    int threads = 0;
    bool deterministic = false;
};

std::vector<const TechniqueInfo*> bakeable(const std::string& list) {
    std::vector<const TechniqueInfo*> infos;
    std::string known;
    for (const TechniqueInfo& info : techniques())
        if (info.buildMaps) known += (known.empty() ? "" : ", ") + std::string(info.name);
    size_t start = 0;
    while (start <= list.size()) {
        size_t comma = list.find(',', start);
        if (comma == std::string::npos) comma = list.size();
        const std::string name = list.substr(start, comma - start);
        const TechniqueInfo* info = findTechnique(name);
        if (info && std::find(infos.begin(), infos.end(), info) != infos.end())
            throw CommandFailed{
                makeError(ErrorKind::BadArgument, "bake: --maps names '{}' twice", name)};
        if (!info || !info->buildMaps)
            throw CommandFailed{makeError(ErrorKind::BadArgument, "bake: '{}' has no maps to bake "
                                          "(techniques with maps: {})", name, known.empty() ? "none yet" : known)};
        infos.push_back(info);
        start = comma + 1;
    }
    return infos;
}

// --format, else the output's extension (.exr, .png, .ktx2; stdout and names without one: EXR).
// An unknown extension or one that contradicts --format is refused before anything is baked.
MapFormat outputFormat(const BakeOptions& o) {
    std::optional<MapFormat> chosen;
    if (!o.format.empty()) {
        chosen = mapFormatFromName(o.format);
        if (!chosen)
            throw CommandFailed{makeError(ErrorKind::BadArgument,
                                          "bake: --format '{}' is not exr, png or ktx2", o.format)};
    }
    const std::string name = o.output.substr(o.output.find_last_of('/') + 1);
    const size_t dot = name.find_last_of('.');
    if (o.output != "-" && dot != std::string::npos && dot > 0) {
        const auto named = mapFormatFromPath(name);
        if (!named)
            throw CommandFailed{makeError(
                ErrorKind::BadArgument,
                "bake: -o {}: unknown map file extension '{}' (relief writes .exr, .png, .ktx2)",
                o.output, name.substr(dot))};
        if (chosen && *chosen != *named)
            throw CommandFailed{makeError(ErrorKind::BadArgument,
                                          "bake: -o {} names {} but --format is {}", o.output,
                                          toString(*named), toString(*chosen))};
        chosen = named;
    }
    return chosen.value_or(MapFormat::Exr);
}

// How each array is stored in `format`: its exact storage, or a refusal saying how to bake it so
// that the format can hold it (rounding is the bake's: the exporter never rounds).
std::vector<MapStorage> storagesFor(const std::vector<const TechniqueInfo*>& infos,
                                    const MapFile& file, MapFormat format, const std::string& path) {
    std::vector<MapStorage> storages;
    for (size_t k = 0; k < infos.size(); ++k) {
        const std::vector<MapArray>& arrays = file.techniques[k].arrays;
        // Before the storages: no bits parameter makes a PNG hold a pyramid.
        if (format == MapFormat::Png && arrays.size() > 1)
            throw CommandFailed{makeError(
                ErrorKind::BadArgument,
                "bake: {}: {} maps are {} arrays ({}, ...) and a PNG holds one: write --format "
                "ktx2 (one file) or exr (docs/maps.md)",
                path, infos[k]->name, arrays.size(), arrays.front().name)};
        for (const MapArray& a : arrays) {
            const auto storage = exactStorage(a, arrayKind(*infos[k], a.name), format);
            if (!storage) {
                const auto specs = channelsOf(*infos[k], a.name);
                const std::string_view quantize = specs.empty() ? "" : specs.front()->quantize;
                throw CommandFailed{makeError(
                    ErrorKind::BadArgument,
                    "bake: {}: {}/{} holds {} and a PNG holds 8/16-bit codes: {}write --format "
                    "ktx2 or exr (docs/maps.md)",
                    path, infos[k]->name, a.name,
                    quantize.empty() ? "32-bit floats" : "32-bit floats (bits=32)",
                    quantize.empty() ? "" : fmt::format("bake with {}, or ", quantize))};
            }
            storages.push_back(*storage);
        }
    }
    return storages;
}

void runBake(const BakeOptions& o) {
    ThreadLimit limit(o.threads);
    const std::vector<const TechniqueInfo*> infos = bakeable(o.techniques);
    const MapFormat format = outputFormat(o);
    if (format != MapFormat::Exr && infos.size() != 1)
        throw CommandFailed{makeError(ErrorKind::BadArgument,
                                      "bake: a {} map file holds the maps of one technique ({} "
                                      "given): bake one per file, or write --format exr",
                                      toString(format), infos.size())};
    auto hf = orFail(loadHeightfield(o.surface));
    auto surface = orFail(makeSurface(o.surface, hf));
    MapFile file;
    file.source = mapSourceOf(*surface);
    // Options and parameters a technique lacks are only an error if no technique has them.
    const std::vector<Overrides> overrides = orFail(parameterOverrides(infos, o.technique));
    std::vector<double> seconds;
    std::vector<std::vector<std::string>> reused;  // per row: what it took from earlier rows
    BuildShare share;                               // e.g. safety-sd's distances for safety-cc
    for (size_t k = 0; k < infos.size(); ++k) {
        // Parameters the maps do not record are refused before anything is printed.
        const auto start = std::chrono::steady_clock::now();
        file.techniques.push_back(orFail(bakeMaps(*infos[k], surface, overrides[k], &share)));
        seconds.push_back(
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        reused.push_back(share.takeNotes());
    }
    // What the format cannot hold is refused before the report, like the parameters above.
    const std::vector<MapStorage> storages = storagesFor(infos, file, format, o.output);
    // Maps on stdout keep stdout to themselves: the report goes to stderr then.
    std::ostream& report = o.output == "-" ? std::cerr : std::cout;
    for (size_t k = 0; k < infos.size(); ++k) {
        size_t bytes = 0;
        for (const MapArray& a : file.techniques[k].arrays) bytes += a.data.size() * sizeof(float);
        std::string notes;
        for (const std::string& note : reused[k]) notes += (notes.empty() ? ", reusing " : ", ") + note;
        if (!Progress::quiet())
            report << fmt::format("{}: {} arrays, {:.2f} bytes per texel{}{}\n", infos[k]->name,
                                 file.techniques[k].arrays.size(),
                                 double(bytes) / double(hf->sampleCount()),
                                 o.deterministic ? ""
                                                 : fmt::format(", built in {:.3f} s on {} threads",
                                                               seconds[k], ThreadLimit::current()),
                                 notes);
    }
    orFail(writeMapFile(o.output, file, format, storages));
    if (!Progress::quiet()) report << "wrote " << o.output << "\n";
}

}  // namespace

void addBakeCommand(CLI::App& app) {
    auto o = std::make_shared<BakeOptions>();
    CLI::App* cmd = app.add_subcommand("bake", "precompute techniques' maps into one OpenEXR, PNG or KTX2 file");
    addSurfaceOptions(*cmd, o->surface);
    cmd->add_option("--maps,-t,--technique", o->techniques, "techniques whose maps to bake, comma-separated")->required();
    cmd->add_option("--max-steps", o->technique.maxSteps,
                    "refused with a message: the iteration cap never changes the maps");
    addRoleOptions(*cmd, o->technique);
    cmd->add_option("--param", o->technique.params, "technique parameter NAME=VALUE (repeatable)");
    cmd->add_option("-o,--output", o->output, "map file: .exr (all maps), .png (one array), .ktx2 "
                    "(one texture); see docs/maps.md")->required();
    cmd->add_option("--format", o->format, "exr, png or ktx2 (default: from -o's extension)");
    cmd->add_flag("--deterministic", o->deterministic, "leave timings out of the output");
    addThreadsOption(*cmd, o->threads);
    cmd->callback([o] { runBake(*o); });
}

}  // namespace relief::cli
