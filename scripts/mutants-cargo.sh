#!/usr/bin/env bash
# The `cargo` that scripts/mutants.sh gives cargo-mutants (as $CARGO): every
# command passes through to the real cargo, except `cargo test` (and its
# `--no-run` build), which runs the fast suite instead of the mutated
# package's tests. The fast suite has no Verilator, Icarus or synthesis run:
#   1. the mutated package (golden-model or rtl-gen, as cargo-mutants names
#      it) and rtl-flow, libraries and test targets (no doctests): the golden
#      models against their exact references, the generators' unit tests and
#      rtl-flow's IR-evaluator cross-checks (silhouette, slab, float ops,
#      pipelining);
#   2. the IR-evaluator tests of the integration crate, the tests named
#      `*evaluator*` in the targets below (cull, node, raycull, transform,
#      triangle), whose other tests run Verilator.
# tool/tests/mutants_config.rs checks that each target below exists and
# holds an evaluator test.
set -euo pipefail
real="${MUTANTS_REAL_CARGO:?scripts/mutants.sh sets MUTANTS_REAL_CARGO}"
evaluator_targets=(cull_rtl node_rtl raycull_rtl transform_rtl triangle_rtl)

if [ "${1:-}" != test ]; then
    exec "$real" "$@"
fi
shift
no_run=()
common=()
for a in "$@"; do
    case "$a" in
        --no-run) no_run=(--no-run) ;;
        --verbose) ;;  # cargo-mutants asks for it; its logs stay readable without
        *) common+=("$a") ;;  # --package=<mutated>, --release, ...
    esac
done
tests=()
for t in "${evaluator_targets[@]}"; do tests+=(--test "$t"); done
"$real" test "${no_run[@]}" "${common[@]}" --package rtl-flow --lib --tests
if [ ${#no_run[@]} -gt 0 ]; then
    exec "$real" test --no-run --release --package integration-tests "${tests[@]}"
fi
exec "$real" test --release --package integration-tests "${tests[@]}" -- evaluator
