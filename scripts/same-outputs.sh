#!/usr/bin/env bash
# Prints one line per (model, arithmetic, mode) with the SHA-256 of the image, the depth
# map and the counters (wall times removed) of a small render, of headless previews
# (global and local Lipschitz bounds), and of meshes (the mesh file and its counters).
# Two runs of this script on two commits must print the same lines when a change claims
# "same images, depth maps, meshes and counters":
#   scripts/same-outputs.sh > before.txt; (change); scripts/same-outputs.sh > after.txt
#   diff before.txt after.txt
# TRACER=path/to/tracer skips the build; SIZE=WxH sets the render size (default 96x72);
# DEPTH=N the meshes' depth (default 4).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ -z "${TRACER:-}" ]; then
    cargo build --release -q -p tracer-cli --bin tracer
    TRACER=target/release/tracer
fi
size=${SIZE:-96x72}
depth=${DEPTH:-4}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
h() { sha256sum "$1" | cut -c1-16; }
models=$("$TRACER" list | grep -v '^ ')
ariths="ia aa raa revaa"
for m in $models; do
    for a in $ariths; do
        for mode in culling no-culling; do
            flag=""
            [ "$mode" = no-culling ] && flag="--no-culling"
            "$TRACER" render "$m" --arith "$a" --size "$size" $flag \
                --out "$tmp/i.png" --depth "$tmp/d.npy" > "$tmp/s.txt"
            grep -v -e 'wall time' -e '^wrote' "$tmp/s.txt" > "$tmp/c.txt"
            echo "render $m $a $mode png=$(h "$tmp/i.png") depth=$(h "$tmp/d.npy") stats=$(h "$tmp/c.txt")"
        done
    done
done
# The previewer: only models with a Lipschitz bound of their own run without --lambda.
for m in $models; do
    for bound in global local; do
        flag=""
        [ "$bound" = local ] && flag="--bound local"
        if "$TRACER" preview "$m" --headless --width 64 --height 64 $flag \
            --out "$tmp/p.png" > "$tmp/s.txt" 2> "$tmp/e.txt"; then
            sed -E 's/, [0-9.]+ s$//' "$tmp/s.txt" > "$tmp/c.txt"
            echo "preview $m $bound png=$(h "$tmp/p.png") stats=$(h "$tmp/c.txt")"
        else
            echo "preview $m $bound refused: $(head -c 80 "$tmp/e.txt")"
        fi
    done
done
# The mesher: every model in two arithmetics, the counters as JSON without wall times.
for m in $models; do
    for a in ia revaa; do
        if "$TRACER" mesh "$m" --arith "$a" --depth "$depth" --quiet --stats json \
            --out "$tmp/m.ply" > "$tmp/s.txt" 2> "$tmp/e.txt"; then
            sed -E 's/"(check_)?wall_s": [0-9.e-]+, //g' "$tmp/s.txt" > "$tmp/c.txt"
            echo "mesh $m $a ply=$(h "$tmp/m.ply") stats=$(h "$tmp/c.txt")"
        else
            echo "mesh $m $a refused: $(head -c 80 "$tmp/e.txt")"
        fi
    done
done
