import random, struct
from fractions import Fraction as Fr
import sys
K, C = int(sys.argv[1]), int(sys.argv[2])
def wval(bits):  # e11m23 normal/zero
    s = bits >> 34; e = (bits >> 23) & 0x7ff; f = bits & 0x7fffff
    if e == 0: return Fr(0)
    v = Fr(0x800000 + f, 1 << 23) * (Fr(2) ** (e - 1023))
    return -v if s else v
def bval(bits):  # binary32 finite
    s = bits >> 31; e = (bits >> 23) & 0xff; f = bits & 0x7fffff
    v = Fr(f, 1 << 23) * Fr(2) ** -126 if e == 0 else Fr(0x800000 + f, 1 << 23) * Fr(2) ** (e - 127)
    return -v if s else v
def sx(x, w=21):
    x &= (1 << w) - 1
    return x - (1 << w) if x >> (w - 1) else x
def seg(T, D, L, H):
    lT = (T >> (23 - K)) & ((1 << (11+K)) - 1); lD = (D >> (23 - K)) & ((1 << (11+K)) - 1)
    dH = ((H >> 23) & 0xff) == 0; dL = ((L >> 23) & 0xff) == 0
    lH = (1<<K) if dH else (H >> (23 - K)) & ((1<<(8+K))-1)
    lL = (1<<K) if dL else (L >> (23 - K)) & ((1<<(8+K))-1)
    sH, sL = H >> 31, L >> 31
    zH = dH and ((H & 0x7fffff) == 0 or sH)
    zL = dL and ((L & 0x7fffff) == 0 or not sL)
    q = sx(lT - lD); rH = sx(q + (127 << K) - lH); rL = sx(q + (127 << K) - lL)
    sT = (T >> 34) ^ (D >> 34); zT = ((T >> 23) & 0x7ff) == 0
    gtH, ltH, gtL, ltL = rH > C, rH < -C, rL > C, rL < -C
    bm = (not sH or zH) if zT else (sT if zH else ((not gtH) if (not sT and not sH) else ((not ltH) if (sT and sH) else sT)))
    iH = ((H >> 23) & 0xff) == 0xff; iL = ((L >> 23) & 0xff) == 0xff
    am = (sL or zL) if zT else ((not sT) if zL else ((not ltL) if (not sT and not sL) else ((not gtL) if (sT and sL) else (not sT))))
    bm = (not sH) if iH else bm
    am = bool(sL) if iL else am
    far = (not zT) and q >= (128 << K) - C
    return am, bm, far, q
random.seed(7)
def rw(center=1023, spread=140):
    e = max(1, min(2046, center + random.randint(-spread, spread)))
    return (random.getrandbits(1) << 34) | (e << 23) | random.getrandbits(23)
bad = 0; acc = 0; tot = 0; loose = []
for i in range(300000):
    D = rw(); T = rw() if random.random() > 0.05 else (random.getrandbits(1) << 34)
    tv = wval(T) / wval(D)
    # bounds around t (often within a factor 2) or random
    def rb(near):
        if near and tv != 0 and abs(tv) < Fr(2)**120 and abs(tv) > Fr(2)**-120:
            x = float(tv) * random.uniform(0.5, 2.0) * random.choice([1, 1, 1, -1])
        else:
            x = random.choice([0.0, -0.0, 1e-40, -1e-40, 3.0, -3.0, float('inf'), -float('inf'), random.uniform(-10, 10)])
        return struct.unpack('<I', struct.pack('<f', x))[0]
    L, H = rb(random.random() < 0.7), rb(random.random() < 0.7)
    am, bm, far, q = seg(T, D, L, H)
    lv = bval(L) if (L >> 23) & 0xff != 0xff else (-Fr(10)**400 if L >> 31 else Fr(10)**400)
    hv = bval(H) if (H >> 23) & 0xff != 0xff else (-Fr(10)**400 if H >> 31 else Fr(10)**400)
    ea, eb = lv <= tv, tv <= hv
    tot += 1
    if (ea and not am) or (eb and not bm) or (abs(tv) >= Fr(2)**128 and not far):
        bad += 1
        if bad < 5: print("BAD", hex(T), hex(D), hex(L), hex(H), float(tv), ea, am, eb, bm)
    if tv > 0 and hv > 0 and bm and not eb and (H >> 23) & 0xff: loose.append(float(tv / hv))
print("cases", tot, "violations", bad, "max accepted t/t_max beyond bound", max(loose) if loose else None)
