#!/usr/bin/env bash
# Mutation check (issue #17): applies each mutant of scripts/mutants.txt to a
# scratch copy of the repository (a git worktree of HEAD, so the checkout is
# never touched), runs the test the mutant names and counts it killed when
# that test fails. Prints one line per mutant and `mutants: K killed of N`;
# exit 0 only when every mutant is killed, 1 when one survives, 2 when a
# mutant no longer applies (its text must occur exactly once).
#
#   bash scripts/mutants.sh [LIST]          # default scripts/mutants.txt
#
# Each mutant costs an incremental build of the generator and its test
# (about a minute on 2 cores); the tests it runs use the IR evaluator, no
# Verilator build. Run from the repository root, after `bash scripts/setup.sh`.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
list="${1:-$root/scripts/mutants.txt}"
work="$root/target/mutants"
tree="$work/tree"
mkdir -p "$work"
git -C "$root" worktree remove --force "$tree" >/dev/null 2>&1 || rm -rf "$tree"
git -C "$root" worktree prune
git -C "$root" worktree add --detach "$tree" HEAD >/dev/null
trap 'git -C "$root" worktree remove --force "$tree" >/dev/null 2>&1 || true' EXIT
# the worktree sits two levels deeper than the checkout: give it ../shared too
if [ -d "$root/../shared" ] && [ ! -e "$work/shared" ]; then
    ln -s "$root/../shared" "$work/shared"
fi
export CARGO_TARGET_DIR="$work/target"
total=0
killed=0
while IFS= read -r line; do
    case "$line" in ''|'#'*) continue ;; esac
    total=$((total + 1))
    IFS=$'\x1f' read -r unit file from to test < <(printf '%s\n' "$line" | sed 's/ ||| /\x1f/g')
    if ! python3 - "$tree/$file" "$from" "$to" <<'EOF'
import sys
path, old, new = sys.argv[1:4]
text = open(path).read()
if text.count(old) != 1:
    sys.exit(f"{path}: `{old}` occurs {text.count(old)} times (must be once)")
open(path, "w").write(text.replace(old, new))
EOF
    then
        echo "mutant $total ($unit): does not apply any more: $from" >&2
        exit 2
    fi
    start=$(date +%s)
    # shellcheck disable=SC2086
    if (cd "$tree" && cargo test --release $test >"$work/mutant-$total.log" 2>&1); then
        verdict="SURVIVED"
    else
        if grep -q "error\[E\|could not compile" "$work/mutant-$total.log"; then
            echo "mutant $total ($unit): does not compile, see $work/mutant-$total.log" >&2
            exit 2
        fi
        verdict="killed"
        killed=$((killed + 1))
    fi
    git -C "$tree" checkout -- "$file"
    printf 'mutant %2d %-10s %-8s %4ss  %s -> %s\n' "$total" "$unit" "$verdict" \
        "$(( $(date +%s) - start ))" "$from" "$to"
done <"$list"
echo "mutants: $killed killed of $total"
[ "$killed" -eq "$total" ]
