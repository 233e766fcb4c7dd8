#!/usr/bin/env bash
# The lessons page, as a person sees it: run the quick lessons into a scratch folder, open
# index.html from disk in headless Chromium, check that every image it references loaded, and
# save a screenshot. Usage: tests/page_test.sh BUILD_DIR
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$(cd "${1:-$ROOT/build}" && pwd)"
OUT="$BUILD/page_test"
rm -rf "$OUT"
LESSONS_SKIP_SETUP=1 BUILD_DIR="$BUILD" LESSONS_OUT="$OUT" bash "$ROOT/scripts/lessons.sh" --quick > "$OUT.log" 2>&1 ||
    { cat "$OUT.log"; echo "page_test: the quick lessons run failed"; exit 1; }

CHROMIUM="$(command -v chromium || command -v chromium-browser || true)"
[ -n "$CHROMIUM" ] || { echo "page_test: chromium is not installed (scripts/test.sh installs it)"; exit 1; }
PROFILE="$(mktemp -d)"
trap 'rm -rf "$PROFILE"' EXIT
FLAGS=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run
       --disable-background-networking --disable-component-update --disable-sync
       --user-data-dir="$PROFILE" --allow-file-access-from-files --virtual-time-budget=10000)
URL="file://$OUT/index.html"

DOM="$(timeout 120 "$CHROMIUM" "${FLAGS[@]}" --dump-dom "$URL" 2> "$OUT/chromium.log" || true)"
echo "page_test: chromium returned ${#DOM} bytes of DOM"
loaded="$(sed -n 's/.*data-images-loaded="\([0-9]*\)".*/\1/p' <<< "$DOM" | head -1)"
failed="$(sed -n 's/.*data-images-failed="\([0-9]*\)".*/\1/p' <<< "$DOM" | head -1)"
referenced="$(grep -o '<img ' "$OUT/index.html" | wc -l)"
echo "page_test: $referenced images referenced, ${loaded:-?} loaded, ${failed:-?} failed"
[ -n "$loaded" ] && [ -n "$failed" ] || { echo "page_test: the page's load script did not run"; exit 1; }
[ "$failed" = 0 ] || { echo "page_test: $failed images did not load"; exit 1; }
[ "$loaded" -ge "$referenced" ] || { echo "page_test: fewer images loaded than referenced"; exit 1; }

timeout 120 "$CHROMIUM" "${FLAGS[@]}" --window-size=1400,2400 --screenshot="$OUT/index_screenshot.png" "$URL" > /dev/null 2>&1
[ -s "$OUT/index_screenshot.png" ] || { echo "page_test: no screenshot"; exit 1; }
echo "page_test: screenshot $OUT/index_screenshot.png"
echo "1 passed, 0 failed"
