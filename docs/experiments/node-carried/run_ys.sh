#!/bin/sh
# run_ys.sh: every synthesis of the README's tables, one after the other (one Yosys at a time,
# niced by ys.sh); results appended to ys.log. About 25 min (iCE40 most of it).
for d in "" "-DVSAT=39"; do
  ./ys.sh carried_axis "$d" xc7 >> ys.log
  ./ys.sh carried_axis_opt "$d" xc7 >> ys.log
  ./ys.sh node_carried_pernode "$d" xc7 >> ys.log
  ./ys.sh node_carried_pernode "-DOPT $d" xc7 >> ys.log
done
./ys.sh carried_axis_hand "" xc7 >> ys.log
./ys.sh carried_axis_hand39 "" xc7 >> ys.log
./ys.sh node_carried_pernode "-DHAND" xc7 >> ys.log
./ys.sh node_carried_pernode "-DHAND39 -DVSAT=39" xc7 >> ys.log
for t in carried_time carried_time_opt carried_time_hand carried_prod; do ./ys.sh $t "" xc7 >> ys.log; done
for t in carried_axis carried_axis_opt carried_time carried_time_opt carried_prod; do ./ys.sh $t "" ecp5 >> ys.log; done
for d in "" "-DOPT" "-DVSAT=39" "-DOPT -DVSAT=39"; do ./ys.sh node_carried_pernode "$d" ecp5 >> ys.log; done
for t in carried_axis carried_axis_opt carried_time carried_time_opt carried_prod; do ./ys.sh $t "" ice40 >> ys.log; done
for d in "" "-DOPT"; do ./ys.sh node_carried_pernode "$d" ice40 >> ys.log; done
