#!/usr/bin/env bash
# Side-by-side meshing: our `tracer mesh` against fidget's mesher (crates.io `fidget`,
# Manifold Dual Contouring, `fidget-peer mesh` in bench-suite/peers/fidget) on the same
# .vm models, the same cube of cells at the same depth. Whole-process wall times are
# measured alternately in one run (ROUNDS rounds, the order flipped every round;
# medians); each mesh is then checked by scripts/mesh_check.py (triangles, watertight,
# manifold, self-intersecting pairs, largest vertex distance to the surface).
# Prints markdown tables and writes them, with the command and the date, to DOC.
#
#   scripts/peer-fidget-mesh.sh                         # depth 6, 3 rounds, 6 models
#   DEPTH=7 ROUNDS=5 MODELS="bear:1:revaa csg:1:revaa" scripts/peer-fidget-mesh.sh
#
# MODELS: NAME:SCALE:ARITH, one per model: NAME.vm is looked for in MODELS_DIRS; the
# model box is [-1/SCALE, 1/SCALE]^3 (fidget's --scale, as in scripts/peer-fidget.sh),
# our --domain; ARITH is our --arith. MAX_DEPTH: our --max-depth (empty: ours' default,
# DEPTH + 4). DIAG=1 (default) also times ours once with --no-check and once with
# --max-depth DEPTH --no-check (not when MAX_DEPTH=DEPTH), to show what our time goes
# to (0 skips them). TIMEOUT:
# seconds before a run is stopped (its tool's row then says so). OUT_DIR keeps the
# meshes (PLY) and the checker's JSON. DOC= (empty) skips the document. PYTHON: a
# python3 with numpy (default: python3 if it has numpy, else a venv made under
# bench-out/mesh-venv with numpy from PyPI). CARGO_TARGET_DIR is honoured.
set -euo pipefail
cd "$(dirname "$0")/.."
DEPTH=${DEPTH:-6}
ROUNDS=${ROUNDS:-3}
MODELS_DIRS=${MODELS_DIRS:-"bench-suite/peers/fidget/models bench-suite/peers/own-models"}
MODELS=${MODELS:-"bear:1:revaa colonnade:1:revaa gyroid-sphere:1:revaa tanglecube:0.25:revaa decocube:0.8:revaa csg:1:revaa"}
MAX_DEPTH=${MAX_DEPTH:-}
DIAG=${DIAG:-1}
TIMEOUT=${TIMEOUT:-600}
OUT_DIR=${OUT_DIR:-bench-out/peer-fidget-mesh}
DOC=${DOC-docs/peers/fidget-mesh.md}
TARGET=${CARGO_TARGET_DIR:-target}

