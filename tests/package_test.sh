#!/bin/sh
# The installed package from a consumer's side (ctest package_*). Usage:
#   package_test.sh SOURCE_DIR BUILD_DIR WORK_DIR CXX install|cmake|pkgconfig
# install:   `cmake --install` of BUILD_DIR into WORK_DIR/staged, moved to WORK_DIR/prefix (so the
#            package must be relocatable); no installed package file names the source or build
#            tree, every <relief/...> include of an installed header is installed, internals are not.
# cmake:     examples/consumer configured with find_package against the prefix, built and run
#            (with its relief::embree + relief::gl program).
# pkgconfig: the same main.cpp compiled with `pkg-config --cflags --libs relief`, run; and every
#            installed header compiles on its own with those flags.
# Everything is written under WORK_DIR.
set -eu
src=$1 build=$2 work=$3 cxx=$4 mode=$5
prefix=$work/prefix
fail() { echo "package_test: $*" >&2; exit 1; }

case $mode in
install)
    rm -rf "$work"
    mkdir -p "$work"
    cmake --install "$build" --prefix "$work/staged" >"$work/install.log"
    mv "$work/staged" "$prefix"
    for f in bin/relief include/relief/techniques/registry.h include/relief/core/heightfield.h \
             share/doc/relief/README.md share/doc/relief/architecture.md; do
        [ -e "$prefix/$f" ] || fail "not installed: $f"
    done
    for f in librelief.a librelief_embree.a librelief_gl.a relief-config.cmake \
             relief-config-version.cmake relief-targets.cmake relief.pc; do
        [ -n "$(find "$prefix" -name "$f")" ] || fail "not installed: $f"
    done
    # Relocatable: the package files name paths relative to themselves only.
    if grep -rlF -e "$src" -e "$build" "$prefix/lib/cmake/relief" "$(dirname "$(find "$prefix" \
            -name relief.pc)")"; then
        fail "the files above name the source or build tree"
    fi
    # Internals stay internal: no CLI, bench or viewer header is public.
    for d in cli bench viewer; do
        [ ! -e "$prefix/include/relief/$d" ] || fail "internal headers installed: include/relief/$d"
    done
    # The header set is closed under its <relief/...> includes.
    find "$prefix/include" -name '*.h' | while read -r h; do
        sed -n 's/^[ \t]*#[ \t]*include[ \t]*[<"]\(relief\/[^>"]*\)[>"].*/\1/p' "$h" |
            while read -r inc; do
                [ -f "$prefix/include/$inc" ] || fail "${h#"$prefix"/} includes $inc, not installed"
            done
    done
    "$prefix/bin/relief" --version
    ;;
cmake)
    rm -rf "$work/cmake" "$work/cmake-run"
    mkdir -p "$work/cmake-run"
    cmake -S "$src/examples/consumer" -B "$work/cmake" -G Ninja -DCMAKE_BUILD_TYPE=Release \
          -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_PREFIX_PATH="$prefix" \
          -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DRELIEF_CONSUMER_COMPONENTS=ON \
          >"$work/cmake-configure.log" ||
        { cat "$work/cmake-configure.log"; fail "examples/consumer does not configure"; }
    cmake --build "$work/cmake"
    "$work/cmake/relief_consumer" "$work/cmake-run"
    "$work/cmake/relief_consumer_components"
    ;;
pkgconfig)
    rm -rf "$work/pkgconfig"
    mkdir -p "$work/pkgconfig"
    PKG_CONFIG_PATH=$(dirname "$(find "$prefix" -name relief.pc)")
    export PKG_CONFIG_PATH
    flags=$(pkg-config --cflags --libs relief)
    echo "pkg-config --cflags --libs relief: $flags"
    # shellcheck disable=SC2086  # the flags are words
    "$cxx" -std=c++20 -O1 -o "$work/pkgconfig/relief_consumer" "$src/examples/consumer/main.cpp" \
           $flags
    "$work/pkgconfig/relief_consumer" "$work/pkgconfig"
    cflags=$(pkg-config --cflags relief)
    find "$prefix/include" -name '*.h' | sort | while read -r h; do
        echo "#include <${h#"$prefix"/include/}>" >"$work/pkgconfig/header.cpp"
        # shellcheck disable=SC2086
        "$cxx" -std=c++20 -fsyntax-only $cflags "$work/pkgconfig/header.cpp" ||
            fail "${h#"$prefix"/} does not compile on its own"
    done
    ;;
*)
    fail "unknown mode '$mode' (install, cmake or pkgconfig)"
    ;;
esac
