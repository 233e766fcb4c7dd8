#!/usr/bin/env bash
# Every test that the documentation names exists (docs/accuracy.md: "each with the test that
# checks it"). A test is named in docs/*.md as `Suite.Name` in backticks, both parts starting
# with an upper-case letter (so that `scene.toml` or `bvh.cpp` are not taken for tests); it must
# be declared in tests/*.cpp as TEST(Suite, Name), TEST_F(...), TEST_P(...), TYPED_TEST(...) or
# TYPED_TEST_P(...), whitespace and line breaks between the arguments allowed, or be the name of
# a ctest test added by add_test in tests/CMakeLists.txt. `Suite.*` asks for a suite with at
# least one test, `*.Name` for a test of that name in some suite.
# Prints each missing reference as "docs/FILE.md: Suite.Name: no such test" and exits 1 if there
# is one; else prints how many references (distinct per file) it checked and exits 0.
# Usage: tests/check_doc_tests.sh [REPOSITORY_ROOT]   (default: this script's parent folder)
set -euo pipefail
ROOT="$(cd "${1:-$(dirname "${BASH_SOURCE[0]}")/..}" && pwd)"
cd "$ROOT"

shopt -s nullglob
docs=(docs/*.md)
sources=(tests/*.cpp)
[ ${#docs[@]} -gt 0 ] || { echo "check_doc_tests: no docs/*.md under $ROOT" >&2; exit 2; }
[ ${#sources[@]} -gt 0 ] || { echo "check_doc_tests: no tests/*.cpp under $ROOT" >&2; exit 2; }

# The declared tests, one "Suite.Name" a line. grep -z reads each file as one line, so that a
# macro's arguments may be split across lines; \b keeps MY_TEST( from counting.
macro='\b(TEST|TEST_F|TEST_P|TYPED_TEST|TYPED_TEST_P)'
arguments='\s*\(\s*[A-Za-z_]\w*\s*,\s*[A-Za-z_]\w*\s*\)'
declared="$(grep -hPzo "$macro$arguments" \
                "${sources[@]}" |
            tr -d ' \t\r\n' | tr '\0' '\n' |
            sed -E 's/^[A-Z_]+\(([A-Za-z0-9_]+),([A-Za-z0-9_]+)\)$/\1.\2/' |
            sort -u)"
# ctest names given to add_test(NAME ...).
ctest_names=""
if [ -f tests/CMakeLists.txt ]; then
    ctest_names="$(grep -Po 'add_test\s*\(\s*NAME\s+\K[^\s)]+' tests/CMakeLists.txt |
                   sort -u || true)"
fi

exists() {
    local ref="$1" suite="${1%%.*}" name="${1#*.}"
    if [ "$name" = "*" ]; then
        grep -q "^${suite}\." <<< "$declared"
    elif [ "$suite" = "*" ]; then
        grep -q "\.${name}\$" <<< "$declared"
    else
        grep -qxF "$ref" <<< "$declared" || grep -qxF "$ref" <<< "$ctest_names"
    fi
}

checked=0 missing=0
for doc in "${docs[@]}"; do
    # Whole backticked spans only (not a Suite.Name inside a longer span such as a command).
    refs="$(grep -oP '`\K(?:[A-Z][A-Za-z0-9_]*|\*)\.(?:[A-Z][A-Za-z0-9_]*|\*)(?=`)' "$doc" |
            grep -vxF '*.*' | sort -u || true)"
    [ -n "$refs" ] || continue
    while IFS= read -r ref; do
        checked=$((checked + 1))
        if ! exists "$ref"; then
            echo "$doc: $ref: no such test"
            missing=$((missing + 1))
        fi
    done <<< "$refs"
done

if [ "$missing" -gt 0 ]; then
    echo "$missing of $checked test references in docs/ name no test" >&2
    exit 1
fi
echo "$checked test references in docs/ checked, all exist"
