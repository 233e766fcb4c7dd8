#!/usr/bin/env bash
# Shared set-up for scripts/lessons.sh and scripts/test.sh: install the Debian packages the
# suite needs (only those missing), then configure and build in Release with every core.
# Source it; it defines $ROOT and $BUILD.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${BUILD_DIR:-$ROOT/build}"

PACKAGES=(
    cmake g++ make pkg-config
    libglm-dev libstb-dev libtinyobjloader-dev libgtest-dev
    libtomlplusplus-dev libcli11-dev libopenexr-dev libcpp-httplib-dev libtinygltf-dev
    parallel
)

install_missing_packages() {
    local missing=()
    for p in "$@"; do
        if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
            missing+=("$p")
        fi
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    echo "setup: installing ${missing[*]}" >&2
    local sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null; then sudo="sudo"; else
            echo "setup: need root to install: ${missing[*]}" >&2
            exit 1
        fi
    fi
    export DEBIAN_FRONTEND=noninteractive
    $sudo apt-get update -qq
    $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

build_suite() {
    cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
    cmake --build "$BUILD" --parallel "$(nproc)"
}

install_missing_packages "${PACKAGES[@]}"