whole() { [ -n "$1" ] && [ -z "${1//[0-9]/}" ] && [ ${#1} -le 6 ]; }
for v in DEPTH ROUNDS TIMEOUT MAX_DEPTH; do  # decimal, without leading zeros
    if whole "${!v}"; then printf -v "$v" '%d' "$((10#${!v}))"; fi
done
whole "$DEPTH" && [ "$DEPTH" -ge 1 ] && [ "$DEPTH" -le 12 ] \
    || { echo "error: DEPTH '$DEPTH' is not a whole number in 1..12 (fidget-peer's range)" >&2; exit 2; }
whole "$ROUNDS" && [ "$ROUNDS" -ge 1 ] || { echo "error: ROUNDS '$ROUNDS' is not a whole number above 0" >&2; exit 2; }
whole "$TIMEOUT" && [ "$TIMEOUT" -ge 1 ] || { echo "error: TIMEOUT '$TIMEOUT' is not a whole number of seconds above 0" >&2; exit 2; }
[ -z "$MAX_DEPTH" ] || { whole "$MAX_DEPTH" && [ "$MAX_DEPTH" -ge "$DEPTH" ]; } \
    || { echo "error: MAX_DEPTH '$MAX_DEPTH' is not a whole number >= DEPTH ($DEPTH)" >&2; exit 2; }
[ "$DIAG" = 0 ] || [ "$DIAG" = 1 ] || { echo "error: DIAG '$DIAG' is not 0 or 1" >&2; exit 2; }
[ -n "$MODELS" ] || { echo "error: MODELS is empty" >&2; exit 2; }
declare -A VM
for spec in $MODELS; do
    IFS=: read -r name scale arith rest <<< "$spec"
    [ -n "$name" ] && [ -n "$scale" ] && [ -n "$arith" ] && [ -z "$rest" ] \
        || { echo "error: MODELS entry '$spec' is not NAME:SCALE:ARITH" >&2; exit 2; }
    python3 -c "import math,sys; s=float(sys.argv[1]); sys.exit(0 if math.isfinite(s) and s > 0 else 1)" \
        "$scale" 2>/dev/null || { echo "error: MODELS entry '$spec': SCALE '$scale' is not a positive number" >&2; exit 2; }
    case "$arith" in ia|aa|raa|revaa|hull) ;; *)
        echo "error: MODELS entry '$spec': ARITH '$arith' is not ia, aa, raa, revaa or hull" >&2; exit 2;; esac
    for d in $MODELS_DIRS; do
        if [ -f "$d/$name.vm" ]; then VM[$name]=$d/$name.vm; break; fi
    done
    [ -n "${VM[$name]:-}" ] || { echo "error: $name.vm not found in MODELS_DIRS ($MODELS_DIRS)" >&2; exit 2; }
done

# A python3 with numpy for the checker.
if [ -z "${PYTHON:-}" ]; then
    if python3 -c "import numpy" 2>/dev/null; then
        PYTHON=python3
    else
        venv=bench-out/mesh-venv
        if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import numpy" 2>/dev/null; then
            echo "installing numpy into $venv (PyPI)..." >&2
            python3 -m venv "$venv" || { echo "error: cannot make a venv at $venv" >&2; exit 1; }
            "$venv/bin/pip" install -q numpy || { echo "error: pip could not install numpy into $venv" >&2; exit 1; }
        fi
        PYTHON=$venv/bin/python
    fi
fi
"$PYTHON" -c "import numpy" 2>/dev/null || { echo "error: PYTHON '$PYTHON' cannot import numpy" >&2; exit 2; }

echo "building fidget-peer and tracer (release)..." >&2
# The peer's own target dir, whatever CARGO_TARGET_DIR says (it is not our workspace).
CARGO_TARGET_DIR=bench-suite/peers/fidget/target \
    nice -n 10 cargo build --release -q --manifest-path bench-suite/peers/fidget/Cargo.toml
nice -n 10 cargo build --release -q -p tracer-cli --bin tracer
PEER=bench-suite/peers/fidget/target/release/fidget-peer
TRACER=$TARGET/release/tracer
mkdir -p "$OUT_DIR"
[ -z "$DOC" ] || mkdir -p "$(dirname "$DOC")"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
now_ns() { date +%s%N; }

# Runs "$@" with the timeout; records its wall time in ns to $1.ns, or "stopped".
timed() {
    local base=$1
    shift
    local t0 t1 rc=0
    t0=$(now_ns)
    timeout "$TIMEOUT" "$@" > "$base.out" 2> "$base.err" || rc=$?
    t1=$(now_ns)
    if [ "$rc" = 124 ]; then
        echo stopped > "$base.ns"
    elif [ "$rc" != 0 ]; then
        echo "error: this run failed (exit $rc):" >&2
        echo "  $*" >&2
        cat "$base.err" >&2
        exit 1
    else
        echo $((t1 - t0)) > "$base.ns"
    fi
}

n=$((1 << DEPTH))
for spec in $MODELS; do
    IFS=: read -r name scale arith <<< "$spec"
    model=${VM[$name]}
    # Our cube at depth N over the domain [-H, H]^3 (H = 1/SCALE) is centred on it with
    # 2^N cells along a side, one cell longer than the domain's side: half-side
    # H * 2^N / (2^N - 1). fidget's octree is world [-1, 1]^3 scaled by 1/S: the same
    # cube when S = SCALE * (2^N - 1) / 2^N. Cell side 2H / (2^N - 1).
    read -r half peer_scale cell <<< "$(python3 -c "
s = float('$scale'); n = $n
h = 1 / s
print(repr(h), repr(s * (n - 1) / n), repr(2 * h / (n - 1)))")"
    domain="-$half,-$half,-$half,$half,$half,$half"
    echo "$half $peer_scale $cell $model" > "$tmp/$name.frame"
    peer_cmd=("$PEER" mesh "$model" --depth "$DEPTH" --scale "$peer_scale" --out "$OUT_DIR/$name-fidget.ply")
    ours_cmd=("$TRACER" mesh "$model" --depth "$DEPTH" --domain="$domain" --arith "$arith"
              ${MAX_DEPTH:+--max-depth "$MAX_DEPTH"} --stats json -q --out "$OUT_DIR/$name-ours.ply")
    stopped_peer=0 stopped_ours=0
    for r in $(seq 1 "$ROUNDS"); do
        order="peer ours"
        [ $((r % 2)) -eq 0 ] && order="ours peer"
        for who in $order; do
            if [ "$who" = peer ]; then
                [ "$stopped_peer" = 1 ] && { echo stopped > "$tmp/$name-peer-$r.ns"; continue; }
                echo "$name depth $DEPTH round $r/$ROUNDS: fidget" >&2
                timed "$tmp/$name-peer-$r" "${peer_cmd[@]}"
                grep -q stopped "$tmp/$name-peer-$r.ns" && stopped_peer=1
            else
                [ "$stopped_ours" = 1 ] && { echo stopped > "$tmp/$name-ours-$r.ns"; continue; }
                echo "$name depth $DEPTH round $r/$ROUNDS: ours" >&2
                timed "$tmp/$name-ours-$r" "${ours_cmd[@]}"
                grep -q stopped "$tmp/$name-ours-$r.ns" && stopped_ours=1
            fi
        done
    done
    if [ "$DIAG" = 1 ] && [ "$stopped_ours" = 0 ]; then
        echo "$name: ours with --no-check, and at --max-depth $DEPTH" >&2
        timed "$tmp/$name-nocheck" "$TRACER" mesh "$model" --depth "$DEPTH" --domain="$domain" \
            --arith "$arith" ${MAX_DEPTH:+--max-depth "$MAX_DEPTH"} --no-check --stats json -q \
            --out "$tmp/diag.ply"
        [ "${MAX_DEPTH:-}" = "$DEPTH" ] || timed "$tmp/$name-flat" "$TRACER" mesh "$model" --depth "$DEPTH" --domain="$domain" \
            --arith "$arith" --max-depth "$DEPTH" --no-check --stats json -q --out "$tmp/diag.ply"
    fi
    echo "$name: checking the meshes" >&2
    [ "$stopped_peer" = 1 ] || "$PYTHON" scripts/mesh_check.py "$OUT_DIR/$name-fidget.ply" --vm "$model" \
        --cell "$cell" > "$OUT_DIR/$name-fidget-check.json"
    [ "$stopped_ours" = 1 ] || "$PYTHON" scripts/mesh_check.py "$OUT_DIR/$name-ours.ply" --vm "$model" \
        --clip="$domain" --cell "$cell" > "$OUT_DIR/$name-ours-check.json"
done

fidget_version=$(sed -n 's/^fidget = { version = "\([^"]*\)".*/\1/p' bench-suite/peers/fidget/Cargo.toml)
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1)
cpu="$(nproc) cores (${cpu:-unknown CPU})"
python3 - "$tmp" "$OUT_DIR" "$DEPTH" "$ROUNDS" "$TIMEOUT" "$DIAG" "${MAX_DEPTH:-}" "$fidget_version" "$cpu" \
    "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" "$(date -u +%Y-%m-%d)" \
    "DEPTH=$DEPTH ROUNDS=$ROUNDS${MAX_DEPTH:+ MAX_DEPTH=$MAX_DEPTH} DIAG=$DIAG TIMEOUT=$TIMEOUT MODELS=\"$MODELS\" OUT_DIR=$OUT_DIR DOC=$DOC scripts/peer-fidget-mesh.sh" \
    "$DOC" $MODELS <<'EOF'
