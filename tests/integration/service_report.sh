#!/usr/bin/env bash
# service_report: a job created with evaluate=true gets a self-contained HTML report at
# /report (the job's method against the input layout, evaluated by the engine) once it
# succeeded, and links.report only then; the job's progress never runs backwards (the
# comparison is the stage "compare"), reaches 1, and its result is still served.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
start_server
[ "$(post_glb "$SPOT" "method=input&relative_cost=0.5&evaluate=true&eval_resolution=128")" = 202 ] || fail "upload"
id=$(json "$WORK/resp" 'd["id"]')
[ -z "$(json "$WORK/resp" 'd["links"].get("report", "")')" ] || fail "links.report before the report exists"
timeout 300 curl -s -N -o "$WORK/events.txt" "$BASE/v1/jobs/$id/events" || fail "event stream"
wait_state "$id" succeeded 300
# Progress never runs backwards, and the comparison is the stage "compare".
/usr/bin/python3 - "$WORK/events.txt" <<'PY' || fail "progress: $(grep -o '"stage":"[a-z0-9]*","progress":[0-9.e-]*' "$WORK/events.txt" | tr '\n' ' ')"
import json, sys
jobs = [json.loads(l[6:]) for l in open(sys.argv[1]) if l.startswith("data: {\"id")]
progress = [j["progress"] for j in jobs]
assert all(a <= b for a, b in zip(progress, progress[1:])), progress
assert "compare" in [j["stage"] for j in jobs], "no compare stage"
PY
curl -s -o "$WORK/job.json" "$BASE/v1/jobs/$id"
[ "$(json "$WORK/job.json" 'd["links"]["report"]')" = "/v1/jobs/$id/report" ] || fail "no links.report: $(cat "$WORK/job.json")"
[ "$(get "/v1/jobs/$id/report")" = 200 ] || fail "report answered $(cat "$WORK/resp")"
grep -qi '^content-type: text/html' "$WORK/headers" || fail "report is not HTML"
grep -q '<svg' "$WORK/resp" || fail "report has no plot"
grep -q 'data-method="input"' "$WORK/resp" || fail "report has no input curve"
! grep -Eq '(src|href)="https?://' "$WORK/resp" || fail "report fetches from the network"
[ "$(get "/v1/jobs/$id/result")" = 200 ] || fail "result of an evaluated job"
[ ! -e "$DATA/jobs/$id/report-work" ] || fail "report scratch directory left behind"
curl -s -o "$WORK/job.json" "$BASE/v1/jobs/$id"
[ "$(json "$WORK/job.json" 'd["progress"]')" = 1 ] || fail "progress of a finished evaluated job"
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_report: ok"
