#!/usr/bin/env bash
# Installs relief's build and test dependencies from Debian 12 packages. Idempotent: packages that are
# already installed are skipped, so a second run does not touch apt at all.
set -euo pipefail
packages=(
    g++ cmake ninja-build pkg-config python3
    libembree-dev libtbb-dev libglm-dev libstb-dev libpng-dev libjpeg-dev libopenexr-dev
    libcli11-dev libfmt-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev libtinygltf-dev
    libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
    libglfw3-dev libimgui-dev xvfb xauth
    chromium
    pybind11-dev python3-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib
    glslang-tools spirv-cross libhwy-dev
)
missing=()
# npm (for the pinned ktx-parse that validates KTX2 exports) comes with Node.js: Debian's nodejs + npm
# packages on a fresh machine; a machine that already has a node with its npm keeps it (installing
# Debian's npm beside another vendor's nodejs would fight over the same files).
command -v npm >/dev/null 2>&1 || packages+=(nodejs npm)
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
    echo "install-deps: all ${#packages[@]} packages present"
    exit 0
fi
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
echo "install-deps: installing ${missing[*]}"
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
