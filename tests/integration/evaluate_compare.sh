#!/usr/bin/env bash
# evaluate_compare: `texopt evaluate` and `texopt compare` end to end on tests/data/Fox.
# Checks that a model against itself has q = 0 and c_r = 1, that a reduced copy (made by
# `texopt optimize --method input`) has q > 0 and the asked cost, that compare's JSON holds
# one curve per method with q growing as the cost falls, and that the HTML report parses
# (python3 html.parser), is balanced, holds one plot curve per method and references
# nothing outside itself; that compare passes its stage-1 and refinement options on (its
# perceptual point with --refinements 0, --epsilon and --lambda-min is the q of `texopt
# optimize` with the same options, which differs from the default's refined one on Fox at c_r
# 0.3); that compare's JSON names the build (the version and revision --version prints). --texture: the JSON names the slot, `--texture base` is the default's q, `--texture
# lit` is another measure (Fox has only base colour: lit, not 0, not base colour's q; compare
# --texture lit gives the same q as evaluate --texture lit and names it), a slot
# Fox has no texture in (normal) is an engine error naming it (exit 1, evaluate and compare),
# an unknown slot a usage error. --maps: q of every map Fox binds (base colour only, no lit)
# beside q, base colour's the same. Also the usage errors' exit codes, the seed's range included.
set -euo pipefail
: "${TEXOPT_BIN:?TEXOPT_BIN must point to the texopt executable}"
: "${TEXOPT_SOURCE_DIR:?TEXOPT_SOURCE_DIR must point to the source tree}"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
FOX="$TEXOPT_SOURCE_DIR/tests/data/Fox/Fox.glb"

"$TEXOPT_BIN" evaluate "$FOX" "$FOX" --resolution 200 --json > "$WORK/self.json" ||
    fail "evaluate of Fox against itself exited $?"
"$TEXOPT_BIN" optimize "$FOX" -o "$WORK/quarter.glb" --method input --relative-cost 0.25 --quiet ||
    fail "optimize --method input exited $?"
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/quarter.glb" --resolution 200 --json > "$WORK/quarter.json" ||
    fail "evaluate of the reduced Fox exited $?"
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/quarter.glb" --resolution 200 --texture base --json > "$WORK/quarter_base.json" ||
    fail "evaluate --texture base exited $?"
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/quarter.glb" --resolution 200 --maps --json > "$WORK/quarter_maps.json" ||
    fail "evaluate --maps exited $?"
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/quarter.glb" --resolution 200 --texture lit --json > "$WORK/quarter_lit.json" ||
    fail "evaluate --texture lit exited $?"
"$TEXOPT_BIN" compare "$FOX" --methods input --costs 1,0.25,0.0625 --resolution 200 --quiet \
    --json "$WORK/curves.json" -o "$WORK/report.html" > "$WORK/table.txt" || fail "compare exited $?"
"$TEXOPT_BIN" optimize "$FOX" -o "$WORK/plain.glb" --relative-cost 0.3 --refinements 0 --seed 4294967299 \
    --epsilon 0.02 --lambda-min 0.2 --quiet ||
    fail "optimize --refinements 0 exited $?"
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/plain.glb" --resolution 200 --json > "$WORK/plain.json" ||
    fail "evaluate of the unrefined Fox exited $?"
"$TEXOPT_BIN" compare "$FOX" --texture lit --methods input --costs 0.25 --resolution 200 --quiet \
    --json "$WORK/lit_curves.json" > /dev/null || fail "compare --texture lit exited $?"
"$TEXOPT_BIN" compare "$FOX" --methods perceptual --costs 0.3 --refinements 0 --seed 4294967299 --resolution 200 \
    --epsilon 0.02 --lambda-min 0.2 --quiet --json "$WORK/plain_curves.json" > /dev/null || fail "compare --refinements 0 exited $?"

"$TEXOPT_BIN" --version > "$WORK/version.txt" || fail "--version exited $?"

/usr/bin/python3 - "$WORK" <<'EOF'
import html.parser, json, sys
work = sys.argv[1]
def fail(msg):
    print("FAIL:", msg, file=sys.stderr); sys.exit(1)

