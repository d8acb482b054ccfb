#!/usr/bin/env bash
# service_report: a job created with evaluate=true gets a self-contained HTML report at
# /report (the job's method against the input layout, evaluated by the engine) once it
# succeeded; the job's progress reaches 1 and its result is still served.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
start_server
[ "$(post_glb "$SPOT" "method=input&relative_cost=0.5&evaluate=true&eval_resolution=128")" = 202 ] || fail "upload"
id=$(json "$WORK/resp" 'd["id"]')
wait_state "$id" succeeded 300
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
