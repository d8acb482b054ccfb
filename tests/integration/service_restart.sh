#!/usr/bin/env bash
# service_restart: nothing accepted is lost. kill -9 with one job running and two queued:
# after a restart all three succeed (the interrupted one on its second attempt) and a job
# finished before the kill is still served. Then SIGTERM with a job running and an event
# stream open: texoptd exits 0, the stream ends, the job is back to "queued" on disk, and the
# next start finishes it.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
LONG="method=ssp&texture_width=2048&texture_height=2048"
start_server --workers 1

[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "upload"
done_id=$(json "$WORK/resp" 'd["id"]')
wait_state "$done_id" succeeded 120
# One long job to be running at the kill, two short ones queued behind it.
ids=()
for query in "$LONG" method=input method=input; do
  [ "$(post_glb "$SPOT" "$query")" = 202 ] || fail "upload: $(cat "$WORK/resp")"
  ids+=("$(json "$WORK/resp" 'd["id"]')")
done
wait_state "${ids[0]}" running 60
for id in "${ids[1]}" "${ids[2]}"; do
  [ "$(json "$DATA/jobs/$id/job.json" 'd["state"]')" = queued ] || fail "job $id not queued at the kill"
done
stop_server KILL || true

# The interrupted upload of a fourth job (a directory without job.json) must not survive.
mkdir -p "$DATA/jobs/ffffffffffffffffffffffffffffffff/input"
start_server --workers 1
[ ! -e "$DATA/jobs/ffffffffffffffffffffffffffffffff" ] || fail "half upload kept after restart"
for id in "${ids[@]}"; do wait_state "$id" succeeded 180; done
curl -s -o "$WORK/first.json" "$BASE/v1/jobs/${ids[0]}"
[ "$(json "$WORK/first.json" 'd["attempts"]')" = 2 ] || fail "interrupted job did not run twice: $(cat "$WORK/first.json")"
[ "$(get "/v1/jobs/$done_id/result")" = 200 ] || fail "finished job not served after restart"
[ "$(head -c 4 "$WORK/resp")" = glTF ] || fail "finished job's result after restart"
grep -q "event=recover job=${ids[0]} action=requeue" "$WORK/server.log" || fail "requeue not logged"

# SIGTERM while a job runs: clean exit, the job goes back to queued, and finishes later.
[ "$(post_glb "$SPOT" "$LONG")" = 202 ] || fail "upload before SIGTERM"
term_id=$(json "$WORK/resp" 'd["id"]')
wait_state "$term_id" running 60
# An open event stream must not hold the shutdown up: it ends with the server.
timeout 60 curl -s -N -o "$WORK/term_events.txt" "$BASE/v1/jobs/$term_id/events" &
stream=$!
for _ in $(seq 100); do grep -q '"state":"running"' "$WORK/term_events.txt" 2>/dev/null && break; sleep 0.1; done
grep -q '"state":"running"' "$WORK/term_events.txt" || fail "the stream saw no running state"
start=$SECONDS
stop_server TERM || fail "texoptd exited non-zero on SIGTERM"
[ $((SECONDS - start)) -le 20 ] || fail "SIGTERM took $((SECONDS - start)) s"
# curl ends with 0: the stream's last chunk arrived before the server stopped (18 would be
# a stream cut mid-way, 124 one that held on past the shutdown).
rc=0
wait "$stream" || rc=$?
[ "$rc" = 0 ] || fail "the event stream did not end cleanly at shutdown (curl exit $rc)"
[ "$(json "$DATA/jobs/$term_id/job.json" 'd["state"]')" = queued ] || fail "job not re-queued at SIGTERM"
start_server --workers 1
wait_state "$term_id" succeeded 180
stop_server TERM || fail "second SIGTERM"
echo "service_restart: ok"
