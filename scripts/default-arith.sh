#!/usr/bin/env bash
# Measurements for the default arithmetic: every built-in model in
# its default view and fidget's .vm models in the peer frame (scripts/peer-fidget.sh),
# rendered in each arithmetic of ARITHS; per model and arithmetic: hits, unconfirmed
# hits, deterministic work counters and the median render time (`wall_s` of
# `--stats json`), then which candidate default rules meet the goal
#   unconfirmed(default) <= unconfirmed(ia) + 0.1% of the hits, and
#   time(default) <= 1.10 x time(fastest arithmetic measured).
# Times come from one run: every round renders the model in every arithmetic, the order
# rotated each round (ia revaa hull raa / revaa hull raa ia / ...), medians of ROUNDS.
# Probe renders at PROBE_SIZE (PROBE_VM for .vm) in every arithmetic feed the probe rules:
# kind "probe" with the tracer's default precision for that small image, kind "probe-eps"
# with --eps set to the full-size render's precision (a quarter pixel at the distance of
# the look-at point), so that the probe searches as deep as the full render. PROBES picks
# the kinds (default both; empty: none); a probe running past PROBE_CAP seconds is stopped
# and counted as lost (as a race between the arithmetics would stop it).
# Prints markdown on stdout; progress on stderr. Does not build anything.
#
#   scripts/default-arith.sh                                   # all models, 3 rounds
#   TRACER=/tmp/tracer SIZE=200x150 VM_SIZE=128 ROUNDS=3 scripts/default-arith.sh
#   MODELS="mitchell hair@100x75" VM_MODELS="bear:1@96" ROUNDS=1 scripts/default-arith.sh
#
# MODELS: built-in names, each optionally NAME@WxH to override SIZE (default: all of
# `tracer list`). VM_MODELS: NAME:SCALE[@N] (NAME.vm in VM_DIR, SCALE as in
# peer-fidget.sh, N overrides VM_SIZE; N x N pixels). RAW=FILE keeps the raw JSON lines;
# FROM_RAW=FILE skips rendering and reports from such a file (several files: cat them).
# NOISE_S (default 0.05): a time over 1.10 x the fastest by less than NOISE_S seconds is
# flagged t (timing noise on a loaded machine) rather than T.
# PROBE_TOL (default 0.01): a probe shows walls when it has more unconfirmed hits than
# IA's probe plus this fraction of its hits (at least 2 pixels).
# SLOW_S: an arithmetic whose first full render of a model takes more than SLOW_S seconds
# is not rendered again for that model (one time is enough to show it is not the fastest).
# Rules checked: (a) hull, (b) revaa, (c) ia everywhere; per model from the probes: (d)
# cheapest by range evaluations x a per-arithmetic weight, (e) revaa or hull on walls,
# (f) fastest probe, (g) evaluations x the model's own time per evaluation, (h) ia or
# revaa (hull on walls) by probe time, (i) as (h), ia only under 0.8 x the other's probe
# time; primed rules use the probe-eps probes; (o) the oracle. Results: docs/default-arith.md.
set -euo pipefail
cd "$(dirname "$0")/.."
TRACER=${TRACER:-target/release/tracer}
SIZE=${SIZE:-400x300}
VM_SIZE=${VM_SIZE:-256}
ROUNDS=${ROUNDS:-3}
PROBE_SIZE=${PROBE_SIZE:-48x36}
PROBE_VM=${PROBE_VM:-48}
PROBES=${PROBES-"probe probe-eps"}
PROBE_CAP=${PROBE_CAP:-10}
ARITHS=${ARITHS:-"ia revaa hull raa"}
VM_DIR=${VM_DIR:-bench-suite/peers/fidget/models}
VM_MODELS=${VM_MODELS-"bear:1 colonnade:1 gyroid-sphere:1 tanglecube:0.25"}
SLOW_S=${SLOW_S:-20}
RAW=${RAW:-}
FROM_RAW=${FROM_RAW:-}
NOISE_S=${NOISE_S:-0.05}
PROBE_TOL=${PROBE_TOL:-0.01}

die() { echo "error: $*" >&2; exit 2; }
[[ $NOISE_S =~ ^[0-9]*\.?[0-9]+$ ]] || die "NOISE_S '$NOISE_S' is not a number of seconds"
[[ $PROBE_TOL =~ ^[0-9]*\.?[0-9]+$ ]] || die "PROBE_TOL '$PROBE_TOL' is not a fraction"
for a in $ARITHS; do
    case $a in ia|aa|raa|revaa|hull) ;; *) die "ARITHS: unknown arithmetic '$a'" ;; esac