same = json.load(open(f"{work}/self.json"))
if same["q"] != 0 or same["relative_cost"] != 1 or len(same["view_gmsd"]) != 20:
    fail(f"self evaluation: {same}")
if same["resolution"] != 200 or same["lookup"] != "bilinear" or same["texture"] != "baseColor":
    fail(f"self evaluation settings: {same}")
quarter = json.load(open(f"{work}/quarter.json"))
if not quarter["q"] > 0.004:
    fail(f"reduced Fox q {quarter['q']}")
if abs(quarter["relative_cost"] - 0.25) > 0.02:
    fail(f"reduced Fox relative cost {quarter['relative_cost']}")
if quarter["output"]["texture_pixels"] != 512 * 512:
    fail(f"reduced Fox texture pixels {quarter['output']['texture_pixels']}")
quarter_lit = json.load(open(f"{work}/quarter_lit.json"))
if quarter_lit["texture"] != "lit" or not quarter_lit["q"] > 0 or quarter_lit["q"] == quarter["q"]:
    fail(f"--texture lit: {quarter_lit['q']} {quarter_lit['texture']} (base colour q {quarter['q']})")
lit_curves = json.load(open(f"{work}/lit_curves.json"))
lit_point = lit_curves["curves"]["input"][0]["q"]
if lit_curves["texture"] != "lit" or abs(lit_point - quarter_lit["q"]) > 1e-9:
    fail(f"compare --texture lit: {lit_curves['texture']} q {lit_point} vs evaluate's {quarter_lit['q']}")
quarter_maps = json.load(open(f"{work}/quarter_maps.json"))
if quarter_maps["q_maps"] != {"baseColor": quarter["q"]} or quarter_maps["q"] != quarter["q"]:
    fail(f"--maps: {quarter_maps.get('q_maps')} (q {quarter['q']})")
quarter_base = json.load(open(f"{work}/quarter_base.json"))
if quarter_base["q"] != quarter["q"] or quarter_base["texture"] != "baseColor":
    fail(f"--texture base: {quarter_base['q']} {quarter_base['texture']} vs default q {quarter['q']}")

curves = json.load(open(f"{work}/curves.json"))
built = curves["texopt"]
if open(f"{work}/version.txt").read() != f"texopt {built['version']} ({built['revision']})\n":
    fail(f"compare JSON names {built}, --version says {open(f'{work}/version.txt').read()!r}")
if curves["texture"] != "baseColor":
    fail(f"compare texture {curves['texture']}")
if list(curves["curves"]) != ["input"]:
    fail(f"curves: {list(curves['curves'])}")
pts = curves["curves"]["input"]
qs = [p["q"] for p in pts]
if qs[0] != 0 or not (qs[0] < qs[1] < qs[2]):
    fail(f"q along the costs 1, 0.25, 0.0625: {qs}")
# The same reduction through compare and through optimize + evaluate gives the same loss.
if abs(qs[1] - quarter["q"]) > 1e-9:
    fail(f"compare q {qs[1]} vs evaluate q {quarter['q']}")

plain = json.load(open(f"{work}/plain.json"))["q"]
plain_point = json.load(open(f"{work}/plain_curves.json"))["curves"]["perceptual"][0]["q"]
if abs(plain_point - plain) > 1e-9:
    fail(f"compare --refinements 0 q {plain_point} vs optimize --refinements 0 q {plain}")

class Checker(html.parser.HTMLParser):
    void = {"img", "meta", "br", "line", "circle", "rect", "polyline"}
    def __init__(self):
        super().__init__()
        self.stack, self.curves, self.imgs, self.errors = [], [], 0, []
    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("src", "href"):
            v = a.get(key)
            if v is not None and not v.startswith("data:"):
                self.errors.append(f"<{tag} {key}={v[:40]}> leaves the file")
        if tag == "img":
            self.imgs += 1
            if not a.get("src", "").startswith("data:image/png;base64,"):
                self.errors.append("an <img> is not an inline PNG")
        if tag == "polyline" and a.get("class") == "curve":
            self.curves.append(a.get("data-method"))
        if tag not in self.void:
            self.stack.append(tag)
    def handle_startendtag(self, tag, attrs):
        self.handle_starttag(tag, attrs)
        if tag not in self.void:
            self.stack.pop()
    def handle_endtag(self, tag):
        if tag in self.void:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes {self.stack[-1] if self.stack else 'nothing'}")
        else:
            self.stack.pop()

