#!/usr/bin/env bash
# Our `tracer mesh` with its default flags against fidget's mesher (`fidget-peer mesh`,
# bench-suite/peers/fidget) at one depth, fidget's frame: whole-process wall times
# measured alternately by `farm-bench --vs` (ROUNDS pairs per model, medians, the ratio
# ours / fidget as the median of the pairs' ratios with min and max), and our columns
# from one `--stats json` run. Prints one markdown row per model:
#
#   | model | fidget s | ours s | ours / fidget | leaf level | triangles |
#   | watertight, manifold | self-intersecting pairs | unresolved | checks' share |
#
#   scripts/gen-vm-scenes.py /tmp/scenes          # the CSG-300 and 2000-sphere scenes
#   scripts/mesh-vs-fidget.sh                     # every model below, depth 6, 3 rounds
#   ROUNDS=5 scripts/mesh-vs-fidget.sh bear colonnade
#
# Models: tanglecube (domain [-4, 4]^3, fidget --scale 0.25), decocube ([-1.25,
# 1.25]^3, 0.8), csg, csg-300 and spheres-2000 ([-1, 1]^3) and fidget's bear, colonnade
# and gyroid-sphere ([-1, 1]^3, --scale 0.984375: fidget's octree is then our cube, one
# cell longer than the domain). TRACER (default target/release/tracer, built by
# `cargo build --release -p tracer-cli`), FIDGET (default the peer's release build),
# SCENES (default /tmp/scenes), DEPTH (default 6), ROUNDS (default 3).
set -euo pipefail
cd "$(dirname "$0")/.."
TRACER=${TRACER:-target/release/tracer}
FIDGET=${FIDGET:-bench-suite/peers/fidget/target/release/fidget-peer}
SCENES=${SCENES:-/tmp/scenes}
DEPTH=${DEPTH:-6}
ROUNDS=${ROUNDS:-3}
M=bench-suite/peers/fidget/models
O=bench-suite/peers/own-models
[ -x "$TRACER" ] || { echo "error: TRACER '$TRACER' is not an executable" >&2; exit 2; }
[ -x "$FIDGET" ] || { echo "error: FIDGET '$FIDGET' is not an executable (cargo build --release in bench-suite/peers/fidget)" >&2; exit 2; }
[ $# -gt 0 ] || set -- tanglecube colonnade decocube csg csg-300 spheres-2000 bear gyroid-sphere
for m in "$@"; do
    case $m in
        tanglecube) f=$M/$m.vm d=-4,-4,-4,4,4,4 s=0.25 ;;
        decocube | csg) f=$O/$m.vm d=-1,-1,-1,1,1,1 s=0.984375
            [ "$m" = decocube ] && d=-1.25,-1.25,-1.25,1.25,1.25,1.25 s=0.8 ;;
        csg-300 | spheres-2000) f=$SCENES/$m.vm d=-1,-1,-1,1,1,1 s=0.984375 ;;
        bear | colonnade | gyroid-sphere) f=$M/$m.vm d=-1,-1,-1,1,1,1 s=0.984375 ;;
        *) echo "error: unknown model '$m'" >&2; exit 2 ;;
    esac
    [ -f "$f" ] || { echo "error: $f not found (scripts/gen-vm-scenes.py $SCENES?)" >&2; exit 2; }
    out=$(farm-bench -n "$ROUNDS" --timeout 900 \
        --vs "$FIDGET mesh $f --depth $DEPTH --scale $s --out /tmp/mesh-vs-fidget-f.ply" -- \
        "$TRACER" mesh "$f" --domain="$d" --depth "$DEPTH" -q --out /tmp/mesh-vs-fidget-m.ply 2>&1)
    ours=$(awk '/^A wall s/{print $5}' <<< "$out")
    theirs=$(awk '/^B wall s/{print $5}' <<< "$out")
    ratio=$(awk '/^A\/B wall/{printf "%.2f (%.2f-%.2f)", $4, $3, $5}' <<< "$out")
    stats=$("$TRACER" mesh "$f" --domain="$d" --depth "$DEPTH" -q --stats json \
        --out /tmp/mesh-vs-fidget-m.ply 2>/dev/null)
    python3 - "$m" "$theirs" "$ours" "$ratio" "$stats" <<'PY'
import json, sys
m, theirs, ours, ratio, stats = sys.argv[1:6]
s = json.loads(stats)
ok = "yes" if s["watertight"] and s["manifold"] else "NO"
share = 100 * s["check_wall_s"] / s["wall_s"]
print(f"| {m} | {theirs} | {ours} | {ratio} | {s['level']} | {s['triangles']} | {ok} "
      f"| {s['self_intersections']} | {s['unresolved_at_max_depth']:,} "
      f"| {share:.0f}% ({s['check_wall_s']:.3f} of {s['wall_s']:.3f}) |")
PY
done
