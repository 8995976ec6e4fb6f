#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# tests/fuzz/build.sh [BUILD_DIR] -- build the libFuzzer scene harness
# (clang, AddressSanitizer + UndefinedBehaviorSanitizer) into BUILD_DIR
# (default build-fuzz), installing clang's fuzzer runtime if missing.
# Then: sh tests/fuzz/run.sh [SECONDS]   (docs/robustness.md)
set -eu
cd "$(dirname "$0")/../.."
build_dir=${1:-build-fuzz}

# Debian 12: clang 14 and its runtime libraries (libclang_rt.fuzzer).
if ! command -v clang > /dev/null 2>&1 || \
   ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a > /dev/null 2>&1; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        clang libclang-rt-14-dev >&2
fi

if [ ! -f "$build_dir/build.ninja" ]; then
    # b_lundef=false: clang links the sanitizer runtimes into executables
    # only, so the shared library has undefined __asan_* symbols.
    CC=clang CXX=clang++ meson setup "$build_dir" -Dfuzz=true \
        -Db_sanitize=address,undefined -Db_lundef=false -Dbuildtype=debugoptimized >&2
fi
meson compile -C "$build_dir" tests/fuzz/fuzz_scene tests/fuzz/fuzz_scene_replay >&2
echo "$build_dir/tests/fuzz/fuzz_scene"
