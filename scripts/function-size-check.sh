#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# clang-tidy's readability-function-size on the C++ sources of libs/ changed
# since BASE_REF (committed or not): lists every function of them over 80
# lines and fails if one is over 120.
#   scripts/function-size-check.sh [BASE_REF] [BUILD_DIR]   (defaults: main, build)
# Needs clang-tidy (Debian: clang-tidy) and BUILD_DIR/compile_commands.json
# (CMAKE_EXPORT_COMPILE_COMMANDS is on). clang-tidy counts the lines of the
# body, braces included (scripts/function-sizes.sh counts from the name's
# line). A changed header is checked through the changed sources that
# include it. About as long as compiling the changed sources.
set -euo pipefail
cd "$(dirname "$0")/.."

base="${1:-main}"
build="${2:-build}"
warn_lines=80
max_lines=120

if ! command -v clang-tidy >/dev/null; then
    echo "function-size-check: needs clang-tidy (apt-get install clang-tidy)" >&2
    exit 2
fi
if [ ! -f "$build/compile_commands.json" ]; then
    echo "function-size-check: no $build/compile_commands.json (configure the build first)" >&2
    exit 2
fi

mapfile -t changed < <(git diff --name-only --diff-filter=d "$base" -- 'libs/*.cpp' 'libs/*.h')
sources=()
headers=()
for f in "${changed[@]}"; do
    case "$f" in
    *.cpp) grep -qF "\"$PWD/$f\"" "$build/compile_commands.json" && sources+=("$f") ;;
    *.h) headers+=("$f") ;;
    esac
done
if [ ${#sources[@]} -eq 0 ]; then
    echo "function-size-check: no changed source of libs/ since $base"
    exit 0
fi
# Functions of the changed headers only, not of every header included.
header_filter='^$'
if [ ${#headers[@]} -gt 0 ]; then
    header_filter="^$PWD/($(printf '%s|' "${headers[@]}" | sed 's/[.]/[.]/g; s/|$//'))\$"
fi

config="{Checks: '-*,readability-function-size', CheckOptions: \
[{key: readability-function-size.LineThreshold, value: '$warn_lines'}]}"
# GCC's warning flags in the compile commands mean nothing to clang.
report=$(clang-tidy -p "$build" --quiet --config="$config" --header-filter="$header_filter" \
    --extra-arg=-Wno-unknown-warning-option "${sources[@]}" 2>/dev/null || true)

# "FILE:LINE:COL: warning: function 'NAME' exceeds ..." then
# "FILE:LINE:COL: note: N lines including whitespace and comments (threshold 80)"
sizes=$(awk -v root="$PWD/" '
    / warning: function .* exceeds recommended size/ {
        split($1, at, ":"); file = at[1]; sub("^" root, "", file)
        name = $0; sub(/^.*function \047/, "", name); sub(/\047 exceeds.*$/, "", name)
        where = file ":" at[2]
    }
    / note: [0-9]+ lines including whitespace/ && where != "" {
        n = $0; sub(/^.* note: /, "", n); sub(/ lines.*$/, "", n)
        if (!(where in seen)) { seen[where] = 1; print n, where, name }
        where = ""
    }' <<<"$report" | sort -k1,1nr -k2,2)

if [ -z "$sizes" ]; then
    echo "function-size-check: ${#sources[@]} changed source(s), no function over $warn_lines lines"
    exit 0
fi
echo "function-size-check: functions over $warn_lines lines in the changed sources:"
awk '{ printf "%5d  %s  %s\n", $1, $3, $2 }' <<<"$sizes"
over=$(awk -v m="$max_lines" '$1 > m' <<<"$sizes" | wc -l)
if [ "$over" -gt 0 ]; then
    echo "function-size-check: $over function(s) over $max_lines lines: split them along their steps" >&2
    exit 1
fi
