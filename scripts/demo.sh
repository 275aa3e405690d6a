#!/usr/bin/env bash
# The main job from a fresh Debian 12 machine: install, build (Release), render the demo set with
# every registered technique, a bricks material preview, mesh previews (cube and sphere, two
# techniques, through the shader library on EGL), the engine exports (16-bit PNG, KTX2 and
# the shader files) and the Python example, and write images plus comparison tables to demo-out/.
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
echo "== bricks (built-in), 512x512: material preview (sRGB, mipmaps, specular) with its colour map"
"$relief" render gen:bricks:512x512:1 --color gen --depth-ratio 0.03 -t exact,relaxed-cone,cone --elevation 35 \
    --azimuth 30 --distance 0.9 --size 960x720 --shadows --out-dir "$out/bricks"

echo "== Mesh previews (relief render --mesh): bricks on a cube and a sphere, cone and relaxed-cone"
mkdir -p "$out/mesh"
for mesh in cube sphere; do
    for technique in cone relaxed-cone; do
        "$relief" render gen:bricks:512x512:1 --color gen --depth-ratio 0.03 --edge repeat \
            -t "$technique" --mesh "$mesh" --tiles 2 --shadows --light-elevation 40 \
            --light-azimuth 150 --elevation 30 --azimuth 35 --size 640x480 \
            -o "$out/mesh/$mesh-$technique.png"
    done
done
"$relief" render gen:bricks:256x256:1 --color gen --depth-ratio 0.05 -t cone --mesh plane \
    --shadows --crossing-plane 0.6 --elevation 30 --azimuth 35 --distance 0.6 --size 640x480 \
    -o "$out/mesh/plane-crossing-cone.png"

echo "== Engine exports (docs/engine.md): the Colorado cone map as a 16-bit PNG and a KTX2"
mkdir -p "$out/engine"
for format in png ktx2; do
    "$relief" bake "$root/data/colorado-elevation-400.png" -t cone --param bits=16 \
        -o "$out/engine/colorado-cone.$format"
done
cp "$root"/shaders/relief/{common,safe_step_march,cone}.glsl "$out/engine/"

echo "== Python (docs/python.md): error vs steps of three techniques on the same rays"
PYTHONPATH="$root/build/python" MPLBACKEND=Agg MPLCONFIGDIR="$out/.matplotlib" /usr/bin/python3 \
    "$root/examples/compare.py" "$out/python-compare.png"

{
    echo "# relief demo"
    echo
    echo "Built $(date -u +%Y-%m-%dT%H:%MZ) on $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | xargs), $(nproc) threads."
    echo "Error is |t - t_exact| in texels along the primary ray; 'wrong px' = hit/miss differs or |dt| > 0.5."
    for set in peaks6 colorado bricks; do
        echo
        tail -n +2 "$out/$set/summary.md"
        echo
        echo "Images: $set/NAME.png, $set/NAME-steps.png, $set/NAME-error.png"
    done
    echo
    echo "Engine kit: engine/colorado-cone.png (16-bit, grey = apex, alpha = cone ratio),"
    echo "engine/colorado-cone.ktx2 (R16G16_UNORM) and the shader files to paste (docs/engine.md)."
    echo "Python: python-compare.png (examples/compare.py)."
    echo "Mesh previews: mesh/{cube,sphere}-{cone,relaxed-cone}.png, mesh/plane-crossing-cone.png"
    echo "(a flat square at 0.6 of the relief's height crossing it: pixel depth offset)."
} > "$out/README.md"
echo
cat "$out/README.md"
echo
echo "demo written to $out"
