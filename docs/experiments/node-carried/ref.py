#!/usr/bin/env python3
"""Behavioural reference of carried.v (Python integers, no width limits) and vector writer.

usage: ref.py NV [SEED] [VSAT]  -> vin.hex (444-bit input words), vout.hex (352-bit expected outputs)
The first vectors are corner cases (every k with dsh at both ends, zero dsig, both signs, every
saturation), then NV random vectors from a mix of families (see rand_vec).
"""
import random
import sys

G, F, K = 4, 16, 14


def sat(v, lo, hi):
    return lo if v < lo else hi if v > hi else v


def axis(entry, xp_lo, xp_hi, lo_j, k, dsig, dneg, dsh, vsat=33):
    P = entry * dsig
    if dsh >= 0:
        vf = vc = P << dsh
    else:
        s = -dsh
        vf = P >> s
        vc = -((-P) >> s)          # ceiling
    vf, vc = min(vf, 1 << vsat), min(vc, 1 << vsat)
    lower, upper = (-vc, -vf) if dneg else (vf, vc)
    base = lo_j << (G + F)
    xc_lo = sat(((xp_lo - base) << k) + lower, -2**31, 2**31 - 1)
    xc_hi = sat(((xp_hi - base) << k) + upper, -2**31, 2**31 - 1)
    x_lo = xc_lo >> F                                  # floor
    x_hi = min(-((-xc_hi) >> F), 2**15 - 1)            # ceiling, clamped to 16-bit signed
    return xc_lo, xc_hi, x_lo, x_hi


def time(entry, gp, t_p, tmax, gc):
    t_c = min(t_p + (entry << gp), 2**48 - 1)
    D = tmax - t_c
    if D < 0:
        return t_c, 0, 1
    far = -((-D) >> gc)
    return t_c, min(far, 1 << K), 0


IN_FIELDS = [('xp_lo', 32, 3), ('xp_hi', 32, 3), ('lo_j', 8, 3), ('k', 3, 3), ('dsig', 24, 3),
             ('dneg', 1, 3), ('dsh', 7, 3), ('entry', 15, 1), ('gp', 6, 1), ('t_p', 48, 1),
             ('tmax', 48, 1), ('gc', 6, 1)]
OUT_FIELDS = [('xc_lo', 32, 3), ('xc_hi', 32, 3), ('x_lo', 16, 3), ('x_hi', 16, 3), ('t_c', 48, 1),
              ('far_top', 15, 1), ('empty', 1, 1)]


def pack(fields, d):
    v = 0
    for name, w, n in fields:
        vals = d[name] if n > 1 else [d[name]]
        for a in reversed(range(n)):                   # axis 2 at the top of each bus
            v = (v << w) | (vals[a] & ((1 << w) - 1))
    return v


def evaluate(d, vsat=33):
    o = {n: [0, 0, 0] for n in ('xc_lo', 'xc_hi', 'x_lo', 'x_hi')}
    for a in range(3):
        r = axis(d['entry'], d['xp_lo'][a], d['xp_hi'][a], d['lo_j'][a], d['k'][a], d['dsig'][a],
                 d['dneg'][a], d['dsh'][a], vsat)
        for n, x in zip(('xc_lo', 'xc_hi', 'x_lo', 'x_hi'), r):
            o[n][a] = x
    o['t_c'], o['far_top'], o['empty'] = time(d['entry'], d['gp'], d['t_p'], d['tmax'], d['gc'])
    return o


def rdsig(R):
    return 0 if R.random() < 0.1 else R.randrange(1 << 23, 1 << 24)


def rand_axis(R):
    fam = R.randrange(4)
    k = R.randrange(8)
    lo_j = R.randrange(256)
    dsig = rdsig(R)
    dneg = R.randrange(2)
    dsh = R.randrange(-48, 16)
    if fam == 0:                                        # uniform bits
        xp_lo, xp_hi = R.randrange(-2**31, 2**31), R.randrange(-2**31, 2**31)
    else:                                               # aimed: near the slot, no saturation
        span = 1 << R.randrange(8, 31 - k)
        c = (lo_j << 20) + R.randrange(-span, span)
        w = R.randrange(0, 1 << R.randrange(1, 24))
        xp_lo = sat(c, -2**31, 2**31 - 1)
        xp_hi = sat(c + w, -2**31, 2**31 - 1)
        if fam == 2:                                    # V near the 2^33 / 2^31 boundaries
            dsh = R.randrange(-20, 12)
    return xp_lo, xp_hi, lo_j, k, dsig, dneg, dsh


