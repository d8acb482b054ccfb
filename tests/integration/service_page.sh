#!/usr/bin/env bash
# service_page: the page at / and its files over HTTP (types, caching, no way out of the
# page's directory, public with a token on), then in a real browser (headless Chromium
# driven by service_page.mjs): upload, progress to the end, result sizes, download, 3D
# views, heat maps (texel density and each distortion metric, checked against `texopt
# info`), q-cost plot, cancel, job list, no console error; once without and once with an
# API token (which must not reach the log). The browser part skips (with a message) only
# where Chromium or puppeteer-core is not installed.
source "$(dirname "$0")/service_common.bash"

# The files, served by a server with a token: the page needs none, the API does.
cp -r "$TEXOPT_SOURCE_DIR/web" "$WORK/web"
ln -s /etc/passwd "$WORK/web/ui/link.txt"
TEXOPT_API_TOKEN=not-needed-here start_server --web-dir "$WORK/web"
[ "$(get /)" = 200 ] || fail "/ answered $(cat "$WORK/resp")"
grep -qi '^content-type: text/html; charset=utf-8' "$WORK/headers" || fail "/ is not text/html"
grep -qi "^content-security-policy: default-src 'self'" "$WORK/headers" || fail "/ without its CSP"
grep -qi '^cache-control: no-cache' "$WORK/headers" || fail "/ without Cache-Control"
etag=$(grep -i '^etag:' "$WORK/headers" | cut -d' ' -f2 | tr -d '\r')
[ -n "$etag" ] || fail "/ without an ETag"
[ "$(get / -H "If-None-Match: $etag")" = 304 ] || fail "an unchanged page is not 304"
[ "$(get /ui/app.js)" = 200 ] || fail "/ui/app.js answered $(cat "$WORK/resp")"
grep -qi '^content-type: text/javascript; charset=utf-8' "$WORK/headers" || fail "app.js is not JavaScript"
grep -qi '^x-content-type-options: nosniff' "$WORK/headers" || fail "app.js without nosniff"
cmp -s "$WORK/resp" "$TEXOPT_SOURCE_DIR/web/ui/app.js" || fail "app.js differs from web/ui/app.js"
[ "$(get /ui/page.css)" = 200 ] && grep -qi '^content-type: text/css' "$WORK/headers" || fail "page.css"
for path in /ui/../openapi.yaml /ui/%2e%2e/openapi.yaml /ui/..%2fui%2fapp.js /ui/.gitignore /ui/ /ui/missing.js \
            /index.html /web/index.html; do
  code=$(curl -s --path-as-is -o /dev/null -w '%{http_code}' "$BASE$path")
  [ "$code" = 404 ] || fail "$path answered $code, not 404"
done
code=$(curl -s -o /dev/null -w '%{http_code}' "$BASE/ui/link.txt")
[ "$code" = 404 ] || fail "a symbolic link in web/ui was followed ($code)"
[ "$(get /v1/params)" = 401 ] || fail "/v1/params without the token is not 401"
stop_server || fail "texoptd did not stop cleanly"

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
