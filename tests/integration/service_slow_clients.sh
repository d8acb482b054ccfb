#!/usr/bin/env bash
# service_slow_clients: request heads that trickle cannot starve the server. With 64
# connections at most, 100 sockets each sending a header byte a second (reconnecting when
# closed) leave /healthz answering every probe (before: every slot taken, probes refused for
# the 120 s timeout); a few heads under the caps are cut at --header-timeout however they
# trickle; and an ordinary request still works afterwards.
source "$(dirname "$0")/service_common.bash"
SLOW="$TEXOPT_SOURCE_DIR/tests/integration/slow_clients.py"
start_server --max-connections 64 --header-timeout 2
port=${BASE##*:}

/usr/bin/python3 "$SLOW" --port "$port" --sockets 100 --seconds 5 --probe-source 127.0.0.2 >"$WORK/flood.json" ||
  fail "slow_clients.py"
[ "$(json "$WORK/flood.json" 'd["probes_failed"]')" = 0 ] && [ "$(json "$WORK/flood.json" 'd["probes_ok"]')" -ge 10 ] ||
  fail "/healthz under 100 trickling sockets: $(cat "$WORK/flood.json")"

# Four heads, under every cap: only the deadline cuts them (2 s, swept each second).
/usr/bin/python3 "$SLOW" --port "$port" --sockets 4 --seconds 4.5 --probe-source 127.0.0.2 >"$WORK/late.json" ||
  fail "slow_clients.py"
[ "$(json "$WORK/late.json" 'd["closed_by_server"]')" -ge 4 ] || fail "late heads not cut: $(cat "$WORK/late.json")"
grep -q 'event=slow-heads cut=' "$WORK/server.log" || fail "no slow-heads line in the log"

[ "$(get /v1/jobs)" = 200 ] || fail "an ordinary request after the load"
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_slow_clients: ok"
