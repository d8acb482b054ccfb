#!/usr/bin/env bash
# service_roundtrip: the real texoptd on a loopback port. Uploads spot.glb (raw body) and a
# .gltf with its .bin and texture (multipart + params part), polls both to "succeeded",
# downloads a result that the Khronos validator accepts, reads stats, and checks the
# Idempotency-Key replay (and a reused key refused), listing, report 404, metrics, CORS, auth, and delete.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
make_fixtures "$WORK/fx"
export TEXOPT_API_TOKEN=secret-token
start_server --cors-origin 'https://other.example, https://app.example'

# Auth: everything but the probes needs the token.
[ "$(get /healthz)" = 200 ] || fail "healthz without token"
[ "$(get /readyz)" = 200 ] || fail "readyz without token"
expect_problem 401 "$(get /v1/jobs)" unauthorized
AUTH=(-H "Authorization: Bearer secret-token")
grep -qi '^www-authenticate: Bearer' "$WORK/headers" || fail "401 without WWW-Authenticate"
expect_problem 401 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -H 'Authorization: Bearer wrong' "$BASE/metrics")" unauthorized

# Raw upload with parameters in the query string.
code=$(post_glb "$SPOT" "method=input&relative_cost=0.5" -H 'Idempotency-Key: upload-1' -H 'Origin: https://app.example')
[ "$code" = 202 ] || fail "raw upload answered $code: $(cat "$WORK/resp")"
id=$(json "$WORK/resp" 'd["id"]')
grep -qi "^location: /v1/jobs/$id" "$WORK/headers" || fail "202 without Location"
grep -qi '^retry-after: ' "$WORK/headers" || fail "202 without Retry-After"
grep -qi '^access-control-allow-origin: https://app.example' "$WORK/headers" || fail "no CORS header"
[ "$(json "$WORK/resp" 'd["params"]["relative_cost"]')" = 0.5 ] || fail "relative_cost not taken from the query"
# An origin not in the list gets no CORS header, and Vary tells caches so.
[ "$(get /healthz -H 'Origin: https://app.example.evil')" = 200 ] || fail "healthz with another origin"
! grep -qi '^access-control-allow-origin' "$WORK/headers" || fail "CORS header for an unlisted origin"
grep -qi '^vary: origin' "$WORK/headers" || fail "no Vary: Origin"

# The same Idempotency-Key returns the same job, without a second one.
code=$(post_glb "$SPOT" "method=input&relative_cost=0.5" -H 'Idempotency-Key: upload-1')
[ "$code" = 202 ] || fail "replayed upload answered $code"
[ "$(json "$WORK/resp" 'd["id"]')" = "$id" ] || fail "Idempotency-Key replay made a new job"
grep -qi '^idempotent-replayed: true' "$WORK/headers" || fail "replay not marked"
# The same key with other parameters, or with another file, is a different request.
expect_problem 422 "$(post_glb "$SPOT" "method=input&relative_cost=0.25" -H 'Idempotency-Key: upload-1')" \
  idempotency-key-reused
expect_problem 422 "$(post_glb "$WORK/fx/nouv.glb" "method=input&relative_cost=0.5" -H 'Idempotency-Key: upload-1')" \
  idempotency-key-reused
# Parameters that resolve to the same values are the same request.
code=$(post_glb "$SPOT" "relative_cost=0.5&method=input" -H 'Idempotency-Key: upload-1')
[ "$code" = 202 ] && [ "$(json "$WORK/resp" 'd["id"]')" = "$id" ] || fail "reordered query not replayed ($code)"

# Multipart: a .gltf, its .bin and its texture, params as JSON.
code=$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "${AUTH[@]}" \
  -F "model=@$WORK/fx/quad.gltf" -F "files=@$WORK/fx/quad.bin" -F "files=@$WORK/fx/tex.png" \
  -F 'params={"method":"input","texture_width":32,"texture_height":32};type=application/json' "$BASE/v1/jobs")
