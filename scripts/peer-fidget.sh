#!/usr/bin/env bash
# Side-by-side comparison of our `tracer` with the peer renderer fidget (crates.io
# `fidget`, JIT, bench-suite/peers/fidget): both render each model at SIZE x SIZE in
# the same orthographic frame; whole-process wall times are measured alternately in one
# run (ROUNDS rounds, the order flipped every round), the hit masks are compared.
# Prints a markdown table and writes it, with the command and the date, to DOC.
#
#   scripts/peer-fidget.sh                      # 1024x1024, 3 rounds, 4 models
#   SIZE=512 ROUNDS=5 MODELS="colonnade:1:revaa" scripts/peer-fidget.sh
#
# MODELS: NAME:SCALE:ARITH, one per model (NAME.vm in MODELS_DIR; SCALE is fidget's
# render3d --scale, the view box [-1/SCALE, 1/SCALE]^3; ARITH is our --arith). A model
# rendered with another arithmetic than revaa (our default) also gets one revaa render
# at PROBE_SIZE, reported in the notes. SHIFT_CHECK=1 (default) also renders ours once
# without the half-pixel shift of the frame and reports that mask agreement (0 skips it).
# OUT_DIR keeps the images, masks and diff images
# (gray both hit, red fidget only, green ours only). DOC= (empty) skips the document.
set -euo pipefail
cd "$(dirname "$0")/.."
SIZE=${SIZE:-1024}
ROUNDS=${ROUNDS:-3}
MODELS_DIR=${MODELS_DIR:-bench-suite/peers/fidget/models}
MODELS=${MODELS:-"bear:1:hull colonnade:1:revaa gyroid-sphere:1:revaa tanglecube:0.25:revaa"}
OUT_DIR=${OUT_DIR:-bench-out/peer-fidget}
DOC=${DOC-docs/peers/fidget.md}
PROBE_SIZE=${PROBE_SIZE:-128}
SHIFT_CHECK=${SHIFT_CHECK:-1}
[ -n "${SIZE##*[!0-9]*}" ] && [ "$SIZE" -ge 1 ] || { echo "error: SIZE '$SIZE' is not a whole number above 0" >&2; exit 2; }
[ -n "${ROUNDS##*[!0-9]*}" ] && [ "$ROUNDS" -ge 1 ] || { echo "error: ROUNDS '$ROUNDS' is not a whole number above 0" >&2; exit 2; }
for spec in $MODELS; do
    IFS=: read -r name scale arith <<< "$spec"
    [ -f "$MODELS_DIR/$name.vm" ] || { echo "error: $MODELS_DIR/$name.vm not found (MODELS entry '$spec')" >&2; exit 2; }
    [ -n "$scale" ] && [ -n "$arith" ] || { echo "error: MODELS entry '$spec' is not NAME:SCALE:ARITH" >&2; exit 2; }
done

echo "building fidget-peer and tracer (release)..." >&2
# The peer in its own target dir, whatever CARGO_TARGET_DIR says (it is not our
# workspace); our tracer where CARGO_TARGET_DIR (default target/) puts it.
CARGO_TARGET_DIR=bench-suite/peers/fidget/target \
    nice -n 10 cargo build --release -q --manifest-path bench-suite/peers/fidget/Cargo.toml
nice -n 10 cargo build --release -q -p tracer --bin tracer
PEER=bench-suite/peers/fidget/target/release/fidget-peer
TRACER=${CARGO_TARGET_DIR:-target}/release/tracer
mkdir -p "$OUT_DIR"
[ -z "$DOC" ] || mkdir -p "$(dirname "$DOC")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
now_ns() { date +%s%N; }

