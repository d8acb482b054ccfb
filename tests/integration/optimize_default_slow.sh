#!/usr/bin/env bash
# texopt optimize with the default (perceptual) method on the bundled spot model at half
# cost, with a short stage-1 search (--iterations 10) to keep it near a minute: the output
# passes the glTF validator with no warning the input lacks, the cost lands within 2% of
# the request, no triangle flips, and the layout was packed anew into a smaller texture.
set -euo pipefail
bin=${TEXOPT_BIN:?TEXOPT_BIN not set}
src=${TEXOPT_SOURCE_DIR:?TEXOPT_SOURCE_DIR not set}
spot="$src/tests/data/spot/spot.glb"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" optimize "$spot" -o "$tmp/out.glb" --relative-cost 0.5 --iterations 10 --quiet --stats "$tmp/stats.json" ||
  fail "texopt optimize exited $?"
/usr/bin/python3 - "$tmp/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
d = s["domains"][0]
assert s["method"] == "perceptual", s["method"]
assert abs(d["relative_cost"] / 0.5 - 1) <= 0.02, d["relative_cost"]
assert d["repacked"] is True
assert d["stage2"]["flipped_triangles"] == 0, d["stage2"]
assert d["output_size"][0] * d["output_size"][1] < 1024 * 1024, d["output_size"]
assert 0 < d["stage1"]["within_epsilon_share"] <= 1, d["stage1"]
PY
if [ -f "$src/tools/node_modules/gltf-validator/package.json" ] && command -v node >/dev/null; then
  node "$src/tools/validate-gltf.mjs" "$tmp/out.glb" --baseline "$spot" > "$tmp/validate.json" ||
    fail "validator: $(cat "$tmp/validate.json")"
fi
echo "optimize_default_slow: ok"
