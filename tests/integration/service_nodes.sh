#!/usr/bin/env bash
# service_nodes: three texoptd nodes share one PostgreSQL job store (a throw-away cluster in
# a temp directory) and one blob directory. 30 jobs are submitted across the nodes; one node
# is killed with SIGKILL while it runs a job and not restarted (until the last check): every
# job succeeds exactly once (the killed node's job runs again elsewhere once its lease runs
# out), every result is
# a valid model, and events of a job reach clients connected to other nodes. A cancel sent
# to one node stops the job another node runs. With the database stopped, /readyz and
# uploads answer 503 + Retry-After; once it is back, uploads are accepted again. With
# --max-attempts 1, the job of a killed node fails with the reason instead of running again,
# and a day-old upload directory without a job is swept away.
source "$(dirname "$0")/pg_cluster.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
JOB_QUERY="method=input" # a fraction of a second: the queue's work, not the engine's
: "${TEXOPT_BIN:?TEXOPT_BIN must name the texopt binary}"

pg_start || fail "cannot start a PostgreSQL cluster"
BLOBS="$WORK/blobs"
declare -a NODE_PID NODE_BASE
launch_node() { # launch_node N [flags...]: starts node N on a free loopback port
  local n="$1"
  shift
  rm -f "$WORK/port$n"
  "$TEXOPTD_BIN" --bind 127.0.0.1 --port 0 --port-file "$WORK/port$n" --data-dir "$WORK/node$n" \
    --store "$PG_URL" --blob-dir "$BLOBS" --lease-seconds 3 --workers 1 --queue-limit 100 "$@" \
    >>"$WORK/node$n.log" 2>&1 &
  NODE_PID[$n]=$!
}
await_node() { # await_node N: waits for node N to listen; sets NODE_BASE[N]
  local n="$1"
  for _ in $(seq 1 150); do
    [ -s "$WORK/port$n" ] && break
    kill -0 "${NODE_PID[$n]}" 2>/dev/null || fail "node $n exited at start: $(tail -n 5 "$WORK/node$n.log")"
    sleep 0.1
  done
  [ -s "$WORK/port$n" ] || fail "node $n did not start"
  NODE_BASE[$n]="http://127.0.0.1:$(cat "$WORK/port$n")"
}
start_node() { launch_node "$@" && await_node "$1"; }
# wait_all_succeeded SECONDS ID...: polls node 1's job list until every ID has succeeded.
wait_all_succeeded() {
  local deadline=$((SECONDS + $1)) left=""
  shift
  while [ $SECONDS -lt $deadline ]; do
    curl -s -o "$WORK/list" "${NODE_BASE[1]}/v1/jobs?limit=100" || true
    left=$(/usr/bin/python3 -c 'import json, sys
d = {j["id"]: j["state"] for j in json.load(open(sys.argv[1]))["jobs"]}
bad = [i for i in sys.argv[2:] if d.get(i) in ("failed", "canceled")]
if bad: print("jobs ended badly: " + " ".join(bad)); sys.exit(1)
print(sum(d.get(i) != "succeeded" for i in sys.argv[2:]))' "$WORK/list" "$@") || fail "$left"
    [ "$left" = 0 ] && return 0
    sleep 0.2
  done
  fail "$left jobs not succeeded after the wait"
}
stop_nodes() {
  for n in 1 2 3 4; do
    if [ -n "${NODE_PID[$n]:-}" ] && kill -0 "${NODE_PID[$n]}" 2>/dev/null; then
      kill -9 "${NODE_PID[$n]}" 2>/dev/null || true
      wait "${NODE_PID[$n]}" 2>/dev/null || true
    fi
  done
}
cleanup_all() {
  stop_nodes
  pg_stop
  cleanup
}
trap cleanup_all EXIT
for n in 1 2 3; do launch_node "$n"; done
for n in 1 2 3; do await_node "$n"; done

# Node 3 dies in the middle of a job, while the jobs below are uploaded. Its /metrics says
# when it runs one; it is frozen (SIGSTOP) to read which job it took last from its log: that
# job must still be running (asked of node 1: a frozen node commits nothing), else it thaws
# and the watch goes on. The job's id goes to $WORK/killed.
kill_node3_mid_job() {
  for _ in $(seq 1 2000); do
    if curl -s "${NODE_BASE[3]}/metrics" | grep -q '^texopt_workers_busy 1$'; then
      kill -STOP "${NODE_PID[3]}"
      last=$(grep 'event=job .*state=running' "$WORK/node3.log" | tail -n 1 | sed 's/.* job=\([0-9a-f]*\) .*/\1/')
      if [ -n "$last" ] && [ "$(curl -s "${NODE_BASE[1]}/v1/jobs/$last" | sed -n 's/.*"state":"\([a-z]*\)".*/\1/p')" = running ]; then
        kill -9 "${NODE_PID[3]}"
        echo "$last" >"$WORK/killed"
        return 0
      fi
      kill -CONT "${NODE_PID[3]}"
    fi
    sleep 0.01
  done
}
kill_node3_mid_job &
watcher=$!

# 30 jobs uploaded to nodes 1 and 2 in turn (node 3 is the one to die); every node takes
# jobs from the shared queue. Events: streams opened on nodes 1 and 2 for the last one (at
# most one of them is the node that runs it); it waits behind the others, so the streams see
# it queued, running and succeeded.
ids=()
for i in $(seq 1 30); do
  n=$((i % 2 + 1))
  BASE="${NODE_BASE[$n]}"
  [ "$(post_glb "$SPOT" "$JOB_QUERY")" = 202 ] || fail "upload $i to node $n: $(cat "$WORK/resp")"
  ids+=("$(json "$WORK/resp" 'd["id"]')")
done
watched="${ids[29]}"
stream_pids=()
for n in 1 2; do
  curl -s -N --max-time 120 "${NODE_BASE[$n]}/v1/jobs/$watched/events" >"$WORK/events$n" &
  stream_pids+=($!)
done
wait "$watcher"
[ -s "$WORK/killed" ] || fail "node 3 was never caught running a job"
killed_job=$(cat "$WORK/killed")
wait "${NODE_PID[3]}" 2>/dev/null || true
NODE_PID[3]=""

BASE="${NODE_BASE[1]}"
wait_all_succeeded 150 "${ids[@]}"
[ "$(get "/v1/jobs/$killed_job")" = 200 ] || fail "the killed node's job is gone"
[ "$(json "$WORK/resp" 'd["attempts"]')" -ge 2 ] || fail "the killed node's job did not run again: $(cat "$WORK/resp")"
grep -q "job=$killed_job action=queued reason=lease-expired" "$WORK"/node[12].log ||
  fail "no node took back the killed node's job"

# Exactly once: one succeeded per job over every node's log, none for an unknown job.
cat "$WORK"/node[123].log | grep 'event=job .*state=succeeded' | sed 's/.* job=\([0-9a-f]*\) .*/\1/' | sort >"$WORK/succeeded"
[ "$(wc -l <"$WORK/succeeded")" = 30 ] || fail "$(wc -l <"$WORK/succeeded") successes logged for 30 jobs"
[ "$(sort -u "$WORK/succeeded" | wc -l)" = 30 ] || fail "a job was reported succeeded twice"
printf '%s\n' "${ids[@]}" | sort | cmp -s - "$WORK/succeeded" || fail "successes are not the 30 jobs"

# Every result is a model texopt can read, whichever node is asked. The jobs have the same
# input and parameters, so their results are compared byte for byte and each distinct one
# (here: one) is read with `texopt info`.
mkdir -p "$WORK/results"
for i in "${!ids[@]}"; do
  base="${NODE_BASE[$((i % 2 + 1))]}"
  code=$(curl -s -o "$WORK/results/${ids[$i]}.glb" -w '%{http_code}' "$base/v1/jobs/${ids[$i]}/result")
  [ "$code" = 200 ] && [ -s "$WORK/results/${ids[$i]}.glb" ] || fail "result of ${ids[$i]}: HTTP $code"
done
sha256sum "$WORK"/results/*.glb | sort -u -k1,1 | while read -r _ file; do
  "$TEXOPT_BIN" info "$file" >"$file.info" 2>&1 || fail "$file does not validate: $(cat "$file.info")"
done

wait "${stream_pids[@]}" || true # the streams end after the finished state
for n in 1 2; do
  grep -q '"state":"running"' "$WORK/events$n" || fail "the start did not reach node $n: $(cat "$WORK/events$n")"
  grep -q '"state":"succeeded"' "$WORK/events$n" || fail "the end did not reach node $n: $(tail -n 3 "$WORK/events$n")"
done

# A cancel sent to one node reaches the node running the job.
[ "$(post_glb "$SPOT" "method=ssp")" = 202 ] || fail "upload to cancel"
long=$(json "$WORK/resp" 'd["id"]')
wait_state "$long" running 60
runner=$(grep -l "job=$long state=running" "$WORK"/node[12].log)
other=1
[ "$runner" = "$WORK/node1.log" ] && other=2
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "${NODE_BASE[$other]}/v1/jobs/$long")" = 202 ] ||
  fail "cancel through node $other"
wait_state "$long" canceled 30

# The database goes away: no node is ready and uploads are refused with Retry-After (nothing
# is accepted that could be lost); when it is back, they are accepted again.
pg_stop
for _ in $(seq 1 50); do
  [ "$(get /readyz)" = 503 ] && break
  sleep 0.1
done
expect_problem 503 "$(get /readyz)" database-unavailable
expect_problem 503 "$(post_glb "$SPOT" "$JOB_QUERY")" database-unavailable
grep -qi '^retry-after: [1-9]' "$WORK/headers" || fail "503 without Retry-After"
pg_start_again || fail "cannot restart PostgreSQL"
for _ in $(seq 1 100); do
  [ "$(get /readyz)" = 200 ] && break
  sleep 0.1
done
[ "$(get /readyz)" = 200 ] || fail "not ready after the database came back: $(cat "$WORK/resp")"
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "upload after the database came back: $(cat "$WORK/resp")"
wait_state "$(json "$WORK/resp" 'd["id"]')" succeeded 60

# Bounded retries: nodes 1 and 2 stop (SIGTERM: clean exit); node 3 starts with
# --max-attempts 1, takes a job and is killed; node 4 (same setting) reaps it as failed,
# with the reason, instead of running it again.
for n in 1 2; do
  kill -TERM "${NODE_PID[$n]}"
  wait "${NODE_PID[$n]}" || fail "node $n did not exit cleanly on SIGTERM"
  NODE_PID[$n]=""
done
start_node 3 --max-attempts 1
BASE="${NODE_BASE[3]}"
[ "$(post_glb "$SPOT" "method=ssp")" = 202 ] || fail "upload for the retry limit"
doomed=$(json "$WORK/resp" 'd["id"]')
wait_state "$doomed" running 60
kill -9 "${NODE_PID[3]}"
wait "${NODE_PID[3]}" 2>/dev/null || true
NODE_PID[3]=""
# Also: an upload directory without a job (its node died mid-upload) a day old is removed
# when node 4 starts (its first retention sweep); an old directory of a job is kept.
orphan="$BLOBS/jobs/$(printf '%032d' 7)"
mkdir -p "$orphan/input"
touch -d '2 days ago' "$orphan" "$BLOBS/jobs/${ids[1]}"
start_node 4 --max-attempts 1
BASE="${NODE_BASE[4]}"
for _ in $(seq 1 100); do
  [ "$(get "/v1/jobs/$doomed")" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = failed ] && break
  sleep 0.1
done
[ "$(json "$WORK/resp" 'd["state"]')" = failed ] || fail "the job of a killed node was not failed: $(cat "$WORK/resp")"
[ "$(json "$WORK/resp" 'd["problem"]["type"]')" = urn:texopt:problem:attempts-exhausted ] ||
  fail "no reason for the failure: $(cat "$WORK/resp")"
[ ! -e "$orphan" ] || fail "the orphaned upload directory is still there"
[ "$(get "/v1/jobs/${ids[1]}/result")" = 200 ] || fail "an old job's files were removed"
echo "service_nodes: ok"