for spec in $MODELS; do
    IFS=: read -r name scale arith <<< "$spec"
    model=$MODELS_DIR/$name.vm
    # fidget samples pixel (i, j) at world x = -1 + 2i/N, y = 1 - 2(j+1)/N (model units:
    # divided by SCALE); our orthographic rays pass through pixel centres, so our eye and
    # look-at move by -1/(N*SCALE) on x and y. The eye sits at z = 2/SCALE, in front of
    # the box, looking down -z with +y up.
    read -r width shift eyez half <<< "$(python3 -c "
s = float('$scale'); n = $SIZE
assert s > 0
print(repr(2 / s), repr(-1 / (n * s)), repr(2 / s), repr(1 / s))")"
    frame=(--ortho "$width" --eye "$shift,$shift,$eyez" --look-at "$shift,$shift,0" --up 0,1,0
           --domain="-$half,-$half,-$half,$half,$half,$half")
    echo "${frame[*]}" > "$tmp/$name.frame"
    peer_cmd=("$PEER" "$model" --size "$SIZE" --scale "$scale" --out "$OUT_DIR/$name-fidget.png"
              --mask "$OUT_DIR/$name-fidget-mask.npy" --depth "$OUT_DIR/$name-fidget-depth.npy")
    ours_cmd=("$TRACER" render "$model" "${frame[@]}" --size "${SIZE}x$SIZE" --arith "$arith"
              --stats json -q --out "$OUT_DIR/$name-ours.png" --depth "$OUT_DIR/$name-ours-depth.npy")
    for r in $(seq 1 "$ROUNDS"); do
        order="peer ours"
        [ $((r % 2)) -eq 0 ] && order="ours peer"
        for who in $order; do
            echo "$name round $r/$ROUNDS: $who" >&2
            t0=$(now_ns)
            if [ "$who" = peer ]; then
                "${peer_cmd[@]}" 2> "$tmp/$name-peer-$r.err" || { cat "$tmp/$name-peer-$r.err" >&2; exit 1; }
            else
                "${ours_cmd[@]}" > "$tmp/$name-ours-$r.json" 2> "$tmp/$name-ours-$r.err" \
                    || { cat "$tmp/$name-ours-$r.err" >&2; exit 1; }
            fi
            t1=$(now_ns)
            echo $((t1 - t0)) > "$tmp/$name-$who-$r.ns"
        done
    done
    python3 scripts/peer_masks.py "$OUT_DIR/$name-fidget-mask.npy" "$OUT_DIR/$name-ours-depth.npy" \
        --peer-depth "$OUT_DIR/$name-fidget-depth.npy" --offset "$half" \
        --diff "$OUT_DIR/$name-diff.png" > "$tmp/$name-cmp.json"
    if [ "$SHIFT_CHECK" = 1 ]; then
        echo "$name: unshifted frame" >&2
        "$TRACER" render "$model" --ortho "$width" --eye "0,0,$eyez" --look-at 0,0,0 --up 0,1,0 \
            --domain="-$half,-$half,-$half,$half,$half,$half" --size "${SIZE}x$SIZE" --arith "$arith" \
            -q --out "$tmp/unshifted.png" --depth "$tmp/unshifted.npy" > /dev/null 2>&1
        python3 scripts/peer_masks.py "$OUT_DIR/$name-fidget-mask.npy" "$tmp/unshifted.npy" \
            > "$tmp/$name-unshifted.json"
    fi
    if [ "$arith" != revaa ]; then
        read -r pwidth pshift peyez phalf <<< "$(python3 -c "
s = float('$scale'); n = $PROBE_SIZE
print(repr(2 / s), repr(-1 / (n * s)), repr(2 / s), repr(1 / s))")"
        echo "$name: revaa probe at ${PROBE_SIZE}x$PROBE_SIZE" >&2
        "$TRACER" render "$model" --ortho "$pwidth" --eye "$pshift,$pshift,$peyez" \
            --look-at "$pshift,$pshift,0" --up 0,1,0 --domain="-$phalf,-$phalf,-$phalf,$phalf,$phalf,$phalf" \
            --size "${PROBE_SIZE}x$PROBE_SIZE" --arith revaa --stats json -q \
            --out "$tmp/probe.png" > "$tmp/$name-probe.json" 2> "$tmp/$name-probe.err" || true
    fi