import json, os, statistics, sys
tmp, out_dir, depth, rounds, timeout, diag, max_depth, fver, cpu, commit, date, command, doc = sys.argv[1:14]
specs = sys.argv[14:]
depth, rounds = int(depth), int(rounds)

def read(path):
    with open(path) as f:
        return f.read()

def times(name, who):
    ts = [read(f"{tmp}/{name}-{who}-{r}.ns").strip() for r in range(1, rounds + 1)]
    if "stopped" in ts:
        return None
    return statistics.median(int(t) / 1e9 for t in ts)

def check(name, who):
    try:
        return json.loads(read(f"{out_dir}/{name}-{who}-check.json"))
    except (FileNotFoundError, json.JSONDecodeError):
        return None

yn = lambda b: "yes" if b else "no"
rows, diag_rows, notes, frames = [], [], [], []
for spec in specs:
    name, scale, arith = spec.split(":")
    half, peer_scale, cell, model = read(f"{tmp}/{name}.frame").split()
    frames.append(f"- {name} (`{model}`): domain [-{float(half):g}, {float(half):g}]^3, "
                  f"fidget `--scale {float(peer_scale):.9g}`, cell {float(cell):.6g}")
    tp, to = times(name, "peer"), times(name, "ours")
    cp, co = check(name, "fidget"), check(name, "ours")
    stats = None
    if to is not None:
        stats = json.loads(read(f"{tmp}/{name}-ours-{rounds}.out").splitlines()[0])
    def cols(c):
        if c is None:
            return ["stopped"] * 6
        nm = c["non_manifold_edges"] + c["non_manifold_vertices"]
        return [str(c["triangles"]),
                yn(c["watertight"]) + ("" if c["watertight"] else f" ({c['boundary_edges']} open)"),
                yn(c["manifold"]) + ("" if c["manifold"] or not c["watertight"] else f" ({nm})"),
                str(c["self_intersections"]),
                f"{c['max_distance_cells']:.2f}",
                f"{c['components']} ({c['euler']})"]
    fp, fo = cols(cp), cols(co)
    ratio = f"{to / tp:.2f}" if tp and to else "-"
    rows.append([name, arith,
                 f"{tp:.2f}" if tp is not None else f"> {timeout} (stopped)",
                 f"{to:.2f}" if to is not None else f"> {timeout} (stopped)", ratio,
                 f"{fp[0]} / {fo[0]}", f"{fp[1]} / {fo[1]}", f"{fp[2]} / {fo[2]}",
                 f"{fp[3]} / {fo[3]}", f"{fp[4]} / {fo[4]}", f"{fp[5]} / {fo[5]}"])
    if stats is not None:
        def diag_time(tag):
            try:
                t = read(f"{tmp}/{name}-{tag}.ns").strip()
            except FileNotFoundError:
                return "-"
            if t == "stopped":
                return f"> {timeout}"
            s = json.loads(read(f"{tmp}/{name}-{tag}.out").splitlines()[0])
            return f"{int(t) / 1e9:.2f} (level {s['level']}, {s['triangles']} tris)"
        share = stats["certified_share"]
        diag_rows.append([name, f"{stats['wall_s']:.2f}", str(stats["level"]),
                          str(stats["cells_visited"]), str(stats["cells_probed"]),
                          str(stats["finer_cells"]), str(stats["edge_evals"]),
                          "-" if share is None else f"{share:.0%}",
                          str(stats["unresolved_at_max_depth"]),
                          str(stats["self_intersections"]),
                          diag_time("nocheck"), diag_time("flat")])
        if co is not None and stats["self_intersections"] != co["self_intersections"]:
            notes.append(f"- {name}: our mesher counted {stats['self_intersections']} "
                         f"self-intersecting pairs, the checker {co['self_intersections']}.")
        if stats["unresolved_at_max_depth"]:
            notes.append(f"- {name}: {stats['unresolved_at_max_depth']} probes of ours "
                         "unresolved at --max-depth (the tracer warned).")
    for who, c in (("fidget", cp), ("ours", co)):
        if c is not None and (c.get("nan_distances") or c.get("degenerate")):
            notes.append(f"- {name} ({who}): {c.get('degenerate', 0)} degenerate triangles, "
                         f"{c.get('nan_distances', 0)} vertices where |f|/|grad f| is undefined.")

