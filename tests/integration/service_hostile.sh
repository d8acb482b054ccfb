#!/usr/bin/env bash
# service_hostile: every bad request is answered with the right 4xx problem+json (same
# status in the body) and the server keeps serving: truncated .glb, wrong Content-Type,
# oversized body, bad JSON params, unknown and out-of-range params, a .gltf whose buffer URI
# leaves its directory, an unsafe multipart file name, a model without TEXCOORD_0, no model
# part, an empty body, unknown routes and methods, unknown jobs; and nothing of a refused
# upload stays on disk.
source "$(dirname "$0")/service_common.bash"
SPOT="$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
make_fixtures "$WORK/fx"
start_server --max-upload-bytes 1000000

head -c 5000 "$SPOT" >"$WORK/truncated.glb"
expect_problem 400 "$(post_glb "$WORK/truncated.glb" "method=input")" malformed-model

expect_problem 415 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X POST \
  -H 'Content-Type: text/plain' --data-binary "@$SPOT" "$BASE/v1/jobs")" unsupported-media-type
expect_problem 415 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X POST \
  --data-binary "@$SPOT" "$BASE/v1/jobs")" unsupported-media-type

head -c 1100000 /dev/zero >"$WORK/big.glb"
expect_problem 413 "$(post_glb "$WORK/big.glb" "")" body-too-large
# Without Content-Length (chunked), the limit is enforced while streaming.
expect_problem 413 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X POST \
  -H 'Content-Type: model/gltf-binary' -H 'Transfer-Encoding: chunked' --data-binary "@$WORK/big.glb" \
  "$BASE/v1/jobs")" body-too-large

multipart() {
  curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' "$@" "$BASE/v1/jobs"
}
expect_problem 400 "$(multipart -F "model=@$SPOT" -F 'params={"method": "input",')" invalid-params
expect_problem 400 "$(multipart -F "model=@$SPOT" -F 'params={"method":"input","iteration":5}')" invalid-params
grep -q "unknown key 'iteration'" "$WORK/resp" || fail "unknown key not named: $(cat "$WORK/resp")"
expect_problem 400 "$(post_glb "$SPOT" "method=input&colour=red")" invalid-params
expect_problem 400 "$(post_glb "$SPOT" "method=fastest")" invalid-params
expect_problem 400 "$(post_glb "$SPOT" "relative_cost=9")" invalid-params
expect_problem 400 "$(post_glb "$SPOT" "relative_cost=0.5&texture_width=64&texture_height=64")" invalid-params

# A .gltf whose buffer URI is ../secret.bin: the loader refuses to leave the upload.
echo secret >"$WORK/secret.bin"
expect_problem 400 "$(multipart -F "model=@$WORK/fx/escape.gltf" -F "files=@$WORK/fx/tex.png")" malformed-model
grep -q 'secret.bin' "$WORK/resp" || fail "escape refusal does not name the URI: $(cat "$WORK/resp")"
# A multipart file name that climbs out of the job directory.
expect_problem 400 "$(multipart -F "model=@$WORK/fx/quad.gltf" -F "files=@$WORK/fx/quad.bin;filename=../quad.bin")" unsafe-file-name
expect_problem 400 "$(multipart -F "model=@$WORK/fx/quad.gltf" -F "files=@$WORK/fx/quad.bin;filename=/etc/quad.bin")" unsafe-file-name
# The .gltf without its .bin: the missing file is named.
expect_problem 400 "$(multipart -F "model=@$WORK/fx/quad.gltf" -F "files=@$WORK/fx/tex.png")"
grep -q 'quad.bin' "$WORK/resp" || fail "missing file not named: $(cat "$WORK/resp")"
expect_problem 400 "$(multipart -F 'params={"method":"input"}')" bad-multipart
expect_problem 400 "$(multipart -F "model=@$SPOT" -F 'colour=red')" bad-multipart
expect_problem 415 "$(multipart -F "model=@$WORK/fx/tex.png")" unsupported-media-type