done

fidget_version=$(sed -n 's/^fidget = { version = "\([^"]*\)".*/\1/p' bench-suite/peers/fidget/Cargo.toml)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
cpu="$(nproc) cores (${cpu:-unknown CPU})"
python3 - "$tmp" "$SIZE" "$ROUNDS" "$PROBE_SIZE" "$fidget_version" "$cpu" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" "$(date -u +%Y-%m-%d)" \
    "SIZE=$SIZE ROUNDS=$ROUNDS PROBE_SIZE=$PROBE_SIZE MODELS=\"$MODELS\" scripts/peer-fidget.sh" \
    "$DOC" $MODELS <<'EOF'
import json, re, statistics, sys
tmp, size, rounds, probe_size, fver, cpu, commit, date, command, doc = sys.argv[1:11]
specs = sys.argv[11:]
size, rounds = int(size), int(rounds)

def read(path):
    with open(path) as f:
        return f.read()

def med(xs):
    return statistics.median(xs)

rows, notes, frames = [], [], []
for spec in specs:
    name, scale, arith = spec.split(":")
    peer_s = [int(read(f"{tmp}/{name}-peer-{r}.ns")) / 1e9 for r in range(1, rounds + 1)]
    ours_s = [int(read(f"{tmp}/{name}-ours-{r}.ns")) / 1e9 for r in range(1, rounds + 1)]
    peer_render = []
    for r in range(1, rounds + 1):
        m = re.search(r"render ([0-9.]+) ms", read(f"{tmp}/{name}-peer-{r}.err"))
        peer_render.append(float(m.group(1)) / 1e3)
    stats = [json.loads(read(f"{tmp}/{name}-ours-{r}.json").splitlines()[0])
             for r in range(1, rounds + 1)]
    ours_render = [s["wall_s"] for s in stats]
    cmp = json.loads(read(f"{tmp}/{name}-cmp.json"))
    px = cmp["pixels"]
    hits, unconf = stats[-1]["hits"], stats[-1]["unconfirmed"]
    voxel = 2.0 / (size * float(scale))
    ddiff = cmp.get("depth_diff_median")
    warned = any("warning" in read(f"{tmp}/{name}-ours-{r}.err") for r in range(1, rounds + 1))
    rows.append([
        name, scale, arith,
        f"{med(peer_s):.2f}", f"{med(ours_s):.2f}", f"{med(ours_s) / med(peer_s):.1f}",
        f"{med(peer_render):.2f}", f"{med(ours_render):.2f}",
        f"{cmp['peer_hits'] / px:.4f}", f"{cmp['our_hits'] / px:.4f}",
        f"{unconf} ({unconf / hits:.1%})" if hits else "0",
        f"{cmp['agreement']:.5f}",
        f"{cmp['peer_only']} / {cmp['ours_only']}",
        f"{ddiff / voxel:.2f}" if ddiff is not None else "-",
    ])
    frame = f"- {name}: `{read(f'{tmp}/{name}.frame').strip()}`"
    try:
        u = json.loads(read(f"{tmp}/{name}-unshifted.json"))
        frame += (f"; mask agreement {cmp['agreement']:.5f}, without the shift (eye on the "
                  f"z axis) {u['agreement']:.5f}")
    except FileNotFoundError:
        pass
    frames.append(frame)
    if warned or (hits and unconf * 4 > hits):
        notes.append(f"- {name} ({arith}): our tracer warned: {unconf} of {hits} hit pixels "
                     "are unconfirmed.")
    elif unconf:
        notes.append(f"- {name} ({arith}): {unconf} unconfirmed of {hits} hits "
                     f"({unconf / hits:.2%}), below the tracer's warning threshold (25%).")
    try:
        p = json.loads(read(f"{tmp}/{name}-probe.json").splitlines()[0])
        perr = read(f"{tmp}/{name}-probe.err").strip()
        notes.append(
            f"- {name} with our default arithmetic (revaa) instead, one render at "
            f"{probe_size}x{probe_size}: {p['hits']} hits of {p['width'] * p['height']} pixels "
            f"({p['hits'] / (p['width'] * p['height']):.1%}), {p['unconfirmed']} unconfirmed "
            f"({p['unconfirmed'] / max(p['hits'], 1):.1%}), {p['wall_s']:.1f} s render"
            + (" (the tracer warned)" if "warning" in perr else "") + ".")
    except (FileNotFoundError, IndexError, json.JSONDecodeError):
        pass

