#include <relief/bench/report.h>

#include <relief/bench/peers.h>
#include <relief/bench/peers_report.h>
#include <relief/bench/svg_plot.h>
#include <relief/techniques/registry.h>

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <algorithm>
#include <optional>
#include <regex>
#include <tuple>
#include <set>

namespace relief::bench {

namespace {

using Table = ReportTable;

std::string formatRatio(double r) { return r > 0 ? fmt::format("{:.2f}×", r) : "-"; }

bool sameView(const BenchRow& a, const BenchRow& b) {
    return a.map == b.map && a.elevation == b.elevation && a.backend == b.backend;
}

// The largest cap each technique ran with on each backend (0 for techniques without one).
std::map<std::pair<std::string, std::string>, int> largestCaps(const std::vector<BenchRow>& rows) {
    std::map<std::pair<std::string, std::string>, int> caps;
    for (const BenchRow& r : rows) {
        int& cap = caps[{r.technique, r.backend}];
        cap = std::max(cap, r.cap);
    }
    return caps;
}

std::vector<const BenchRow*> atLargestCap(const std::vector<BenchRow>& rows) {
    const auto caps = largestCaps(rows);
    std::vector<const BenchRow*> selected;
    for (const BenchRow& r : rows)
        if (r.cap == caps.at({r.technique, r.backend})) selected.push_back(&r);
    return selected;
}

const BenchRow* findRow(const std::vector<const BenchRow*>& rows, const BenchRow& view, const std::string& technique) {
    for (const BenchRow* r : rows)
        if (r->technique == technique && sameView(*r, view)) return r;
    return nullptr;
}

std::string referenceName() { return std::string(referenceTechnique().name); }

Table summaryTable(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta) {
    Table t{"Summary", fmt::format("Per technique and backend, averaged over every map and view at its largest cap. "
                                   "× {} and × peer are speed ratios on the same rays in this run (peer: Embree "
                                   "rtcIntersect1 on the CPU, the rasterized mesh on GL), geometric means over the views.",
                                   referenceName())};
    t.header = {"technique", "contract", "backend", "mean abs err", "p95 abs err", "wrong %", "mean steps"};
    if (meta.timings) t.header.insert(t.header.end(), {"Mrays/s", "× " + referenceName(), "× peer", "build s"});
    t.header.push_back("bytes/texel");
    for (const TechniqueSummary& s : summarize(rows, config)) {
        std::vector<std::string> line = {s.technique, s.contract, s.backend, fmt::format("{:.3g}", s.errorMean),
                                         fmt::format("{:.3g}", s.errorP95), fmt::format("{:.3f}", s.wrongPercent),
                                         fmt::format("{:.2f}", s.stepsMean)};
        if (meta.timings)
            line.insert(line.end(), {fmt::format("{:.2f}", s.mraysPerSecond), formatRatio(s.vsExact),
                                     formatRatio(s.vsPeer), fmt::format("{:.2f}", s.buildSeconds)});
        line.push_back(fmt::format("{:.1f}", s.bytesPerTexel));
        t.rows.push_back(std::move(line));
    }
    return t;
}

// Mean of `value` over the rows of one technique on the CPU, keyed by `key`.
template <class Key, class KeyFn, class ValueFn>
std::map<std::string, std::map<Key, std::pair<double, double>>> meanBy(const std::vector<const BenchRow*>& rows,
                                                                       KeyFn key, ValueFn value) {
    std::map<std::string, std::map<Key, std::pair<double, double>>> sums;  // (sum, count) per key
    for (const BenchRow* r : rows) {
        if (r->backend != "cpu" || r->contract == "peer") continue;
        auto& [sum, count] = sums[r->technique][key(*r)];
        sum += value(*r);
        count += 1;
    }
    return sums;
}

Table errorVsCapTable(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    Table t{"Error vs iteration cap",
            fmt::format("CPU: mean |t − t_{}| (texels) / wrong-pixel %, over every map and view.", referenceName())};
    std::vector<const BenchRow*> capped;
    for (const BenchRow& r : rows)
        if (r.cap > 0) capped.push_back(&r);
    const auto error = meanBy<int>(capped, [](const BenchRow& r) { return r.cap; },
                                   [](const BenchRow& r) { return r.stats.error.mean; });
    const auto wrong = meanBy<int>(capped, [](const BenchRow& r) { return r.cap; },
                                   [](const BenchRow& r) { return 100 * r.stats.wrongRate(); });
    t.header = {"technique"};
    std::vector<int> caps = config.caps;
    std::erase(caps, 0);  // the defaults are not a cap
    for (int cap : caps) t.header.push_back(std::to_string(cap));
    for (const auto& [technique, byCap] : error) {
        std::vector<std::string> line = {technique};
        for (int cap : caps) {
            const auto e = byCap.find(cap);
            const auto w = wrong.at(technique).find(cap);
            line.push_back(e == byCap.end() ? "-"
                                            : fmt::format("{:.3g} / {:.2f}", e->second.first / e->second.second,
                                                          w->second.first / w->second.second));
        }
        t.rows.push_back(std::move(line));
    }
    return t;
}

Table stepsVsElevationTable(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    Table t{"Steps vs elevation", "CPU: mean steps per pixel at the largest cap, over every map."};
    const auto steps = meanBy<float>(atLargestCap(rows), [](const BenchRow& r) { return r.elevation; },
                                     [](const BenchRow& r) { return r.stats.steps.mean; });
    t.header = {"technique"};
    for (float e : config.elevations) t.header.push_back(fmt::format("{:.1f}°", e));
    for (const auto& [technique, byElevation] : steps) {
        std::vector<std::string> line = {technique};
        for (float e : config.elevations) {
            const auto it = byElevation.find(e);
            line.push_back(it == byElevation.end() ? "-" : fmt::format("{:.2f}", it->second.first / it->second.second));
        }
        t.rows.push_back(std::move(line));
    }
    return t;
}

Table paperTable(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    Table t{"The paper's figures beside ours", config.paperNotes};
    t.header = {"comparison", "paper", "ours (this run)"};
    for (const PaperRatio& ratio : config.paperRatios) t.rows.push_back({ratio.what, ratio.paper, measuredRatio(rows, ratio)});
    return t;
}

Table allRowsTable(const std::vector<BenchRow>& rows, const BenchMeta& meta) {
    Table t{"All rows", "One row per technique, map, view, cap and backend."};
    t.header = {"technique", "backend", "map", "elev", "cap", "mean err", "p95 err", "max err", "wrong %", "mean steps", "max steps"};
    if (meta.timings) t.header.insert(t.header.end(), {"Mrays/s", "ms/frame", "build s"});
    for (const BenchRow& r : rows) {
        std::vector<std::string> line = {r.technique, r.backend, r.map, fmt::format("{:.1f}", r.elevation),
                                         r.cap ? std::to_string(r.cap) : "-", fmt::format("{:.3g}", r.stats.error.mean),
                                         fmt::format("{:.3g}", r.stats.error.p95), fmt::format("{:.3g}", r.stats.error.max),
                                         fmt::format("{:.3f}", 100 * r.stats.wrongRate()), fmt::format("{:.2f}", r.stats.steps.mean),
                                         fmt::format("{:.0f}", r.stats.steps.max)};
        if (meta.timings)
            line.insert(line.end(), {fmt::format("{:.2f}", r.mraysPerSecond), fmt::format("{:.3f}", r.msPerFrame),
                                     fmt::format("{:.3f}", r.buildSeconds)});
        t.rows.push_back(std::move(line));
    }
    return t;
}

// The names of the rows' map statistics (TechniqueInfo::mapSummary), in first-seen order: extra
// columns of the builds table and of results.csv.
std::vector<std::string> mapSummaryNames(const std::vector<BenchRow>& rows) {
    std::vector<std::string> names;
    for (const BenchRow& r : rows)
        for (const auto& [name, value] : r.mapSummary)
            if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    return names;
}

std::string mapSummaryCell(const BenchRow& r, const std::string& name) {
    for (const auto& [n, value] : r.mapSummary)
        if (n == name) return fmt::format("{:.3g}", value);
    return "-";
}

// Builds studies: one row per technique and map size, no views.
Table buildsTable(const std::vector<BenchRow>& rows, const BenchMeta& meta) {
    Table t{"Map builds", "Map build per technique and map size: wall and process CPU seconds (all threads), "
                          "and bytes per texel of the maps."};
    t.header = {"technique", "map"};
    if (meta.timings) t.header.insert(t.header.end(), {"wall s", "CPU s"});
    t.header.push_back("bytes/texel");
    const std::vector<std::string> summaries = mapSummaryNames(rows);
    if (!summaries.empty()) t.caption += " Then the statistics each row reports of its maps.";
    for (std::string name : summaries) {
        std::replace(name.begin(), name.end(), '_', ' ');  // mean_r → "mean r", as docs/safety.md
        t.header.push_back(name);
    }
    for (const BenchRow& r : rows) {
        std::vector<std::string> line = {r.technique, r.map};
        if (meta.timings)
            line.insert(line.end(), {fmt::format("{:.3f}", r.buildSeconds), fmt::format("{:.3f}", r.buildCpuSeconds)});
        line.push_back(fmt::format("{:.1f}", r.bytesPerTexel));
        for (const std::string& name : summaries) line.push_back(mapSummaryCell(r, name));
        t.rows.push_back(std::move(line));
    }
    return t;
}

// Scaling studies, one table per elevation: steps per ray (over the rays that enter the box) of
// every row against the map size, and the hits that disagree with the reference.
std::vector<Table> scalingTables(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    const std::vector<const BenchRow*> selected = atLargestCap(rows);
    std::vector<std::string> names, maps;
    for (const BenchRow* r : selected) {
        if (r->backend != "cpu" || isPeer(r->technique)) continue;
        if (std::find(names.begin(), names.end(), r->technique) == names.end()) names.push_back(r->technique);
        if (std::find(maps.begin(), maps.end(), r->map) == maps.end()) maps.push_back(r->map);
    }
    std::vector<Table> tables;
    for (float e : config.elevations) {
        Table t{fmt::format("Steps per ray against map size, elevation {:.1f}°", e),
                fmt::format("CPU: mean / p99 steps over the rays that enter the box; wrong hits: pixels where a row "
                            "and {} differ (hit/miss, or |Δt| > 1e-3 texel), all rows together.", referenceName())};
        t.header = {"map", "log2 p"};
        t.header.insert(t.header.end(), names.begin(), names.end());
        t.header.push_back("wrong hits");
        for (const std::string& map : maps) {
            std::vector<std::string> line = {map, "-"};
            size_t wrong = 0;
            for (const std::string& name : names) {
                const BenchRow* found = nullptr;
                for (const BenchRow* r : selected)
                    if (r->technique == name && r->map == map && r->elevation == e && r->backend == "cpu") found = r;
                if (found) {
                    line[1] = fmt::format("{:.1f}", std::log2(double(found->mapSamples)));
                    wrong += size_t(std::llround((1.0 - found->agreeRate) * double(found->stats.pixels)));
                }
                line.push_back(found ? fmt::format("{:.1f} / {:.0f}", found->boxSteps.mean, found->boxSteps.p99) : "-");
            }
            line.push_back(std::to_string(wrong));
            t.rows.push_back(std::move(line));
        }
        tables.push_back(std::move(t));
    }
    return tables;
}

// Every CPU row and peer per map and view, on the same rays in this run (DESIGN §8): the
// reference's hits and cells per ray, Mrays/s, the first row over each peer, and each row's
// agreement with the reference (same hit/miss and |Δt| ≤ 1e-3 texel).
Table viewTable(const std::vector<BenchRow>& rows, const BenchMeta& meta) {
    const std::string ref = referenceName();
    Table t{"Per view", fmt::format("CPU, per map and view, at the largest cap: pixels hit and cells per ray of {0}, "
                                    "speeds, and agreement with {0} (same hit/miss and |Δt| ≤ 1e-3 texel).", ref)};
    const std::vector<const BenchRow*> selected = atLargestCap(rows);
    std::vector<std::string> names, peerNames;
    for (const BenchRow* r : selected)
        if (r->backend == "cpu" && std::find(names.begin(), names.end(), r->technique) == names.end())
            names.push_back(r->technique);
    for (const PeerInfo& p : peers())
        if (p.backend == "cpu" && std::find(names.begin(), names.end(), p.name) != names.end())
            peerNames.emplace_back(p.name);
    std::erase_if(names, [](const std::string& n) { return isPeer(n); });
    std::vector<std::string> all = names;
    all.insert(all.end(), peerNames.begin(), peerNames.end());
    std::vector<std::string> compared;  // agreement columns: every row but the reference
    for (const std::string& n : all)
        if (n != ref) compared.push_back(n);
    t.header = {"map", "elevation", "hits", "cells/ray"};
    if (meta.timings) {
        for (const std::string& n : all) t.header.push_back(n + " Mrays/s");
        if (!names.empty())
            for (const std::string& p : peerNames) t.header.push_back(names.front() + "/" + p);
    }
    for (const std::string& n : compared) t.header.push_back("agree " + n);
    for (const BenchRow* r : selected) {
        if (r->technique != ref || r->backend != "cpu") continue;
        auto value = [&](const std::string& name, auto format) {
            const BenchRow* row = findRow(selected, *r, name);
            return row ? format(*row) : std::string("-");
        };
        std::vector<std::string> line = {r->map, fmt::format("{:.1f}°", r->elevation),
                                         fmt::format("{:.1f}%", 100.0 * double(r->stats.hits) / double(std::max<size_t>(1, r->stats.pixels))),
                                         fmt::format("{:.0f}", r->stats.steps.mean)};
        if (meta.timings) {
            for (const std::string& n : all)
                line.push_back(value(n, [](const BenchRow& x) { return fmt::format("{:.2f}", x.mraysPerSecond); }));
            const BenchRow* first = names.empty() ? nullptr : findRow(selected, *r, names.front());
            for (const std::string& p : peerNames)
                line.push_back(value(p, [&](const BenchRow& x) {
                    return first && x.mraysPerSecond > 0 ? fmt::format("{:.3f}", first->mraysPerSecond / x.mraysPerSecond)
                                                         : std::string("-");
                }));
        }
        for (const std::string& n : compared)
            line.push_back(value(n, [](const BenchRow& x) { return fmt::format("{:.4f}%", 100.0 * x.agreeRate); }));
        t.rows.push_back(std::move(line));
    }
    return t;
}

// BenchConfig::userGeometry: each row behind an Embree user geometry against Embree's triangles
// of the same solid, per map and view, on the same rays; memory per heightfield texel of each.
Table userGeometryTable(const std::vector<BenchRow>& rows, const BenchMeta& meta) {
    Table t{"Embree user geometry",
            fmt::format("CPU, per map and view, at the largest cap: each row traced by Embree as a user geometry "
                        "(rtcIntersect1 / rtcIntersect16; the callbacks trace each call's rays as one batch) and "
                        "Embree's triangles of the same solid (embree-1 / embree-16), on the same rays in this run. "
                        "Bytes per heightfield texel: the user geometry's (heightfield, padded heights, the row's "
                        "maps, Embree's one-box scene; maps alone in brackets) and the triangle scene's (Embree's "
                        "BVH and buffers, by the device's memory monitor). Agree: same hit/miss and |Δt| ≤ 1e-3 "
                        "texel as {}.", referenceName())};
    t.header = {"map", "elevation", "technique"};
    if (meta.timings)
        t.header.insert(t.header.end(), {"relief Mrays/s", "user-1 Mrays/s", "user-16 Mrays/s", "embree-1 Mrays/s",
                                         "embree-16 Mrays/s", "user-1 / embree-1", "user-16 / embree-16"});
    t.header.insert(t.header.end(), {"user bytes/texel", "triangles bytes/texel", "agree user-1", "agree user-16",
                                     "agree embree-1", "agree embree-16"});
    const std::vector<const BenchRow*> selected = atLargestCap(rows);
    auto ratio = [](const BenchRow* a, const BenchRow* b) {
        return a && b && b->mraysPerSecond > 0 ? formatRatio(a->mraysPerSecond / b->mraysPerSecond) : std::string("-");
    };
    auto speed = [](const BenchRow* r) { return r ? fmt::format("{:.2f}", r->mraysPerSecond) : std::string("-"); };
    auto agree = [](const BenchRow* r) { return r ? fmt::format("{:.4f}%", 100.0 * r->agreeRate) : std::string("-"); };
    for (const BenchRow* r : selected) {
        if (r->backend != "cpu" || isPeer(r->technique)) continue;
        const BenchRow* user1 = findRow(selected, *r, userGeometryLabel(r->technique, PeerKind::Embree1));
        const BenchRow* user16 = findRow(selected, *r, userGeometryLabel(r->technique, PeerKind::Embree16));
        if (!user1 || !user16) continue;
        const BenchRow* tri1 = findRow(selected, *r, "embree-1");
        const BenchRow* tri16 = findRow(selected, *r, "embree-16");
        std::vector<std::string> line = {r->map, fmt::format("{:.1f}°", r->elevation), r->technique};
        if (meta.timings)
            line.insert(line.end(), {speed(r), speed(user1), speed(user16), speed(tri1), speed(tri16),
                                     ratio(user1, tri1), ratio(user16, tri16)});
        line.insert(line.end(), {fmt::format("{:.1f} ({:.1f})", user1->bytesPerTexel, r->bytesPerTexel),
                                 tri1 ? fmt::format("{:.1f}", tri1->bytesPerTexel) : std::string("-"),
                                 agree(user1), agree(user16), agree(tri1), agree(tri16)});
        t.rows.push_back(std::move(line));
    }
    return t;
}

// Two rows A/B side by side (a paper's figures of one method against another): per elevation and
// cap (0 = the defaults), means over the maps of the CPU rows.
std::vector<Table> compareTables(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta) {
    const size_t slash = config.compare.find('/');
    const std::string a = config.compare.substr(0, slash), b = config.compare.substr(slash + 1);
    struct Sums {
        double error = 0, wrong = 0, steps = 0, ms = 0;
        int n = 0;
    };
    std::map<std::tuple<std::string, float, int>, Sums> sums;
    for (const BenchRow& r : rows) {
        if (r.backend != "cpu" || (r.technique != a && r.technique != b)) continue;
        Sums& s = sums[{r.technique, r.elevation, r.cap}];
        s.error += r.stats.error.mean;
        s.wrong += 100 * r.stats.wrongRate();
        s.steps += r.stats.steps.mean;
        s.ms += r.msPerFrame;
        ++s.n;
    }
    std::vector<int> caps = config.caps.empty() ? std::vector<int>{0} : config.caps;
    auto table = [&](std::string title, std::string caption, auto cell) {
        Table t{std::move(title), std::move(caption)};
        t.header = {"elevation"};
        for (int cap : caps) t.header.push_back(cap ? std::to_string(cap) : "default");
        for (float e : config.elevations) {
            std::vector<std::string> line = {fmt::format("{:.1f}°", e)};
            for (int cap : caps) {
                const auto x = sums.find({a, e, cap}), y = sums.find({b, e, cap});
                line.push_back(x == sums.end() || y == sums.end() ? "-" : cell(x->second, y->second));
            }
            t.rows.push_back(std::move(line));
        }
        return t;
    };
    std::vector<Table> tables;
    tables.push_back(table(fmt::format("Mean |Δt|, {} / {}", a, b),
                           "Texels along the ray, by elevation and cap, mean over the maps.",
                           [](const Sums& x, const Sums& y) {
                               return fmt::format("{:.3g} / {:.3g}", x.error / x.n, y.error / y.n);
                           }));
    tables.push_back(table(fmt::format("Wrong-hit pixels (%), {} / {}", a, b),
                           "Unconverged rays at a cap stop short.", [](const Sums& x, const Sums& y) {
                               return fmt::format("{:.2g} / {:.2g}", x.wrong / x.n, y.wrong / y.n);
                           }));
    tables.push_back(table(fmt::format("Mean steps per pixel, {} / {}", a, b), "Until termination.",
                           [](const Sums& x, const Sums& y) {
                               return fmt::format("{:.1f} / {:.1f}", x.steps / x.n, y.steps / y.n);
                           }));
    if (meta.timings) {
        tables.push_back(table(fmt::format("{1} minus {0} time per frame (ms)", a, b),
                               fmt::format("Mean over the maps; positive = {} faster.", a),
                               [](const Sums& x, const Sums& y) {
                                   return fmt::format("{:+.2f}", y.ms / y.n - x.ms / x.n);
                               }));
        tables.push_back(table(fmt::format("Time ratio {} / {} per frame", a, b),
                               fmt::format("< 1 = {} faster.", a), [](const Sums& x, const Sums& y) {
                                   return fmt::format("{:.2f}", (x.ms / x.n) / (y.ms / y.n));
                               }));
    }
    return tables;
}

bool hasCurves(const std::vector<BenchRow>& rows) {
    return std::any_of(rows.begin(), rows.end(), [](const BenchRow& r) { return r.curves.has_value(); });
}

// The visibility-curve rows as the paper's Table 1: one column per row and view, one line per
// counter, then the reference on the same sample rays and the per-sample error.
Table curvesTable(const std::vector<BenchRow>& rows, const BenchMeta& meta) {
    Table t{"Visibility curves (Table 1)",
            fmt::format("Rows drawn by the visibility-curve renderer (as `relief render` draws them); {} traced on the "
                        "very same sample rays; errors per sample.", referenceName())};
    std::vector<const BenchRow*> curves;
    for (const BenchRow& r : rows)
        if (r.curves) curves.push_back(&r);
    t.header = {"quantity"};
    for (const BenchRow* r : curves)
        t.header.push_back(fmt::format("{} {} e={:.1f}{}", r->technique, r->map, r->elevation,
                                       r->cap > 0 ? fmt::format(" cap {}", r->cap) : ""));
    auto line = [&](const std::string& label, auto get) {
        std::vector<std::string> cells{label};
        for (const BenchRow* r : curves) cells.push_back(get(*r, *r->curves));
        t.rows.push_back(std::move(cells));
    };
    auto count = [&](const char* label, int64_t curves::StepCounts::*field) {
        line(label, [&](const BenchRow&, const CurvesFigures& c) { return fmt::format("{}", c.counts.*field); });
    };
    count("visibility curves", &curves::StepCounts::curves);
    count("inside samples", &curves::StepCounts::insideSamples);
    count("extra samples", &curves::StepCounts::extraSamples);
    line("total samples", [](const BenchRow&, const CurvesFigures& c) { return fmt::format("{}", c.counts.samples()); });
    count("advance steps", &curves::StepCounts::advanceSteps);
    count("reverse steps", &curves::StepCounts::reverseSteps);
    count("binary cuts", &curves::StepCounts::binaryCuts);
    count("wall hits (leading edge)", &curves::StepCounts::wallHits);
    line("curves evaluations / sample", [](const BenchRow&, const CurvesFigures& c) {
        return fmt::format("{:.2f}", double(c.counts.evaluations()) / double(std::max<int64_t>(1, c.counts.samples())));
    });
    line(referenceName() + " cells / ray",
         [](const BenchRow&, const CurvesFigures& c) { return fmt::format("{:.2f}", c.referenceCellsPerRay); });
    if (meta.timings) {
        line("curves Msamples/s", [](const BenchRow&, const CurvesFigures& c) { return fmt::format("{:.2f}", c.msamplesPerSecond); });
        line(referenceName() + " Mrays/s (same rays)",
             [](const BenchRow&, const CurvesFigures& c) { return fmt::format("{:.2f}", c.referenceMraysPerSecond); });
    }
    line("mean abs dt (texels)", [](const BenchRow& r, const CurvesFigures&) { return fmt::format("{:.3g}", r.stats.error.mean); });
    line("wrong samples", [](const BenchRow& r, const CurvesFigures&) { return fmt::format("{:.3f}%", 100.0 * r.stats.wrongRate()); });
    return t;
}

std::vector<Table> reportTables(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta) {
    if (config.kind == StudyKind::Builds) return {buildsTable(rows, meta)};
    std::vector<Table> tables = {summaryTable(rows, config, meta)};
    if (!config.caps.empty()) tables.push_back(errorVsCapTable(rows, config));
    tables.push_back(stepsVsElevationTable(rows, config));
    if (config.kind == StudyKind::Scaling)
        for (Table& t : scalingTables(rows, config)) tables.push_back(std::move(t));
    if (config.peerTable) tables.push_back(viewTable(rows, meta));
    if (config.userGeometry) tables.push_back(userGeometryTable(rows, meta));
    if (hasCurves(rows))
        tables.push_back(curvesTable(rows, meta));
    if (!config.compare.empty())
        for (Table& t : compareTables(rows, config, meta)) tables.push_back(std::move(t));
    if (!config.paperNotes.empty() || !config.paperRatios.empty()) tables.push_back(paperTable(rows, config));
    if (!config.targets.empty()) {  // the page's point: first
        std::vector<Table> peers = cpuPeersTables(rows, config, meta);
        tables.insert(tables.begin(), std::make_move_iterator(peers.begin()), std::make_move_iterator(peers.end()));
    }
    return tables;
}

std::string markdownTable(const Table& t) {
    auto line = [](const std::vector<std::string>& cells) {
        std::string s = "|";
        for (const std::string& c : cells) s += " " + c + " |";
        return s + "\n";
    };
    std::string s = line(t.header) + "|";
    for (size_t c = 0; c < t.header.size(); ++c) s += "---|";
    s += "\n";
    for (const auto& row : t.rows) s += line(row);
    return s;
}

std::string htmlEscape(const std::string& text) {
    std::string s;
    for (char c : text) s += c == '<' ? "&lt;" : c == '>' ? "&gt;" : c == '&' ? "&amp;" : std::string(1, c);
    return s;
}

std::string htmlTable(const Table& t) {
    std::string s = "<table><tr>";
    for (const std::string& h : t.header) s += "<th>" + htmlEscape(h) + "</th>";
    s += "</tr>";
    for (const auto& row : t.rows) {
        s += "<tr>";
        for (const std::string& c : row) s += "<td>" + htmlEscape(c) + "</td>";
        s += "</tr>";
    }
    return s + "</table>";
}

std::string runDescription(const BenchMeta& meta) {
    std::string s = fmt::format("Machine: {}; threads: {}; image {}; date {}.", meta.machine, meta.threads,
                                meta.imageSize, meta.date);
    if (!meta.glDevice.empty()) s += fmt::format(" GL device: {}.", meta.glDevice);
    if (!meta.loadBefore.empty())
        s += fmt::format(" Load average before the run: {}; after: {}.", meta.loadBefore, meta.loadAfter);
    return s + " Every row of one map and view traced the same primary rays in one run (on the CPU, rows and "
               "peers alike, made before the timing and in one order: 4×4 pixel tiles, as rtcIntersect16 "
               "takes them); times are the best of the timed repeats.";
}

// Why: an HTML report whose images failed to load looks fine in a table-only glance; the page
// records what it saw so that a headless browser test (and a reader) can tell.
constexpr const char* kSelfCheckScript =
    "<script>window.addEventListener('load',function(){var broken=0,imgs=document.images;"
    "for(var i=0;i<imgs.length;++i)if(!imgs[i].complete||imgs[i].naturalWidth===0)++broken;"
    "document.body.setAttribute('data-images',imgs.length);document.body.setAttribute('data-broken-images',broken);"
    "if(broken)console.error('relief report: '+broken+' images failed to load');});</script>";

}  // namespace

std::vector<TechniqueSummary> summarize(const std::vector<BenchRow>& rows, const BenchConfig&) {
    const std::vector<const BenchRow*> selected = atLargestCap(rows);
    std::vector<TechniqueSummary> summaries;
    std::set<std::pair<std::string, std::string>> done;
    for (const BenchRow* first : selected) {
        if (!done.insert({first->technique, first->backend}).second) continue;
        TechniqueSummary s{first->technique, first->contract, first->backend};
        RatioMean vsExact, vsPeer;
        int n = 0;
        for (const BenchRow* r : selected) {
            if (r->technique != s.technique || r->backend != s.backend) continue;
            ++n;
            s.errorMean += r->stats.error.mean;
            s.errorP95 += r->stats.error.p95;
            s.wrongPercent += 100 * r->stats.wrongRate();
            s.stepsMean += r->stats.steps.mean;
            s.mraysPerSecond += r->mraysPerSecond;
            s.buildSeconds += r->buildSeconds;
            s.bytesPerTexel += r->bytesPerTexel;
            if (const BenchRow* ref = findRow(selected, *r, referenceName())) vsExact.add(r->mraysPerSecond, ref->mraysPerSecond);
            const PeerInfo* peer = summaryPeerOf(r->backend);
            if (const BenchRow* p = peer ? findRow(selected, *r, std::string(peer->name)) : nullptr)
                vsPeer.add(r->mraysPerSecond, p->mraysPerSecond);
        }
        for (double* v : {&s.errorMean, &s.errorP95, &s.wrongPercent, &s.stepsMean, &s.mraysPerSecond, &s.buildSeconds, &s.bytesPerTexel})
            *v /= n;
        s.vsExact = vsExact.value();
        s.vsPeer = vsPeer.value();
        summaries.push_back(s);
    }
    return summaries;
}

std::string measuredRatio(const std::vector<BenchRow>& rows, const PaperRatio& ratio) {
    const std::vector<const BenchRow*> selected = atLargestCap(rows);
    auto matches = [&](const BenchRow& r, const std::string& technique, const std::string& map) {
        return r.backend == ratio.backend && r.technique == technique && (map.empty() || r.map == map);
    };
    RatioMean mean;
    for (const BenchRow* num : selected) {
        if (!matches(*num, ratio.numeratorTechnique, ratio.numeratorMap)) continue;
        for (const BenchRow* den : selected)
            if (matches(*den, ratio.denominatorTechnique, ratio.denominatorMap) && den->elevation == num->elevation &&
                (ratio.numeratorMap != ratio.denominatorMap || den->map == num->map))
                mean.add(num->mraysPerSecond, den->mraysPerSecond);
    }
    return formatRatio(mean.value());
}

nlohmann::json rowJson(const BenchRow& r, bool timings) {
    nlohmann::json j = {{"technique", r.technique}, {"contract", r.contract}, {"map", r.map},
                        {"backend", r.backend}, {"elevation", r.elevation}, {"cap", r.cap},
                        {"error_mean", r.stats.error.mean}, {"error_p95", r.stats.error.p95},
                        {"error_max", r.stats.error.max}, {"wrong_rate", r.stats.wrongRate()},
                        {"past_first_hit_rate", r.stats.pastFirstHitRate()},
                        {"shadow_wrong_rate", r.shadowWrongRate},
                        {"agree_rate", r.agreeRate}, {"box_steps_mean", r.boxSteps.mean},
                        {"box_steps_p99", r.boxSteps.p99}, {"map_samples", r.mapSamples},
                        {"steps_mean", r.stats.steps.mean}, {"steps_max", r.stats.steps.max},
                        {"fetches_mean", r.stats.fetches.mean}, {"fetches_max", r.stats.fetches.max},
                        {"bytes_per_texel", r.bytesPerTexel}, {"images", r.images}};
    for (const auto& [name, value] : r.mapSummary) j[name] = value;
    if (timings) {
        j["mrays_per_s"] = r.mraysPerSecond;
        j["ms_per_frame"] = r.msPerFrame;
        j["build_seconds"] = r.buildSeconds;
        j["build_cpu_seconds"] = r.buildCpuSeconds;
        if (r.shadowMraysPerSecond > 0) j["shadow_mrays_per_s"] = r.shadowMraysPerSecond;
        if (!r.pairedRatios.empty()) j["paired_ratios"] = r.pairedRatios;
    }
    if (r.curves) {
        const curves::StepCounts& c = r.curves->counts;
        j.update({{"visibility_curves", c.curves}, {"inside_samples", c.insideSamples},
                  {"extra_samples", c.extraSamples}, {"total_samples", c.samples()},
                  {"advance_steps", c.advanceSteps}, {"reverse_steps", c.reverseSteps},
                  {"binary_cuts", c.binaryCuts}, {"wall_hits", c.wallHits},
                  {"capped_samples", c.cappedSamples},
                  {"reference_cells_per_ray", r.curves->referenceCellsPerRay}});
        if (timings) {
            j["msamples_per_s"] = r.curves->msamplesPerSecond;
            j["reference_mrays_per_s"] = r.curves->referenceMraysPerSecond;
        }
    }
    return j;
}

std::string resultsJson(const std::vector<BenchRow>& rows, const nlohmann::json& meta, bool timings) {
    nlohmann::json list = nlohmann::json::array();
    for (const BenchRow& r : rows) list.push_back(rowJson(r, timings));
    return nlohmann::json{{"meta", meta}, {"rows", list}}.dump(2) + "\n";
}

std::string resultsCsv(const std::vector<BenchRow>& rows, bool timings) {
    static const char* const kColumns[] = {"technique", "contract", "map", "backend", "elevation", "cap",
        "error_mean", "error_p95", "error_max", "wrong_rate", "steps_mean", "steps_max", "fetches_mean",
        "fetches_max", "mrays_per_s", "ms_per_frame", "build_seconds", "bytes_per_texel", "build_cpu_seconds",
        "agree_rate", "box_steps_mean", "box_steps_p99", "map_samples"};
    // The visibility-curve rows' columns, only in runs that have such rows (empty for the others).
    static const char* const kCurvesColumns[] = {"visibility_curves", "inside_samples", "extra_samples",
        "total_samples", "advance_steps", "reverse_steps", "binary_cuts", "wall_hits", "capped_samples",
        "reference_cells_per_ray", "msamples_per_s", "reference_mrays_per_s"};
    std::vector<const char*> columns(std::begin(kColumns), std::end(kColumns));
    if (hasCurves(rows))
        columns.insert(columns.end(), std::begin(kCurvesColumns), std::end(kCurvesColumns));
    std::string csv;
    for (const char* c : columns) csv += std::string(c == columns[0] ? "" : ",") + c;
    const std::vector<std::string> summaries = mapSummaryNames(rows);
    for (const std::string& name : summaries) csv += "," + name;
    csv += "\n";
    for (const BenchRow& r : rows) {
        const nlohmann::json row = rowJson(r, timings);
        for (const char* c : columns) {
            const auto it = row.find(c);
            csv += c == columns[0] ? "" : ",";
            if (it == row.end()) continue;
            csv += it->is_string() ? it->get<std::string>() : it->dump();
        }
        for (const std::string& name : summaries) csv += "," + (row.contains(name) ? row[name].dump() : "");
        csv += "\n";
    }
    return csv;
}

std::pair<std::string, std::string> benchPlots(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    std::map<std::pair<std::string, double>, std::pair<double, int>> errorSum, stepsSum;
    for (const BenchRow& r : rows) {
        if (r.cap > 0) {
            auto& acc = errorSum[{r.technique, r.cap}];
            acc.first += r.stats.error.mean;
            acc.second++;
        }
        if (r.cap == 0 || (!config.caps.empty() && r.cap == config.caps.back())) {
            auto& acc = stepsSum[{r.technique, r.elevation}];
            acc.first += r.stats.steps.mean;
            acc.second++;
        }
    }
    auto series = [](const std::map<std::pair<std::string, double>, std::pair<double, int>>& sums) {
        std::map<std::string, PlotSeries> byName;
        for (const auto& [key, acc] : sums) {
            PlotSeries& s = byName[key.first];
            s.label = key.first;
            s.x.push_back(key.second);
            s.y.push_back(acc.first / acc.second);
        }
        std::vector<PlotSeries> v;
        for (const auto& [k, s] : byName) v.push_back(s);
        return v;
    };
    return {svgLinePlot({fmt::format("mean |t - t_{}| vs iteration cap (all maps and views)", referenceName()),
                         "iteration cap", "mean |error| (texels)", true, true}, series(errorSum)),
            svgLinePlot({"mean steps per pixel vs camera elevation", "elevation (degrees)", "mean steps", false, true},
                        series(stepsSum))};
}

std::string scalingPlot(const std::vector<BenchRow>& rows, const BenchConfig& config) {
    if (config.elevations.empty()) return "";
    const float elevation = *std::min_element(config.elevations.begin(), config.elevations.end());
    // A map's family is its label with the size taken out (fbm:256x256:1 → fbm:N:1); a family
    // with one map (a file taken once) is no curve.
    const std::regex size("[0-9]+x[0-9]+");
    std::map<std::string, std::set<std::string>> familyMaps;
    std::vector<const BenchRow*> selected;
    for (const BenchRow* r : atLargestCap(rows))
        if (r->backend == "cpu" && !isPeer(r->technique) && r->elevation == elevation && r->mapSamples > 0) {
            selected.push_back(r);
            familyMaps[std::regex_replace(r->map, size, "N")].insert(r->map);
        }
    std::erase_if(familyMaps, [](const auto& f) { return f.second.size() < 2; });
    struct Curve {
        std::string label;
        bool reference = false;
        std::vector<std::tuple<double, double, double>> points;  // log2 p, mean, p99
    };
    std::vector<Curve> curves;
    for (const BenchRow* r : selected) {
        const std::string family = std::regex_replace(r->map, size, "N");
        if (!familyMaps.count(family)) continue;
        const std::string label = r->technique + (familyMaps.size() > 1 ? " (" + family + ")" : "");
        auto it = std::find_if(curves.begin(), curves.end(), [&](const Curve& c) { return c.label == label; });
        if (it == curves.end()) it = curves.insert(curves.end(), {label, r->technique == referenceName(), {}});
        it->points.emplace_back(std::log2(double(r->mapSamples)), r->boxSteps.mean, r->boxSteps.p99);
    }
    // The reference last, so that the other rows keep their colours from one panel to the other.
    std::stable_partition(curves.begin(), curves.end(), [](const Curve& c) { return !c.reference; });
    std::vector<PlotSeries> means, p99s;
    for (Curve& c : curves) {
        std::sort(c.points.begin(), c.points.end());  // by size, whatever order the maps ran in
        PlotSeries mean{c.label, {}, {}}, p99{c.label, {}, {}};
        for (const auto& [x, m, p] : c.points) {
            mean.x.push_back(x);
            mean.y.push_back(m);
            p99.x.push_back(x);
            p99.y.push_back(p);
        }
        if (!c.reference) means.push_back(std::move(mean));  // its steps would flatten the others
        p99s.push_back(std::move(p99));
    }
    const std::string x = "log2 p (p = map samples)";
    return svgSideBySide({{{fmt::format("Mean steps per ray, {:.1f}°", elevation), x, "mean steps", false, false}, means},
                          {{fmt::format("99th percentile of steps per ray, {:.1f}°", elevation), x, "p99 steps", false, true},
                           p99s}});
}

std::string benchMarkdown(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta,
                          const std::string& assetPrefix) {
    std::string s = fmt::format("# relief bench: {}\n\nGenerated by `{}`. {}\n\n", meta.preset, meta.commandLine,
                                runDescription(meta));
    for (const Table& t : reportTables(rows, config, meta))
        s += fmt::format("## {}\n\n{}\n\n{}\n", t.title, t.caption, markdownTable(t));
    s += fmt::format("## Plots\n\n![error vs cap]({0}error_vs_cap.svg)\n![steps vs elevation]({0}steps_vs_elevation.svg)\n\n",
                     assetPrefix);
    if (config.kind == StudyKind::Scaling) s += fmt::format("![steps vs map size]({}{})\n\n", assetPrefix, kScalingPlotName);
    const Table all = allRowsTable(rows, meta);
    s += fmt::format("## {}\n\n<details><summary>{} rows</summary>\n\n{}\n</details>\n", all.title, all.rows.size(),
                     markdownTable(all));
    return s;
}

std::string benchHtml(const std::vector<BenchRow>& rows, const BenchConfig& config, const BenchMeta& meta) {
    std::string h = "<!doctype html><html><head><meta charset=\"utf-8\"><title>relief bench</title><style>"
                    "body{font-family:sans-serif;margin:20px}table{border-collapse:collapse;font-size:12px}"
                    "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}img{max-width:320px}"
                    "</style></head><body><h1>relief bench: " + htmlEscape(meta.preset) + "</h1>";
    h += "<p>" + htmlEscape(runDescription(meta)) + "</p>";
    std::vector<Table> tables = reportTables(rows, config, meta);
    tables.push_back(allRowsTable(rows, meta));
    for (size_t k = 0; k < tables.size(); ++k) {
        if (k + 1 == tables.size())
            h += "<h2>Plots</h2><img src=\"error_vs_cap.svg\" style=\"max-width:640px\"> "
                 "<img src=\"steps_vs_elevation.svg\" style=\"max-width:640px\">";
        h += "<h2>" + htmlEscape(tables[k].title) + "</h2><p>" + htmlEscape(tables[k].caption) + "</p>" + htmlTable(tables[k]);
    }
    h += "<h2>Images (render, steps, error vs " + htmlEscape(referenceName()) + ")</h2>";
    for (const BenchRow& r : rows)
        if (!r.images.empty())
            h += fmt::format("<h3>{} — {} — elevation {:.1f}</h3><img src=\"{}.png\"> <img src=\"{}-steps.png\"> "
                             "<img src=\"{}-error.png\">", htmlEscape(r.technique), htmlEscape(r.map), r.elevation,
                             r.images, r.images, r.images);
    return h + kSelfCheckScript + "</body></html>\n";
}

}  // namespace relief::bench
