#!/usr/bin/env bash
# The .deb installed as a lab installs it (README.md, "Installing for a lab"): `apt-get install
# ./FILE.deb`, which must find every dependency the package declares; then a lesson renders a
# shipped scene by name from /usr/bin, and `apt-get purge` removes the package, leaving no file
# of it behind. It changes the system, so it runs only as root and only where the package is not
# installed already, and the package is removed on every way out; otherwise it is skipped (exit
# 77, which ctest counts as skipped). Usage: tests/package/apt_install.sh BUILD_DIR
set -euo pipefail
BUILD="$(cd "$1" && pwd)"
PACKAGE=illumination-lessons
skip() { echo "SKIPPED: $*"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }

[ "$(id -u)" = 0 ] || skip "not root: apt-get cannot install the package"
command -v apt-get > /dev/null || skip "no apt-get on this machine"
if dpkg-query -W -f='${Status}' "$PACKAGE" 2> /dev/null | grep -q "install ok installed"; then
    skip "$PACKAGE is installed already: left as it is"
fi

WORK="$(mktemp -d /tmp/package_apt.XXXXXX)"
installed=0
cleanup() {
    if [ "$installed" = 1 ]; then
        DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq -o DPkg::Lock::Timeout=120 \
            "$PACKAGE" > /dev/null || echo "FAIL: apt-get purge $PACKAGE"
    fi
    rm -rf "$WORK"
}
trap cleanup EXIT

cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK/cpack" > "$WORK/cpack.log" 2>&1 ||
    { cat "$WORK/cpack.log"; fail "cpack -G DEB"; }
DEBS=("$WORK/cpack/${PACKAGE}"_*.deb)
[ -f "${DEBS[0]}" ] || fail "cpack made no ${PACKAGE}_*.deb"

installed=1  # from here on, the package may be (partly) installed: cleanup removes it
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    -o DPkg::Lock::Timeout=120 "${DEBS[0]}" > "$WORK/apt.log" 2>&1 ||
    { cat "$WORK/apt.log"; fail "apt-get install ${DEBS[0]}"; }
dpkg-query -W -f='${Status}' "$PACKAGE" | grep -q "install ok installed" || fail "not installed"
echo "ok: apt-get installed $(basename "${DEBS[0]}")"

mkdir "$WORK/run"
cd "$WORK/run"
/usr/bin/01_ray_casting --scene cornell_box --width 32 --height 24 --spp 1 --quiet \
    --out cornell --report cornell.json > /dev/null || fail "/usr/bin/01_ray_casting --scene cornell_box"
grep -qF '"scene": "/usr/share/illumination-lessons/scenes/cornell_box.toml"' cornell.json ||
    fail "the installed lesson did not read /usr/share/illumination-lessons/scenes/cornell_box.toml"
echo "ok: /usr/bin/01_ray_casting --scene cornell_box read /usr/share/illumination-lessons/scenes"
cd /

DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq -o DPkg::Lock::Timeout=120 "$PACKAGE" \
    > "$WORK/purge.log" 2>&1 || { cat "$WORK/purge.log"; fail "apt-get purge"; }
installed=0
if dpkg-query -W -f='${Status}' "$PACKAGE" 2> /dev/null | grep -q "installed"; then
    fail "$PACKAGE is still installed after apt-get purge"
fi
for path in /usr/bin/01_ray_casting /usr/bin/illumination-studio /usr/share/$PACKAGE; do
    [ ! -e "$path" ] || fail "$path is left after apt-get purge"
done
echo "ok: apt-get purge removed it"