done
[[ " $ARITHS " == *" ia "* ]] || die "ARITHS must include ia (the goal is relative to IA)"
is_size() { [[ $1 =~ ^[1-9][0-9]*x[1-9][0-9]*$ ]]; }
is_n() { [[ $1 =~ ^[1-9][0-9]*$ ]]; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
raw=$tmp/raw.jsonl

if [ -n "$FROM_RAW" ]; then
    [ -f "$FROM_RAW" ] || die "FROM_RAW '$FROM_RAW' not found"
    cp "$FROM_RAW" "$raw"
else
    [ -x "$TRACER" ] || die "TRACER '$TRACER' is not an executable (build it: cargo build --release -p tracer-cli)"
    is_size "$SIZE" || die "SIZE '$SIZE' is not WxH"
    is_size "$PROBE_SIZE" || die "PROBE_SIZE '$PROBE_SIZE' is not WxH"
    is_n "$VM_SIZE" || die "VM_SIZE '$VM_SIZE' is not a whole number above 0"
    is_n "$PROBE_VM" || die "PROBE_VM '$PROBE_VM' is not a whole number above 0"
    [[ $ROUNDS =~ ^[0-9]+$ ]] || die "ROUNDS '$ROUNDS' is not a whole number (0: probes only)"
    [[ $PROBE_CAP =~ ^[0-9]+(\.[0-9]+)?$ ]] || die "PROBE_CAP '$PROBE_CAP' is not a number of seconds"
    for k in $PROBES; do
        case $k in probe|probe-eps) ;; *) die "PROBES: unknown kind '$k' (probe, probe-eps)" ;; esac
    done
    command -v timeout > /dev/null || die "timeout (coreutils) not found"
    command -v python3 > /dev/null || die "python3 not found"
    for a in $ARITHS; do
        case $a in ia|aa|raa|revaa|hull) ;; *) die "ARITHS: unknown arithmetic '$a'" ;; esac
    done
    listed=$("$TRACER" list | grep -E '^[a-z0-9]' | awk '{print $1}') \
        || die "'$TRACER list' failed"
    MODELS=${MODELS:-$listed}
    for spec in $MODELS; do
        name=${spec%@*}
        grep -qx -- "$name" <<< "$listed" || die "MODELS: '$name' is not a built-in model ($TRACER list)"
        [ "$spec" = "$name" ] || is_size "${spec#*@}" || die "MODELS entry '$spec': size is not WxH"
    done
    for spec in $VM_MODELS; do
        IFS=: read -r name rest <<< "$spec"
        scale=${rest%@*}
        [ -f "$VM_DIR/$name.vm" ] || die "$VM_DIR/$name.vm not found (VM_MODELS entry '$spec')"
        [[ $scale =~ ^[0-9]*\.?[0-9]+$ ]] || die "VM_MODELS entry '$spec' is not NAME:SCALE[@N]"
        [ "$rest" = "$scale" ] || is_n "${rest#*@}" || die "VM_MODELS entry '$spec': N is not a number"
    done

    # vm_frame SCALE N: the peer-fidget.sh orthographic frame for N x N pixels.
    vm_frame() {
        python3 -c "
s = float('$1'); n = $2
w, d, e, h = 2 / s, -1 / (n * s), 2 / s, 1 / s
print(f'--ortho {w!r} --eye {d!r},{d!r},{e!r} --look-at {d!r},{d!r},0 --up 0,1,0 --domain=-{h!r},-{h!r},-{h!r},{h!r},{h!r},{h!r}')"
    }
    # view_eps NAME WxH: the precision of a full render of a built-in model at its
    # default view, a quarter pixel at the distance of the look-at point (as --eps).
    view_eps() {
        "$TRACER" list | python3 -c "
import math, re, sys
name, (w, h) = sys.argv[1], map(int, sys.argv[2].split('x'))
lines = sys.stdin.read().splitlines()
i = lines.index(name)
block = []
for l in lines[i + 1:]:
    if not l.startswith(' '):
        break
    block.append(l.strip())
dom = [float(v) for v in next(l for l in block if l.startswith('domain')).split()[1].split(',')]
view = next(l for l in block if l.startswith('view'))
get = lambda k: [float(v) for v in re.search(k + r' (\\S+)', view).group(1).split(',')]
eye, at, fov = get('--eye'), get('--look-at'), get('--fov')[0]
diag = math.dist(dom[:3], dom[3:])
print(repr(1e-7 * diag + 0.25 * 2 * math.tan(math.radians(fov) / 2) / h * math.dist(eye, at)))" "$1" "$2"
    }
    # render LABEL KIND ROUND ARITH SIZE ARGS...: one render, its stats as one JSON line.
    render() {
        local label=$1 kind=$2 round=$3 arith=$4 size=$5 cap=0 rc=0
        shift 5
        [ "$kind" = full ] || cap=$PROBE_CAP
        local out t0 t1
        t0=$(date +%s%N)
        out=$(timeout "$cap" "$TRACER" render "$@" --arith "$arith" --size "$size" --stats json -q \
              --out "$tmp/img.png" 2> "$tmp/err") || rc=$?
        if [ "$rc" = 124 ] && [ "$kind" != full ]; then
            echo "{\"label\": \"$label\", \"kind\": \"$kind\", \"arith\": \"$arith\", \"size\": \"$size\", \"round\": $round, \"timed_out\": true, \"wall_s\": $cap}" >> "$raw"
            echo "  $label $kind $arith $size: stopped after PROBE_CAP=$cap s" >&2
            return 0
        fi
        [ "$rc" = 0 ] || { echo "error: $label ($arith, $size) failed: $(tail -1 "$tmp/err")" >&2; exit 1; }
        t1=$(date +%s%N)
        python3 -c "
import json, sys
s = json.loads(sys.argv[1].splitlines()[0])
s.update(label=sys.argv[2], kind=sys.argv[3], round=int(sys.argv[4]), size=sys.argv[5],
         process_s=int(sys.argv[6]) / 1e9)
print(json.dumps(s))" "$out" "$label" "$kind" "$round" "$size" $((t1 - t0)) >> "$raw"
        last_s=$(python3 -c "import json,sys; print(json.loads(sys.argv[1].splitlines()[0])['wall_s'])" "$out")
        echo "  $label $kind r$round $arith $size: $last_s s" >&2
    }
    rotate() { local r=$1; shift; local a=("$@") n=$#; for ((i = 0; i < n; i++)); do echo "${a[$(((i + r) % n))]}"; done; }

    # run_model LABEL FULL_SIZE PROBE_SIZE FULL_ARGS PROBE_ARGS EPS (args: strings)
    run_model() {
        local label=$1 fsize=$2 psize=$3 fargs=$4 pargs=$5 eps=$6 r a k slow=" "
        echo "$label (full-size precision $eps)" >&2
        for k in $PROBES; do
            for a in $ARITHS; do
                # shellcheck disable=SC2086
                if [ "$k" = probe ]; then
                    render "$label" "$k" 0 "$a" "$psize" $pargs
                else
                    render "$label" "$k" 0 "$a" "$psize" $pargs --eps "$eps"
                fi
            done
        done
        for ((r = 1; r <= ROUNDS; r++)); do
            # shellcheck disable=SC2046,SC2086
            for a in $(rotate $((r - 1)) $ARITHS); do
                if [[ $slow == *" $a "* ]]; then continue; fi
                render "$label" full "$r" "$a" "$fsize" $fargs
                if python3 -c "import sys; sys.exit(float(sys.argv[1]) <= float(sys.argv[2]))" \
                    "$last_s" "$SLOW_S"; then
                    slow="$slow$a "
                    echo "  ($a: slower than SLOW_S=$SLOW_S s, not repeated)" >&2
                fi
            done
        done
    }

    for spec in $MODELS; do
        name=${spec%@*}
        size=$SIZE
        [ "$spec" = "$name" ] || size=${spec#*@}
        run_model "$name" "$size" "$PROBE_SIZE" "$name" "$name" "$(view_eps "$name" "$size")"
    done
    for spec in $VM_MODELS; do
        IFS=: read -r name rest <<< "$spec"
        scale=${rest%@*}
        n=$VM_SIZE
        [ "$rest" = "$scale" ] || n=${rest#*@}
        run_model "$name.vm" "${n}x$n" "${PROBE_VM}x$PROBE_VM" \
            "$VM_DIR/$name.vm $(vm_frame "$scale" "$n")" "$VM_DIR/$name.vm $(vm_frame "$scale" "$PROBE_VM")" \
            "$(python3 -c "s = float('$scale'); print(repr(1e-7 * 3 ** 0.5 * 2 / s + 0.25 * (2 / s) / $n))")"
    done
fi
[ -z "$RAW" ] || cp "$raw" "$RAW"

python3 - "$raw" "$ARITHS" "$NOISE_S" "$PROBE_TOL" <<'EOF'
import json, math, statistics, sys
from collections import defaultdict
raw, ariths, noise = sys.argv[1], sys.argv[2].split(), float(sys.argv[3])
PTOL = float(sys.argv[4])  # wall bound on a probe: + PTOL of its hits, at least 2 pixels
full = defaultdict(lambda: defaultdict(list))
probes = defaultdict(lambda: defaultdict(dict))  # kind -> model -> arith -> stats
order = []
for line in open(raw):
    s = json.loads(line)
    if s["label"] not in order:
        order.append(s["label"])
    if s["kind"] == "full":
        full[s["label"]][s["arith"]].append(s)
    else:
        probes[s["kind"]][s["label"]][s["arith"]] = s
order = [m for m in order if "ia" in full[m]]
ariths = [a for a in ariths if any(a in full[m] for m in order)]
if not order:
    print("No full renders with an IA one (ROUNDS=0?): nothing to compare.")
    sys.exit(0)
TOL_UNC, TOL_T = 0.001, 1.10
med = statistics.median
T = {m: {a: med(x["wall_s"] for x in full[m][a]) for a in full[m]} for m in order}

def evals(s):  # all range evaluations: rays, culling cells, shading boxes
    return s["range_evals"] + s["cell_evals"] + s["shade_evals"]

# Cost of one range evaluation in each arithmetic relative to revaa's on the same model
# (the median over models whose fastest render takes at least 0.2 s): the weight that
# turns a probe's evaluation counts into a cost.
ref = "revaa" if "revaa" in ariths else ariths[0]
W = {}
for a in ariths:
    r = [(T[m][a] / evals(full[m][a][0])) / (T[m][ref] / evals(full[m][ref][0]))
         for m in order if a in T[m] and ref in T[m] and min(T[m].values()) >= 0.2]
    W[a] = med(r) if r else 1.0

def done(p):  # the probes that ran to the end (not stopped at PROBE_CAP)
    return {a: x for a, x in p.items() if not x.get("timed_out")}

def lim(p, base="ia"):
    """Wall bound on a probe: the base's unconfirmed hits + PTOL of its hits (>= 2
    pixels: a probe of a few hundred hits cannot see 0.1%); when the base's probe was
    stopped, the fewest unconfirmed of the others."""
    p = done(p)
    if not p:
        return -1
    b = p[base] if base in p else min(p.values(), key=lambda x: x["unconfirmed"])
    return b["unconfirmed"] + max(2, PTOL * b["hits"])

def rule_probe(m, probe):
    """(d): probes in every arithmetic; drop those with more unconfirmed hits than IA's
    plus the probe tolerance (lim); take the lowest cost, cost =
    range evaluations x the arithmetic's weight W."""
    p = probe.get(m, {})
    l = lim(p)
    ok = [a for a in ariths if a in done(p) and p[a]["unconfirmed"] <= l]
    if not ok:
        return None
    return min(ok, key=lambda a: evals(p[a]) * W[a])

def rule_revaa_hull(m, probe):
    """(e): probes in revaa and hull only; revaa unless its probe has more unconfirmed
    hits than hull's plus the probe tolerance (lim), then hull."""
    p = done(probe.get(m, {}))
    if "revaa" not in p or "hull" not in p:
        return None
    return "hull" if p["revaa"]["unconfirmed"] > lim(p, "hull") else "revaa"

def rule_probe_time(m, probe):
    """(f): as (d), but cost = the probe's own render time (wall_s) instead of counters."""
    p = probe.get(m, {})
    l = lim(p)
    ok = [a for a in ariths if a in done(p) and p[a]["unconfirmed"] <= l]
    if not ok:
        return None
    return min(ok, key=lambda a: p[a]["wall_s"])

def rule_probe_unit(m, probe):
    """(g): as (d), but cost = probe evaluations x this model's own time per range
    evaluation in that arithmetic (here taken from the full renders: what timing a batch of
    the probe's evaluations on the model's tape would give; an upper bound for (d)-(f))."""
    p = probe.get(m, {})
    l = lim(p)
    ok = [a for a in ariths if a in done(p) and a in T[m] and p[a]["unconfirmed"] <= l]
    if not ok:
        return None
    return min(ok, key=lambda a: evals(p[a]) * T[m][a] / evals(full[m][a][0]))

def rule_ia_revaa(m, probe):
    """(h): probes in ia and revaa (hull too when revaa's shows walls); revaa's probe
    with more unconfirmed hits than IA's + the probe tolerance (lim) drops revaa and
    brings in hull; take the candidate whose probe ran fastest (a stopped probe loses)."""
    p = done(probe.get(m, {}))
    if "ia" not in p and "revaa" not in p:
        return None
    cand = [a for a in ("ia", "revaa") if a in p]
    if "revaa" in p and "ia" in p and p["revaa"]["unconfirmed"] > lim(p):
        cand = [a for a in ("ia", "hull") if a in p]
    return min(cand, key=lambda a: p[a]["wall_s"])

def rule_ia_revaa_margin(m, probe):
    """(i): as (h), but IA only when its probe ran in under 0.8 x the other's time (IA's
    evaluation count grows faster with the resolution than the affine ones')."""
    p = done(probe.get(m, {}))
    if "ia" not in p and "revaa" not in p:
        return None
    other = "revaa"
    if "revaa" in p and "ia" in p and p["revaa"]["unconfirmed"] > lim(p):
        other = "hull"
    if other not in p:
        return "ia"
    if "ia" not in p:
        return other
    return "ia" if p["ia"]["wall_s"] < 0.8 * p[other]["wall_s"] else other

def oracle(m):
    """(o): the best any rule could do: the fastest arithmetic meeting the wall bound."""
    ia = full[m]["ia"][0]
    ok = [a for a in T[m] if full[m][a][0]["unconfirmed"]
          <= ia["unconfirmed"] + TOL_UNC * full[m][a][0]["hits"]]
    return min(ok, key=lambda a: T[m][a])

rules = [(f"({c}) {a}", (lambda a: lambda m: a)(a))
         for c, a in zip("abc", ("hull", "revaa", "ia")) if a in ariths]
for kind, tag in (("probe", ""), ("probe-eps", "'")):
    if kind in probes:
        for c, n, f in (("d", "probe, evals x W", rule_probe), ("e", "probe, revaa/hull", rule_revaa_hull),
                        ("f", "probe, time", rule_probe_time), ("g", "probe, unit cost", rule_probe_unit),
                        ("h", "probe ia/revaa, time", rule_ia_revaa),
                        ("i", "as h, ia by a 0.8 margin", rule_ia_revaa_margin)):
            rules.append((f"({c}{tag}) {n}", (lambda f, pr: lambda m: f(m, pr))(f, probes[kind])))
rules.append(("(o) oracle", oracle))

kinds = [k for k in ("probe", "probe-eps") if k in probes]
head = ["model", "size", "arith", "hits", "unconfirmed", "unc - ia (% of hits)",
        "median s (n)", "t / fastest", "range evals", "evals x W / min"]
for k in kinds:
    head += [f"{k}: unc / hits", f"{k}: evals", f"{k}: s"]
print("| " + " | ".join(head) + " |")
print("|" + "---|" * len(head))
track = []
for m in order:
    F, t = full[m], T[m]
    tmin = min(t.values())
    cmin = min(evals(F[a][0]) * W[a] for a in F)
    ia = F["ia"][0]
    fastest = min(t, key=t.get)
    for a in ariths:
        if a not in F:
            continue
        s = F[a][0]
        d = s["unconfirmed"] - ia["unconfirmed"]
        c = evals(s) * W[a] / cmin
        if tmin >= 0.2:
            track.append(abs(math.log(c) - math.log(t[a] / tmin)))
        print(f"| {m} | {s['size']} | {a} | {s['hits']} | {s['unconfirmed']} | "
              f"{d:+d} ({d / max(s['hits'], 1):+.2%}) | {t[a]:.2f} ({len(F[a])}) | "
              f"{t[a] / tmin:.2f}{' *' if a == fastest else ''} | {evals(s)} | {c:.2f} | "
              + "".join((f"stopped | - | >{p['wall_s']} | " if p.get("timed_out") else
                         f"{p['unconfirmed']} / {p['hits']} | {evals(p)} | {p['wall_s']:.3f} | ")
                        if p else "- | - | - | "
                        for p in (probes[k].get(m, {}).get(a) for k in kinds)))
print()
print("Weights W (cost of one range evaluation relative to " + ref + "'s, median over the "
      "models whose fastest render takes >= 0.2 s): "
      + ", ".join(f"{a} {W[a]:.2f}" for a in ariths) + ".")
if track:
    print(f"Counters against time (same models): |ln(evals x W ratio) - ln(time ratio)| "
          f"median {med(track):.2f}, max {max(track):.2f} (0.10 is about 10%).")
print()
print("Candidate rules: per model, the arithmetic the rule picks and whether it meets the "
      "goal (W: more unconfirmed hits than IA's + 0.1% of the hits; T: slower than 1.10 x "
      f"the fastest; t: slower than that, but by less than {noise} s, within this machine's "
      "noise).")
print()
print("| model | " + " | ".join(n for n, _ in rules) + " |")
print("|---|" + "---|" * len(rules))
fails = defaultdict(list)
for m in order:
    F, t = full[m], T[m]
    tmin = min(t.values())
    ia = F["ia"][0]
    cells = []
    for name, f in rules:
        a = f(m)
        if a is None or a not in F:
            cells.append(f"{a or '-'} ?")
            fails[name].append(f"{m} (no data)")
            continue
        s = F[a][0]
        flag = ""
        if s["unconfirmed"] > ia["unconfirmed"] + TOL_UNC * s["hits"]:
            flag += "W"
        if t[a] > TOL_T * tmin:
            flag += "T" if t[a] - TOL_T * tmin > noise else "t"
        if flag not in ("", "t"):
            fails[name].append(f"{m} ({flag}, {t[a] / tmin:.2f}x)")
        cells.append(f"{a} {flag or 'ok'}")
    print(f"| {m} | " + " | ".join(cells) + " |")
if "ia" in ariths and "revaa" in ariths and kinds:
    print()
    print("How well probes predict IA against RevAA (ratios ia / revaa; > 1: revaa cheaper):")
    print()
    hd = ["model", "full time", "full evals"]
    for k in kinds:
        hd += [f"{k} evals", f"{k} time"]
    hd.append("agree on the winner (time)")
    print("| " + " | ".join(hd) + " |")
    print("|" + "---|" * len(hd))
    for m in order:
        F = full[m]
        if "revaa" not in F:
            continue
        ft = T[m]["ia"] / T[m]["revaa"]
        row = [m, f"{ft:.2f}", f"{evals(F['ia'][0]) / evals(F['revaa'][0]):.2f}"]
        agree = []
        for k in kinds:
            p = probes[k].get(m, {})
            if "ia" in p and "revaa" in p and not p["ia"].get("timed_out") \
                    and not p["revaa"].get("timed_out"):
                pt = p["ia"]["wall_s"] / p["revaa"]["wall_s"]
                row += [f"{evals(p['ia']) / evals(p['revaa']):.2f}", f"{pt:.2f}"]
                agree.append("yes" if (pt > 1) == (ft > 1) else "no")
            elif "ia" in p and p["ia"].get("timed_out"):
                row += ["ia stopped", "ia stopped"]
                agree.append("yes" if ft > 1 else "no")
            else:
                row += ["-", "-"]
        row.append(" / ".join(agree))
        print("| " + " | ".join(row) + " |")

over = []
probe = probes[kinds[0]] if kinds else {}
for m in order:
    p = done(probe.get(m, {}))
    if p:
        # raced probes: each arithmetic's probe stopped once it exceeds the fastest one
        over.append((len(p) * min(x["wall_s"] for x in p.values()) / min(T[m].values()), m))
if over:
    print()
    print("Probe overhead, if the probes race (each stopped when it passes the fastest): "
          "arithmetics x fastest probe time / fastest full render: median "
          f"{med(o for o, _ in over):.0%}, max {max(over)[0]:.0%} ({max(over)[1]}); "
          "unraced (every probe to its end): median "
          f"{med(sum(x['wall_s'] for x in probe[m].values()) / min(T[m].values()) for _, m in over):.0%}"
          f" ({kinds[0]} set).")
print()
for name, _ in rules:
    print(f"- {name}: " + ("meets the goal on every model (t counted as met)" if not fails[name]
                            else f"misses on {len(fails[name])}: " + ", ".join(fails[name])))
EOF
