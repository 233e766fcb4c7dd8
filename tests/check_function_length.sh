#!/usr/bin/env bash
# No function of the core is longer than 60 lines (docs/architecture.md, "The floors"): a longer one is cut into steps with names. Functions are found by Universal Ctags
# (their first and last lines); a function's length counts both.
# Prints each function over the limit as "FILE:LINE: NAME is N lines" and exits 1 if there is
# one; else prints how many functions it measured and exits 0.
# Usage: tests/check_function_length.sh [REPOSITORY_ROOT]   (default: this script's parent folder)
#        tests/check_function_length.sh --negative-control [REPOSITORY_ROOT]
# The second form checks the check: on a copy of the core with a 61-line function added to
# render/film.cpp, it must report it and fail.
set -euo pipefail
limit=60

if [ "${1:-}" = "--negative-control" ]; then
    source_root="$(cd "${2:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
    copy="$(mktemp -d)"
    trap 'rm -rf "$copy"' EXIT
    cp -r "$source_root/common" "$copy/"
    {
        echo 'namespace lessons {'
        echo 'int planted_long_function() {'
        echo '    int n = 0;'
        for _ in $(seq 57); do echo '    ++n;'; done
        echo '    return n;'
        echo '}'
        echo '}  // namespace lessons'
    } >>"$copy/common/render/film.cpp"
    status=0
    out="$(bash "${BASH_SOURCE[0]}" "$copy")" || status=$?
    [ "$status" -ne 2 ] || { echo "$out"; exit 2; }  # the check could not run (no ctags)
    if [ "$status" -eq 0 ]; then
        echo "negative control: the check passed a 61-line function:"
        echo "$out"
        exit 1
    fi
    echo "$out"
    grep -q '^common/render/film.cpp:[0-9]*: planted_long_function is 61 lines' <<<"$out" ||
        { echo "negative control: the planted function was not reported"; exit 1; }
    echo "negative control: the 61-line function reported"
    exit 0
fi
ROOT="$(cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
cd "$ROOT"
ctags="$(command -v ctags-universal || command -v ctags || true)"
if [ -z "$ctags" ] || ! "$ctags" --version 2>/dev/null | grep -q Universal; then
    echo "check_function_length: needs Universal Ctags (Debian: universal-ctags)" >&2
    exit 2
fi

"$ctags" -R --fields=+ne --c++-kinds=f --languages=C++ -o - common |
    awk -F'\t' -v limit="$limit" '
        { line = ""; end = ""
          for (i = 4; i <= NF; i++) {
              if ($i ~ /^line:/) line = substr($i, 6)
              if ($i ~ /^end:/) end = substr($i, 5)
          }
          if (end == "") { printf "%s:%s: %s: ctags found no end\n", $2, line, $1; open_ended++; next }
          measured++
          n = end - line + 1
          if (n > limit) { printf "%s:%s: %s is %d lines\n", $2, line, $1, n; over++ } }
        END { if (measured == 0) { print "check_function_length: no functions found" > "/dev/stderr"; exit 2 }
              if (over || open_ended) exit 1
              printf "check_function_length: %d functions of the core, none over %d lines\n", measured, limit }'
