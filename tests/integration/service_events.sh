#!/usr/bin/env bash
# service_events: server-sent events. A job queued behind a long one (the perceptual method,
# canceled once the stream is open) is watched from before it starts: the stream has id:
# lines that increase, the queued and running states, progress with an engine stage, and
# ends by itself after "succeeded". Resuming with Last-Event-ID at the last id answers 204
# (so an EventSource stops); resuming earlier gives the current state. DELETE cancels a queued
# job at once and a running one at its next checkpoint.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
start_server --workers 1

# A long job first (stage 1 takes tens of seconds on spot), so the second waits in the queue.
[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "first upload"
long=$(json "$WORK/resp" 'd["id"]')
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "second upload"
id=$(json "$WORK/resp" 'd["id"]')
[ "$(json "$WORK/resp" 'd["state"]')" = queued ] || fail "second job is not queued behind the first"

timeout 120 curl -s -N -o "$WORK/events.txt" -D "$WORK/ev_headers" "$BASE/v1/jobs/$id/events" &
stream=$!
wait_state "$long" running 60
sleep 0.5
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$long")" = 202 ] || fail "cancel the long job"
wait "$stream" || fail "event stream did not end by itself"
wait_state "$long" canceled 60
grep -qi '^content-type: text/event-stream' "$WORK/ev_headers" || fail "not text/event-stream"
[ "$(head -n 1 "$WORK/events.txt")" = "retry: 2000" ] || fail "stream does not start with its retry delay"
/usr/bin/python3 - "$WORK/events.txt" <<'PY' || fail "event stream content: $(head -c 3000 "$WORK/events.txt")"
import json, sys
events, cur = [], {}
for line in open(sys.argv[1]).read().split("\n"):
    if not line:
        if "data" in cur: events.append(cur)
        elif cur: assert cur == {"retry": "2000"}, cur
        cur = {}
    elif not line.startswith(":"):
        k, _, v = line.partition(": ")
        cur[k] = v
ids = [int(e["id"]) for e in events]
assert ids == sorted(ids) and len(set(ids)) == len(ids), f"ids not increasing: {ids}"
states = [json.loads(e["data"])["state"] for e in events]
assert states[0] == "queued", states
assert "running" in states, states
assert states[-1] == "succeeded", states
assert events[-1]["event"] == "state"
progress = [json.loads(e["data"]) for e in events if e["event"] == "progress"]
assert progress and all(p["stage"] for p in progress), "no progress event with a stage"
assert all(0 <= p["progress"] <= 1 for p in progress)
open(sys.argv[1] + ".last", "w").write(str(ids[-1]))
PY
last=$(cat "$WORK/events.txt.last")

# Resume at the last id: nothing new, 204 (an EventSource stops reconnecting on it).
code=$(timeout 10 curl -s -N -o "$WORK/resume.txt" -w '%{http_code}' -H "Last-Event-ID: $last" \
  "$BASE/v1/jobs/$id/events") || fail "resumed stream of a finished job did not end"
[ "$code" = 204 ] || fail "resume at the last id of a finished job answered $code, not 204"
[ ! -s "$WORK/resume.txt" ] || fail "resume at the last id repeated events: $(cat "$WORK/resume.txt")"
# Resume from an older id: the current (final) state comes at once.
timeout 10 curl -s -N -o "$WORK/resume2.txt" -H "Last-Event-ID: 1" "$BASE/v1/jobs/$id/events" || fail "resume from 1"
grep -q "^id: $last$" "$WORK/resume2.txt" || fail "resume from 1 did not give the latest event"
grep -q '"state":"succeeded"' "$WORK/resume2.txt" || fail "resume from 1 did not give the final state"

# Cancel: a queued job at once (200), a running one at its next checkpoint (202).
[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "third upload"
run=$(json "$WORK/resp" 'd["id"]')
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "fourth upload"
queued=$(json "$WORK/resp" 'd["id"]')
wait_state "$run" running 60
code=$(curl -s -o "$WORK/resp" -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$queued")
[ "$code" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = canceled ] || fail "cancel queued: $code $(cat "$WORK/resp")"
code=$(curl -s -o "$WORK/resp" -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$run")
[ "$code" = 202 ] && [ "$(json "$WORK/resp" 'd["cancel_requested"]')" = True ] || fail "cancel running: $code"
wait_state "$run" canceled 60
expect_problem 409 "$(get "/v1/jobs/$run/result")" job-not-succeeded
[ "$(json "$DATA/jobs/$queued/job.json" 'd["state"]')" = canceled ] || fail "canceled state not on disk"
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_events: ok"