# JSON nesting 100,000 deep (200 KB) overflowed the connection thread's stack: raw .glb,
# multipart .gltf, params part, and `texopt info` on the same file.
/usr/bin/python3 - "$WORK/fx/quad.gltf" "$WORK/deep" <<'PY'
import json, struct, sys
doc = open(sys.argv[1]).read()
deep = '{"extras":' + "[" * 100000 + "]" * 100000 + "," + doc[1:]
open(sys.argv[2] + ".gltf", "w").write(deep)
j = deep.encode() + b" " * (-len(deep) % 4)
open(sys.argv[2] + ".glb", "wb").write(struct.pack("<III", 0x46546C67, 2, 20 + len(j)) + struct.pack("<I", len(j)) + b"JSON" + j)
open(sys.argv[2] + "-params.json", "w").write('{"seed":' + "[" * 5000 + "]" * 5000 + "}")
PY
expect_problem 400 "$(post_glb "$WORK/deep.glb" "")" malformed-model
grep -q 'JSON nests deeper than 128' "$WORK/resp" || fail "deep .glb refusal: $(cat "$WORK/resp")"
expect_problem 400 "$(multipart -F "model=@$WORK/deep.gltf" -F "files=@$WORK/fx/quad.bin" -F "files=@$WORK/fx/tex.png")" malformed-model
expect_problem 400 "$(multipart -F "model=@$WORK/fx/quad.gltf" -F "files=@$WORK/fx/quad.bin" -F "files=@$WORK/fx/tex.png" \
  -F "params=<$WORK/deep-params.json")" invalid-params
grep -q 'nests deeper than' "$WORK/resp" || fail "deep params refusal: $(cat "$WORK/resp")"
set +e
"$TEXOPT_BIN" info "$WORK/deep.gltf" >"$WORK/info.txt" 2>&1
rc=$?
set -e
[ "$rc" = 1 ] && grep -q 'JSON nests deeper than 128' "$WORK/info.txt" || fail "texopt info on the deep file: rc $rc, $(cat "$WORK/info.txt")"
# Params JSON with text after it or a key twice.
expect_problem 400 "$(multipart -F "model=@$SPOT" -F 'params={"method":"input"} trailing')" invalid-params
expect_problem 400 "$(multipart -F "model=@$SPOT" -F 'params={"method":"input","method":"arap"}')" invalid-params
grep -q "key 'method' given twice" "$WORK/resp" || fail "duplicate key refusal: $(cat "$WORK/resp")"

# A texture whose header is sound but whose pixels do not decode: the upload check reads
# headers only (a PNG may declare 256 Mpx in 250 KB), so the job is accepted and fails.
/usr/bin/python3 - "$WORK/fx" "$WORK/corrupt.glb" <<'PY'
import json, struct, sys
fx, out = sys.argv[1], sys.argv[2]
doc = json.load(open(f"{fx}/quad.gltf"))
binary, png = open(f"{fx}/quad.bin", "rb").read(), bytearray(open(f"{fx}/tex.png", "rb").read())
at = 8
while at + 12 <= len(png):
    n = struct.unpack(">I", png[at:at + 4])[0]
    if png[at + 4:at + 8] == b"IDAT":
        png[at + 8:at + 8 + n] = b"\x5a" * n
    at += 12 + n
body = binary + bytes(png) + b"\0" * (-len(png) % 4)
doc["buffers"] = [{"byteLength": len(body)}]
doc["bufferViews"].append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(png)})
doc["images"] = [{"bufferView": 3, "mimeType": "image/png"}]
j = json.dumps(doc).encode()
j += b" " * (-len(j) % 4)
open(out, "wb").write(struct.pack("<III", 0x46546C67, 2, 28 + len(j) + len(body)) + struct.pack("<II", len(j), 0x4E4F534A)
                      + j + struct.pack("<II", len(body), 0x004E4942) + body)
PY
[ "$(post_glb "$WORK/corrupt.glb" "method=input")" = 202 ] || fail "corrupt texture upload: $(cat "$WORK/resp")"
corrupt=$(json "$WORK/resp" 'd["id"]')
wait_state "$corrupt" failed 60
curl -s -o "$WORK/corrupt.json" "$BASE/v1/jobs/$corrupt"
[ "$(json "$WORK/corrupt.json" 'd["problem"]["type"]')" = urn:texopt:problem:malformed-model ] ||
  fail "corrupt texture job: $(cat "$WORK/corrupt.json")"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X DELETE "$BASE/v1/jobs/$corrupt")" = 204 ] || fail "delete the failed job"

