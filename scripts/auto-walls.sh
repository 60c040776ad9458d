#!/usr/bin/env bash
# Does the default arithmetic (`--arith auto`) draw walls? On every built-in model
# (default view) and fidget's four .vm models (the peer frame), renders in ia, hull and
# auto and checks "auto's unconfirmed hits <= IA's + 0.1% of the hits (rounded up)";
# also the peer table's three generated scenes.
# A render that takes longer than CAP seconds is dropped (IA is slow on some models);
# the check then uses Hull, whose ranges are never wider than IA's. Prints a markdown
# table; exit 1 when a model fails the check.
#
#   scripts/auto-walls.sh                 # SIZE=96x72, VM_SIZE=128, CAP=60
#   TRACER=/path/to/tracer SIZE=160x120 scripts/auto-walls.sh
set -euo pipefail
cd "$(dirname "$0")/.."
SIZE=${SIZE:-96x72}
VM_SIZE=${VM_SIZE:-128}
CAP=${CAP:-60}
TRACER=${TRACER:-${CARGO_TARGET_DIR:-target}/release/tracer}
if [ -z "${TRACER_PREBUILT:-}" ] && [ "$TRACER" = "${CARGO_TARGET_DIR:-target}/release/tracer" ]; then
    cargo build --release -q -p tracer-cli --bin tracer
fi
[ -x "$TRACER" ] || { echo "error: TRACER '$TRACER' is not an executable" >&2; exit 2; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
stats() {  # ARITH ARGS... -> "hits unconfirmed researched tiles_hull wall_s" or "- - - - -"
    local arith=$1; shift
    if out=$(timeout "$CAP" "$TRACER" render "$@" --arith "$arith" --out "$tmp/o.png" --stats json -q 2>/dev/null); then
        python3 -c 'import json,sys; d=json.loads(sys.argv[1]); print(d["hits"], d["unconfirmed"], d.get("researched",0), d.get("tiles_hull",0), round(d["wall_s"],2))' "$out"
    else
        echo "- - - - -"
    fi
}
echo "| model | size | hits | unconfirmed ia | hull | auto | auto: searched again, tiles in hull | auto s / hull s | check |"
echo "|---|---|---|---|---|---|---|---|---|"
fail=0
row() {  # NAME SIZE ARGS...
    local name=$1 size=$2; shift 2
    read -r ih iu _ _ _ <<< "$(stats ia "$@" --size "$size")"
    read -r hh hu _ _ hs <<< "$(stats hull "$@" --size "$size")"
    read -r ah au ar at as <<< "$(stats auto "$@" --size "$size")"
    local ref=$iu refh=$ih
    if [ "$iu" = - ]; then ref=$hu; refh=$hh; fi
    local ok
    ok=$(python3 -c "import math,sys; r,h,a=sys.argv[1:4]; print('ok' if a!='-' and r!='-' and int(a) <= int(r) + math.ceil(0.001*int(h)) else 'FAIL')" "$ref" "$refh" "$au")
    [ "$ok" = ok ] || fail=1
    local ratio
    ratio=$(python3 -c "import sys; a,h=sys.argv[1:3]; print('-' if '-' in (a,h) or float(h)==0 else f'{float(a)/float(h):.2f}')" "$as" "$hs")
    echo "| $name | $size | $ah | $iu | $hu | $au | $ar, $at | $ratio | $ok |"
}
for m in $("$TRACER" list | grep -v '^ '); do
    row "$m" "$SIZE" "$m"
done
frame=(--ortho 2 --eye 0,0,2 --look-at 0,0,0 --up 0,1,0 --domain=-1,-1,-1,1,1,1)
for m in bear colonnade gyroid-sphere; do
    row "$m.vm" "${VM_SIZE}x$VM_SIZE" "bench-suite/peers/fidget/models/$m.vm" "${frame[@]}"
done
row tanglecube.vm "${VM_SIZE}x$VM_SIZE" bench-suite/peers/fidget/models/tanglecube.vm \
    --ortho 8 --eye 0,0,8 --look-at 0,0,0 --up 0,1,0 --domain=-4,-4,-4,4,4,4
# The peer table's generated scenes (scripts/gen-vm-scenes.py).
python3 scripts/gen-vm-scenes.py "$tmp/scenes" --kinds spheres,csg,lattice > /dev/null
for m in spheres-2000 csg-300 lattice; do
    row "$m.vm" "${VM_SIZE}x$VM_SIZE" "$tmp/scenes/$m.vm" "${frame[@]}"
done
echo
echo "command: SIZE=$SIZE VM_SIZE=$VM_SIZE CAP=$CAP scripts/auto-walls.sh; $(date -u +%F), commit $(git rev-parse --short HEAD)"
exit $fail
