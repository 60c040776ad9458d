#!/usr/bin/env bash
# On a machine with a real GPU and a Vulkan driver: builds the GPU renderer, runs the
# GPU tests and `bench-suite table2` (512x512 and 1920x1080), and writes everything to
# gpu-device-check.txt (or the file given as $1). Prints the device first.
set -uo pipefail
cd "$(dirname "$0")/.."
out="${1:-gpu-device-check.txt}"
{
    echo "== $(date -u) $(uname -a)"
    command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv
    echo "== build"
    time cargo build --release -p tracer-cli --features gpu -p bench-suite --features bench-suite/gpu
    echo "== GPU tests"
    time cargo test --release -p tracer-gpu
    echo "== table2"
    time cargo run --release -p bench-suite --features gpu -- table2 --hd --frames 15 --out bench-out
    echo "== CLI"
    ./target/release/tracer render mitchell --device gpu --size 512x512 --out bench-out/mitchell-gpu.png -q
} 2>&1 | tee "$out"
