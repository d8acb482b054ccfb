#!/usr/bin/env bash
# texopt optimize end to end on the bundled spot model: method "input" at half cost writes a
# .glb that loads again, passes the glTF validator (when tools/node_modules has it) and whose
# stats say the cost is within 2% of the request; --target-loss (method input) meets its
# target and reports the search; --mipmap is recorded as the lookups of the job and of its q;
# usage errors exit 2, engine failures 1,
# SIGINT during the perceptual method exits 3 and leaves no output file. --version and the
# stats name the source revision the binary was built from (HEAD's commit in a git checkout).
set -euo pipefail
bin=${TEXOPT_BIN:?TEXOPT_BIN not set}
src=${TEXOPT_SOURCE_DIR:?TEXOPT_SOURCE_DIR not set}
spot="$src/tests/data/spot/spot.glb"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# Captured first: grep -q leaves the pipe early, and a help text past one stdio buffer would
# then end on SIGPIPE, which pipefail reports as the command failing.
help=$("$bin" optimize --help) || fail "--help exits non-zero"
grep -q -- "--packing-efficiency" <<<"$help" || fail "--help does not list the options"

version=$("$bin" --version)
revision=$(printf '%s' "$version" | sed -n 's/^texopt [0-9][0-9.]* (\(.*\))$/\1/p')
[ -n "$revision" ] || fail "--version is not 'texopt VERSION (REVISION)': $version"
if head=$(git -C "$src" rev-parse --short=12 HEAD 2>/dev/null); then
  case "$revision" in *"$head"*) ;; *) fail "--version names $revision, the checkout is at $head" ;; esac
fi

set +e
"$bin" optimize "$spot" 2>/dev/null; rc=$?
[ $rc -eq 2 ] || fail "missing -o: exit $rc, expected 2"
"$bin" optimize "$spot" -o "$tmp/x.glb" --relative-cost 0.5 --texture-size 64x64 2>/dev/null; rc=$?
[ $rc -eq 2 ] || fail "two budgets: exit $rc, expected 2"
"$bin" optimize "$spot" -o "$tmp/x.glb" --method nonsense 2>/dev/null; rc=$?
[ $rc -eq 2 ] || fail "unknown method: exit $rc, expected 2"
"$bin" optimize "$spot" -o "$tmp/x.glb" --refine-by shininess 2>"$tmp/err"; rc=$?
[ $rc -eq 2 ] || fail "unknown --refine-by: exit $rc, expected 2"
grep -q "refine-by" "$tmp/err" || fail "a bad --refine-by is not named: $(cat "$tmp/err")"
for bad in "--hessian-floor 1.5" "--hessian-floor -1" "--metric-candidates maybe" "--resize-check 1"; do
  # shellcheck disable=SC2086 # option and value split on purpose
  "$bin" optimize "$spot" -o "$tmp/x.glb" $bad 2>"$tmp/err"; rc=$?
  [ $rc -eq 2 ] || fail "$bad: exit $rc, expected 2"
  grep -q -- "${bad%% *}" "$tmp/err" || fail "a bad ${bad%% *} is not named: $(cat "$tmp/err")"
done
for bad in 0 1 -0.5 abc; do
  "$bin" optimize "$spot" -o "$tmp/x.glb" --target-loss "$bad" 2>"$tmp/err"; rc=$?
  [ $rc -eq 2 ] || fail "--target-loss $bad: exit $rc, expected 2"
done
grep -q "target" "$tmp/err" || fail "a bad --target-loss is not named: $(cat "$tmp/err")"
"$bin" optimize "$spot" -o "$tmp/x.glb" --target-loss 0.05 --relative-cost 0.5 2>/dev/null; rc=$?
[ $rc -eq 2 ] || fail "--target-loss with --relative-cost: exit $rc, expected 2"
"$bin" optimize "$tmp/missing.glb" -o "$tmp/x.glb" --quiet 2>"$tmp/err"; rc=$?
[ $rc -eq 1 ] || fail "missing input: exit $rc, expected 1"
grep -q "missing.glb" "$tmp/err" || fail "the error does not name the file: $(cat "$tmp/err")"
set -e
[ ! -e "$tmp/x.glb" ] || fail "a failed run left an output file"

"$bin" optimize "$spot" -o "$tmp/half.glb" --method input --relative-cost 0.5 --stats "$tmp/half.json" \
  --hessian-floor 0 --metric-candidates no --resize-check no 2>"$tmp/progress"
grep -q "save 100%" "$tmp/progress" || fail "no final progress line: $(cat "$tmp/progress")"
/usr/bin/python3 - "$tmp/half.json" "$revision" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["texopt"]["revision"] == sys.argv[2], s["texopt"]
d = s["domains"][0]
assert s["method"] == "input", s["method"]
assert abs(d["relative_cost"] - 0.5) <= 0.01, d["relative_cost"]
assert d["output_size"] == [724, 724], d["output_size"]
assert d["images"][0]["rewritten"] is True
assert s["params"]["lookup"] == "bilinear", s["params"]
assert s["params"]["hessian_floor"] == 0 and s["params"]["metric_candidates"] is False, s["params"]
assert s["params"]["resize_check"] is False, s["params"]
PY
# --mipmap: the lookups the job tunes for and measures with (the engine's side is unit-tested).
"$bin" optimize "$spot" -o "$tmp/mip.glb" --method input --relative-cost 0.5 --mipmap --evaluate --stats "$tmp/mip.json" --quiet
/usr/bin/python3 - "$tmp/mip.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
assert s["params"]["lookup"] == "mipmapped", s["params"]
assert s["evaluation"]["lookup"] == "mipmapped" and s["evaluation"]["q"] > 0, s["evaluation"]
PY
"$bin" info "$tmp/half.glb" > "$tmp/info.json" || fail "texopt info cannot read the output"
if [ -f "$src/tools/node_modules/gltf-validator/package.json" ] && command -v node >/dev/null; then
  node "$src/tools/validate-gltf.mjs" "$tmp/half.glb" > "$tmp/validate.json" || fail "validator: $(cat "$tmp/validate.json")"
fi

# The target_loss budget: the cost found meets the target; one search step below does not.
"$bin" optimize "$spot" -o "$tmp/tl.glb" --method input --target-loss 0.03 --stats "$tmp/tl.json" --quiet
/usr/bin/python3 - "$tmp/tl.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["target_search"]
assert s["params"]["budget"] == "target_loss", s["params"]
assert t["reached"] is True and t["q"] <= 0.03, t
assert s["evaluation"]["q"] == t["q"], (s["evaluation"], t)
assert t["q_below"] > 0.03 and t["relative_cost"] / t["relative_cost_below"] <= 1.05 + 1e-9, t
assert 0 < t["relative_cost"] < 1, t
PY

# SIGINT while stage 1 runs (seen in its progress lines, not guessed with a sleep: stage 1
# of spot takes only seconds): exit 3, no output file.
"$bin" optimize "$spot" -o "$tmp/canceled.glb" 2>"$tmp/progress.txt" &
pid=$!
for _ in $(seq 600); do
  grep -q 'stage1' "$tmp/progress.txt" && break
  sleep 0.1
done
grep -q 'stage1' "$tmp/progress.txt" || fail "no stage1 progress line within 60 s: $(cat "$tmp/progress.txt")"
kill -INT $pid
set +e
wait $pid; rc=$?
set -e
[ $rc -eq 3 ] || fail "SIGINT: exit $rc, expected 3"
[ ! -e "$tmp/canceled.glb" ] || fail "a canceled run left an output file"
echo "optimize_cli: ok"
