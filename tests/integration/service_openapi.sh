#!/usr/bin/env bash
# service_openapi: openapi.yaml lints clean (Redocly, recommended rules, no warnings) and
# documents exactly the routes of api/routes.c with the methods each allows (HEAD and
# OPTIONS aside), so the spec and the code cannot drift apart.
set -euo pipefail
: "${TEXOPT_SOURCE_DIR:?}"
cd "$TEXOPT_SOURCE_DIR"
redocly=tools/node_modules/.bin/redocly
[ -x "$redocly" ] || { echo "FAIL: $redocly missing (run scripts/setup)" >&2; exit 1; }
export REDOCLY_TELEMETRY=off REDOCLY_SUPPRESS_UPDATE_NOTICE=true
out=$(timeout 120 "$redocly" lint openapi.yaml 2>&1) || { echo "$out" >&2; echo "FAIL: lint" >&2; exit 1; }
# Redocly exits 0 with warnings; its summary then says "You have N warning(s)".
if ! echo "$out" | grep -q 'Your API description is valid' || echo "$out" | grep -q 'You have [0-9]'; then
  echo "$out" >&2; echo "FAIL: lint warnings" >&2; exit 1
fi

/usr/bin/python3 - <<'PY'
import re, sys
code = open("api/routes.c").read()
routes = dict(re.findall(r'\[ROUTE_\w+\] = \{"(/[^"]*)", "([^"]*)"\}', code))
assert len(routes) >= 10, f"parsed only {len(routes)} routes from api/routes.c"
spec = open("openapi.yaml").read()
paths = {}
current = None
for line in spec.split("\n"):
    m = re.match(r"^  (/\S*):\s*$", line)
    if m:
        current = m.group(1); paths[current] = set(); continue
    if re.match(r"^\S", line):
        current = None
    m = re.match(r"^    (get|post|put|delete|patch):\s*$", line)
    if current and m:
        paths[current].add(m.group(1).upper())
bad = []
for route, allow in routes.items():
    methods = {m.strip() for m in allow.split(",")} - {"HEAD", "OPTIONS"}
    if route not in paths:
        bad.append(f"{route} is served but not in openapi.yaml")
    elif paths[route] != methods:
        bad.append(f"{route}: code allows {sorted(methods)}, spec has {sorted(paths[route])}")
for path in paths:
    if path not in routes:
        bad.append(f"{path} is in openapi.yaml but not served")
if bad:
    print("FAIL:\n  " + "\n  ".join(bad), file=sys.stderr); sys.exit(1)
print(f"service_openapi: {len(routes)} routes match")
PY
echo "service_openapi: ok"
