#!/usr/bin/env bash
# service_disk_full: on a full disk (a 16 MB tmpfs as the data directory, filled up) no
# state change is reported that is not on disk. /readyz says not ready and an upload is
# refused with 503 + Retry-After; canceling a queued job answers 503 and it stays queued;
# a running job that is canceled stays "running" until its end can be written. Once space
# is back the end is written within seconds, and after a kill -9 and a restart both jobs
# are still canceled (before, the canceled job ran again). Needs root for the mount (CI
# runs as root); prints a skip otherwise.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
if [ "$(id -u)" != 0 ]; then echo "service_disk_full: skipped (needs root to mount a tmpfs)"; exit 0; fi
mkdir -p "$DATA"
mount -t tmpfs -o size=16m tmpfs "$DATA" || fail "cannot mount a tmpfs on $DATA"
cleanup() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -9 "$SERVER_PID" 2>/dev/null || true
    wait "$SERVER_PID" 2>/dev/null || true
  fi
  umount "$DATA" 2>/dev/null || true
  rm -rf "$WORK"
}
start_server --workers 1

[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "long upload"
long=$(json "$WORK/resp" 'd["id"]')
[ "$(post_glb "$SPOT" "method=perceptual")" = 202 ] || fail "queued upload"
queued=$(json "$WORK/resp" 'd["id"]')
wait_state "$long" running 60
dd if=/dev/zero of="$DATA/fill" bs=64k 2>/dev/null || true

expect_problem 503 "$(get /readyz)" storage-full
grep -qi '^retry-after: ' "$WORK/headers" || fail "not-ready without Retry-After"
expect_problem 503 "$(post_glb "$SPOT" "method=input")" storage-full
grep -qi '^retry-after: ' "$WORK/headers" || fail "refused upload without Retry-After"
expect_problem 503 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$queued")" \
  storage-full
grep -qi '^retry-after: ' "$WORK/headers" || fail "unsaved cancel without Retry-After"
[ "$(get "/v1/jobs/$queued")" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = queued ] ||
  fail "a cancel that is not on disk was reported: $(cat "$WORK/resp")"

[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$long")" = 202 ] || fail "cancel the running job"
for _ in $(seq 100); do grep -q "event=persist job=$long state=canceled" "$WORK/server.log" && break; sleep 0.1; done
grep -q "event=persist job=$long state=canceled" "$WORK/server.log" || fail "the end of the canceled run was written"
[ "$(get "/v1/jobs/$long")" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = running ] ||
  fail "an end that is not on disk was reported: $(cat "$WORK/resp")"

rm -f "$DATA/fill"
wait_state "$long" canceled 10
[ "$(get /readyz)" = 200 ] || fail "not ready once space is back: $(cat "$WORK/resp")"
# The worker may have taken it already: canceled at once (200) or at its next checkpoint.
code=$(curl -s -o "$WORK/resp" -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$queued")
[ "$code" = 200 ] || [ "$code" = 202 ] || fail "cancel with space: $code"
wait_state "$queued" canceled 30

stop_server KILL || true
start_server --workers 1
sleep 1
for id in "$long" "$queued"; do
  [ "$(get "/v1/jobs/$id")" = 200 ] && [ "$(json "$WORK/resp" 'd["state"]')" = canceled ] ||
    fail "job $id is not canceled after a restart: $(cat "$WORK/resp")"
done
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_disk_full: ok"
