#!/usr/bin/env bash
# texr's one entry point for building, the demo and the tests.
#   ./build.sh demo   install what is missing, build (Release), render models/demo.scene to out/demo.png
#   ./build.sh test   install what is missing, build (Release) and run every test; then the
#                     same tests built with AddressSanitizer + UBSan, the multi-threaded
#                     tests built with ThreadSanitizer, then a short libFuzzer run of the
#                     scene parser and the OBJ path (TEXR_FUZZ_SECONDS, default 20)
#   ./build.sh bench  install what is missing, build (Release), run texr bench
#   ./build.sh fuzz-images [SECONDS]  fuzz image loading and mip building (default 600 s);
#                     not part of `test`: see README, "Quick start"
set -euo pipefail
cd "$(dirname "$0")"

packages=(cmake make g++ libglm-dev libstb-dev libtinyobjloader-dev zlib1g-dev doctest-dev)
test_packages=(clang libclang-rt-14-dev)  # the fuzz targets (libFuzzer), for ./build.sh test only

# install_missing PACKAGE...: apt-get those not installed (as root), else say how.
install_missing() {
    local missing=()
    for p in "$@"; do
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

# build [TARGET]: every target, or the one named.
build() {
    cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build build -j "$(nproc)" ${1:+--target "$1"}
}

sanitized_tests() {
    echo "== the tests again, under AddressSanitizer and UBSan"
    cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXR_SANITIZE=ON >/dev/null
    cmake --build build-asan -j "$(nproc)"
    ctest --test-dir build-asan --output-on-failure -j "$(nproc)"
}

# The multi-threaded tests under ThreadSanitizer: workers share counters, batches, the
# frame and the textures' lazily made mip levels and decoded copies, and a data race would
# make frames depend on timing.
threaded_tests() {
    echo "== the multi-threaded tests again, under ThreadSanitizer"
    cmake -S . -B build-tsan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXR_TSAN=ON >/dev/null
    cmake --build build-tsan -j "$(nproc)" --target texr_tests
    # (run in build-tsan, where ctest runs the others: the tests make their scratch folders in
    # the working folder)
    (cd build-tsan && TSAN_OPTIONS="halt_on_error=1" ./texr_tests -tc='frames are byte-identical*,texr explain records*,*threads*,*decoded copies*')
}

fuzz() {
    local seconds="${TEXR_FUZZ_SECONDS:-20}"
    echo "== fuzzing the scene parser and the OBJ path, ${seconds} s each"
    CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXR_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
    cmake --build build-fuzz -j "$(nproc)" --target texr_fuzz_scene texr_fuzz_obj
    for target in scene obj; do
        # New inputs go to a scratch folder; the committed corpus is only read.
        local scratch
        scratch="$(mktemp -d)"
        (cd build-fuzz && ./texr_fuzz_$target -max_total_time="$seconds" -max_len=4096 -rss_limit_mb=4096 \
            -print_final_stats=0 "$scratch" "../tests/fuzz/corpus/$target" 2>&1 | tail -n 2)
        rm -rf "$scratch"
    done
    echo "fuzzing: no crash"
}

# fuzz_images SECONDS: image files through stb_image, texr's checks before it, and the mip
# levels; finds are written to build-fuzz/ as crash-* files.
fuzz_images() {
    echo "== fuzzing image loading, $1 s"
    CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTEXR_FUZZ=ON -DBUILD_TESTING=OFF >/dev/null
    cmake --build build-fuzz -j "$(nproc)" --target texr_fuzz_image
    # New inputs are kept in build-fuzz/image-corpus (the next run starts from them); the fuzz
    # target's scratch file goes to a folder removed however the run ends.
    scratch="$(mktemp -d)"  # (not local: the trap reads it when the script exits)
    trap 'rm -rf "$scratch"' EXIT
    mkdir -p build-fuzz/image-corpus
    (cd build-fuzz && TEXR_FUZZ_SCRATCH="$scratch" ./texr_fuzz_image -max_total_time="$1" -max_len=65536 -rss_limit_mb=4096 \
        -timeout=20 -print_final_stats=1 image-corpus ../tests/fuzz/corpus/image)
}

case "${1:-}" in
    demo)
        install_missing "${packages[@]}"
        build texr
        mkdir -p out
        ./build/texr render models/demo.scene -o out/demo.png
        ;;
    test)
        install_missing "${packages[@]}" "${test_packages[@]}"
        build
        ctest --test-dir build --output-on-failure -j "$(nproc)"
        sanitized_tests
        threaded_tests
        fuzz
        ;;
    fuzz-images)
        install_missing "${packages[@]}" "${test_packages[@]}"
        fuzz_images "${2:-600}"
        ;;
    bench)
        install_missing "${packages[@]}"
        build texr
        shift
        ./build/texr bench "$@"
        ;;
    *)
        echo "usage: ./build.sh demo | test | bench [ARGS] | fuzz-images [SECONDS]" >&2
        exit 2
        ;;
esac