[ "$code" = 202 ] || fail "multipart upload answered $code: $(cat "$WORK/resp")"
id2=$(json "$WORK/resp" 'd["id"]')
[ "$(json "$WORK/resp" 'd["params"]["budget"]')" = texture_size ] || fail "params part not applied"
[ "$(json "$WORK/resp" 'd["model"]["name"]')" = quad.gltf ] || fail "model name lost"
files=$(cat "$WORK/fx/quad.gltf" "$WORK/fx/quad.bin" "$WORK/fx/tex.png" | wc -c)
[ "$(json "$WORK/resp" 'd["model"]["upload_bytes"]')" = "$files" ] ||
  fail "upload_bytes $(json "$WORK/resp" 'd["model"]["upload_bytes"]') is not the files' $files bytes"

wait_state "$id" succeeded 120
wait_state "$id2" succeeded 120

# Result: a .glb with a download name, accepted by the validator.
curl -s -o "$WORK/result.glb" -D "$WORK/headers" "${AUTH[@]}" "$BASE/v1/jobs/$id/result"
grep -qi '^content-type: model/gltf-binary' "$WORK/headers" || fail "result content type"
grep -qi '^content-disposition: attachment; filename="model-texopt.glb"' "$WORK/headers" || fail "no Content-Disposition"
[ "$(head -c 4 "$WORK/result.glb")" = glTF ] || fail "result is not a .glb"
if [ -f "$TEXOPT_SOURCE_DIR/tools/validate-gltf.mjs" ] && command -v node >/dev/null; then
  node "$TEXOPT_SOURCE_DIR/tools/validate-gltf.mjs" "$WORK/result.glb" >"$WORK/validation.json" ||
    fail "validator refused the result: $(head -c 2000 "$WORK/validation.json")"
  [ "$(json "$WORK/validation.json" 'd["errors"]')" = 0 ] || fail "validator errors"
fi
curl -s -o "$WORK/result2.glb" "${AUTH[@]}" "$BASE/v1/jobs/$id2/result"
[ "$(head -c 4 "$WORK/result2.glb")" = glTF ] || fail "multipart result is not a .glb"

code=$(curl -s -o "$WORK/stats.json" -w '%{http_code}' "${AUTH[@]}" "$BASE/v1/jobs/$id/stats")
[ "$code" = 200 ] || fail "stats answered $code"
/usr/bin/python3 -c 'import json,sys; json.load(open(sys.argv[1]))' "$WORK/stats.json" || fail "stats is not JSON"

# No evaluation was asked: no report.
expect_problem 404 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "${AUTH[@]}" "$BASE/v1/jobs/$id/report")" no-report

# Listing, newest first, paged.
code=$(curl -s -o "$WORK/list.json" -w '%{http_code}' "${AUTH[@]}" "$BASE/v1/jobs?limit=1")
[ "$code" = 200 ] || fail "list answered $code"
[ "$(json "$WORK/list.json" 'd["jobs"][0]["id"]')" = "$id2" ] || fail "list is not newest first"
next=$(json "$WORK/list.json" 'd["next"]')
curl -s -o "$WORK/list2.json" "${AUTH[@]}" "$BASE$next"
[ "$(json "$WORK/list2.json" 'd["jobs"][0]["id"]')" = "$id" ] || fail "second page"
[ "$(json "$WORK/list2.json" 'd["next"]')" = None ] || fail "a third page of two jobs"

# Metrics: jobs by state, requests by route and status, upload bytes, stage histogram.
curl -s -o "$WORK/metrics.txt" "${AUTH[@]}" "$BASE/metrics"
grep -q '^texopt_jobs{state="succeeded"} 2$' "$WORK/metrics.txt" || fail "metrics: succeeded jobs"
grep -q '^texopt_queue_depth 0$' "$WORK/metrics.txt" || fail "metrics: queue depth"
grep -q '^texopt_http_requests_total{route="/v1/jobs",status="202"} 4$' "$WORK/metrics.txt" || fail "metrics: requests"
grep -q '^texopt_http_requests_total{route="/v1/jobs",status="401"} 1$' "$WORK/metrics.txt" || fail "metrics: 401s"
bytes=$(sed -n 's/^texopt_upload_bytes_total //p' "$WORK/metrics.txt")
[ "$bytes" -ge "$(stat -c %s "$SPOT")" ] || fail "metrics: upload bytes $bytes"
grep -q '^texopt_stage_duration_seconds_count{stage="save"} 2$' "$WORK/metrics.txt" || fail "metrics: stage histogram"
grep -q '^texopt_stage_duration_seconds_bucket{stage="save",le="+Inf"} 2$' "$WORK/metrics.txt" || fail "metrics: +Inf bucket"

