#!/usr/bin/env bash
# The main job from a fresh Debian 12 machine: install, build (Release), render the demo set with
# every registered technique and write images plus comparison tables to demo-out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/demo-out}
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" Release
relief="$root/build/relief"
mkdir -p "$out"
common=(-t all --size 960x720 --shadows --light-elevation 35 --light-azimuth 150)

echo "== peaks6 (built-in), 512x512"
"$relief" render gen:peaks6:512x512:1 --depth-ratio 0.15 --elevation 27.8 --azimuth 35 \
    --distance 0.9 "${common[@]}" --out-dir "$out/peaks6"
echo "== Colorado DEM (real data), 400x400, with its colour image"
"$relief" render "$root/data/colorado-elevation-400.png" --color "$root/data/colorado-image-400.png" \
    --elevation 40.2 --azimuth 200 --distance 0.85 "${common[@]}" --out-dir "$out/colorado"

{
    echo "# relief demo"
    echo
    echo "Built $(date -u +%Y-%m-%dT%H:%MZ) on $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | xargs), $(nproc) threads."
    echo "Error is |t - t_exact| in texels along the primary ray; 'wrong px' = hit/miss differs or |dt| > 0.5."
    for set in peaks6 colorado; do
        echo
        tail -n +2 "$out/$set/summary.md"
        echo
        echo "Images: $set/NAME.png, $set/NAME-steps.png, $set/NAME-error.png"
    done
} > "$out/README.md"
echo
cat "$out/README.md"
echo
echo "demo written to $out"
