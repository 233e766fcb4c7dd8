#!/usr/bin/env bash
# The installed suite, from its installed files only (README.md, "Installing for a lab";
# docs/architecture.md, "Installed"). Installs the build twice: `cmake --install --prefix` into a
# temporary prefix, and the .deb that `cpack -G DEB` makes, unpacked by `dpkg-deb -x` into a
# temporary root (its metadata checked by `dpkg-deb -I`: name, version, maintainer, the Debian
# packages it depends on). Then, for each, with the source and build trees hidden (a private
# mount namespace with an empty tmpfs over each, where unshare(1) may make one), from an empty
# folder (tests/package/installed_checks.sh):
#   - lessons render shipped scenes by name, byte for byte the images of the build tree's
#     programs given the source tree's files;
#   - an unknown name is an error (exit 2) naming where it looked, a file here comes before a
#     shipped scene, and with the shipped scene taken away the name is no longer found;
#   - the installed studio, on a free loopback port, serves its page and its scenes, and stops
#     on SIGINT.
# Usage: tests/package/run.sh BUILD_DIR VERSION   (VERSION: project()'s, which the .deb must carry)
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
BUILD="$(cd "$1" && pwd)"
VERSION="$2"
PACKAGE=illumination-lessons

WORK="$(mktemp -d /tmp/package_test.XXXXXX)"
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# What the installed programs must reproduce: the build tree's, on the source tree's scenes.
# (lesson, scene name, flags): a box by name, a scene with a mesh, textures and an environment
# map read relative to its folder, a scene of a subfolder.
mkdir -p "$WORK/expected"
RENDERS=(
    "01_ray_casting|cornell_box|--width 64 --height 48 --spp 2"
    "04_rendering_equation|sky_map.toml|--width 48 --height 32 --spp 4"
    "02_whitted|hard/cornell_tiny|--width 40 --height 40 --spp 2"
)
for i in "${!RENDERS[@]}"; do
    IFS='|' read -r lesson scene flags <<< "${RENDERS[$i]}"
    file="$ROOT/scenes/${scene%.toml}.toml"
    # shellcheck disable=SC2086
    "$BUILD/bin/$lesson" --scene "$file" $flags --seed 11 --threads 2 --quiet \
        --out "$WORK/expected/render$i" > /dev/null
done
printf '%s\n' "${RENDERS[@]}" > "$WORK/renders.txt"

# 1. cmake --install into a prefix of its own.
cmake --install "$BUILD" --prefix "$WORK/prefix" --strip > "$WORK/install.log" ||
    { cat "$WORK/install.log"; fail "cmake --install"; }

# 2. The .deb, made outside the build tree, and unpacked.
cpack -G DEB --config "$BUILD/CPackConfig.cmake" -B "$WORK/cpack" > "$WORK/cpack.log" 2>&1 ||
    { cat "$WORK/cpack.log"; fail "cpack -G DEB"; }
DEBS=("$WORK/cpack/${PACKAGE}"_*.deb)
[ -f "${DEBS[0]}" ] || { cat "$WORK/cpack.log"; fail "cpack made no ${PACKAGE}_*.deb"; }
DEB="${DEBS[0]}"
echo "package: $(basename "$DEB"), $(du -k "$DEB" | cut -f1) KiB"
dpkg-deb -I "$DEB" > "$WORK/info.txt"
field() { sed -n "s/^ $1: //p" "$WORK/info.txt"; }
[ "$(field Package)" = "$PACKAGE" ] || fail "Package: '$(field Package)'"
[ "$(field Version)" = "$VERSION" ] || fail "Version: '$(field Version)', project() says '$VERSION'"
[ -n "$(field Maintainer)" ] || fail "no Maintainer"
depends="$(field Depends)"
echo "package: Depends: $depends"
# Every shared library a packaged program needs comes from a package that Depends names.
names=" $(sed 's/ ([^)]*)//g; s/,//g' <<< "$depends") "
owners() {  # the Debian packages that hold a file named $1 in some folder
    dpkg -S "*/$1" 2> /dev/null |
        awk -F': ' -v l="/$1" 'substr($2, length($2) - length(l) + 1) == l {
            n = split($1, owner, ", ")
            for (i = 1; i <= n; i++) { split(owner[i], name, ":"); print name[1] } }' | sort -u
}
dpkg-deb -x "$DEB" "$WORK/root"
needed="$(for program in "$WORK"/root/usr/bin/*; do readelf -d "$program"; done |
          sed -n 's/.*Shared library: \[\(.*\)\]$/\1/p' | sort -u)"
[ -n "$needed" ] || fail "readelf found no shared library the programs need"
for library in $needed; do
    found=""
    for owner in $(owners "$library"); do [[ "$names" == *" $owner "* ]] && found="$owner"; done
    [ -n "$found" ] || fail "$library: none of its packages ($(owners "$library" | tr '\n' ' ')) is in Depends: $depends"
done
echo "package: each of the $(wc -w <<< "$needed") shared libraries the programs need is in Depends"
dpkg-deb -c "$DEB" > "$WORK/contents.txt"
for path in ./usr/bin/01_ray_casting ./usr/bin/illumination-studio ./usr/bin/illumination-merge \
            ./usr/share/$PACKAGE/scenes/cornell_box.toml ./usr/share/$PACKAGE/scenes/maps/sky.exr \
            ./usr/share/$PACKAGE/page/index.html ./usr/share/doc/$PACKAGE/README.md; do
    grep -q " $path\$" "$WORK/contents.txt" || fail "the package has no $path"
done

# 3. The checks, for each install, with the trees out of reach. The check script runs from a
# copy: its own folder is hidden too.
cp "$HERE/installed_checks.sh" "$WORK/installed_checks.sh"
hide="mount -t tmpfs -o size=1m,mode=000 none '$ROOT'"
case "$BUILD/" in "$ROOT/"*) ;; *) hide="$hide && mount -t tmpfs -o size=1m,mode=000 none '$BUILD'" ;; esac
hidden() {
    if [ "$(id -u)" = 0 ] && unshare -m bash -c "$hide" 2> /dev/null; then
        unshare -m bash -c "$hide && exec bash \"\$@\"" hidden "$@"
    elif unshare -r -m bash -c "$hide" 2> /dev/null; then
        unshare -r -m bash -c "$hide && exec bash \"\$@\"" hidden "$@"
    else
        echo "note: no mount namespace here (unshare refused): the trees stay visible; the" \
             "check with the shipped scene taken away still shows where the programs look"
        bash "$@"
    fi
}
status=0
for prefix in "$WORK/prefix" "$WORK/root/usr"; do
    echo "== installed in $prefix"
    hidden "$WORK/installed_checks.sh" "$prefix" "$WORK" "$ROOT" "$BUILD" || status=1
done
[ "$status" = 0 ] && echo "ok: both installs render by name, byte for byte, and serve the studio"
exit "$status"
