#!/usr/bin/env bash
# The checks of one install, run by tests/package/run.sh (which see) with the source and build
# trees hidden, from an empty folder, with the install's bin/ first on PATH.
# Usage: installed_checks.sh PREFIX WORK ROOT BUILD
#   PREFIX  the install (PREFIX/bin, PREFIX/share/illumination-lessons)
#   WORK    run.sh's folder: expected/renderI.exr, renders.txt (lesson|scene|flags a line)
#   ROOT, BUILD  the trees that should be out of reach
set -euo pipefail
PREFIX="$1"
WORK="$2"
ROOT="$3"
BUILD="$4"
SHIPPED="$PREFIX/share/illumination-lessons"
fail() { echo "FAIL ($PREFIX): $*"; exit 1; }
export PATH="$PREFIX/bin:/usr/bin:/bin"
RUN="$(mktemp -d "$WORK/run.XXXXXX")"
cd "$RUN"

if [ -e "$ROOT/scenes" ] || [ -e "$BUILD/bin" ]; then
    echo "note: the source or build tree is visible (no mount namespace)"
else
    echo "ok: $ROOT and $BUILD are out of reach"
fi

# Lessons render the shipped scenes by name, byte for byte the build tree's images.
i=0
while IFS='|' read -r lesson scene flags; do
    [ "$(command -v "$lesson")" = "$PREFIX/bin/$lesson" ] || fail "$lesson is not $PREFIX/bin/$lesson"
    # shellcheck disable=SC2086
    "$lesson" --scene "$scene" $flags --seed 11 --threads 2 --quiet --out "render$i" \
        --report "render$i.json" > /dev/null 2> "render$i.err" ||
        { cat "render$i.err"; fail "$lesson --scene $scene"; }
    grep -qF "\"scene\": \"$SHIPPED/scenes/${scene%.toml}.toml\"" "render$i.json" ||
        fail "$lesson --scene $scene did not read $SHIPPED/scenes/${scene%.toml}.toml"
    for ext in exr png; do
        cmp -s "render$i.$ext" "$WORK/expected/render$i.$ext" ||
            fail "$lesson --scene $scene: render$i.$ext differs from the build tree's"
    done
    echo "ok: $lesson --scene $scene: the build tree's image, byte for byte"
    i=$((i + 1))
done < "$WORK/renders.txt"
[ "$i" -gt 0 ] || fail "no renders listed"

# The tools by name: a scene as JSON.
illumination-scene-export cornell_box --out scene.json ||
    fail "illumination-scene-export cornell_box"
grep -q '"camera"' scene.json || fail "illumination-scene-export wrote no camera"
echo "ok: illumination-scene-export cornell_box"

# An unknown name: exit 2, naming where it looked.
code=0
01_ray_casting --scene cornell_boks --quiet > /dev/null 2> unknown.err || code=$?
[ "$code" = 2 ] || fail "an unknown scene: exit $code, not 2"
grep -qF "scene file not found (looked for ./cornell_boks, ./cornell_boks.toml, $SHIPPED/scenes/cornell_boks," unknown.err ||
    { cat unknown.err; fail "the error does not say where it looked"; }
echo "ok: an unknown name: exit 2, $(cat unknown.err)"

# A file here comes before the shipped scene of that name.
sed 's/^width = .*/width = 24/; s/^height = .*/height = 18/' "$SHIPPED/scenes/cornell_box.toml" > cornell_box.toml
01_ray_casting --scene cornell_box --spp 1 --quiet --out here --report here.json > /dev/null
if ! grep -q '"scene": "cornell_box.toml"' here.json || ! grep -q '"width": 24' here.json; then
    fail "./cornell_box.toml was not the scene of --scene cornell_box"
fi
rm cornell_box.toml
echo "ok: ./cornell_box.toml comes before the shipped one"

# With the shipped scene taken away, the name is no longer found: the programs read this install,
# nothing else.
mv "$SHIPPED/scenes/cornell_box.toml" "$WORK/taken_away.toml"
code=0
01_ray_casting --scene cornell_box --quiet > /dev/null 2> away.err || code=$?
mv "$WORK/taken_away.toml" "$SHIPPED/scenes/cornell_box.toml"
[ "$code" = 2 ] || fail "with the shipped cornell_box.toml taken away: exit $code, not 2"
echo "ok: without the shipped cornell_box.toml, cornell_box is not found"

