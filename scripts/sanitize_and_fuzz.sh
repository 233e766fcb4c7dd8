#!/usr/bin/env bash
# Reliability checks beyond the test suite: build everything with clang under AddressSanitizer
# and UndefinedBehaviorSanitizer, run each libFuzzer target for FUZZ_SECONDS (default 60) from
# its checked-in seed corpus, then the quick tests there (any report fails them).
# A crash leaves its input as crash-* in build-sanitize/: add it to the target's corpus.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
install_missing_packages clang libclang-rt-14-dev
SAN="$ROOT/build-sanitize"
cmake -S "$ROOT" -B "$SAN" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DLESSONS_SANITIZE=ON -DLESSONS_FUZZ=ON > /dev/null
cmake --build "$SAN" --parallel "$(nproc)"
cd "$SAN"
# Leaks inside Debian's libraries, if any, are theirs: tests/lsan.supp.
export LSAN_OPTIONS="suppressions=$ROOT/tests/lsan.supp"
for target in scene obj part gltf exr hdr; do
    corpus="$(mktemp -d)"
    log="$(mktemp)"
    echo "fuzz_$target: ${FUZZ_SECONDS:-60} s from tests/fuzz/corpus_$target"
    status=0
    "./bin/fuzz_$target" -max_total_time="${FUZZ_SECONDS:-60}" -timeout=10 -rss_limit_mb=4096 \
        -print_final_stats=1 "$corpus" "$ROOT/tests/fuzz/corpus_$target" \
        > "$log" 2>&1 || status=$?
    grep -E "^stat::number_of_executed_units|^Done|ERROR|SUMMARY|crash" "$log" || true
    if [ "$status" -ne 0 ]; then
        tail -40 "$log"
        echo "fuzz_$target found a failure (exit status $status)"
        exit 1
    fi
    rm -rf "$corpus" "$log"
done
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --output-on-failure --parallel "$(nproc)" --label-exclude slow
