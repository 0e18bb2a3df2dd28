#!/bin/sh
# run_ys.sh: every synthesis of the README's table, one after the other; results appended to ys.log
for f in "" "-DEXACT"; do
  for o in child_own_plain child_own_plain4 child_own_hand; do ./ys.sh $o "$f" >> ys.log; done
  for o in child_own_plain4 child_own_hand; do
    ./ys.sh child_mul "$f -DOWN=$o" >> ys.log
    ./ys.sh child_mul "$f -DOWN=$o" -nodsp >> ys.log
    for t in child_booth child_dsp3 child_dsp2 child_dsp1; do ./ys.sh $t "$f -DOWN=$o" >> ys.log; done
  done
  # far product xf*(s + 1)
  ./ys.sh child_mul "$f -DF2 -DOWN=child_own_hand" >> ys.log
  ./ys.sh child_mul "$f -DF2 -DOWN=child_own_hand" -nodsp >> ys.log
  for t in child_booth child_dsp3 child_dsp2 child_dsp1; do ./ys.sh $t "$f -DF2 -DOWN=child_own_hand" >> ys.log; done
done
