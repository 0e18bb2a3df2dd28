#!/usr/bin/env bash
# `rtl-gen prove --property equiv` for every unit of `rtl-gen list` at a small format, two
# depths and both register placements (issue 39): each pipelined design against the same unit at
# stages=0. Prints a markdown table (unit, parameters, depth, placement, result, seconds) and
# exits 1 if any proof fails. Usage: bash scripts/prove-equiv.sh [rtl-gen binary] > table.md
# (docs/proofs.md has the last run's table and its time). PROVE_TIMEOUT: seconds per proof;
# PROVE_SOLVER: boolector (default), sat or structural (rtl-gen prove --solver); PROVE_HANDSHAKE=1
# adds each unit's valid/ready wrapper at 2 stages (-p handshake=ready; the triangle's around a
# stand-in core), =only runs just those.
set -uo pipefail
cd "$(dirname "$0")/.."
bin="${1:-target/release/rtl-gen}"
limit="${PROVE_TIMEOUT:-600}"  # seconds per proof
solver="${PROVE_SOLVER:-boolector}"
[ -x "$bin" ] || { echo "no $bin: cargo build --release --bin rtl-gen first" >&2; exit 2; }

# the small format of each unit (parameters besides stages and pipeline); a unit not named
# here is proved at its defaults
small() {
    case "$1" in
        mulcmp) echo "-p a_width=6 -p b_width=6" ;;
        cull | cull_ray) echo "-p exp_bits=2 -p frac_bits=1 -p plane_exp_bits=2 -p plane_frac_bits=1 -p k=1" ;;
        transform) echo "-p exp_bits=2 -p frac_bits=1 -p id_bits=1" ;;
        fcvt) echo "-p exp_bits=3 -p frac_bits=2 -p to_exp_bits=2 -p to_frac_bits=1" ;;
        node) echo "-p exp_bits=3 -p frac_bits=2 -p children=2 -p box_bits=4 -p slope_bits=4" ;;
        node_child) echo "-p box_bits=4" ;;
        node_sort) echo "-p children=4 -p box_bits=4" ;;
        raycull) echo "" ;;
        tilerange) echo "-p samples=16" ;;
        *) echo "-p exp_bits=2 -p frac_bits=1" ;;
    esac
}

units=$("$bin" list | grep -E '^[a-z0-9_]+:' | cut -d: -f1)
echo "| unit | parameters | stages | pipeline | result | seconds |"
echo "|---|---|---|---|---|---|"
failed=0
# one proof, one row: unit, stages, placement, the placement column's text, the job
# directory, then the proof's own arguments
row() {
    local u=$1 s=$2 p=$3 shown=$4 job=$5
    shift 5
    local t0 t1 out rc line result
    t0=$(date +%s.%N)
    # shellcheck disable=SC2046
    out=$(timeout "$limit" "$bin" prove "$u" $(small "$u") -p stages="$s" -p pipeline="$p" \
        "$@" --work "out/prove-equiv/$job" 2>&1)
    rc=$?
    line=$(tail -1 <<< "$out")
    t1=$(date +%s.%N)
    [ $rc -eq 124 ] && line="timeout"
    case "$line" in
        proved:*) result="proved" ;;
        timeout) result="not finished in $limit s"; failed=1 ;;
        counterexample:*) result="**counterexample**"; failed=1 ;;
        *) result="error: ${line//|/\\|}"; failed=1 ;;
    esac
    printf '| %s | %s | %s | %s | %s | %.1f |\n' "$u" "$(small "$u" | sed 's/-p //g')" \
        "$s" "$shown" "$result" "$(awk "BEGIN { print $t1 - $t0 }")"
}
handshake="${PROVE_HANDSHAKE:-0}"
if [ "$handshake" != only ]; then
    for u in $units; do
        for s in 2 4; do
            for p in plan balanced; do
                row "$u" "$s" "$p" "$p" "$u-s$s-$p" --solver "$solver"
            done
        done
    done
fi
# PROVE_HANDSHAKE=1 (or only): each unit's valid/ready wrapper at 2 stages (k-induction,
# Boolector); the triangle's around a stand-in core (--solver structural: its own core's
# k-induction does not finish, docs/proofs.md)
if [ "$handshake" != 0 ]; then
    for u in $units; do
        case "$u" in
            triangle) row "$u" 2 plan "plan, handshake=ready, stand-in core" "$u-s2-ready" \
                -p handshake=ready --solver structural ;;
            *) row "$u" 2 plan "plan, handshake=ready" "$u-s2-ready" -p handshake=ready ;;
        esac
    done
fi
exit $failed
