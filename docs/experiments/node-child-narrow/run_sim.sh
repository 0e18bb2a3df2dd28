#!/bin/sh
# run_sim.sh: the Icarus checks of the README, one after the other; results appended to sim.log
S="child.v tb.sv hand.v hm_8x9.v hm_8x10.v dsp2.v cells_sim.v"
run() { echo "== $*" >> sim.log; iverilog -g2012 "$@" -o sim_run $S && nice -n 10 vvp -n sim_run | grep -v '^VCD' >> sim.log; }
# own logic (three modules, products fed by the testbench): 10^6 vectors per flavour
run -DNV=1000000
run -DNV=1000000 -DEXACT
# whole children (five product arrangements), 2*10^4 vectors (the first 4,096 extremes)
for f in "" "-DF2"; do
  for x in "" "-DEXACT"; do run -DNV=20000 -DFULL -DOWN=child_own_hand $f $x; done
done
run -DNV=20000 -DFULL -DOWN=child_own_plain4
run -DNV=20000 -DFULL -DOWN=child_own_plain4 -DEXACT
