#!/usr/bin/env bash
# Tape-length scaling: scenes of N balls whose radii shrink as N^(-1/3)
# (scripts/gen-vm-scenes.py --kinds balls: |p - c|^2 - r^2 joined by a balanced tree of
# min, fidget's .vm format), each rendered by `tracer render` in the view its header's
# domain frames, with our default arithmetic unless ARITH says otherwise. Reports per N
# the .vm tape's instructions, the mean tape length per range evaluation (range_ops over
# the ray, cell and shading-box range evaluations of `--stats json`), those evaluation
# counts, hits, and the best whole-process wall time of ROUNDS rounds (the sizes
# alternate within a round). Prints a markdown table and writes it, with the command and
# the date, to DOC (DOC= skips the document).
#
#   scripts/tape-scaling.sh                       # N = 10 100 1000 10000, 512x512, 3 rounds
#   NS="10 100" SIZE=256 ROUNDS=1 DOC= scripts/tape-scaling.sh
#
# Goal: the mean tape length grows at most 2x from the smallest N to the largest.
set -euo pipefail
cd "$(dirname "$0")/.."
NS=${NS:-"10 100 1000 10000"}
SIZE=${SIZE:-512}
ROUNDS=${ROUNDS:-3}
ARITH=${ARITH:-auto}
SEED=${SEED:-41}
GEN_DIR=${GEN_DIR:-bench-out/tape-scaling}
DOC=${DOC-docs/tape-scaling.md}
[ -n "${SIZE##*[!0-9]*}" ] && [ "$SIZE" -ge 1 ] || { echo "error: SIZE '$SIZE' is not a whole number above 0" >&2; exit 2; }
[ -n "${ROUNDS##*[!0-9]*}" ] && [ "$ROUNDS" -ge 1 ] || { echo "error: ROUNDS '$ROUNDS' is not a whole number above 0" >&2; exit 2; }
[ -n "${SEED##*[!0-9]*}" ] || { echo "error: SEED '$SEED' is not a whole number" >&2; exit 2; }
for n in $NS; do
    [ -n "${n##*[!0-9]*}" ] && [ "$n" -ge 1 ] || { echo "error: NS entry '$n' is not a whole number above 0" >&2; exit 2; }
done
[ -n "$NS" ] || { echo "error: NS is empty" >&2; exit 2; }
case "$ARITH" in auto|ia|aa|raa|revaa|hull) ;;
    *) echo "error: ARITH '$ARITH' is not auto, ia, aa, raa, revaa or hull" >&2; exit 2 ;;
esac

echo "building tracer (release)..." >&2
nice -n 10 cargo build --release -q -p tracer-cli --bin tracer
TRACER=${CARGO_TARGET_DIR:-target}/release/tracer
python3 scripts/gen-vm-scenes.py "$GEN_DIR" --kinds balls --n "${NS// /,}" --seed "$SEED" > /dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load0=$(cut -d' ' -f1-3 /proc/loadavg)
now_ns() { date +%s%N; }
for r in $(seq 1 "$ROUNDS"); do
    for n in $NS; do
        echo "round $r/$ROUNDS: $n balls" >&2
        t0=$(now_ns)
        /usr/bin/time -f "%U %S" -o "$tmp/$n-$r.cpu" "$TRACER" render "$GEN_DIR/balls-$n.vm" --size "${SIZE}x$SIZE" --arith "$ARITH" --stats json -q \
            --out "$tmp/balls-$n.png" > "$tmp/$n-$r.json" 2> "$tmp/$n-$r.err" \
            || { cat "$tmp/$n-$r.err" >&2; exit 1; }
        t1=$(now_ns)
        echo $((t1 - t0)) > "$tmp/$n-$r.ns"
    done
done

