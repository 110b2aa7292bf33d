#!/usr/bin/env bash
# texr's one entry point for building, the demo and the tests.
#   ./build.sh demo   install what is missing, build (Release), render models/demo.scene to out/demo.png
#   ./build.sh test   install what is missing, build (Release), run every test
#   ./build.sh bench  install what is missing, build (Release), run texr bench
set -euo pipefail
cd "$(dirname "$0")"

packages=(cmake make g++ libglm-dev libstb-dev libtinyobjloader-dev doctest-dev)

install_missing() {
    local missing=()
    for p in "${packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    if [ "$(id -u)" -eq 0 ]; then
        echo "installing: ${missing[*]}"
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        apt-get install -y -qq "${missing[@]}" >/dev/null
    else
        echo "texr needs these Debian packages; install them with:" >&2
        echo "  sudo apt-get install -y ${missing[*]}" >&2
        exit 1
    fi
}

build() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build build -j "$(nproc)"
}

case "${1:-}" in
    demo)
        install_missing
        build
        mkdir -p out
        ./build/texr render models/demo.scene -o out/demo.png
        ;;
    test)
        install_missing
        build
        ctest --test-dir build --output-on-failure -j "$(nproc)"
        ;;
    bench)
        install_missing
        build
        shift
        ./build/texr bench "$@"
        ;;
    *)
        echo "usage: ./build.sh demo | test | bench" >&2
        exit 2
        ;;
esac
