#!/usr/bin/env bash
# Issue 21's CPU page: `relief bench --preset cpu-peers` (the CPU rows against Embree's
# rtcIntersect1/16 and rtcOccluded1/16 on the same rays) into docs/benchmarks-cpu-peers.md, raw
# rows in docs/bench-cpu-peers/, then its run line and targets table copied into
# docs/benchmarks.md's "CPU peers" section (replaced, before "## Other measurements").
# Usage: scripts/bench-cpu-peers.sh [--section-only] [extra relief bench options, e.g. --threads 2]
#   --section-only: skip the run, only refresh the section from the existing page.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
if [[ "${1:-}" == --section-only ]]; then
    shift
else
    build/relief bench --preset cpu-peers --no-images --out-dir docs/bench-cpu-peers \
        --markdown docs/benchmarks-cpu-peers.md "$@"
fi
section=$(
    echo "## CPU peers"
    echo
    echo "\`relief bench --preset cpu-peers\` (the whole report, every view, means and bakes: [benchmarks-cpu-peers.md](benchmarks-cpu-peers.md)):"
    sed -n 3p docs/benchmarks-cpu-peers.md
    if [[ -f docs/benchmarks-cpu-peers-avx512.md ]]; then
        echo
        echo "The last run on a machine with AVX-512 (packet target AVX3, 16 lanes), kept beside it: [benchmarks-cpu-peers-avx512.md](benchmarks-cpu-peers-avx512.md)."
    fi
    sed -n '/^## CPU peers: targets/,/^## /{/^## /d;p}' docs/benchmarks-cpu-peers.md
)
tmp=$(mktemp)
SECTION="$section" awk '
    /^## CPU peers$/ { skip = 1; next }
    skip && /^## / { skip = 0 }
    /^## Other measurements/ && !done { print ENVIRON["SECTION"]; print ""; done = 1 }
    !skip { print }
' docs/benchmarks.md > "$tmp"
mv "$tmp" docs/benchmarks.md
echo "bench-cpu-peers: wrote docs/benchmarks-cpu-peers.md, docs/bench-cpu-peers/ and docs/benchmarks.md's CPU peers section"
