#!/usr/bin/env bash
# Bake timing table: every map builder × heightfield × size, wall seconds and peak RSS of one
# `relief bake` process each (so the RSS is the builder's, not a neighbour's), as Markdown rows.
# Usage: scripts/bake-table.sh [--threads N] [--sizes "256 1024"] [--ratios "0.05 0.1"]
#          [--builders "safety-sd safety-cc cone cone:variant=1 relaxed-cone qdm"]
#          [--maps "fbm peaks6 sea srtm colorado finland"] [--timeout SECONDS] [--relief PATH]
# A run past the timeout is written as "> T". `sea`: a window of data/earth-topology-2048x1024.png
# (flat sea, 63-73 % of the texels, and coasts); `srtm`: a window of
# ../shared/data/earth-srtm-5400x2700.png (the Mediterranean, with bathymetry: no flat sea; above
# 2700², of earth-srtm-10800x5400.png);
# Colorado and Finland are the DEMs in data/ at their own size (400²), whatever --sizes says.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
threads=2
sizes="256 1024"
ratios="0.05 0.1"
builders="safety-sd safety-cc cone cone:variant=1 relaxed-cone qdm"
maps="fbm peaks6 sea srtm colorado finland"
timeout_s=600
relief="$root/build/relief"
while [[ $# -gt 0 ]]; do
    case "$1" in
        --threads) threads=$2; shift 2 ;;
        --sizes) sizes=$2; shift 2 ;;
        --ratios) ratios=$2; shift 2 ;;
        --builders) builders=$2; shift 2 ;;
        --maps) maps=$2; shift 2 ;;
        --timeout) timeout_s=$2; shift 2 ;;
        --relief) relief=$2; shift 2 ;;
        *) echo "bake-table: unknown option '$1'" >&2; exit 1 ;;
    esac
done
[[ -x "$relief" ]] || { echo "bake-table: no relief binary at $relief" >&2; exit 2; }
srtm="$root/../shared/data/earth-srtm-5400x2700.png"
srtm_large="$root/../shared/data/earth-srtm-10800x5400.png"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The heightfield argument for a map name and size (empty: that map has no such size; the sea
# crop's source is 1024 rows high).
source_of() {
    local name=$1 n=$2
    case "$name" in
        fbm|peaks6) echo "gen:$name:${n}x$n" ;;
        # Flat sea (one value) and coasts: ~2/3 of the texels at sea level, centred on the Atlantic.
        sea) (( n <= 1024 )) && echo "$root/data/earth-topology-2048x1024.png@centre=768,512,$n,$n" ;;
        # Centred on the Tyrrhenian sea (12.5°E, 40°N at 15 px per degree): sea, coast, the Alps;
        # moved south as far as a window of n rows needs, and past 2700 rows from the 10800×5400
        # map (30 px per degree, the same place).
        srtm) if (( n <= 2700 )); then
                  [[ -f "$srtm" ]] && echo "$srtm@centre=2888,$(( n / 2 > 750 ? n / 2 : 750 )),$n,$n"
              elif (( n <= 5400 )); then
                  [[ -f "$srtm_large" ]] && echo "$srtm_large@centre=5776,$(( n / 2 > 1500 ? n / 2 : 1500 )),$n,$n"
              fi ;;
        colorado) [[ $n == "${sizes%% *}" ]] && echo "$root/data/colorado-elevation-400.png" ;;
        finland) [[ $n == "${sizes%% *}" ]] && echo "$root/data/finland-topography-400-16bit.png" ;;
        *) echo "bake-table: unknown map '$name'" >&2; exit 1 ;;
    esac
    return 0  # a map without this size prints nothing (a false test above is not a failure)
}

echo "Machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) hardware threads; $threads threads; $(date -u +%Y-%m-%d); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| builder | map | size | depth ratio | wall s | peak RSS MiB |"
echo "|---|---|---|---|---:|---:|"
for b in $builders; do
    technique=${b%%:*}
    params=()
    [[ $b == *:* ]] && params=(--param "${b#*:}")
    for m in $maps; do
        for n in $sizes; do
            src=$(source_of "$m" "$n") || exit 1
            [[ -n "$src" ]] || continue
            for r in $ratios; do
                status=0
                /usr/bin/time -f "%e %M" -o "$tmp/time" timeout "$timeout_s" "$relief" bake "$src" \
                    --maps "$technique" "${params[@]}" --threads "$threads" --depth-ratio "$r" \
                    -o "$tmp/out.exr" >/dev/null 2>"$tmp/err" || status=$?
                read -r wall rss < <(tail -1 "$tmp/time")
                label="$n²"
                [[ $m == colorado || $m == finland ]] && label="400²"
                if [[ $status == 124 ]]; then
                    wall="> $timeout_s"
                elif [[ $status != 0 ]]; then
                    echo "bake-table: $b on $src failed: $(tail -1 "$tmp/err")" >&2
                    wall="failed"
                fi
                echo "| $b | $m | $label | $r | $wall | $((rss / 1024)) |"
            done
        done
    done
done