echo "$load0 / $(cut -d' ' -f1-3 /proc/loadavg)" > "$tmp/load"
python3 - "$tmp" "$GEN_DIR" "$ROUNDS" "$(git rev-parse --short HEAD 2>/dev/null || echo unknown)" \
    "$(date -u '+%Y-%m-%d %H:%M UTC')" "$(nproc)" \
    "NS=\"$NS\" SIZE=$SIZE ROUNDS=$ROUNDS ARITH=$ARITH SEED=$SEED scripts/tape-scaling.sh" \
    "$DOC" $NS <<'EOF'
import json, sys
tmp, gen, rounds, commit, date, cores, command, doc = sys.argv[1:9]
ns = [int(n) for n in sys.argv[9:]]
rounds = int(rounds)
rows, means = [], []
for n in ns:
    with open(f"{gen}/balls-{n}.vm") as f:
        instr = sum(1 for l in f if l.strip() and not l.lstrip().startswith("#")
                    and l.split()[1] != "const")
    secs = [int(open(f"{tmp}/{n}-{r}.ns").read()) / 1e9 for r in range(1, rounds + 1)]
    cpus = [sum(float(v) for v in open(f"{tmp}/{n}-{r}.cpu").read().split()[-2:])
            for r in range(1, rounds + 1)]
    s = json.loads(open(f"{tmp}/{n}-{rounds}.json").read().splitlines()[0])
    evals = s["range_evals"] + s["cell_evals"] + s["shade_evals"]
    mean = s["range_ops"] / evals if evals else 0.0
    means.append(mean)
    rows.append([f"{n}", s["arith"], f"{instr}", f"{mean:.1f}", f"{mean / means[0]:.2f}",
                 f"{s['range_evals']}", f"{s['cell_evals']}", f"{s['shade_evals']}",
                 f"{evals / max(s['hits'], 1):.1f}", f"{s['hits']}", f"{s['unconfirmed']}",
                 f"{s['wall_s']:.3f}", f"{min(secs):.3f}", f"{min(cpus):.3f}"])
head = ["N balls", "arith", ".vm instructions", "mean tape per range eval",
        f"mean tape / N={ns[0]}", "ray range evals", "cell range evals", "shading-box range evals",
        "range evals per hit", "hits", "unconfirmed", "render s (stats)", "best whole-process s",
        "best CPU s"]
table = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
table += ["| " + " | ".join(r) + " |" for r in rows]
growth = means[-1] / means[0] if means[0] else float("inf")
verdict = (f"Mean tape length from N = {ns[0]} to N = {ns[-1]}: {means[0]:.1f} -> {means[-1]:.1f}, "
           f"{growth:.2f}x (goal: at most 2x): {'met' if growth <= 2 else 'not met'}.")
print("\n".join(table))
print(verdict)
if doc:
    with open(doc, "w") as f:
        f.write(f"""# Tape-length scaling: N balls, radii shrinking as N^(-1/3)

- Command: `{command}`
- Date: {date}, commit {commit}; {cores} cores, a shared machine: times are indicative,
  the counters are exact and repeatable. Load average (1, 5, 15 min) at the start / the
  end of the run: {open(f"{tmp}/load").read().strip()}.
- Scenes: `scripts/gen-vm-scenes.py DIR --kinds balls` (the `.vm` files, f < 0 inside,
  `|p - c|^2 - r^2` per ball, balanced `min` tree), rendered by `tracer render FILE
  --size WxH --stats json` in the view framing the header's domain `[-1, 1]^3`.

Columns: *.vm instructions*: the tape as written (constants not counted); *mean tape
per range eval*: `range_ops / (range_evals + cell_evals + shade_evals)` of `--stats
json`, i.e. the mean length of the specialised tapes that range evaluations ran;
*range evals per hit*: all three kinds of range evaluations over the hit pixels;
*render s*: the tracer's own `wall_s` (last round); *best whole-process s*: best of
{rounds} rounds, start to exit; *best CPU s*: user + system seconds of the process.

{chr(10).join(table)}

{verdict}
""")
    print(f"wrote {doc}", file=sys.stderr)
EOF
