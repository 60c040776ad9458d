#!/usr/bin/env bash
# The README's mesh tables: `tracer mesh` on models at one depth, one row per model (and,
# with ARITHS, per arithmetic), from `--stats json`: wall time, leaf level, triangles,
# watertight, manifold, Euler characteristic, self-intersecting pairs, certified share,
# cells visited. Each run is stopped after TIMEOUT seconds (a row "stopped").
#
#   scripts/mesh-table.sh [DEPTH] [MODEL...]
#   TRACER=target/debug/tracer ARITHS="ia aa raa revaa hull" scripts/mesh-table.sh 5 mitchell
#   MAX_DEPTH=6 scripts/mesh-table.sh 5 hair     # --max-depth (default: depth + 4)
#
# TRACER defaults to target/release/tracer (built if missing).
set -uo pipefail
cd "$(dirname "$0")/.."
depth="${1:-6}"
shift || true
tracer="${TRACER:-target/release/tracer}"
ariths="${ARITHS:-revaa}"
timeout_s="${TIMEOUT:-60}"
if [ ! -x "$tracer" ]; then
    cargo build --release -p tracer-cli || exit 1
fi
models=("$@")
if [ ${#models[@]} -eq 0 ]; then
    mapfile -t models < <("$tracer" list | grep -v '^ ')
fi
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| model | arith | time s | leaf level | triangles | watertight | manifold | Euler | self-intersections | certified | cells visited |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for m in "${models[@]}"; do
    for a in $ariths; do
        json="$(timeout "$timeout_s" "$tracer" mesh "$m" --depth "$depth" --arith "$a" \
            ${MAX_DEPTH:+--max-depth "$MAX_DEPTH"} --out "$out/m.ply" --stats json -q 2>/dev/null)"
        if [ -z "$json" ]; then
            echo "| $m | $a | > $timeout_s (stopped) | | | | | | | | |"
            continue
        fi
        python3 - "$m" "$a" "$json" <<'EOF'
import json, sys
m, a, d = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
yn = lambda b: "yes" if b else "no"
share = d["certified_share"]
print(f"| {m} | {a} | {d['wall_s']:.2f} | {d['level']} | {d['triangles']} | "
      f"{yn(d['watertight'])} | {yn(d['manifold'])} ({d['non_manifold_edges']} edges) | "
      f"{d['euler']} | {d['self_intersections']} | "
      f"{'-' if share is None else f'{100 * share:.0f}%'} | {d['cells_visited']} |")
EOF
    done
done
