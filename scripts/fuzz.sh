#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Builds the libFuzzer harnesses of fuzz/ with clang (AddressSanitizer with
# leak detection, UndefinedBehaviorSanitizer) into ./build-fuzz and runs each
# for SECONDS_PER_HARNESS seconds (default 60) on a copy of its seed corpus.
# Prints executions and coverage per harness; exits 1 if one crashed, hung,
# leaked or ran out of memory (the input is kept in build-fuzz/artifacts/).
#   scripts/fuzz.sh [SECONDS_PER_HARNESS] [HARNESS...]   (default: all)
# FUZZ_SKIP_BUILD=1 runs what is built (e.g. two instances in parallel).
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
shift || true
build=build-fuzz

# libFuzzer ships with clang's runtime (Debian: clang + libclang-rt-14-dev).
probe="$(mktemp -d)"
trap 'rm -rf "$probe"' EXIT
echo 'extern "C" int LLVMFuzzerTestOneInput(const unsigned char*, unsigned long) { return 0; }' \
    >"$probe/probe.cpp"
if ! clang++ -fsanitize=fuzzer,address "$probe/probe.cpp" -o "$probe/probe" 2>/dev/null; then
    if [ "$(id -u)" -eq 0 ] || command -v sudo >/dev/null; then
        echo "fuzz.sh: clang or its libFuzzer runtime is missing; installing clang libclang-rt-14-dev"
        SUDO=""
        [ "$(id -u)" -ne 0 ] && SUDO="sudo"
        $SUDO apt-get install -y -q --no-install-recommends clang libclang-rt-14-dev
    else
        echo "fuzz.sh: needs clang++ with libFuzzer: apt-get install clang libclang-rt-14-dev" >&2
        exit 2
    fi
fi

if [ "${FUZZ_SKIP_BUILD:-0}" != 1 ]; then
    launcher=()
    if command -v ccache >/dev/null; then
        launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
    fi
    # -O1 -g with assertions on (no NDEBUG), and libstdc++'s bounds checks.
    cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug \
        -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g -D_GLIBCXX_ASSERTIONS" "${launcher[@]}" \
        -DEMSLAM_FUZZ=ON -DEMSLAM_SANITIZE=address,undefined \
        -DEMSLAM_BUILD_TESTS=OFF -DEMSLAM_BUILD_APPS=OFF -DEMSLAM_BUILD_BENCHMARKS=OFF
    cmake --build "$build" -j2
fi

harnesses=("$@")
if [ ${#harnesses[@]} -eq 0 ]; then
    for src in fuzz/*.cpp; do
        harnesses+=("$(basename "$src" .cpp)")
    done
fi

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
mkdir -p "$build/artifacts" "$build/logs"
failed=0
summary=()
for h in "${harnesses[@]}"; do
    corpus="$build/corpus/$h"
    mkdir -p "$corpus"
    log="$build/logs/$h.log"
    echo "fuzz.sh: $h for $seconds s (log: $log)"
    status=0
    runs=""
    limits=(-rss_limit_mb=2048)
    if [ "$h" = rawlog_input ]; then
        # MRPT's deserializers size a string from its 32-bit length field before
        # reading it: a damaged length costs up to 4 GiB (and seconds of zero
        # fill), then the read fails cleanly (doc/reliability.md). Such inputs
        # are counted and kept in artifacts/, and fuzzing goes on (fork mode).
        # A damaged image or range-image size asks MRPT for more memory than
        # the machine has and ASan aborts there. Fork mode keeps fuzzing past
        # these; every one is kept in artifacts/ with its stack in the log:
        # a stack through emslam code is a finding, one that ends in an MRPT
        # deserializer's allocation is MRPT's (doc/reliability.md).
        limits=(-rss_limit_mb=2048 -malloc_limit_mb=1024 -fork=1 -ignore_ooms=1
            -ignore_timeouts=1 -ignore_crashes=1)
    fi
    "$build/fuzz/fuzz_$h" "$corpus" "fuzz/corpus/$h" -max_total_time="$seconds" -timeout=10 \
        "${limits[@]}" -detect_leaks=1 -print_final_stats=1 -close_fd_mask=1 \
        -artifact_prefix="$build/artifacts/$h-" >"$log" 2>&1 || status=$?
    mrpt_allocations=0
    if [ "$h" = rawlog_input ] && [ "$status" -ne 0 ]; then
        # Fork mode exits non-zero when it went past a crash. Each one must be
        # an allocation failure inside an MRPT deserializer; anything else is
        # a finding.
        status=0
        for a in "$build/artifacts/$h"-crash-*; do
            [ -e "$a" ] || continue
            report="$(ASAN_OPTIONS="$ASAN_OPTIONS:fast_unwind_on_malloc=0" \
                "$build/fuzz/fuzz_$h" "$a" 2>&1 || true)"
            if grep -qE 'requested allocation size|allocator is out of memory' <<<"$report" &&
                grep -qE 'in mrpt::[a-zA-Z:0-9_]*::serializeFrom' <<<"$report"; then
                mrpt_allocations=$((mrpt_allocations + 1))
            else
                status=1
                echo "fuzz.sh: $a is a finding:"
                grep -E '^==[0-9]+==ERROR|SUMMARY' <<<"$report" | head -n 3 || true
            fi
        done
        # The log's last line was "exiting: 1": take the run's own count.
        runs="$(grep -oE '^#[0-9]+:' "$log" | tail -n 1 | tr -d '#:')"
    fi
    runs="${runs:-$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)}"
    cov="$(grep -E '^#[0-9]+' "$log" | tail -n 1 | grep -oE 'cov: [0-9]+ ft: [0-9]+' || true)"
    if [ "$status" -ne 0 ]; then
        failed=1
        summary+=("$h: FAILED (exit $status), see $log")
        grep -E '^==[0-9]+==ERROR|SUMMARY|Test unit written' "$log" | head -n 5 || true
    else
        summary+=("$h: ${runs:-?} executions in $seconds s, ${cov:-no coverage line}$(
            [ "$mrpt_allocations" -eq 0 ] ||
                echo ", $mrpt_allocations allocation failures inside MRPT deserializers")")
    fi
done
printf '%s\n' "${summary[@]}"
exit "$failed"
