#!/usr/bin/env bash
# info_models: `texopt info` on the bundled models (tests/data spot and Fox). Checks the JSON
# fields against an independent reading of each .glb with numpy (triangle count, UV vertices
# = distinct (position, uv), points = distinct positions, texel area), the covered-texel
# count against the texel area (no overlaps in these layouts), and the exit codes and
# messages of usage errors and broken files.
set -euo pipefail
: "${TEXOPT_BIN:?TEXOPT_BIN must point to the texopt executable}"
: "${TEXOPT_SOURCE_DIR:?TEXOPT_SOURCE_DIR must point to the source tree}"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

check_model() {
    local model=$1
    "$TEXOPT_BIN" info "$model" > "$WORK/info.json" 2> "$WORK/err" ||
        fail "texopt info $model exited $?: $(cat "$WORK/err")"
    /usr/bin/python3 - "$model" "$WORK/info.json" <<'EOF'
import json, struct, sys
import numpy as np

path, info_path = sys.argv[1], sys.argv[2]
info = json.load(open(info_path))

# Independent reading of the GLB: JSON chunk, BIN chunk, accessors of every primitive.
data = open(path, 'rb').read()
magic, version, length = struct.unpack_from('<III', data, 0)
assert magic == 0x46546C67 and version == 2
jlen, _ = struct.unpack_from('<II', data, 12)
doc = json.loads(data[20:20 + jlen])
blen, _ = struct.unpack_from('<II', data, 20 + jlen)
binary = data[28 + jlen:28 + jlen + blen]
ctypes = {5120: np.int8, 5121: np.uint8, 5122: np.int16, 5123: np.uint16, 5125: np.uint32, 5126: np.float32}
ncomp = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3, 'VEC4': 4}

def accessor(i):
    a = doc['accessors'][i]
    bv = doc['bufferViews'][a['bufferView']]
    dt = np.dtype(ctypes[a['componentType']])
    n = ncomp[a['type']]
    stride = bv.get('byteStride', dt.itemsize * n)
    start = bv.get('byteOffset', 0) + a.get('byteOffset', 0)
    rows = [np.frombuffer(binary, dt, n, start + k * stride) for k in range(a['count'])]
    out = np.array(rows)
    if a.get('normalized'):
        out = out.astype(np.float64) / np.iinfo(dt).max
    return out

tris, keys_uv, keys_pt, texel_area = 0, set(), set(), 0.0
dom = info['domains'][0]
W, H = dom['frame']['width'], dom['frame']['height']
for mesh in doc['meshes']:
    for prim in mesh['primitives']:
        attrs = prim['attributes']
        if 'TEXCOORD_0' not in attrs or prim.get('mode', 4) != 4:
            continue
        pos = accessor(attrs['POSITION'])
        uv = accessor(attrs['TEXCOORD_0']).astype(np.float64)
        idx = accessor(prim['indices']).reshape(-1) if 'indices' in prim else np.arange(len(pos))
        tri = idx.reshape(-1, 3)
        tris += len(tri)
        used = np.unique(idx)
        for v in used:
            keys_pt.add(tuple(pos[v].tolist()))
            keys_uv.add(tuple(pos[v].tolist()) + tuple(uv[v].tolist()))
        p = uv[tri] * np.array([W, H])
        cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
        texel_area += float(np.abs(cross).sum()) / 2

def check(cond, what):
    if not cond:
        sys.exit(f"FAIL {path}: {what}")

check(info['file'] == path, 'file field')
check(info['triangles'] == tris, f"triangles {info['triangles']} != {tris}")
check(len(info['domains']) == 1, 'one texture domain')
check(dom['triangles'] == tris, 'domain triangles')
check(dom['uv_vertices'] == len(keys_uv), f"uv_vertices {dom['uv_vertices']} != {len(keys_uv)}")
check(dom['points'] == len(keys_pt), f"points {dom['points']} != {len(keys_pt)}")
check(dom['charts'] >= 1 and dom['charts'] <= dom['triangles'], 'chart count')
check(abs(dom['texel_area'] - texel_area) <= 1e-6 * texel_area, f"texel_area {dom['texel_area']} != {texel_area}")
check(dom['overlap_texels'] == 0, 'no overlaps in this layout')
check(abs(dom['covered_texels'] - texel_area) < 0.01 * texel_area, 'covered texels ~ texel area')
check(abs(dom['packing_efficiency'] - dom['covered_texels'] / (W * H)) < 1e-12, 'packing efficiency')
tex = dom['textures']
check(len(tex) >= 1 and tex[0]['slot'] == 'baseColor', 'base colour texture listed')
check(tex[0]['width'] == W and tex[0]['height'] == H and tex[0]['channels'] in (3, 4), 'texture size')
check(dom['wrap']['s'] in ('repeat', 'clamp', 'mirror'), 'wrap names')
for k in ('flipped', 'overlapping', 'degenerate', 'degenerate_3d', 'degenerate_uv', 'wrapped',
          'mirrored_charts', 'folded_charts'):
    check(isinstance(dom[k], int) and 0 <= dom[k] <= dom['triangles'], k)
print(f"ok {path}: {tris} triangles, {len(keys_uv)} UV vertices, {len(keys_pt)} points, "
      f"{dom['charts']} charts, {dom['covered_texels']} covered texels")
EOF
}

check_model "$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb"
check_model "$TEXOPT_SOURCE_DIR/tests/data/Fox/Fox.glb"

# --pretty prints the same document, indented.
"$TEXOPT_BIN" info --pretty "$TEXOPT_SOURCE_DIR/tests/data/Fox/Fox.glb" > "$WORK/pretty.json"
"$TEXOPT_BIN" info "$TEXOPT_SOURCE_DIR/tests/data/Fox/Fox.glb" > "$WORK/flat.json"
[ "$(wc -l < "$WORK/pretty.json")" -gt 10 ] || fail "--pretty is not indented"
/usr/bin/python3 -c 'import json,sys; sys.exit(json.load(open(sys.argv[1])) != json.load(open(sys.argv[2])))' \
    "$WORK/pretty.json" "$WORK/flat.json" || fail "--pretty differs from the one-line document"

# Usage errors exit 2, engine refusals exit 1 with the path and a reason, never a crash.
expect_exit() {
    local want=$1; shift
    set +e
    "$TEXOPT_BIN" info "$@" > "$WORK/out" 2> "$WORK/err"
    local got=$?
    set -e
    [ "$got" = "$want" ] || fail "texopt info $* exited $got, expected $want: $(cat "$WORK/err")"
}
expect_exit 0 --help
grep -q "usage: texopt info" "$WORK/out" || fail "--help prints no usage"
expect_exit 2
expect_exit 2 --bogus "$TEXOPT_SOURCE_DIR/tests/data/Fox/Fox.glb"
expect_exit 2 a.glb b.glb
expect_exit 1 "$WORK/missing.glb"
grep -q "missing.glb" "$WORK/err" || fail "missing file not named: $(cat "$WORK/err")"
head -c 5000 "$TEXOPT_SOURCE_DIR/tests/data/spot/spot.glb" > "$WORK/truncated.glb"
expect_exit 1 "$WORK/truncated.glb"
grep -q "^texopt info: .*truncated.glb: " "$WORK/err" || fail "truncated file message: $(cat "$WORK/err")"
[ ! -s "$WORK/out" ] || fail "a failed info printed to stdout"
echo "info_models: ok"
