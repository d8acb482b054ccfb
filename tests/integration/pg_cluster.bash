# pg_cluster.bash - a throw-away PostgreSQL cluster for service tests and benchmarks (sourced,
# not a test itself; sources service_common.bash).
#
# pg_start        initdb into $WORK/pg (as the unprivileged user nobody when run as root:
#                 PostgreSQL refuses to run as root), then starts it on a free port with
#                 its unix socket in $WORK/pg and no TCP listener; sets PG_URL.
# pg_stop         stops it at once (as a crash would), when running.
# pg_start_again  starts the stopped cluster on the same port.
# PG_FSYNC=on makes commits durable (off by default: a test's cluster is thrown away).
source "$(dirname "${BASH_SOURCE[0]}")/service_common.bash"

PG_BIN=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)
PG_DIR="$WORK/pg"
PG_PORT=""
PG_URL=""

pg_as() {
  if [ "$(id -u)" -eq 0 ]; then runuser -u nobody -- "$@"; else "$@"; fi
}

pg_start_again() {
  pg_as "$PG_BIN/pg_ctl" -D "$PG_DIR/data" -l "$PG_DIR/log" -w -t 30 \
    -o "-p $PG_PORT -k $PG_DIR -c listen_addresses= -c fsync=${PG_FSYNC:-off} -c max_connections=200" start >/dev/null
}

pg_start() {
  [ -n "$PG_BIN" ] && [ -x "$PG_BIN/initdb" ] || fail "PostgreSQL's server is not installed (scripts/setup installs it)"
  mkdir -p "$PG_DIR"
  chmod 755 "$WORK" # the cluster's user must reach $WORK/pg
  [ "$(id -u)" -eq 0 ] && chown nobody "$PG_DIR"
  pg_as "$PG_BIN/initdb" -D "$PG_DIR/data" -U texopt --auth=trust -E UTF8 --no-sync >"$WORK/initdb.log" 2>&1 ||
    fail "initdb failed: $(tail -n 5 "$WORK/initdb.log")"
  PG_PORT=$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
  pg_start_again || fail "PostgreSQL did not start: $(tail -n 5 "$PG_DIR/log")"
  PG_URL="postgresql:///postgres?host=$PG_DIR&port=$PG_PORT&user=texopt"
}

pg_stop() {
  if [ -n "$PG_PORT" ] && [ -f "$PG_DIR/data/postmaster.pid" ]; then
    pg_as "$PG_BIN/pg_ctl" -D "$PG_DIR/data" -m immediate -w stop >/dev/null 2>&1 || true
  fi
}