head = ["model", "scale", "our arith", "fidget s", "ours s", "ours/fidget",
        "fidget render s", "ours render s", "fidget hits", "our hits",
        "our unconfirmed", "mask agreement", "fidget-only / ours-only px",
        "median abs depth diff (voxels)"]
table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
table += ["| " + " | ".join(r) + " |" for r in rows]
print("\n".join(table))

if doc:
    text = f"""# Peer comparison: fidget

Our `tracer` against [fidget](https://github.com/mkeeter/fidget) {fver} (crates.io,
MPL-2.0; its JIT evaluator and `fidget::raster::voxel` 3-D rasteriser, shaded with its
own effects), built and run by `scripts/peer-fidget.sh` from
`bench-suite/peers/fidget/` (outside our workspace).

- Command: `{command}`
- Date: {date}, commit {commit}
- Machine: {cpu}, **shared** (other builds and CI may run alongside), so the times are
  indicative; each ratio comes from one run with the tools alternating. Both tools use
  every core (fidget: rayon's global pool; ours: one worker per core).
- Images: {size} x {size}; fidget also {size} voxels deep. Each tool ran {rounds} times
  per model, the order flipped every round (fidget, ours, ours, fidget, ...); medians.

Columns: *fidget s* / *ours s*: median whole-process wall time (start to exit, reading
the model and writing PNG, mask / depth map included); *ours/fidget*: their ratio;
*render s*: the render alone by each tool's own timer (fidget: `voxel::render`; ours:
the `wall_s` of `--stats json`); *hits*: fraction of pixels hit; *our unconfirmed*: hit
pixels without a sign change of f within the precision; *mask agreement*: fraction of
pixels where both hit or both miss; *depth diff*: median |depth difference| over pixels
both hit, in fidget voxels (fidget's depth is quantised to voxels).

{chr(10).join(table)}

## Framing

fidget's demo `render3d --isometric` uses no rotation and no perspective: world
`[-1, 1]^3` (model `[-1/S, 1/S]^3` with `--scale S`) seen along `-z`, `+y` up. Its
`VoxelSize::screen_to_world` samples pixel `(i, j)` at world `x = -1 + 2i/N`,
`y = 1 - 2(j+1)/N`, voxel `k` at `z = -1 + 2k/N`, a pixel being a hit when a voxel of its
column has f < 0. Our orthographic rays go through pixel centres, so the same samples
need the eye moved by `-1/(N*S)` on x and y:

```
tracer render MODEL.vm --ortho 2/S --eye -1/(N*S),-1/(N*S),2/S --look-at -1/(N*S),-1/(N*S),0 \\
    --up 0,1,0 --domain=-1/S,-1/S,-1/S,1/S,1/S,1/S --size NxN
fidget-peer MODEL.vm --size N --scale S
```

The flags of this run (with the mask agreement they give, and without the shift when
measured):

{chr(10).join(frames)}

## Notes

{chr(10).join(notes) if notes else "- No render of ours reported unconfirmed hits."}
"""
    with open(doc, "w") as f:
        f.write(text)
    print(f"wrote {doc}", file=sys.stderr)
EOF
