"""slow_clients.py - a slowloris load against texoptd, with a health probe alongside.

Holds SOCKETS connections that send a request head one byte every TRICKLE seconds (each one
that the server closes is opened again at once, as an attacker would), while a probe asks
GET PROBE_PATH every 0.2 s on a fresh connection with a 2 s deadline. Prints one JSON line:
probes answered 200 and failed, probe latency p50/p99/max in ms, trickling connections the
server closed, connections refused or reset, and how many trickled at the end.
Used by tests/integration/service_slow_clients.sh and scripts/bench.d/service_slow_clients.
"""
import argparse, json, selectors, socket, threading, time

ap = argparse.ArgumentParser()
ap.add_argument("--port", type=int, required=True)
ap.add_argument("--sockets", type=int, default=520)
ap.add_argument("--seconds", type=float, default=20)
ap.add_argument("--trickle", type=float, default=1.0)
ap.add_argument("--source", default="127.0.0.1", help="address the trickling sockets come from")
ap.add_argument("--probe-source", default="127.0.0.1")
ap.add_argument("--probe-path", default="/healthz")
a = ap.parse_args()

stop = time.monotonic() + a.seconds
stats = {"closed_by_server": 0, "refused": 0}
probes = []          # latency in ms, or None for a failure


def probe():
    while time.monotonic() < stop:
        t0 = time.monotonic()
        try:
            s = socket.socket()
            s.settimeout(2)
            s.bind((a.probe_source, 0))
            s.connect(("127.0.0.1", a.port))
            s.sendall(f"GET {a.probe_path} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n".encode())
            data = b""
            while True:
                chunk = s.recv(4096)
                if not chunk:
                    break
                data += chunk
            s.close()
            ok = data.startswith(b"HTTP/1.1 200")
            probes.append((time.monotonic() - t0) * 1e3 if ok else None)
        except OSError:
            probes.append(None)
        time.sleep(max(0, 0.2 - (time.monotonic() - t0)))


def open_trickler(sel):
    s = socket.socket()
    s.setblocking(False)
    try:
        s.bind((a.source, 0))
        s.connect_ex(("127.0.0.1", a.port))
    except OSError:
        stats["refused"] += 1
        s.close()
        return
    sel.register(s, selectors.EVENT_READ, {"sent": 0, "next": time.monotonic()})


head = b"GET /v1/jobs HTTP/1.1\r\nHost: x\r\nX-Slow: " + b"a" * 100000
t = threading.Thread(target=probe)
t.start()
sel = selectors.DefaultSelector()
for _ in range(a.sockets):
    open_trickler(sel)
while time.monotonic() < stop:
    for key, _ in sel.select(timeout=0.05):
        s = key.fileobj
        try:
            gone = s.recv(4096) == b""
        except OSError:
            gone = True
        if gone:
            # Closed before a response: cut by the server (or refused at accept, reset).
            stats["closed_by_server" if key.data["sent"] > 0 else "refused"] += 1
            sel.unregister(s)
            s.close()
            open_trickler(sel)
    now = time.monotonic()
    for key in list(sel.get_map().values()):
        d = key.data
        if now >= d["next"]:
            try:
                key.fileobj.send(head[d["sent"]:d["sent"] + 1])
                d["sent"] += 1
            except OSError:
                pass
            d["next"] = now + a.trickle
t.join()
held = len(sel.get_map())
ok = sorted(p for p in probes if p is not None)
pct = lambda q: round(ok[min(len(ok) - 1, int(len(ok) * q))], 1) if ok else None
print(json.dumps({"sockets": a.sockets, "seconds": a.seconds, "probes_ok": len(ok),
                  "probes_failed": len(probes) - len(ok), "probe_ms_p50": pct(0.5), "probe_ms_p99": pct(0.99),
                  "probe_ms_max": round(ok[-1], 1) if ok else None, "closed_by_server": stats["closed_by_server"],
                  "refused_or_reset": stats["refused"], "trickling_at_end": held}))
