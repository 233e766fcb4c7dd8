#!/usr/bin/env bash
# The studio in a real browser: starts build/bin/studio on a free loopback port, drives its page
# in headless Chromium with playwright-core (studio_test.mjs), then stops it with Ctrl-C (SIGINT)
# and checks that it exits cleanly. Usage: tests/studio/run.sh BUILD_DIR
# playwright-core comes from npm, pinned by package-lock.json, installed here when missing.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BUILD="$(cd "${1:-$ROOT/build}" && pwd)"
WORK="$BUILD/studio_browser"
rm -rf "$WORK"
mkdir -p "$WORK/refs/cornell_box"

if [ ! -f "$HERE/node_modules/playwright-core/package.json" ]; then
    (cd "$HERE" && npm ci --no-audit --no-fund --loglevel=error)
fi
CHROMIUM="$(command -v chromium || command -v chromium-browser || true)"
[ -n "$CHROMIUM" ] || { echo "studio_test: chromium is not installed (scripts/test.sh installs it)"; exit 1; }

# A reference where scripts/lessons.sh would put one, for the error chart (48 x 36 pixels).
"$BUILD/bin/05_bidirectional" --scene "$ROOT/scenes/cornell_box.toml" --width 48 --height 36 \
    --spp 64 --seed 1000003 --sampler independent --out "$WORK/refs/cornell_box/reference" \
    --variance "$WORK/refs/cornell_box/reference_variance" --quiet

"$BUILD/bin/studio" --port 0 --references "$WORK/refs" --references "$ROOT/references" --cache "$WORK/cache" --max-spp 1000000 \
    --threads 2 > "$WORK/studio.out" 2> "$WORK/studio.err" &
PID=$!
trap 'kill -9 $PID 2> /dev/null || true' EXIT
URL=""
for _ in $(seq 100); do
    URL="$(sed -n 's/^studio: serving \(http:[^ ]*\).*/\1/p' "$WORK/studio.out")"
    [ -n "$URL" ] && break
    sleep 0.1
done
[ -n "$URL" ] || { cat "$WORK/studio.err"; echo "studio_test: the studio did not start"; exit 1; }
case "$URL" in http://127.0.0.1:*) ;; *) echo "studio_test: not on loopback: $URL"; exit 1 ;; esac
echo "studio_test: $URL (pid $PID)"

status=0
timeout 420 node "$HERE/studio_test.mjs" --url "$URL" --pid "$PID" --bin "$BUILD/bin" \
    --work "$WORK" --chromium "$CHROMIUM" || status=$?

# Ctrl-C stops the server cleanly: exit status 0, within a few seconds.
kill -INT "$PID"
for _ in $(seq 50); do kill -0 "$PID" 2> /dev/null || break; sleep 0.1; done
if kill -0 "$PID" 2> /dev/null; then
    echo "FAIL: the studio did not stop within 5 s of SIGINT"; status=1
else
    wait "$PID" && code=0 || code=$?
    if [ "$code" = 0 ]; then echo "ok: SIGINT stopped the studio cleanly"; else
        echo "FAIL: the studio exited with $code after SIGINT"; cat "$WORK/studio.err"; status=1; fi
fi
trap - EXIT
exit "$status"
