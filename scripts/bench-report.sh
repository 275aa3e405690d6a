#!/usr/bin/env bash
# Regenerates docs/benchmarks.md from a full `relief bench` run (the default preset: every
# technique, fbm 512² and the Colorado DEM, four elevations, caps 8/24/200, Embree in the same
# run), plus the embree-user preset's table (docs/benchmarks-embree-user.md) and the cpu-peers
# preset's targets (scripts/bench-cpu-peers.sh). Raw outputs go to
# docs/bench/ and docs/bench-embree-user/ (no per-run images: they would bloat the repository).
# Usage: scripts/bench-report.sh [extra relief bench options, e.g. --threads 2]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" Release
cd "$root"
before=$(cut -d' ' -f1-3 /proc/loadavg)
build/relief bench --preset default --no-images --out-dir docs/bench --markdown docs/benchmarks.md "$@"
# Rows as an Embree user geometry against the triangles, 1024² and 4096² (issue 20).
build/relief bench --preset embree-user --repeats 3 --no-images --out-dir docs/bench-embree-user \
    --markdown docs/benchmarks-embree-user.md "$@"
{
    echo
    echo "Load average before the run: $before; after: $(cut -d' ' -f1-3 /proc/loadavg) (on $(nproc) hardware threads)."
    echo
    echo "## Embree user geometry"
    echo
    echo "\`relief bench --preset embree-user\` (the whole report: [benchmarks-embree-user.md](benchmarks-embree-user.md)):"
    sed -n 3p docs/benchmarks-embree-user.md
    sed -n '/^## Embree user geometry/,/^## /{/^## /d;p}' docs/benchmarks-embree-user.md
    echo "## Other measurements"
    echo
    echo "- [exact vs Embree in detail](benchmarks-exact-embree.md) (\`relief bench --preset exact-embree\`, quiet and shared machines)"
    echo "- [GL backend on an NVIDIA H100](benchmarks-gpu.md) (\`relief bench --preset gpu\`)"
    echo "- [map bake timings](benchmarks-bakes.md) (\`scripts/bake-table.sh\`: every builder × map × size, wall seconds and peak RSS)"
    echo "- Per-technique studies: [quadtree](quadtree.md), [cones](cones.md), [qdm](qdm.md), [safety shapes](safety.md), [curves](curves.md)"
} >> docs/benchmarks.md
# Issue 21's CPU rows against Embree, primary and shadow rays; its section goes before "Other measurements".
"$root/scripts/bench-cpu-peers.sh" "$@"
echo "bench-report: wrote docs/benchmarks.md and docs/bench/"
