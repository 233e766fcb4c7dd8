#!/usr/bin/env bash
# The studio: the lessons rendering live in a browser (docs/studio.md). Installs what the suite
# needs and builds it, like the other scripts, then starts build/bin/studio, which prints the
# address to open (http://127.0.0.1:8642/ by default). Flags go to the studio, e.g.
#   scripts/studio.sh --port 9000
#   scripts/studio.sh --bind 0.0.0.0      # let the classroom's machines in (the page says so)
# Ctrl-C stops it.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
build_suite > /dev/null
cd "$ROOT"
exec "$BUILD/bin/studio" "$@"
