#!/usr/bin/env python3
"""Hand-placed unsigned multiplier p = a * b for Xilinx 7-series (LUT6 / LUT6_2 / CARRY4).

a: n bits (multiplicand, the row width), b: m bits (recoded).
Chain 0: a*(b mod 4) as two AND rows in one carry chain (LUT6_2: O6 = a_i b0 ^ a_(i-1) b1,
O5 = a_i b0 -> DI).  Then one chain per radix-4 Booth digit of b >> 2, each LUT6 taking the
digit's three b bits, a_r, a_(r-1) and the running sum's bit (DI = the running sum's bit, raw).
Rows are signed and sign-extended by the running sum's sign; every chain stops at the sign
position the exact value range needs (or at bit n+m-1: the product is mod 2^(n+m)).

usage: gen.py N M   -> writes hm_NxM.v (module hm_NxM), prints its LUT and CARRY4 count
"""
import sys

def lut_init(inputs, fn):
    """INIT for a LUT6 whose inputs are `inputs` (<= 6 names); fn(env) -> bit"""
    init = 0
    for idx in range(64):
        env = {nm: (idx >> k) & 1 for k, nm in enumerate(inputs)}
        if fn(env):
            init |= 1 << idx
    return init

def lut62_init(inputs, f6, f5):
    """LUT6_2 with I5 = 1: O6 = f6 (upper half), O5 = f5 (lower half), <= 5 inputs"""
    assert len(inputs) <= 5
    init = 0
    for idx in range(32):
        env = {nm: (idx >> k) & 1 for k, nm in enumerate(inputs)}
        if f5(env):
            init |= 1 << idx
        if f6(env):
            init |= 1 << (idx + 32)
    return init

def val(env, s):
    if s == '0':
        return 0
    if s == '1':
        return 1
    return env[s]

class Gen:
    def __init__(self, name, n, m, c_bits=0):
        self.name, self.n, self.m, self.cb = name, n, m, c_bits
        self.W = n + m if c_bits == 0 else max(n + m, c_bits) + 1
        self.lines = []
        self.wires = []
        self.nlut = 0
        self.ncarry = 0
        self.uid = 0

    def a(self, i):
        return f"a[{i}]" if 0 <= i < self.n else '0'

    def b(self, i):
        return f"b[{i}]" if 0 <= i < self.m else '0'

    def c(self, i):
        return f"c[{i}]" if 0 <= i < self.cb else '0'

    def wire(self, base):
        self.uid += 1
        w = f"{base}_{self.uid}"
        self.wires.append(w)
        return w

    def chain(self, cells, cin):
        """cells: list of (inputs, f_S, x) where x is a raw signal / constant (DI) or
        ('o5', f_X) for a computed X (LUT6_2). Returns sum bits and final carry-out."""
        sums, cos = [], []
        for k in range(0, len(cells), 4):
            grp = cells[k:k + 4]
            S, DI = [], []
            for inputs, fS, x in grp:
                s = self.wire("s")
                self.nlut += 1
                ins = list(inputs) + ['1'] * (6 - len(inputs))
                if isinstance(x, tuple):
                    d = self.wire("di")
                    init = lut62_init(inputs, fS, x[1])
                    ins = list(inputs) + ['1'] * (5 - len(inputs)) + ["1'b1"]
                    ins = [i if i not in ('0', '1') else ("1'b" + i) for i in ins]
                    self.lines.append(
                        f"  LUT6_2 #(.INIT(64'h{init:016x})) l{self.uid} (.O6({s}), .O5({d}), "
                        + ", ".join(f".I{j}({ins[j]})" for j in range(6)) + ");")
                    DI.append(d)
                else:
                    init = lut_init(inputs, fS)
                    ins = list(inputs) + ['0'] * (6 - len(inputs))
                    ins = [i if i not in ('0', '1') else ("1'b" + i) for i in ins]
                    self.lines.append(
                        f"  LUT6 #(.INIT(64'h{init:016x})) l{self.uid} (.O({s}), "
                        + ", ".join(f".I{j}({ins[j]})" for j in range(6)) + ");")
                    DI.append(x if x not in ('0', '1') else "1'b" + x)
                S.append(s)
            while len(S) < 4:
                S.append("1'b0")
                DI.append("1'b0")
            o = self.wire("o")
            co = self.wire("co")
            self.wires.remove(o)
            self.wires.remove(co)
            self.lines.append(f"  wire [3:0] {o}, {co};")
            ci = cin if k == 0 else cos[-1]
            ci = ci if ci not in ('0', '1') else "1'b" + ci
            self.ncarry += 1
            self.lines.append(
                f"  CARRY4 c{self.uid} (.CO({co}), .O({o}), .CI({ci}), .CYINIT(1'b0), "
                f".DI({{{', '.join(reversed(DI))}}}), .S({{{', '.join(reversed(S))}}}));")
            for j in range(len(grp)):
                sums.append(f"{o}[{j}]")
            cos.append(f"{co}[{len(grp) - 1}]")
        return sums, cos[-1]


