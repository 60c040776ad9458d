#!/usr/bin/env bash
# Side-by-side comparison of our `tracer` with the peer renderer fidget (crates.io
# `fidget`, JIT, bench-suite/peers/fidget): both render each model at SIZE x SIZE in
# the same orthographic frame; whole-process wall times are measured alternately in one
# run (ROUNDS rounds, the order flipped every round), the hit masks are compared.
# Prints a markdown table and writes it, with the command and the date, to DOC.
#
#   scripts/peer-fidget.sh                      # 1024x1024, 3 rounds, 7 models
#   SIZE=512 ROUNDS=5 MODELS="colonnade:1:revaa" scripts/peer-fidget.sh
#
# MODELS: NAME:SCALE:ARITH, one per model (NAME.vm in MODELS_DIR, else in GEN_DIR; SCALE
# is fidget's render3d --scale, the view box [-1/SCALE, 1/SCALE]^3; ARITH is our --arith:
# auto, ia, aa, raa, revaa or hull). The default runs fidget's four models and the three
# scenes of scripts/gen-vm-scenes.py (a union of 2000 spheres, a CSG tree of 300 spheres
# and boxes with differences, a gyroid and Schwarz P lattice in a box), which it writes
# into GEN_DIR first (SCENES, the generator's kinds; SCENES= skips generating), all in
# our default arithmetic, auto. A model rendered with another arithmetic than auto (our
# default) also gets one auto render at PROBE_SIZE, reported in the notes.
# The binaries are taken from CARGO_TARGET_DIR when it is set (else each crate's own
# target/). SHIFT_CHECK=1 (default) also renders ours once
# without the half-pixel shift of the frame and reports that mask agreement (0 skips it).
# OUT_DIR keeps the images, masks and diff images
# (gray both hit, red fidget only, green ours only). DOC= (empty) skips the document.
set -euo pipefail
cd "$(dirname "$0")/.."
SIZE=${SIZE:-1024}
ROUNDS=${ROUNDS:-3}
MODELS_DIR=${MODELS_DIR:-bench-suite/peers/fidget/models}
GEN_DIR=${GEN_DIR:-bench-out/peer-fidget/scenes}
SCENES=${SCENES-spheres,csg,lattice}
MODELS=${MODELS:-"bear:1:auto colonnade:1:auto gyroid-sphere:1:auto tanglecube:0.25:auto spheres-2000:1:auto csg-300:1:auto lattice:1:auto"}
OUT_DIR=${OUT_DIR:-bench-out/peer-fidget}
DOC=${DOC-docs/peers/fidget.md}
PROBE_SIZE=${PROBE_SIZE:-128}
SHIFT_CHECK=${SHIFT_CHECK:-1}
[ -n "${SIZE##*[!0-9]*}" ] && [ "$SIZE" -ge 1 ] || { echo "error: SIZE '$SIZE' is not a whole number above 0" >&2; exit 2; }
[ -n "${ROUNDS##*[!0-9]*}" ] && [ "$ROUNDS" -ge 1 ] || { echo "error: ROUNDS '$ROUNDS' is not a whole number above 0" >&2; exit 2; }
if [ -n "$SCENES" ]; then
    python3 scripts/gen-vm-scenes.py "$GEN_DIR" --kinds "$SCENES" > /dev/null
fi
model_path() {  # NAME -> its .vm file, MODELS_DIR first
    if [ -f "$MODELS_DIR/$1.vm" ]; then echo "$MODELS_DIR/$1.vm"; else echo "$GEN_DIR/$1.vm"; fi
}
for spec in $MODELS; do
    IFS=: read -r name scale arith <<< "$spec"
    [ -n "$scale" ] && [ -n "$arith" ] || { echo "error: MODELS entry '$spec' is not NAME:SCALE:ARITH" >&2; exit 2; }
    [ -f "$(model_path "$name")" ] || { echo "error: $name.vm is in neither $MODELS_DIR nor $GEN_DIR (MODELS entry '$spec')" >&2; exit 2; }
    case "$arith" in auto|ia|aa|raa|revaa|hull) ;;
        *) echo "error: MODELS entry '$spec': arithmetic '$arith' is not auto, ia, aa, raa, revaa or hull" >&2; exit 2 ;;
    esac
done

echo "building fidget-peer and tracer (release)..." >&2
# The peer in its own target dir, whatever CARGO_TARGET_DIR says (it is not our
# workspace); our tracer where CARGO_TARGET_DIR (default target/) puts it.
CARGO_TARGET_DIR=bench-suite/peers/fidget/target \
    nice -n 10 cargo build --release -q --manifest-path bench-suite/peers/fidget/Cargo.toml
nice -n 10 cargo build --release -q -p tracer-cli --bin tracer
PEER=bench-suite/peers/fidget/target/release/fidget-peer
TRACER=${CARGO_TARGET_DIR:-target}/release/tracer
mkdir -p "$OUT_DIR"
[ -z "$DOC" ] || mkdir -p "$(dirname "$DOC")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load0=$(cut -d' ' -f1-3 /proc/loadavg)
now_ns() { date +%s%N; }

