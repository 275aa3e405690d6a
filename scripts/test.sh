#!/usr/bin/env bash
# The whole test suite from a fresh Debian 12 machine: install, build, ctest; then the same suite
# under ASan + UBSan and a short run of every fuzz target (scripts/test-sanitized.sh).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install-deps.sh"
"$root/scripts/build.sh" "$root/build" Release
cd "$root/build"
ctest --output-on-failure -j "$(nproc)" "$@"
"$root/scripts/test-sanitized.sh"
