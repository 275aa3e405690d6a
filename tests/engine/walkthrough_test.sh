#!/bin/sh
# docs/engine.md's walk-through as a user runs it: its `relief bake` lines (taken from the page, so
# the page cannot drift) on a PNG named wall.png, then the hits of the exported 16-bit PNG and of
# the KTX2 must equal, bit for bit, the hits of the same bake kept in memory (no file), and the
# page's render line must run. Usage: walkthrough_test.sh SOURCE_DIR RELIEF WORK_DIR
set -eu
source_dir=$1 relief=$2 work=$3
rm -rf "$work" && mkdir -p "$work/bin" && cd "$work"
ln -s "$relief" bin/relief
PATH="$work/bin:$PATH"
cp "$source_dir/data/colorado-elevation-400.png" wall.png
# The page's commands: the lines of its sh blocks that start with "relief bake".
sed -n '/^```sh$/,/^```$/p' "$source_dir/docs/engine.md" | grep '^relief bake' > commands.sh
test "$(wc -l < commands.sh)" -ge 2 || { echo "walkthrough: no bake lines in docs/engine.md"; exit 1; }
sh -eux commands.sh
test -s wall-cone.png && test -s wall-cone.ktx2
relief rays wall.png --elevation 35 --azimuth 20 --size 96x96 -o rays.npy
relief trace wall.png -t cone --param bits=16 --rays rays.npy -o in-memory.csv
for map in wall-cone.png wall-cone.ktx2; do
    relief trace wall.png -t cone --param bits=16 --maps "$map" --rays rays.npy -o "$map.csv"
    cmp in-memory.csv "$map.csv" || { echo "walkthrough: $map traces differently"; exit 1; }
done
hits=$(grep -c '^1,' in-memory.csv || true)
test "$hits" -gt 1000 || { echo "walkthrough: only $hits hits"; exit 1; }
# Step 4 of the page: the CPU reference draws the same relief from the exported map.
sed -n 's/.*`\(relief render wall.png[^`]*\)`.*/\1/p' "$source_dir/docs/engine.md" | head -1 > render.sh
test -s render.sh
render=$(cat render.sh)
sh -eux -c "$render -o render.png"
test -s render.png
echo "walkthrough: $hits of 9216 rays hit; PNG and KTX2 exports trace as the bake in memory"