# CORS preflight needs no token.
code=$(curl -s -o /dev/null -D "$WORK/headers" -w '%{http_code}' -X OPTIONS -H "Origin: https://other.example" "$BASE/v1/jobs")
[ "$code" = 204 ] || fail "preflight answered $code"
grep -qi '^access-control-allow-methods: GET, HEAD, POST, OPTIONS' "$WORK/headers" || fail "preflight methods"

# The spec is served.
curl -s -o "$WORK/spec.yaml" "${AUTH[@]}" "$BASE/openapi.yaml"
cmp -s "$WORK/spec.yaml" "$TEXOPT_SOURCE_DIR/openapi.yaml" || fail "served openapi.yaml differs from the file"

# A job the engine refuses after it was queued: spot with a texture transform that repeats
# its texture 5000 times across, more texels than a layout can measure.
/usr/bin/python3 - "$SPOT" "$WORK/repeating.glb" <<'PY' || fail "could not write the repeating model"
import json, struct, sys
b = open(sys.argv[1], "rb").read()
n = struct.unpack_from("<I", b, 12)[0]
doc = json.loads(b[20:20 + n])
doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
    "KHR_texture_transform": {"scale": [5000, 5000]}}
doc.setdefault("extensionsUsed", []).append("KHR_texture_transform")
j = json.dumps(doc).encode()
j += b" " * (-len(j) % 4)
rest = b[20 + n:]
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 20 + len(j) + len(rest)) +
                              struct.pack("<I", len(j)) + b"JSON" + j + rest)
PY
[ "$(post_glb "$WORK/repeating.glb" "method=tewari&relative_cost=0.5")" = 202 ] ||
  fail "repeating upload: $(cat "$WORK/resp")"
bad=$(json "$WORK/resp" 'd["id"]')
wait_state "$bad" failed 120
curl -s -o "$WORK/bad.json" "${AUTH[@]}" "$BASE/v1/jobs/$bad"
[ "$(json "$WORK/bad.json" 'd["problem"]["status"]')" = 413 ] || fail "failed job's problem: $(cat "$WORK/bad.json")"
[ "$(json "$WORK/bad.json" 'd["problem"]["type"]')" = urn:texopt:problem:model-too-large ] || fail "problem type"
grep -q 'the UVs repeat it that often' "$WORK/bad.json" || fail "failed job's problem does not say why"
grep -qi '^retry-after' <(curl -s -D - -o /dev/null "${AUTH[@]}" "$BASE/v1/jobs/$bad") && fail "Retry-After on a finished job"
expect_problem 409 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "${AUTH[@]}" "$BASE/v1/jobs/$bad/result")" job-not-succeeded

# The target_loss budget through the API: the job succeeds and its statistics hold the search.
[ "$(post_glb "$SPOT" "method=input&target_loss=0.05")" = 202 ] || fail "target_loss upload: $(cat "$WORK/resp")"
tl=$(json "$WORK/resp" 'd["id"]')
wait_state "$tl" succeeded 120
curl -s -o "$WORK/tl_stats.json" "${AUTH[@]}" "$BASE/v1/jobs/$tl/stats"
/usr/bin/python3 - "$WORK/tl_stats.json" <<'PY' || fail "target_loss statistics: $(cat "$WORK/tl_stats.json")"
import json, sys
t = json.load(open(sys.argv[1]))["target_search"]
assert t["target_loss"] == 0.05 and t["reached"] is True and t["q"] <= 0.05, t
assert 0 < t["relative_cost"] < 1, t
PY

# Delete a finished job: its files go, and so does the job.
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "${AUTH[@]}" "$BASE/v1/jobs/$id")" = 204 ] || fail "delete"
[ ! -e "$DATA/jobs/$id" ] || fail "deleted job's directory remains"
expect_problem 404 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "${AUTH[@]}" "$BASE/v1/jobs/$id")" job-not-found

stop_server TERM || fail "texoptd did not exit cleanly on SIGTERM"
grep -q 'event=request method=GET path="/v1/jobs" route=/v1/jobs status=401' "$WORK/server.log" || fail "request log line"
echo "service_roundtrip: ok"