# Valid but unusable: no TEXCOORD_0 on a textured primitive.
expect_problem 422 "$(post_glb "$WORK/fx/nouv.glb" "method=input")" unsupported-model
grep -qi 'texcoord' "$WORK/resp" || fail "422 does not say what is missing: $(cat "$WORK/resp")"

: >"$WORK/empty.glb"
code=$(post_glb "$WORK/empty.glb" "")
[ "$code" = 400 ] || fail "empty body answered $code"

# Routes, methods, ids.
expect_problem 404 "$(get /v1/nothing)" not-found
expect_problem 404 "$(get /v1/jobs/0123456789abcdef0123456789abcdef)" job-not-found
expect_problem 404 "$(get /v1/jobs/../../etc/passwd)"
expect_problem 405 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X PUT "$BASE/v1/jobs")" method-not-allowed
grep -qi '^allow: GET, HEAD, POST, OPTIONS' "$WORK/headers" || fail "405 without Allow"
expect_problem 405 "$(curl -s -o "$WORK/resp" -D "$WORK/headers" -w '%{http_code}' -X POST "$BASE/healthz")" method-not-allowed
expect_problem 400 "$(get '/v1/jobs?limit=1000')" bad-query

# A 300 KB URL or header: problem+json from texoptd (libmicrohttpd's own answer was HTML).
# raw_request URL_PAD HEADER_PAD: a GET with that many bytes more in its URL and in one
# header, sent as is (too long for a command line); body and headers as `get` leaves them.
raw_request() {
  /usr/bin/python3 - "${BASE##*:}" "$1" "$2" "$WORK/resp" "$WORK/headers" <<'PY'
import socket, sys
port, url_pad, header_pad, body_path, headers_path = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5]
s = socket.create_connection(("127.0.0.1", port))
s.sendall(b"GET /healthz" + b"a" * url_pad + b" HTTP/1.1\r\nHost: x\r\nConnection: close\r\nX-Pad: " + b"a" * header_pad + b"\r\n\r\n")
data = b""
while chunk := s.recv(65536):
    data += chunk
head, _, body = data.partition(b"\r\n\r\n")
open(headers_path, "wb").write(head.replace(b"\r\n", b"\n") + b"\n")
open(body_path, "wb").write(body)
print(head.split(b" ")[1].decode())
PY
}
expect_problem 414 "$(raw_request 300000 0)" uri-too-long
expect_problem 431 "$(raw_request 0 300000)" headers-too-large

# Still serving, and nothing of the refused uploads was left behind.
[ "$(get /healthz)" = 200 ] || fail "healthz after hostile input"
[ "$(post_glb "$SPOT" "method=input")" = 202 ] || fail "a good upload after hostile input: $(cat "$WORK/resp")"
id=$(json "$WORK/resp" 'd["id"]')
wait_state "$id" succeeded 120
left=$(ls "$DATA/jobs")
[ "$left" = "$id" ] || fail "refused uploads left directories: $left"
# A body on GET, OPTIONS and DELETE (axios sends `{}` with DELETE) is read and dropped.
[ "$(get "/v1/jobs/$id" -H 'Content-Type: application/json' --data-binary '{}' -X GET)" = 200 ] ||
  fail "GET with a body: $(cat "$WORK/resp")"
[ "$(curl -s -o /dev/null -w '%{http_code}' -X OPTIONS -d '{}' "$BASE/v1/jobs")" = 204 ] || fail "OPTIONS with a body"
code=$(curl -s -o "$WORK/resp" -w '%{http_code}' -X DELETE -H 'Content-Type: application/json' -d '{}' "$BASE/v1/jobs/$id")
[ "$code" = 204 ] || fail "DELETE with a JSON body answered $code"
grep -q 'status="400"' <(curl -s "$BASE/metrics") || fail "metrics do not count the 400s"
stop_server TERM || fail "texoptd did not exit cleanly"
echo "service_hostile: ok"