head = ["model", "our arith", "fidget s", "ours s", "ours/fidget", "triangles",
        "watertight", "manifold", "self-intersecting pairs", "max vertex distance (cells)",
        "components (Euler)"]
table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
table += ["| " + " | ".join(r) + " |" for r in rows]
dhead = ["model", "our wall_s", "leaf level", "cells visited", "cells probed",
         "finer cells", "edge evals", "certified", "unresolved", "our self-int. count",
         "--no-check s", f"--max-depth {depth} --no-check s"]
dtable = ["| " + " | ".join(dhead) + " |", "|" + "---|" * len(dhead)]
dtable += ["| " + " | ".join(r) + " |" for r in diag_rows]
print("\n".join(table))
print()
print("\n".join(dtable))

if doc:
    text = f"""# Peer comparison: meshing with fidget

Our `tracer mesh` against the mesher of [fidget](https://github.com/mkeeter/fidget)
{fver} (crates.io, MPL-2.0; `fidget::mesh::Octree::build` to a depth, then
`walk_dual`: Manifold Dual Contouring with its JIT evaluator), built and run by
`scripts/peer-fidget-mesh.sh` from `bench-suite/peers/fidget/` (`fidget-peer mesh`,
outside our workspace). Each mesh is checked by `scripts/mesh_check.py`, the same
code for both.

- Command: `{command}`
- Date: {date}, commit {commit}
- Machine: {cpu}, **shared** (other builds may run alongside), so the times are
  indicative; each ratio comes from one run with the tools alternating. Both tools use
  every core (fidget: rayon's global pool; ours: one worker per core).
- Depth {depth} for both ({2 ** depth} cells along the cube's side at the finest
  level); ours with `--max-depth {max_depth or f'{depth + 4} (default)'}`. Each tool ran
  {rounds} times per model, the order flipped every round (fidget, ours, ours, fidget,
  ...); medians. A run past {timeout} s is stopped.

Columns: *fidget s* / *ours s*: median whole-process wall time (start to exit: reading
the model, meshing, writing a binary PLY; ours also counts its own checks, including
the self-intersection search); *ours/fidget*: their ratio; then each column gives
*fidget / ours*: *triangles*; *watertight*: every edge shared by exactly two triangles
in opposite directions (else the count of edges used once); *manifold*: watertight and
every vertex's triangles one fan (else the non-manifold edges + pinched vertices);
*self-intersecting pairs*: triangle pairs that cross, other than pairs sharing an edge
(f64 orientation tests, touching not counted); *max vertex distance*: the largest
first-order distance |f| / |grad f| of a vertex to the surface, in cells (ours: to the
shape clipped to its domain, which is what we mesh; fidget's mesh is not clipped);
*components (Euler)*: connected components and, in brackets, V - E + F.

{chr(10).join(table)}

fidget splits each dual quad into four triangles around the point where the quad's
edge crosses the surface (that point is the last corner of each: `MeshBuilder::triangle`
in fidget-mesh's `builder.rs`), so it has about twice our triangles at the same cells;
its crossing pairs include pairs of such fans that share only that point and fold
through each other. `scripts/mesh_check_exact.py MESH` re-tests a random sample of the
checker's verdicts (pairs sharing no vertex, and one) in exact rational arithmetic.

What our time goes to (from `--stats json` of the last timed run, and two extra runs:
without the self-intersection check, and without it at `--max-depth {depth}`, i.e. with
no probing below the depth and no raising of the leaf level, the work closest to
fidget's; each skipped where `-`): *leaf level*: the level the surface was contoured at (above {depth} where
probes or the finer check found features thinner than a cell); *cells probed*: cells
evaluated below the leaf level; *finer cells*: leaves whose finer lattice showed another
topology than their corners; *edge evals*: range evaluations of the edge root search.

{chr(10).join(dtable)}

## The same cells for both

`tracer mesh --depth N` divides a cube centred on the domain into `2^N` cells along a
side, the cube one cell longer than the domain's longest side (docs/meshing.md, "The
cube and the clip"): for the domain `[-H, H]^3` its half-side is `H 2^N / (2^N - 1)` and
a cell is `2H / (2^N - 1)`. fidget's octree is world `[-1, 1]^3` split `N` times, mapped
to the model by `world_to_model` = scale by `1/S`. With
`S = SCALE (2^N - 1) / 2^N` (H = 1/SCALE) the two cubes coincide, so both evaluate the
same lattice of corners. Residual differences: fidget works in `f32` (its corners
`-1 + 2i/2^N` are exact dyadics, multiplied by the `f32` of `1/S`, so they differ from
ours by about `1e-7` relative); ours meshes the shape clipped to the domain, half a cell
inside the cube's faces, fidget the unclipped shape over the whole cube (this matters only
where the surface reaches the domain's faces: ours is then capped there, fidget's open
at the cube); fidget collapses leaves whose merged QEF error stays small (so its meshes
are adaptive, `N` being its finest level), ours is uniform at the leaf level; ours
raises the leaf level above `N` where it finds features thinner than a cell (the
*leaf level* column), fidget never does.

The boxes of this run:

{chr(10).join(frames)}

## Notes

{chr(10).join(notes) if notes else "- No discrepancy between our mesher's own counts and the checker's."}
"""
    with open(doc, "w") as f:
        f.write(text)
    print(f"wrote {doc}", file=sys.stderr)
EOF