# The studio: on a free loopback port, its page and its scenes from the install; SIGINT stops it.
illumination-studio --port 0 --threads 1 --reference-spp 4 > studio.out 2> studio.err &
PID=$!
trap 'kill -9 $PID 2> /dev/null || true' EXIT
URL=""
for _ in $(seq 100); do
    URL="$(sed -n 's/^studio: serving \(http:[^ ]*\).*/\1/p' studio.out)"
    [ -n "$URL" ] && break
    sleep 0.1
done
[ -n "$URL" ] || { cat studio.err; fail "the studio did not start"; }
case "$URL" in http://127.0.0.1:*/) ;; *) fail "the studio is not on loopback: $URL" ;; esac
PORT="${URL#http://127.0.0.1:}"
PORT="${PORT%/}"
# METHOD PATH into FILE (the body) with bash's /dev/tcp; fails unless the status is 200. A POST
# carries the header the page sends (X-Studio: 1).
request() {
    # shellcheck disable=SC2016  # (expanded by the inner bash)
    timeout 10 bash -c 'exec 3<> "/dev/tcp/127.0.0.1/$0" &&
        printf "%s %s HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Studio: 1\r\nContent-Length: 0\r\nConnection: close\r\n\r\n" "$1" "$2" >&3 &&
        cat <&3' "$PORT" "$1" "$2" > response || fail "$1 $2: no answer"
    head -1 response | grep -q '^HTTP/1\.[01] 200 ' || fail "$1 $2: $(head -1 response) $(tail -c 300 response)"
    local blank
    blank="$(grep -abo $'^\r$' response | head -1 | cut -d: -f1)"
    tail -c +"$((blank + 3))" response > "$3"
}
get() { request GET "$1" "$2"; }
get / page.html
cmp -s page.html "$SHIPPED/page/index.html" || fail "GET / is not $SHIPPED/page/index.html"
get /studio.js studio.js
cmp -s studio.js "$SHIPPED/page/studio.js" || fail "GET /studio.js is not the shipped one"
get /api/config config.json
for id in scenes/cornell_box hard/cornell_tiny; do
    grep -qF "{\"id\": \"$id\"" config.json || fail "the studio does not offer $id: $(cat config.json)"
done
grep -qF '"name": "06_photon_mapping"' config.json || fail "the studio does not offer lesson 6"
echo "ok: the studio at $URL serves $SHIPPED/page and offers the shipped scenes"
# A pane renders a shipped scene, and names the command that renders it from a terminal: the
# installed lesson on the installed scene.
request POST "/api/start?pane=0&scene=scenes/cornell_box&lesson=01_ray_casting&--width=32&--height=24&--spp=2" started.json
for _ in $(seq 300); do
    get /api/status status.json
    grep -q '^{"panes": \[{"state": "done"' status.json && break
    sleep 0.1
done
grep -q '^{"panes": \[{"state": "done"' status.json || fail "pane 0 did not finish: $(head -c 400 status.json)"
grep -qF "\"command\": \"$PREFIX/bin/01_ray_casting --scene $SHIPPED/scenes/cornell_box.toml " status.json ||
    fail "pane 0's command is not the installed lesson on the shipped scene: $(grep -o '"command": "[^"]*"' status.json | head -1)"
echo "ok: the studio rendered scenes/cornell_box: $(grep -o '"command": "[^"]*"' status.json | head -1)"
kill -INT "$PID"
for _ in $(seq 50); do kill -0 "$PID" 2> /dev/null || break; sleep 0.1; done
kill -0 "$PID" 2> /dev/null && fail "the studio did not stop within 5 s of SIGINT"
code=0
wait "$PID" || code=$?
trap - EXIT
[ "$code" = 0 ] || { cat studio.err; fail "the studio exited with $code after SIGINT"; }
echo "ok: SIGINT stopped the studio"
