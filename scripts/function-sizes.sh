#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-3-Clause
# Function lengths in the libraries: how many functions reach 80 and 120
# lines (from the line of the name to the closing brace, comments inside
# included), and the longest ones.
#   scripts/function-sizes.sh [--list N] [PATH ...]     (default: libs; N: 20)
# Needs Universal Ctags (Debian: universal-ctags) for the end line of each
# function. Lambdas are counted inside the function that holds them.
set -euo pipefail
cd "$(dirname "$0")/.."

list=20
paths=()
while [ $# -gt 0 ]; do
    case "$1" in
    --list)
        list="${2:?--list needs a number}"
        shift 2
        ;;
    -h | --help)
        sed -n '3,8p' "$0" | sed 's/^# \{0,1\}//'
        exit 0
        ;;
    *)
        paths+=("$1")
        shift
        ;;
    esac
done
[ ${#paths[@]} -gt 0 ] || paths=(libs)

if ! ctags --version 2>/dev/null | grep -q "Universal Ctags"; then
    echo "function-sizes: needs Universal Ctags (apt-get install universal-ctags)" >&2
    exit 2
fi

# start end file scope name, one line per function definition
sizes=$(ctags -x --_xformat='%n %{end} %F %{scope} %N' --c++-kinds=f --fields=+neZ \
    --languages=C++ -R "${paths[@]}" |
    awk '$5 !~ /^__anon/ && $2 >= $1 { print $2 - $1 + 1, $3 ":" $1, ($4 == "-" ? "" : $4 "::") $5 }' |
    sort -k1,1nr -k2,2)

awk '{ n++; if ($1 >= 80) a++; if ($1 >= 120) b++ }
     END { printf "functions: %d; >= 80 lines: %d; >= 120 lines: %d\n", n, a, b }' <<<"$sizes"
if [ "$list" -gt 0 ]; then
    echo "longest:"
    head -n "$list" <<<"$sizes" | awk '{ printf "%5d  %s  %s\n", $1, $3, $2 }'
fi
