#!/bin/sh
# sim.sh N M : exhaustive (N+M <= 20) or 10^6 random check of hm_NxM.v
n=$1; m=$2; w=$((n+m)); d=hm_${n}x${m}
iverilog -g2012 -DN=$n -DM=$m -DW=$w -DDUT=$d -o sim_$d tb.sv $d.v cells_sim.v && nice -n 10 vvp -n sim_$d | grep -v VCD