def need_bits(lo, hi):
    """(bits, signed): positions 0..bits-1 stored; signed: bit bits-1 is the sign"""
    if lo >= 0:
        return max(hi.bit_length(), 1), False
    t = 1
    while not (-(1 << (t - 1)) <= lo and hi <= (1 << (t - 1)) - 1):
        t += 1
    return t, True


def build(n, m, c_bits=0):
    name = f"hm_{n}x{m}" + (f"_c{c_bits}" if c_bits else "")
    g = Gen(name, n, m, c_bits)
    W = g.W
    amax = (1 << n) - 1
    cmax = (1 << c_bits) - 1
    acc = {}
    if c_bits == 0:
        cells = []
        for i in range(0, n + 1):
            ai, ai1 = g.a(i), g.a(i - 1)
            ins = [s for s in (ai, ai1, g.b(0), g.b(1)) if s not in ('0', '1')]
            fX = (lambda ai: lambda e: val(e, ai) & val(e, g.b(0)))(ai)
            fY = (lambda ai1: lambda e: val(e, ai1) & val(e, g.b(1)))(ai1)
            fS = (lambda fX, fY: lambda e: fX(e) ^ fY(e))(fX, fY)
            cells.append((ins, fS, ('o5', fX)))
        sums, co = g.chain(cells, '0')
        for i, s in enumerate(sums):
            acc[i] = s
        acc[n + 1] = co
        lo, hi = 0, 3 * amax if m >= 2 else amax
        bits, signed = n + 2, False
        digits = []
        j = 0
        while True:
            hb, mb, lb = 2 * j + 3, 2 * j + 2, (2 * j + 1 if j > 0 else None)
            if mb > m - 1 and (lb is None or lb > m - 1):
                break
            digits.append((g.b(hb), g.b(mb), g.b(lb) if lb is not None else '0', 2 + 2 * j))
            j += 1
        # value of b covered so far, per b: exact ranges by enumeration
        covered = [bb & 3 for bb in range(1 << m)]

    def booth_val(bb, hb, mb_, lb):
        gb = lambda s: 0 if s == '0' else (bb >> int(s[2:-1])) & 1
        return -2 * gb(hb) + gb(mb_) + gb(lb)

    sign = (acc[bits - 1] if signed else '0')
    for (hb, mb_, lb, off) in digits:
        newcov = [covered[bb] + booth_val(bb, hb, mb_, lb) * (1 << off) for bb in range(1 << m)]
        vlo, vhi = min(newcov), max(newcov)
        nlo = min(0, vlo * amax) + (0 if c_bits == 0 else 0)
        nhi = max(0, vhi * amax) + (cmax if c_bits else 0)
        nbits, nsigned = need_bits(nlo, nhi)
        top = min(W - 1, nbits - 1)
        cells = []
        carry_top = None
        for i in range(off, top + 1):
            r = i - off
            X = acc[i] if i in acc else sign
            if r <= n:
                ar, ar1 = g.a(r), g.a(r - 1)
            else:
                ar, ar1 = '0', '0'
            Yconst0 = (hb == '0') and (r > n - 1 + 1 or (ar == '0' and ar1 == '0'))
            if X == '0' and Yconst0 and i > off:
                carry_top = i
                break
            ins = [s for s in dict.fromkeys((ar, ar1, hb, mb_, lb, X)) if s not in ('0', '1')]

            def fY(e, ar=ar, ar1=ar1, hb=hb, mb_=mb_, lb=lb):
                h, mm, l = val(e, hb), val(e, mb_), val(e, lb)
                sel1 = mm ^ l
                sel2 = (h & (1 - mm) & (1 - l)) | ((1 - h) & mm & l)
                v = (sel1 & val(e, ar)) | (sel2 & val(e, ar1))
                return v ^ h
            fS = (lambda X, fY: lambda e: val(e, X) ^ fY(e))(X, fY)
            cells.append((ins, fS, X))
        sums, co = g.chain(cells, hb)
        for k, s in enumerate(sums):
            acc[off + k] = s
        if carry_top is not None:
            acc[carry_top] = co
            for i in range(carry_top + 1, W):
                acc.pop(i, None)
        else:
            for i in range(top + 1, W):
                acc.pop(i, None)
        covered = newcov
        lo, hi, bits, signed = nlo, nhi, nbits, nsigned
        sign = acc[min(bits, W) - 1] if signed else '0'
    outs = []
    for i in range(W):
        outs.append(acc[i] if i in acc else sign)
    ports = f"input [{n-1}:0] a, input [{m-1}:0] b" + (f", input [{c_bits-1}:0] c" if c_bits else "")
    v = [f"module {name}({ports}, output [{W-1}:0] p);"]
    if g.wires:
        v.append("  wire " + ", ".join(g.wires) + ";")
    v += g.lines
    outs_v = [o if o not in ('0', '1') else "1'b" + o for o in outs]
    v.append(f"  assign p = {{{', '.join(reversed(outs_v))}}};")
    v.append("endmodule")
    return name, "\n".join(v) + "\n", g.nlut, g.ncarry, W


if __name__ == "__main__":
    n, m = int(sys.argv[1]), int(sys.argv[2])
    name, text, nl, nc, W = build(n, m)
    open(f"{name}.v", "w").write(text)
    print(f"{name}: {nl} LUT, {nc} CARRY4, {W}-bit result")