c = Checker()
c.feed(open(f"{work}/report.html").read())
c.close()
if c.errors:
    fail("; ".join(c.errors[:5]))
if c.stack:
    fail(f"unclosed tags {c.stack}")
if c.curves != ["input"]:
    fail(f"plot curves {c.curves}")
if c.imgs < 4:
    fail(f"only {c.imgs} images")
EOF

# Usage errors: exit code 2.
set +e
"$TEXOPT_BIN" evaluate "$FOX" > /dev/null 2>&1; [ $? -eq 2 ] || fail "evaluate with one model should exit 2"
"$TEXOPT_BIN" compare "$FOX" --methods nosuch > /dev/null 2>&1; [ $? -eq 2 ] || fail "unknown method should exit 2"
"$TEXOPT_BIN" compare "$FOX" --costs 0,1 > /dev/null 2>&1; [ $? -eq 2 ] || fail "cost 0 should exit 2"
"$TEXOPT_BIN" compare "$FOX" --refinements 21 > /dev/null 2>&1; [ $? -eq 2 ] || fail "21 refinements should exit 2"
"$TEXOPT_BIN" compare "$FOX" --refine-by shininess > /dev/null 2>&1; [ $? -eq 2 ] || fail "unknown --refine-by should exit 2"
"$TEXOPT_BIN" compare "$FOX" --epsilon 1 > /dev/null 2>&1; [ $? -eq 2 ] || fail "epsilon 1 should exit 2"
for lm in 0 1 x; do
    "$TEXOPT_BIN" compare "$FOX" --lambda-min $lm > /dev/null 2>&1; [ $? -eq 2 ] || fail "lambda-min $lm should exit 2"
done
# Seeds: 0 to 2^53 in both commands, as in the service's JSON (the runs above use 2^32 + 3).
for cmd in compare optimize; do
    for seed in -1 9007199254740993 1e3; do
        "$TEXOPT_BIN" $cmd "$FOX" -o "$WORK/never.glb" --seed "$seed" > /dev/null 2>&1
        [ $? -eq 2 ] || fail "$cmd --seed $seed should exit 2"
    done
done
"$TEXOPT_BIN" evaluate "$FOX" "$WORK/missing.glb" > /dev/null 2>&1; [ $? -eq 1 ] || fail "missing model should exit 1"
"$TEXOPT_BIN" evaluate "$FOX" "$FOX" --texture nosuch > /dev/null 2>&1; [ $? -eq 2 ] || fail "unknown slot should exit 2"
"$TEXOPT_BIN" evaluate "$FOX" "$FOX" --texture > /dev/null 2>&1; [ $? -eq 2 ] || fail "--texture without a slot should exit 2"
"$TEXOPT_BIN" compare "$FOX" --texture nosuch > /dev/null 2>&1; [ $? -eq 2 ] || fail "compare: unknown slot should exit 2"
"$TEXOPT_BIN" evaluate "$FOX" "$FOX" --texture normal --resolution 64 > /dev/null 2> "$WORK/normal.err"
[ $? -eq 1 ] || fail "a slot Fox has no texture in should exit 1"
grep -q "no normal texture" "$WORK/normal.err" || fail "the missing slot's error does not name it: $(cat "$WORK/normal.err")"
"$TEXOPT_BIN" compare "$FOX" --texture normal --methods input --costs 1 --quiet > /dev/null 2> "$WORK/cnormal.err"
[ $? -eq 1 ] || fail "compare of a slot Fox has no texture in should exit 1"
grep -q "no normal texture" "$WORK/cnormal.err" || fail "compare's missing slot error: $(cat "$WORK/cnormal.err")"
set -e
echo "evaluate_compare: ok"
