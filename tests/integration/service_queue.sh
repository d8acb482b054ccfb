#!/usr/bin/env bash
# service_queue: a full queue answers 503 + Retry-After (problem+json) before reading the
# upload and /readyz turns 503; once a slot frees (a queued job is canceled) uploads are
# accepted again and /readyz is 200. With a memory budget below every job's estimate, two
# workers run one job at a time.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
start_server --workers 1 --queue-limit 1

[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "first upload"
running=$(json "$WORK/resp" 'd["id"]')
wait_state "$running" running 60
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "second upload"
queued=$(json "$WORK/resp" 'd["id"]')

expect_problem 503 "$(post_glb "$SPOT" "method=input")" queue-full
grep -qi '^retry-after: [1-9]' "$WORK/headers" || fail "503 without Retry-After"
expect_problem 503 "$(get /readyz)" queue-full
[ "$(get /healthz)" = 200 ] || fail "healthz while the queue is full"
[ "$(ls "$DATA/jobs" | wc -l)" = 2 ] || fail "the refused upload left a directory"

[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$queued")" = 200 ] || fail "cancel queued"
[ "$(get /readyz)" = 200 ] || fail "readyz after a slot freed"
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "upload after a slot freed"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$running")" = 202 ] || fail "cancel running"
wait_state "$running" canceled 60
grep -q '^texopt_http_requests_total{route="/v1/jobs",status="503"} 1$' <(curl -s "$BASE/metrics") || fail "503 not counted"
stop_server TERM || fail "texoptd did not exit cleanly"

# The memory budget: two workers, but a budget smaller than any job's estimate, so a second
# job waits (queued) while the first runs alone, and runs once the first is done.
rm -rf "$DATA"
start_server --workers 2 --memory-budget 1000
[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "first job under the budget"
first=$(json "$WORK/resp" 'd["id"]')
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "second job under the budget"
second=$(json "$WORK/resp" 'd["id"]')
wait_state "$first" running 60
sleep 1
[ "$(get "/v1/jobs/$second")" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = queued ] ||
  fail "a second job ran beside the first past the memory budget: $(cat "$WORK/resp")"
grep -q '^texopt_workers_busy 1$' <(curl -s "$BASE/metrics") || fail "more than one worker busy"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$first")" = 202 ] || fail "cancel the first"
wait_state "$second" succeeded 120
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_queue: ok"