for spec in $MODELS; do
    IFS=: read -r name scale arith <<< "$spec"
    model=$(model_path "$name")
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
                /usr/bin/time -f "%U %S" -o "$tmp/$name-peer-$r.cpu" "${peer_cmd[@]}" 2> "$tmp/$name-peer-$r.err" || { cat "$tmp/$name-peer-$r.err" >&2; exit 1; }
            else
                /usr/bin/time -f "%U %S" -o "$tmp/$name-ours-$r.cpu" "${ours_cmd[@]}" > "$tmp/$name-ours-$r.json" 2> "$tmp/$name-ours-$r.err" \
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
    if [ "$arith" != auto ]; then
        read -r pwidth pshift peyez phalf <<< "$(python3 -c "
s = float('$scale'); n = $PROBE_SIZE
print(repr(2 / s), repr(-1 / (n * s)), repr(2 / s), repr(1 / s))")"
        echo "$name: auto probe at ${PROBE_SIZE}x$PROBE_SIZE" >&2
        "$TRACER" render "$model" --ortho "$pwidth" --eye "$pshift,$pshift,$peyez" \
            --look-at "$pshift,$pshift,0" --up 0,1,0 --domain="-$phalf,-$phalf,-$phalf,$phalf,$phalf,$phalf" \
            --size "${PROBE_SIZE}x$PROBE_SIZE" --arith auto --stats json -q \
            --out "$tmp/probe.png" > "$tmp/$name-probe.json" 2> "$tmp/$name-probe.err" || true
    fi
done

echo "$load0 / $(cut -d' ' -f1-3 /proc/loadavg)" > "$tmp/load"
fidget_version=$(sed -n 's/^fidget = { version = "\([^"]*\)".*/\1/p' bench-suite/peers/fidget/Cargo.toml)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
cpu="$(nproc) cores (${cpu:-unknown CPU})"
python3 - "$tmp" "$SIZE" "$ROUNDS" "$PROBE_SIZE" "$fidget_version" "$cpu" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" "$(date -u +%Y-%m-%d)" \
    "SIZE=$SIZE ROUNDS=$ROUNDS PROBE_SIZE=$PROBE_SIZE SHIFT_CHECK=$SHIFT_CHECK MODELS=\"$MODELS\" scripts/peer-fidget.sh" \
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
    cpu_s = lambda who: med([sum(float(v) for v in read(f"{tmp}/{name}-{who}-{r}.cpu").split()[-2:])
                           for r in range(1, rounds + 1)])
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
    st = stats[-1]
    picked = (f"{st.get('researched', 0)} rays, {st.get('tiles_hull', 0)} tiles in hull"
              if st.get("arith") == "auto" else st.get("arith", arith))
    rows.append([
        name, scale, f"auto ({picked})" if arith == "auto" else arith,
        f"{med(peer_s):.2f}", f"{med(ours_s):.2f}", f"{med(ours_s) / med(peer_s):.2f}",
        f"{cpu_s('ours') / cpu_s('peer'):.2f}" if cpu_s('peer') > 0 else "-",
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
            f"- {name} with our default arithmetic (auto: {p.get('researched', 0)} rays and "
            f"{p.get('tiles_hull', 0)} tiles in hull) instead, one render at "
            f"{probe_size}x{probe_size}: {p['hits']} hits of {p['width'] * p['height']} pixels "
            f"({p['hits'] / (p['width'] * p['height']):.1%}), {p['unconfirmed']} unconfirmed "
            f"({p['unconfirmed'] / max(p['hits'], 1):.1%}), {p['wall_s']:.1f} s render"
            + (" (the tracer warned)" if "warning" in perr else "") + ".")
    except (FileNotFoundError, IndexError, json.JSONDecodeError):
        pass

head = ["model", "scale", "our arith", "fidget s", "ours s", "ours/fidget", "ours/fidget CPU",
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
`bench-suite/peers/fidget/` (outside our workspace). fidget's four models are in
`bench-suite/peers/fidget/models/`; `spheres-2000`, `csg-300` and `lattice` are generated
by `scripts/gen-vm-scenes.py` (seed 41: a union of 2000 spheres, a CSG tree of 300
spheres and boxes with differences and intersections, a gyroid sheet and a Schwarz P
sheet in a box with a ball cut out). *our arith*: `auto (...)` is our default arithmetic,
RevAA with the rays of unconfirmed hits searched again in Hull (and the tiles rendered in
Hull throughout where its sample tiles showed walls): how many of each.

- Command: `{command}`
- Date: {date}, commit {commit}
- Machine: {cpu}, **shared** (other builds and CI may run alongside), so the times are
  indicative; each ratio comes from one run with the tools alternating. Both tools use
  every core (fidget: rayon's global pool; ours: one worker per core).
- Load average (1, 5, 15 min) at the start / the end of the run:
  {read(f"{tmp}/load").strip()}.
- Images: {size} x {size}; fidget also {size} voxels deep. Each tool ran {rounds} times
  per model, the order flipped every round (fidget, ours, ours, fidget, ...); medians.

Columns: *fidget s* / *ours s*: median whole-process wall time (start to exit, reading
the model and writing PNG, mask / depth map included); *ours/fidget*: their ratio (goal: at most 0.5); *ours/fidget CPU*:
the ratio of the medians of user + system seconds (all threads);
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
