"""cov.py: what ref.py's vectors (seed 1, 10^5 random + corners) reach, per axis and per vector:
V saturated, V with a fraction, xc clamped each way, x_hi at its clamp, t_c saturated, empty,
far_top at the cap / inside, exact multiples of 2^gc. Run in the folder holding ref.py."""
import random, ref
R = random.Random(1); vs = ref.corners() + [ref.rand_vec(R) for _ in range(100000)]
c = dict(vsat=0, vfrac=0, xclo_pos=0, xclo_neg=0, xchi_pos=0, xchi_neg=0, xhi_clamp=0, inrange=0, xhi_ceil=0, tc_sat=0, empty=0, cap=0, far_mid=0, far_exact=0)
for d in vs:
  for a in range(3):
    P = d['entry']*d['dsig'][a]; dsh=d['dsh'][a]
    V = P<<dsh if dsh>=0 else P>>-dsh
    if V >= 2**33: c['vsat']+=1
    elif dsh<0 and P % (1<<-dsh): c['vfrac']+=1
    xl, xh, a1, b1 = ref.axis(d['entry'], d['xp_lo'][a], d['xp_hi'][a], d['lo_j'][a], d['k'][a], d['dsig'][a], d['dneg'][a], dsh)
    c['xclo_pos'] += xl == 2**31-1; c['xclo_neg'] += xl == -2**31
    c['xchi_pos'] += xh == 2**31-1; c['xchi_neg'] += xh == -2**31
    c['xhi_clamp'] += xh > 2**31-2**16
    c['inrange'] += -2**31 < xl < 2**31-1 and -2**31 < xh < 2**31-1
    c['xhi_ceil'] += xh % 2**16 != 0
  t_c, far, e = ref.time(d['entry'], d['gp'], d['t_p'], d['tmax'], d['gc'])
  c['tc_sat'] += t_c == 2**48-1; c['empty'] += e; c['cap'] += far == 2**14; c['far_mid'] += 0 < far < 2**14
  c['far_exact'] += (not e) and 0 < far < 2**14 and (d['tmax']-t_c) % (1<<d['gc']) == 0
print(len(vs)*3, 'axes;', c)
