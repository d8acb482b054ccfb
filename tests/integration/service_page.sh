#!/usr/bin/env bash
# service_page: the page at / in a real browser (headless Chromium driven by
# service_page.mjs): upload, progress to the end, result sizes, download, cancel, job list,
# no console error; once without and once with an API token (which must not reach the log).
# Skips (exit 0 with a message) only where Chromium or puppeteer-core is not installed.
source "$(dirname "$0")/service_common.bash"

CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$CHROMIUM" ]; then echo "SKIP: no chromium (scripts/setup installs it)"; exit 0; fi
if [ ! -d "$TEXOPT_SOURCE_DIR/tools/node_modules/puppeteer-core" ]; then
  echo "SKIP: no puppeteer-core in tools/node_modules (run scripts/setup)"; exit 0
fi
export CHROMIUM
model="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
run_page() { timeout 300 node "$TEXOPT_SOURCE_DIR/tests/integration/service_page.mjs" "$@"; }

start_server --workers 1
run_page "$BASE" "$model" || fail "the page without a token"
stop_server || fail "texoptd did not stop cleanly"

token="page-test-$RANDOM$RANDOM"
DATA="$WORK/data-token" # a fresh job list
TEXOPT_API_TOKEN="$token" start_server --workers 1
code=$(curl -s -o /dev/null -w '%{http_code}' "$BASE/v1/params")
[ "$code" = 401 ] || fail "/v1/params without the token answered $code"
code=$(curl -s -o /dev/null -w '%{http_code}' "$BASE/")
[ "$code" = 200 ] || fail "the page with a token set answered $code"
run_page "$BASE" "$model" "$token" || fail "the page with a token"
stop_server || fail "texoptd did not stop cleanly"
! grep -q "$token" "$WORK/server.log" || fail "the token is in the server log"
echo "service_page: ok"
