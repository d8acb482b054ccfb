# service_common.bash - helpers the service_*.sh integration tests source (not a test itself).
#
# start_server [texoptd flags...]  starts $TEXOPTD_BIN on a free loopback port (--port 0,
#                                  the port comes back through --port-file) with a data
#                                  directory under $WORK; sets SERVER_PID and BASE.
# stop_server [signal]             stops it (default TERM) and waits; returns its exit code.
# The EXIT trap kills a server still running (by its pid) and removes $WORK.
set -euo pipefail

: "${TEXOPTD_BIN:?TEXOPTD_BIN must name the texoptd binary}"
: "${TEXOPT_SOURCE_DIR:?TEXOPT_SOURCE_DIR must name the source tree}"
WORK=$(mktemp -d "${TMPDIR:-/tmp}/texopt-service-test.XXXXXX")
DATA="$WORK/data"
SERVER_PID=""
BASE=""
AUTH=() # curl arguments every helper request carries (set for a token)

cleanup() {
  if [ -n "$SERVER_PID" ] && kill -0 "$SERVER_PID" 2>/dev/null; then
    kill -9 "$SERVER_PID" 2>/dev/null || true
    wait "$SERVER_PID" 2>/dev/null || true
  fi
  if [ "${KEEP_WORK:-0}" = 1 ]; then echo "kept $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT

fail() {
  echo "FAIL: $*" >&2
  if [ -f "$WORK/server.log" ]; then echo "--- server log (tail)" >&2; tail -n 30 "$WORK/server.log" >&2; fi
  exit 1
}

start_server() {
  rm -f "$WORK/port"
  "$TEXOPTD_BIN" --bind 127.0.0.1 --port 0 --port-file "$WORK/port" --data-dir "$DATA" "$@" \
    >>"$WORK/server.log" 2>&1 &
  SERVER_PID=$!
  for _ in $(seq 1 150); do
    [ -s "$WORK/port" ] && break
    kill -0 "$SERVER_PID" 2>/dev/null || fail "texoptd exited at start"
    sleep 0.1
  done
  [ -s "$WORK/port" ] || fail "texoptd did not start within 15 s"
  BASE="http://127.0.0.1:$(cat "$WORK/port")"
}

stop_server() {
  local sig="${1:-TERM}" rc=0
  kill "-$sig" "$SERVER_PID"
  wait "$SERVER_PID" 2>/dev/null || rc=$?
  SERVER_PID=""
  return $rc
}

# json FILE EXPR: prints a field of a JSON file with python3 (EXPR uses `d`).
json() {
  /usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))' "$1" "$2"
}

# post_glb FILE QUERY [curl args...]: uploads FILE raw; body to $WORK/resp, headers to
# $WORK/headers; prints the status.
post_glb() {
  local file="$1" query="$2"
  shift 2
  curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X POST "${AUTH[@]}" \
    -H 'Content-Type: model/gltf-binary' --data-binary "@$file" "$@" "$BASE/v1/jobs${query:+?$query}"
}

# get PATH [curl args...]: GET to $WORK/resp; prints the status.
get() {
  local path="$1"
  shift
  curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "${AUTH[@]}" "$@" "$BASE$path"
}

# wait_state ID STATE SECONDS: polls the job until it has STATE (fails on another final state).
wait_state() {
  local id="$1" want="$2" deadline=$((SECONDS + $3)) state=""
  while [ $SECONDS -lt $deadline ]; do
    curl -s -o "$WORK/poll" "${AUTH[@]}" "$BASE/v1/jobs/$id" || true
    state=$(json "$WORK/poll" 'd["state"]' 2>/dev/null || echo "?")
    [ "$state" = "$want" ] && return 0
    case "$state" in succeeded|failed|canceled) fail "job $id ended $state, wanted $want: $(cat "$WORK/poll")" ;; esac
    sleep 0.05
  done
  fail "job $id is still '$state' after $3 s (wanted $want)"
}

# expect_problem STATUS GOT [SLUG]: the last answer ($WORK/resp, $WORK/headers) is a
# problem+json with that status (in the body too) and, when given, that type slug.
expect_problem() {
  local want="$1" got="$2" slug="${3:-}"
  [ "$got" = "$want" ] || fail "expected HTTP $want, got $got: $(cat "$WORK/resp")"
  grep -qi '^content-type: application/problem+json' "$WORK/headers" ||
    fail "HTTP $got is not application/problem+json"
  [ "$(json "$WORK/resp" 'd["status"]')" = "$want" ] || fail "problem status differs from HTTP $want"
  if [ -n "$slug" ]; then
    [ "$(json "$WORK/resp" 'd["type"]')" = "urn:texopt:problem:$slug" ] ||
      fail "expected problem type $slug, got $(cat "$WORK/resp")"
  fi
}

# make_fixtures DIR: small generated models (a textured quad as .gltf + .bin + .png, the
# same with a buffer URI leaving its directory, and as .glb without TEXCOORD_0).
make_fixtures() {
  /usr/bin/python3 - "$1" <<'PY'
import json, struct, sys, zlib, os
out = sys.argv[1]
os.makedirs(out, exist_ok=True)

def png(w, h):
    rows = b"".join(b"\x00" + bytes([(x * 37 + y * 91) % 256 for x in range(w) for _ in range(3)]) for y in range(h))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))

pos = [0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]
uv = [0, 1, 1, 1, 1, 0, 0, 0]
idx = [0, 1, 2, 0, 2, 3]

def document(with_uv, buffer_uri, byte_length):
    attributes = {"POSITION": 0}
    if with_uv:
        attributes["TEXCOORD_0"] = 1
    views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48},
             {"buffer": 0, "byteOffset": 48, "byteLength": 32},
             {"buffer": 0, "byteOffset": 80, "byteLength": 12}]
    return {
        "asset": {"version": "2.0"},
        "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": 2, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "tex.png"}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}],
        "bufferViews": views,
        "buffers": [dict({"byteLength": byte_length}, **({"uri": buffer_uri} if buffer_uri else {}))],
    }

binary = struct.pack("<12f", *pos) + struct.pack("<8f", *uv) + struct.pack("<6H", *idx)
binary += b"\x00" * (-len(binary) % 4)
open(f"{out}/quad.bin", "wb").write(binary)
open(f"{out}/tex.png", "wb").write(png(16, 16))
json.dump(document(True, "quad.bin", len(binary)), open(f"{out}/quad.gltf", "w"))
json.dump(document(True, "../secret.bin", len(binary)), open(f"{out}/escape.gltf", "w"))

# .glb without TEXCOORD_0: the image lives in the BIN chunk.
image = png(16, 16)
body = binary + image + b"\x00" * (-len(image) % 4)
doc = document(False, None, len(body))
doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(image)})
doc["images"] = [{"bufferView": 3, "mimeType": "image/png"}]
text = json.dumps(doc).encode()
text += b" " * (-len(text) % 4)
glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(body))
glb += struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(body), 0x004E4942) + body
open(f"{out}/nouv.glb", "wb").write(glb)
PY
}
