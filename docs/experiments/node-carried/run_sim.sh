#!/bin/sh
# run_sim.sh: the Icarus checks of the README; results appended to sim.log.
# Plain and opt: seconds each. The hand-placed modules simulate through cells_sim.v's LUT models
# at about 35 ms a random vector: the full HAND run is about an hour, HAND39 a subset.
run() { echo "== $*" >> sim.log; iverilog -g2012 "$@" -o sim_run tb.v carried.v opt.v hand.v cells_sim.v 2>/dev/null \
        && nice -n 10 vvp -n sim_run | grep -v '^WARNING' >> sim.log; }
python3 ref.py 100000 1 33 >> sim.log; N=$(wc -l < vin.hex)     # 7,920 corners + 10^5 random
python3 cov.py >> sim.log                                        # what the vectors reach
run -DNV=$N                      # plain
run -DNV=$N -DFAULT              # negative control: x_hi floored (must report mismatches)
run -DNV=$N -DVSAT=39            # plain at 2^39 against the 2^33 reference (must differ)
run -DNV=$N -DOPT
run -DNV=$N -DOPT -DFAULT        # negative control: x_hi floored
run -DNV=7920 -DHAND -DFAULT     # negative control: cin_hi without dneg, corners only
run -DNV=$N -DHAND               # about an hour
python3 ref.py 100000 2 39 >> sim.log; N=$(wc -l < vin.hex)     # the reference at VSAT = 39
run -DNV=$N -DVSAT=39
run -DNV=$N -DOPT -DVSAT=39
run -DNV=12920 -DHAND39 -DVSAT=39   # corners + the first 5,000 random vectors
