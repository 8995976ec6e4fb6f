#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# tests/fuzz/run.sh [SECONDS] [BUILD_DIR] -- fuzz the scene parser for
# SECONDS (default 1800) at the lowest priority, one job.  The working corpus
# grows in BUILD_DIR/fuzz-corpus (seeded from share/scenes, tests/driver/scenes/bad
# and tests/fuzz/regressions); crashes land in BUILD_DIR/fuzz-artifacts.
# A crash: copy it to tests/fuzz/regressions/ (meson test --suite fuzz
# replays them), fix, commit both.
set -eu
cd "$(dirname "$0")/../.."
seconds=${1:-1800}
build_dir=${2:-build-fuzz}
fuzzer=$(sh tests/fuzz/build.sh "$build_dir")
corpus=$build_dir/fuzz-corpus
artifacts=$build_dir/fuzz-artifacts
mkdir -p "$corpus" "$artifacts"
cp share/scenes/*.nml share/scenes/paper/*.nml share/scenes/physics/*.nml tests/driver/scenes/bad/*.nml "$corpus"/
cp tests/fuzz/regressions/* "$corpus"/ 2> /dev/null || true
# Scenes are short text files: 64 kB inputs reach every limit of the parser
# but the 8 MB file size (repeat counts still make lists of the longest, 250000 values).
# The dictionary holds the namelist's keywords.
# One fork at a time that goes on after a crash, a timeout or an OOM (each
# written to fuzz-artifacts/), so a campaign lasts its full time.  Log:
# BUILD_DIR/fuzz.log.
top=$(pwd)
cd "$build_dir"
status=0
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
nice -n 19 "$top/$fuzzer" fuzz-corpus \
    -dict="$top/tests/fuzz/scene.dict" -max_len=65536 -timeout=25 -rss_limit_mb=2048 \
    -max_total_time="$seconds" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -artifact_prefix=fuzz-artifacts/ -print_final_stats=1 > fuzz.log 2>&1 || status=$?
tail -n 5 fuzz.log
echo "log: $build_dir/fuzz.log; crashes, timeouts, leaks: $artifacts/"
ls fuzz-artifacts
exit "$status"
