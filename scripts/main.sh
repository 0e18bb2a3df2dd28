#!/usr/bin/env bash
# The main job: install the tools, then for the demo unit, a float operator and the three
# intersection units: generate the Verilog, lint it (verilator -Wall), run the IR evaluator,
# build the Verilator harness (cached), stream 1,000,000 vectors through it and compare every
# output of every valid cycle with the golden model. Stops at the first failing unit.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cargo build --release --bin rtl-gen
vectors="${VECTORS:-1000000}"
checks=(
  "mulcmp"
  "fadd --format binary32 -p round=dyn"
  "silhouette"
  "silhouette -p origin=bounded -p stages=2"
  "slab"
  "cull -p k=4 -p stages=3"
  "transform"
)
for c in "${checks[@]}"; do
  echo
  # shellcheck disable=SC2086 # each entry is a unit and its options
  ./target/release/rtl-gen check $c --vectors "$vectors" --no-progress
done
echo
echo "main job: ${#checks[@]} configurations, ${vectors} vectors each, all bit-exact"
