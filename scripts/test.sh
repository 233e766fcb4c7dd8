#!/usr/bin/env bash
# Builds the suite and runs the whole test suite (on a fresh Debian 12 machine it first installs
# what it needs). `scripts/test.sh --quick` leaves out the tests labelled "slow".
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"

CTEST_ARGS=(--output-on-failure --parallel "$(nproc)" --timeout 900)
if [ "${1:-}" = "--quick" ]; then
    CTEST_ARGS+=(--label-exclude slow)
fi

# The page tests open the lessons page and the studio in headless Chromium (the studio's test
# drives it with playwright-core from npm, installed by tests/studio/run.sh from its lock file);
# the lessons run plots with gnuplot.
install_missing_packages chromium gnuplot-nox
# The package's tests make the .deb with CPack, which finds its dependencies with dpkg-shlibdeps
# (dpkg-dev) and the programs among its files with file(1); util-linux's unshare hides the trees.
install_missing_packages dpkg-dev file util-linux
# The check that no core function is over 60 lines finds functions with Universal Ctags.
install_missing_packages universal-ctags
# The Blender bridge's tests (slow) run Debian's Blender, whose Python needs numpy; the live farm
# tests (slow) start a single-node Slurm cluster (slurm-wlm, munge) and an sshd (openssh-server).
if [ "${1:-}" != "--quick" ]; then
    install_missing_packages blender python3-numpy slurm-wlm munge openssh-server
fi
command -v npm > /dev/null || install_missing_packages nodejs npm
build_suite
cd "$BUILD"
ctest "${CTEST_ARGS[@]}"
