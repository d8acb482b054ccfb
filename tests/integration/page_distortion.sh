#!/usr/bin/env bash
# page_distortion: the distortion metrics the page computes (web/ui/distortion.js) on
# triangles with known answers, in node (page_distortion.mjs). scripts/setup installs node.
set -euo pipefail
command -v node >/dev/null || { echo "FAIL: no node (scripts/setup installs it)"; exit 1; }
node "$TEXOPT_SOURCE_DIR/tests/integration/page_distortion.mjs"
