#!/usr/bin/env bash
# Mutation testing with cargo-mutants (issue 39, docs/proofs.md#mutation-testing):
# the mutants of .cargo/mutants.toml's scope (unit generators, their arithmetic,
# golden models), each built and run against the fast suite of
# scripts/mutants-cargo.sh (golden-model, rtl-gen and IR-evaluator tests; no
# Verilator, no synthesis).
#
#   bash scripts/mutants.sh --shard K/N [ARGS]   # shard K (0..N-1) of the full run
#   bash scripts/mutants.sh --in-diff [BASE]     # the mutants of BASE..HEAD (CI)
#   bash scripts/mutants.sh --list [ARGS]        # list the mutants, run nothing
#
# --shard: a scratch copy of the tree, the baseline first, then every mutant of
# the shard (round-robin, so shards take about as long); ARGS go to cargo-mutants
# (e.g. --file rtl-gen/src/units/slab.rs). Results in target/mutants/shard-K-of-N/.
# The full run is N shards; any N works, all shards must use the same N.
#
# --in-diff: the lines changed from BASE (default HEAD^1, the last commit's
# parent: on a fresh clone of main the last change, a merge's whole branch)
# to HEAD; at most MUTANTS_MAX (default 2) mutants, a fixed round-robin sample
# when the change has more, so CI time is bounded. No baseline (CI's `cargo
# test` has just passed) and a fixed timeout, MUTANTS_TIMEOUT (default 240 s;
# the slowest suite, a golden-model mutant's, takes about 165 s). With CI set
# the checkout itself is mutated (--in-place: its target/ is warm), otherwise
# a scratch copy. Exit status is cargo-mutants': 0 every mutant caught or
# unviable, 2 one missed, 3 one timed out, 4 the baseline failed.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
if ! command -v cargo-mutants >/dev/null; then
    echo "cargo-mutants is not installed: bash scripts/setup.sh installs it" >&2
    exit 2
fi
work="${CARGO_TARGET_DIR:-$root/target}/mutants"
mkdir -p "$work/tmp"
# cargo-mutants's scratch copies live in $TMPDIR; the golden-model tests read
# ../shared/scenes beside the tree, so give the copies that neighbour too
if [ -d "$root/../shared" ]; then ln -sfn "$root/../shared" "$work/tmp/shared"; fi
export TMPDIR="$work/tmp"
export MUTANTS_REAL_CARGO="${CARGO:-cargo}"
export CARGO="$root/scripts/mutants-cargo.sh"
mutants=(cargo-mutants mutants --dir "$root")  # one job: the default
sharded=(--sharding round-robin --shard)  # round-robin: shards take about as long

summary() {  # caught / missed / unviable / timeout of a cargo-mutants output dir
    local out="$1/mutants.out"
    printf 'mutants: %s tested: %s caught, %s missed, %s unviable, %s timeout\n' \
        "$(cat "$out"/{caught,missed,unviable,timeout}.txt 2>/dev/null | wc -l)" \
        "$(wc -l <"$out/caught.txt")" "$(wc -l <"$out/missed.txt")" \
        "$(wc -l <"$out/unviable.txt")" "$(wc -l <"$out/timeout.txt")"
    sed 's/^/missed: /' "$out/missed.txt"
    sed 's/^/timeout: /' "$out/timeout.txt"
}

case "${1:-}" in
    --list)
        shift
        exec "${mutants[@]}" --list "$@"
        ;;
    --shard)
        shard="${2:?--shard K/N}"
        shift 2
        case "$shard" in
            [0-9]*/[0-9]*) ;;
            *) echo "--shard takes K/N, e.g. 0/64 (got $shard)" >&2; exit 2 ;;
        esac
        out="$work/shard-${shard%/*}-of-${shard#*/}"
        mkdir -p "$out"
        status=0
        export CARGO_TARGET_DIR="$work/target"  # its own: the copy never clobbers target/release
        "${mutants[@]}" "${sharded[@]}" "$shard" --output "$out" "$@" || status=$?
        summary "$out"
        exit "$status"
        ;;
    --in-diff)
        base="${2:-HEAD^1}"
        if [ "$(git rev-parse --is-shallow-repository)" = true ]; then
            git fetch -q --deepen=1 || true  # a shallow clone: fetch the parent if it can
        fi
        if ! git rev-parse -q --verify "$base^{commit}" >/dev/null; then
            echo "--in-diff: no commit $base to compare HEAD with (a shallow clone? fetch its history)" >&2
            exit 2
        fi
        out="$work/in-diff"
        mkdir -p "$out"
        git diff "$base" HEAD -- '*.rs' >"$out/change.diff"
        max="${MUTANTS_MAX:-2}"
        n=$("${mutants[@]}" --list --in-diff "$out/change.diff" | wc -l)
        echo "mutants of $(git rev-parse --short "$base")..$(git rev-parse --short HEAD): $n"
        if [ "$n" -eq 0 ]; then
            exit 0
        fi
        shards=$(( (n + max - 1) / max ))
        args=(--in-diff "$out/change.diff" --baseline skip --timeout "${MUTANTS_TIMEOUT:-240}"
              --output "$out")
        if [ "$shards" -gt 1 ]; then
            echo "more than MUTANTS_MAX=$max: testing the round-robin sample 0/$shards"
            args+=("${sharded[@]}" "0/$shards")
        fi
        if [ -n "${CI:-}" ]; then
            args+=(--in-place)
        else
            export CARGO_TARGET_DIR="$work/target"
        fi
        status=0
        "${mutants[@]}" "${args[@]}" || status=$?
        summary "$out"
        exit "$status"
        ;;
    *)
        sed -n '2,/^set /{/^#/p}' "$0" | sed 's/^# \{0,1\}//' >&2
        exit 2
        ;;
esac
