#!/usr/bin/env bash
# Release run (issue #17): the long cross-checks CI does not run.
#
# 1. Verilator against the golden model on at least 10^8 vectors over the seed units'
#    configurations (every output of every valid cycle compared), each configuration with
#    `rtl-gen check --jobs --report --junit`;
# 2. the exact-reference property tests at 10^7 cases (silhouette rays and bundles, cull, the
#    transform unit's hardware inverse against the exact rational inverse) and the triangle
#    unit's closed-cube sweep over the whole float range (TRIANGLE_RANGE=full);
# 3. the golden models' fast paths against the generic models at 10^8 vectors per unit and
#    format class (issue #20; RELEASE_FAST_CASES), unless RELEASE_FAST=0;
# 4. one shard of the mutation testing (scripts/mutants.sh --shard, RELEASE_MUTANTS_SHARD,
#    default 0/150: about 29 mutants, 30 minutes), unless RELEASE_MUTANTS=0.
#
#   bash scripts/release.sh                        # everything, reports in out/release/
#   RELEASE_SHARD=2/4 bash scripts/release.sh      # shard 2 of 4 of the vector checks only
#
# On a CI matrix: N jobs, job K runs `RELEASE_SHARD=K/N RELEASE_EXACT=0 RELEASE_MUTANTS=0
# bash scripts/release.sh`, one more job runs the exact, fast-path and mutation parts
# (`RELEASE_VECTORS=0 bash scripts/release.sh`); `rtl-gen merge-reports` combines the JSON
# reports of one configuration. Knobs: RELEASE_SCALE (vectors multiplier, default 1),
# RELEASE_JOBS (harness processes, default all cores), RELEASE_CASES (exact cases, 10^7).
# Prints one summary line per part and `release: ... all bit-exact` at the end; exits non-zero
# on the first failure.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
out=out/release
mkdir -p "$out"
scale="${RELEASE_SCALE:-1}"
jobs="${RELEASE_JOBS:-$(nproc)}"
cases="${RELEASE_CASES:-10000000}"
shard=()
if [ -n "${RELEASE_SHARD:-}" ]; then
    shard=(--shard "$RELEASE_SHARD")
fi
cargo build --release --bin rtl-gen
# name | vectors (before RELEASE_SCALE) | unit and parameters
configs=(
    "silhouette_bundle_shared|30000000|silhouette"
    "silhouette_ray|30000000|silhouette -p mode=ray"
    "silhouette_bundle_bounded|20000000|silhouette -p origin=bounded -p stages=2"
    "transform|20000000|transform"
    "cull_k4|2000000|cull -p k=4 -p stages=3"
)
total=0
if [ "${RELEASE_VECTORS:-1}" != 0 ]; then
    for c in "${configs[@]}"; do
        IFS='|' read -r name n unit <<<"$c"
        n=$((n * scale))
        t0=$(date +%s)
        # shellcheck disable=SC2086 # the unit and its options are separate words
        ./target/release/rtl-gen check $unit --vectors "$n" --jobs "$jobs" "${shard[@]}" \
            --no-progress --report "$out/$name.json" --junit "$out/$name.xml" >"$out/$name.log"
        python3 - "$out/$name.json" "$name" "$(( $(date +%s) - t0 ))" <<'EOF'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"{sys.argv[2]}: {r['vectors']:,} vectors, {r['mismatches']} mismatches, {sys.argv[3]} s")
if r["mismatches"]:
    sys.exit(1)
EOF
        total=$((total + n))
    done
    echo "vectors: $total through Verilator, 0 mismatches"
fi
if [ "${RELEASE_EXACT:-1}" != 0 ]; then
    t0=$(date +%s)
    SILHOUETTE_CASES="$cases" SILHOUETTE_BUNDLES="$cases" CULL_CASES="$cases" TRANSFORM_CASES="$cases" \
        TRIANGLE_RANGE=full \
        cargo test --release -p golden-model --test silhouette_props --test cull_props \
        --test transform --test triangle_range -- --nocapture >"$out/exact.log" 2>&1
    echo "exact reference: $cases cases each (silhouette rays, bundles, cull, transform inverse), the triangle's closed cube at every scale of binary32, e8m7 and e5m10 in every mode, 0 errors, $(( $(date +%s) - t0 )) s (log $out/exact.log)"
fi
if [ "${RELEASE_FAST:-1}" != 0 ]; then
    t0=$(date +%s)
    fast="${RELEASE_FAST_CASES:-100000000}"
    FAST_CASES="$fast" cargo test --release -p golden-model --test fast_paths -- --nocapture \
        >"$out/fast_paths.log" 2>&1
    classes=$(grep -c "fast == generic" "$out/fast_paths.log")
    echo "fast paths: $classes classes, at least $fast vectors each, fast == generic, $(( $(date +%s) - t0 )) s (log $out/fast_paths.log)"
fi
if [ "${RELEASE_MUTANTS:-1}" != 0 ]; then
    bash scripts/mutants.sh --shard "${RELEASE_MUTANTS_SHARD:-0/150}" | tee "$out/mutants.log" | tail -1
fi
echo "release: done in $(( $(date +%s) - start )) s, all bit-exact"
