#include <fmt/format.h>
#include <relief/bench/peers.h>
#include <relief/bench/peers_report.h>

#include <relief/core/isa.h>
#include <relief/techniques/common/pyramid_walk_packet.h>

#include <algorithm>
#include <map>

namespace relief::bench {

namespace {

// The peers as the page names them: primary (intersection) and shadow (occlusion) queries.
constexpr const char* kEmbree1 = "embree-1";
constexpr const char* kEmbree16 = "embree-16";

std::string peerQuery(const std::string& peer, bool shadow) {
    return embreeQuery(peer == kEmbree16 ? PeerKind::Embree16 : PeerKind::Embree1, shadow);
}

std::string ratioCell(double r) { return r > 0 ? fmt::format("{:.2f}×", r) : "-"; }

double speed(const BenchRow& r, bool shadow) {
    return shadow ? r.shadowMraysPerSecond : r.mraysPerSecond;
}

// The CPU rows of the run, rows with a peer's name being the peers.
struct View {
    std::string map;
    float elevation;
    bool operator<(const View& o) const {
        return std::tie(map, elevation) < std::tie(o.map, o.elevation);
    }
};

class PeerIndex {
  public:
    explicit PeerIndex(const std::vector<BenchRow>& rows) {
        for (const BenchRow& r : rows)
            if (r.backend == "cpu" && isPeer(r.technique))
                m_peers[{r.technique, View{r.map, r.elevation}}] = &r;
    }
    // Row speed over the peer's on the same view, primary or shadow: the paired ratio where the
    // run measured one (BenchConfig::pairedPeers), else the quotient of their best speeds; 0 when
    // either is missing.
    double ratio(const BenchRow& r, const std::string& peer, bool shadow) const {
        const auto paired = r.pairedRatios.find(peerQuery(peer, shadow));  // none for a peer
        if (paired != r.pairedRatios.end() && paired->second > 0) return paired->second;
        const auto it = m_peers.find({peer, View{r.map, r.elevation}});
        if (it == m_peers.end() || speed(*it->second, shadow) <= 0 || speed(r, shadow) <= 0)
            return 0;
        return speed(r, shadow) / speed(*it->second, shadow);
    }