def rand_vec(R):
    d = {n: [0, 0, 0] for n in ('xp_lo', 'xp_hi', 'lo_j', 'k', 'dsig', 'dneg', 'dsh')}
    for a in range(3):
        for n, x in zip(('xp_lo', 'xp_hi', 'lo_j', 'k', 'dsig', 'dneg', 'dsh'), rand_axis(R)):
            d[n][a] = x
    d['entry'] = R.choice([R.randrange(1 << 15), R.randrange(16), (1 << 15) - 1 - R.randrange(4)])
    d['gp'] = R.randrange(64) if R.random() < 0.3 else R.randrange(34)
    d['t_p'] = R.randrange(1 << 48) if R.random() < 0.3 else R.randrange(1 << R.randrange(1, 47))
    tf = R.randrange(5)
    t_c = min(d['t_p'] + (d['entry'] << d['gp']), 2**48 - 1)
    if tf == 0:
        d['tmax'] = R.randrange(1 << 48)
    else:                                               # near t_c: empty, 0, cap, exact multiples
        d['tmax'] = sat(t_c + R.randrange(-(1 << R.randrange(0, 20)), 1 << R.randrange(0, 48)), 0, 2**48 - 1)
    d['gc'] = R.randrange(64) if R.random() < 0.2 else R.randrange(40)
    if tf == 4:                                         # tmax - t_c a multiple of 2^gc
        m = R.randrange(0, 1 << 16) << d['gc']
        d['tmax'] = sat(t_c + m, 0, 2**48 - 1)
    return d


def corners():
    out = []
    base = dict(entry=12345, gp=10, t_p=1 << 30, tmax=(1 << 30) + (12345 << 10) + 5000, gc=3)
    xs = [(0, 0), (-2**31, 2**31 - 1), (2**31 - 1, 2**31 - 1), (-2**31, -2**31), (5 << 20, (5 << 20) + 77)]
    for k in (0, 7):
        for dsh in (-48, -47, -39, -24, -1, 0, 1, 9, 10, 15):
            for dsig in (0, 1 << 23, (1 << 24) - 1):
                for dneg in (0, 1):
                    for entry in (0, 1, (1 << 15) - 1):
                        for xp in xs:
                            for lo_j in (0, 5, 255):
                                d = dict(base)
                                d['entry'] = entry
                                d.update({n: [v] * 3 for n, v in (('xp_lo', xp[0]), ('xp_hi', xp[1]),
                                          ('lo_j', lo_j), ('k', k), ('dsig', dsig), ('dneg', dneg),
                                          ('dsh', dsh))})
                                out.append(d)
    # time corners: shift overflow, sum overflow, empty, zero, cap, gc 0 / 63
    tc = []
    for entry in (0, 1, (1 << 15) - 1):
        for gp in (0, 33, 34, 47, 63):
            for t_p in (0, 1, 2**47, 2**48 - 1):
                t_c = min(t_p + (entry << gp), 2**48 - 1)
                for dt in (-1, 0, 1, 2**14, 2**14 + 1, 2**20, 2**47):
                    for gc in (0, 1, 6, 47, 48, 63):
                        tc.append((entry, gp, t_p, sat(t_c + dt, 0, 2**48 - 1), gc))
    d0 = out[0]
    for entry, gp, t_p, tmax, gc in tc:
        d = dict(d0)
        d.update(entry=entry, gp=gp, t_p=t_p, tmax=tmax, gc=gc)
        out.append(d)
    return out


def main():
    nv = int(sys.argv[1])
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    vsat = int(sys.argv[3]) if len(sys.argv) > 3 else 33
    R = random.Random(seed)
    vecs = corners()
    vecs += [rand_vec(R) for _ in range(nv)]
    with open('vin.hex', 'w') as fi, open('vout.hex', 'w') as fo:
        for d in vecs:
            fi.write(f"{pack(IN_FIELDS, d):0112x}\n")
            fo.write(f"{pack(OUT_FIELDS, evaluate(d, vsat)):088x}\n")
    print(f"{len(vecs)} vectors ({len(vecs) - nv} corners), seed {seed}, VSAT {vsat}")


if __name__ == '__main__':
    main()