  private:
    std::map<std::pair<std::string, View>, const BenchRow*> m_peers;
};

std::vector<const BenchRow*> cpuRows(const std::vector<BenchRow>& rows) {
    std::vector<const BenchRow*> out;
    for (const BenchRow& r : rows)
        if (r.backend == "cpu" && !r.curves) out.push_back(&r);
    return out;
}

ReportTable viewsTable(const std::vector<const BenchRow*>& rows, const PeerIndex& peers) {
    ReportTable t{
        "CPU peers: every view",
        "Mrays/s of each row and peer on the view's primary rays and on its shadow rays (for the "
        "reference's lit-facing primary hits, in 4×4 pixel tiles: segments from the light that "
        "end 0.5 texels before their points, a first-hit search for the rows, an occlusion query "
        "for Embree), and the ratios to Embree on the same rays in this run (with paired timing: "
        "the median over the repeats of the row and the peer timed back to back; Mrays/s are the "
        "best repeats, so a ratio need not equal the quotient of the Mrays/s). wrong %: pixels with "
        "another hit/miss or |Δt| > 0.5 than the reference; shadow wrong %: pixels whose shadow "
        "differs from the reference's."};
    t.header = {"map",
                "elevation",
                "row",
                "Mrays/s",
                "× rtcIntersect1",
                "× rtcIntersect16",
                "shadow Mrays/s",
                "× rtcOccluded1",
                "× rtcOccluded16",
                "wrong %",
                "shadow wrong %"};
    for (const BenchRow* r : rows) {
        const bool peer = isPeer(r->technique);
        t.rows.push_back(
            {r->map, fmt::format("{:.1f}°", r->elevation),
             peer ? peerQuery(r->technique, false) + " / " + peerQuery(r->technique, true)
                  : r->technique,
             fmt::format("{:.2f}", r->mraysPerSecond), ratioCell(peers.ratio(*r, kEmbree1, false)),
             ratioCell(peers.ratio(*r, kEmbree16, false)),
             r->shadowMraysPerSecond > 0 ? fmt::format("{:.2f}", r->shadowMraysPerSecond) : "-",
             ratioCell(peers.ratio(*r, kEmbree1, true)),
             ratioCell(peers.ratio(*r, kEmbree16, true)),
             fmt::format("{:.3f}", 100.0 * r->stats.wrongRate()),
             r->shadowWrongRate >= 0 ? fmt::format("{:.3f}", 100.0 * r->shadowWrongRate) : "-"});
    }
    return t;
}

// Per row: geometric means over each map's views and over every view of the run.
ReportTable meansTable(const std::vector<const BenchRow*>& rows, const PeerIndex& peers) {
    ReportTable t{"CPU peers: geometric means",
                  "Per row, the geometric mean over the views (elevations) of each map "
                  "of the per-view ratios above, then over every view it ran."};
    t.header = {"row",
                "map",
                "views",
                "× rtcIntersect1",
                "× rtcIntersect16",
                "× rtcOccluded1",
                "× rtcOccluded16"};
    std::vector<std::string> order, maps;
    for (const BenchRow* r : rows) {
        if (isPeer(r->technique)) continue;
        if (std::find(order.begin(), order.end(), r->technique) == order.end())
            order.push_back(r->technique);
        if (std::find(maps.begin(), maps.end(), r->map) == maps.end()) maps.push_back(r->map);
    }
    maps.push_back("");  // every map
    for (const std::string& row : order)
        for (const std::string& map : maps) {
            RatioMean means[4];
            for (const BenchRow* r : rows) {
                if (r->technique != row || (!map.empty() && r->map != map)) continue;
                int k = 0;
                for (bool shadow : {false, true})
                    for (const char* peer : {kEmbree1, kEmbree16})
                        means[k++].add(peers.ratio(*r, peer, shadow), 1.0);
            }
            if (means[0].count() == 0 && means[2].count() == 0) continue;
            t.rows.push_back({row, map.empty() ? "all" : map,
                              fmt::format("{}", std::max(means[0].count(), means[2].count())),
                              ratioCell(means[0].value()), ratioCell(means[1].value()),
                              ratioCell(means[2].value()), ratioCell(means[3].value())});
        }
    return t;
}

// Each map's bakes once (its first view): the row's maps and tracer, or Embree's BVH for a peer.
ReportTable bakesTable(const std::vector<const BenchRow*>& rows) {
    ReportTable t{"CPU peers: bakes",
                  "Wall seconds of each row's map build plus tracer creation on this map "
                  "(threads as above), Embree's scene build for the peers; bytes per texel of "
                  "the row's maps."};
    t.header = {"map", "samples", "row", "bake s", "bytes/texel"};
    std::map<std::pair<std::string, std::string>, bool> seen;
    for (const BenchRow* r : rows) {
        if (r->technique == kEmbree16 ||
            !seen.emplace(std::pair{r->map, r->technique}, true).second)
            continue;
        const bool peer = isPeer(r->technique);
        t.rows.push_back({r->map, fmt::format("{}", r->mapSamples),
                          peer ? std::string("Embree BVH") : r->technique,
                          fmt::format("{:.2f}", r->buildSeconds),
                          peer ? "-" : fmt::format("{:.1f}", r->bytesPerTexel)});
    }
    return t;
}

ReportTable targetsTable(const std::vector<const BenchRow*>& rows, const PeerIndex& peers,
                         const std::vector<PeerTarget>& targets) {
    ReportTable t{"CPU peers: targets",
                  "Issue 21's targets, judged from the per-view table below. A target \"at every "
                  "view\" is judged on its worst view "
                  "(named), the others on the geometric mean over the views in scope; views: how "
                  "many ran and how "
                  "many meet the ratio."};
    t.header = {"target", "scope", "measured", "views meeting", "verdict"};
    for (const PeerTarget& target : targets) {
        RatioMean mean;
        double worst = 0;
        std::string worstView;
        int views = 0, meeting = 0;
        for (const BenchRow* r : rows) {
            if (r->technique != target.row ||
                (target.maxSamples > 0 && r->mapSamples > target.maxSamples))
                continue;
            const double ratio = peers.ratio(*r, target.peer, target.shadow);
            if (ratio <= 0) continue;
            ++views;
            meeting += ratio >= target.ratio;
            mean.add(ratio, 1.0);
            if (worstView.empty() || ratio < worst) {
                worst = ratio;
                worstView = fmt::format("{} {:.1f}°", r->map, r->elevation);
            }
        }
        const std::string what = fmt::format("{} {} ≥ {:g}× {}", target.row,
                                             target.shadow ? "shadow rays" : "primary rays",
                                             target.ratio, peerQuery(target.peer, target.shadow));
        const std::string scope = target.maxSamples > 0
                                      ? fmt::format("maps ≤ {} samples", target.maxSamples)
                                      : "every map";
        if (views == 0) {
            t.rows.push_back({what, scope, "-", "0", "not run"});
            continue;
        }
        const double measured = target.everyView ? worst : mean.value();
        const std::string value =
            target.everyView
                ? fmt::format("{:.2f}× (worst: {}; mean {:.2f}×)", worst, worstView, mean.value())
                : fmt::format("{:.2f}× (worst {:.2f}×: {})", measured, worst, worstView);
        t.rows.push_back({what, scope + (target.everyView ? ", at every view" : ", geometric mean"),
                          value, fmt::format("{}/{}", meeting, views),
                          measured >= target.ratio ? "met" : "not met"});
    }
    return t;
}

}  // namespace

// The instruction set the CPU tracers ran with (core/isa.h: --isa, RELIEF_ISA or the CPU's best).
std::string_view benchIsa() { return tracerIsa(); }

// The Highway target the packet rows ran on (the lane width), or why they ran scalar.
static std::string packetTarget() {
    if (!packetsEnabled()) return "none (RELIEF_PACKETS=0: scalar)";
    if (activeIsa() == Isa::Baseline) return "none (baseline ISA: scalar)";
    return packetWalkTarget();
}

std::vector<ReportTable> cpuPeersTables(const std::vector<BenchRow>& rows,
                                        const BenchConfig& config, const BenchMeta& meta) {
    if (!meta.timings) return {};
    const std::vector<const BenchRow*> cpu = cpuRows(rows);
    const PeerIndex peers(rows);
    std::vector<ReportTable> tables = {targetsTable(cpu, peers, config.targets),
                                       meansTable(cpu, peers), viewsTable(cpu, peers),
                                       bakesTable(cpu)};
    tables.front().caption =
        fmt::format(
            "ISA: {}; packet target: {}; threads: {}; machine: {}; date: {}; load average "
            "before: {}, after: {}. ",
            benchIsa(), packetTarget(), meta.threads, meta.machine, meta.date, meta.loadBefore,
            meta.loadAfter) +
        tables.front().caption;
    return tables;
}

}  // namespace relief::bench
