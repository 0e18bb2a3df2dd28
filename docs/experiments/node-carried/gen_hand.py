#!/usr/bin/env python3
"""Hand-placed xc7 version of opt.v (LUT6 / LUT6_2 / CARRY4 instances; small control logic and
the product entry*dsig left to Yosys), written to hand.v:

  carried_axis_hand   V's shift as three levels of LUT6 4:1 muxes (48, 36, 33 LUT); the shared
                      adder operand (V ^ dneg, saturated) as LUT6_2 pairs (17); per bound the
                      13-bit subtraction of lo_j (one chain), the first level of the k-shift
                      (4:1 by k[1:0], 35 LUT), the 36-bit adder whose LUTs also do the k[2] level
                      (S = (k2 ? M[i-4] : M[i]) ^ B[i], DI = B[i], CYINIT = the bound's carry-in);
                      the 32-bit clamp as LUT6_2 pairs, except xc_hi[31:16], whose clamp LUTs are
                      the S inputs of x_hi's increment chain.
  carried_time_hand   entry << gp as two 4:1 levels (18, 30) and the t_p adder whose LUTs do the
                      last 4-way shift by 16; t_c's saturation as LUT6_2 pairs; tmax - t_c as one
                      chain; (tmax - t_c) >> gc as 4:1 levels (29, 17) and a third level that
                      drives the increment chain of the ceiling; the clamp / empty gating as
                      LUT6_2 pairs.
Same function as carried_axis / carried_time (bit-exact): carried_axis_hand at VSAT = 33,
carried_axis_hand39 at VSAT = 39 (all 40 bits of the shifted difference, 41-bit sums).
usage: gen_hand.py   -> hand.v
"""


class Mod:
    def __init__(self):
        self.body = []
        self.nlut = 0
        self.ncarry = 0
        self.uid = 0

    def _vars(self, ins):
        var = []
        for s in ins:
            if s not in ('0', '1') and s not in var:
                var.append(s)
        return var

    def lut(self, out, ins, fn):
        """LUT6: out = fn([bit of each entry of ins]); '0'/'1' entries are constants"""
        var = self._vars(ins)
        assert len(var) <= 6, (out, ins)
        init = 0
        for idx in range(64):
            vals = [0 if s == '0' else 1 if s == '1' else (idx >> var.index(s)) & 1 for s in ins]
            if fn(vals):
                init |= 1 << idx
        pins = var + ["1'b0"] * (6 - len(var))
        self.uid += 1
        self.nlut += 1
        self.body.append(f"  LUT6 #(.INIT(64'h{init:016x})) l{self.uid} (.O({out}), "
                         + ", ".join(f".I{j}({p})" for j, p in enumerate(pins)) + ");")

    def lut2(self, o6, o5, ins, f6, f5):
        """LUT6_2 (I5 = 1): O6 = f6, O5 = f5 over at most 5 distinct inputs"""
        var = self._vars(ins)
        assert len(var) <= 5, (o6, ins)
        init = 0
        for idx in range(32):
            vals = [0 if s == '0' else 1 if s == '1' else (idx >> var.index(s)) & 1 for s in ins]
            if f5(vals):
                init |= 1 << idx
            if f6(vals):
                init |= 1 << (idx + 32)
        pins = var + ["1'b0"] * (5 - len(var)) + ["1'b1"]
        self.uid += 1
        self.nlut += 1
        self.body.append(f"  LUT6_2 #(.INIT(64'h{init:016x})) l{self.uid} (.O6({o6}), .O5({o5}), "
                         + ", ".join(f".I{j}({p})" for j, p in enumerate(pins)) + ");")

    def chain(self, S, DI, cin, O, cout=None):
        """CARRY4 chain: O[i] = S[i] ^ carry_i, carry_0 = cin; cout = carry out of the last bit"""
        n = len(S)
        ci = "1'b0"
        zero = "1'b0"
        for b in range(0, n, 4):
            self.uid += 1
            self.ncarry += 1
            u = self.uid
            s = [S[i] if i < n else "1'b0" for i in range(b, b + 4)]
            d = [c(DI[i]) if i < n else "1'b0" for i in range(b, b + 4)]
            self.body.append(f"  wire [3:0] co{u}, o{u};")
            self.body.append(f"  CARRY4 c{u} (.CO(co{u}), .O(o{u}), .CI({ci}), "
                             f".CYINIT({cin if b == 0 else zero}), "
                             f".DI({{{', '.join(reversed(d))}}}), .S({{{', '.join(reversed(s))}}}));")
            for i in range(b, min(b + 4, n)):
                if O[i] is not None:
                    self.body.append(f"  assign {O[i]} = o{u}[{i - b}];")
            ci = f"co{u}[3]"
            if cout is not None and b + 4 >= n:
                self.body.append(f"  assign {cout} = co{u}[{(n - 1) - b}];")


def c(x):
    """a LUT input name: Verilog constants for the chain ports"""
    return {"0": "1'b0", "1": "1'b1"}.get(x, x)


def mux4(sel0, sel1, cands):
    ins = [sel0, sel1] + cands
    return ins, (lambda v: v[2 + v[0] + 2 * v[1]])


def rng_or(name, lo, hi):
    """Verilog OR of name[hi:lo], or 1'b0 when empty"""
    if lo > hi:
        return "1'b0"
    return f"{name}[{lo}]" if lo == hi else f"(|{name}[{hi}:{lo}])"


def case4(sel, terms):
    return (f"({sel} == 2'd0) ? {terms[0]} : ({sel} == 2'd1) ? {terms[1]} : "
            f"({sel} == 2'd2) ? {terms[2]} : {terms[3]}")


def axis(vsat=33, name="carried_axis_hand"):
    AW = min(54, vsat + 15)          # level A keeps A[AW-1:0]
    BW = vsat + 3                    # level B keeps B[BW-1:0]; level C keeps C[vsat-1:0]
    DKW = min(40, vsat + 2)          # (xp - lo_j<<20) << k kept to DKW bits
    SW = DKW + 1                     # sums
    m = Mod()
    W = lambda j: f"P[{j - 15}]" if 15 <= j <= 53 else '0'
    # V's shift, level A (>> 16 r2), B (>> 4 r1), C (>> r0)
    for j in range(AW):
        m.lut(f"A[{j}]", *mux4("r[4]", "r[5]", [W(j + 16 * t) for t in range(4)]))
    Af = lambda j: f"A[{j}]" if j < AW else '0'
    for j in range(BW):
        m.lut(f"B[{j}]", *mux4("r[2]", "r[3]", [Af(j + 4 * t) for t in range(4)]))
    Bf = lambda j: f"B[{j}]" if j < BW else '0'
    for j in range(vsat):
        m.lut(f"C[{j}]", *mux4("r[0]", "r[1]", [Bf(j + t) for t in range(4)]))
    # shared adder operand: Bop = (vsat ? 2^vsat : C) ^ dneg, bits 0..vsat (above: dneg)
    for j in range(0, vsat + 1, 2):
        if j + 1 < vsat:
            m.lut2(f"Bop[{j}]", f"Bop[{j + 1}]", [f"C[{j}]", f"C[{j + 1}]", "vsat", "dneg"],
                   lambda v: (v[0] & (1 - v[2])) ^ v[3], lambda v: (v[1] & (1 - v[2])) ^ v[3])
        else:
            m.lut2(f"Bop[{j}]", f"Bop[{j + 1}]", [f"C[{j}]", "vsat", "dneg"],
                   lambda v: (v[0] & (1 - v[1])) ^ v[2], lambda v: v[1] ^ v[2])
    Bop = lambda i: f"Bop[{i}]" if i <= vsat else "dneg"
    for X in ("lo", "hi"):
        xp = f"xp_{X}"
        D = f"D{X}"
        # D[32:20] = {xp[31], xp[31:20]} - lo_j
        a = [f"{xp}[{20 + i}]" for i in range(12)] + [f"{xp}[31]"]
        b = [f"lo_j[{i}]" for i in range(8)] + ['0'] * 5
        S = []
        for i in range(13):
            m.lut(f"{D}s[{i}]", [a[i], b[i]], lambda v: v[0] ^ (1 - v[1]))
            S.append(f"{D}s[{i}]")
        m.chain(S, a, "1'b1", [f"{D}[{20 + i}]" for i in range(13)])
        m.body.append(f"  assign {D}[19:0] = {xp}[19:0];")
        Dv = lambda i, D=D: '0' if i < 0 else f"{D}[{min(i, 32)}]"
        # k-shift, first level: M[i] = D[i - k[1:0]]
        M = f"M{X}"
        for i in range(DKW):
            m.lut(f"{M}[{i}]", *mux4("k[0]", "k[1]", [Dv(i - t) for t in range(4)]))
        Mv = lambda i, M=M: '0' if i < 0 else f"{M}[{min(i, DKW - 1)}]"
        # adder with the k[2] level: S = (k2 ? M[i-4] : M[i]) ^ Bop[i], DI = Bop[i]
        S = []
        for i in range(SW):
            m.lut(f"S{X}s[{i}]", ["k[2]", Mv(i), Mv(i - 4), Bop(i)],
                  lambda v: (v[2] if v[0] else v[1]) ^ v[3])
            S.append(f"S{X}s[{i}]")
        m.chain(S, [Bop(i) for i in range(SW)], f"cin_{X}", [f"S{X}[{i}]" for i in range(SW)])
        # clamp: xc = v ? {g, 31{~g}} : S[31:0]
        fc = lambda i: (lambda v: (v[3] if i == 31 else 1 - v[3]) if v[2] else v[0])
        fc5 = lambda i: (lambda v: (v[3] if i == 31 else 1 - v[3]) if v[2] else v[1])
        top = 32 if X == "lo" else 16
        for i in range(0, top, 2):
            m.lut2(f"xc_{X}[{i}]", f"xc_{X}[{i + 1}]",
                   [f"S{X}[{i}]", f"S{X}[{i + 1}]", f"v{X}", f"g{X}"], fc(i), fc5(i + 1))
    # xc_hi[31:16]: clamp LUTs drive x_hi's increment chain
    S = []
    for i in range(16, 32):
        m.lut(f"xc_hi[{i}]", [f"Shi[{i}]", "vhi", "ghi"],
              lambda v, i=i: (v[2] if i == 31 else 1 - v[2]) if v[1] else v[0])
        S.append(f"xc_hi[{i}]")
    m.chain(S, ['0'] * 16, "inc", [f"x_hi[{j}]" for j in range(16)])
    # control logic (left to Yosys): saturation and sticky flags per level, D << k overflow
    vA = case4("r2", [rng_or("P", AW + 16 * t - 15, 38) if AW + 16 * t <= 53 else "1'b0" for t in range(4)])
    vB = case4("r1", [rng_or("A", BW + 4 * t, AW - 1) for t in range(4)])
    vC = case4("r0", [rng_or("B", vsat + t, BW - 1) for t in range(4)])
    # D << k fits DKW bits iff D[b] == D[32] for every b >= DKW - 1 - k
    ov = [f"((D{{X}}[{b}] ^ D{{X}}[32]) & (k >= 3'd{DKW - 1 - b}))" for b in range(32)
          if 0 <= DKW - 1 - b <= 7]
    ovx = lambda X: " | ".join(o.replace("{X}", X) for o in ov) if ov else "1'b0"
    v = [f"module {name} (",
         "  input  [14:0] entry,",
         "  input  [31:0] xp_lo, xp_hi,",
         "  input  [7:0]  lo_j,",
         "  input  [2:0]  k,",
         "  input  [23:0] dsig,",
         "  input         dneg,",
         "  input  [6:0]  dsh,",
         "  output [31:0] xc_lo, xc_hi,",
         "  output [15:0] x_lo, x_hi);",
         f"  // V saturated at 2^{vsat}; A, B, C: {AW}, {BW}, {vsat} bits; D << k: {DKW} bits; sums {SW} bits",
         "  wire [38:0] P = entry * dsig;",
         "  wire [5:0]  r = 6'd15 - dsh[5:0];",
         f"  wire [{AW - 1}:0] A; wire [{BW - 1}:0] B; wire [{vsat - 1}:0] C; wire [{vsat}:0] Bop;",
         f"  wire [32:0] Dlo, Dhi; wire [12:0] Dlos, Dhis; wire [{DKW - 1}:0] Mlo, Mhi;",
         f"  wire [{SW - 1}:0] Slos, Shis, Slo, Shi;",
         "  wire [1:0] r2 = r[5:4], r1 = r[3:2], r0 = r[1:0];",
         f"  wire vA = {vA};",
         "  wire sA = (r2 == 2'd0) ? 1'b0 : (r2 == 2'd1) ? P[0] : (r2 == 2'd2) ? |P[16:0] : |P[32:0];",
         f"  wire vB = {vB};",
         "  wire sB = (r1 == 2'd0) ? 1'b0 : (r1 == 2'd1) ? |A[3:0] : (r1 == 2'd2) ? |A[7:0] : |A[11:0];",
         f"  wire vC = {vC};",
         "  wire sC = (r0 == 2'd0) ? 1'b0 : (r0 == 2'd1) ? B[0] : (r0 == 2'd2) ? |B[1:0] : |B[2:0];",
         "  wire vsat = vA | vB | vC;",
         "  wire st = (sA | sB | sC) & ~vsat;",
         "  wire cin_lo = dneg & ~st;",
         "`ifdef FAULT",
         "  wire cin_hi = st;                 // planted fault: the negated ceiling lost",
         "`else",
         "  wire cin_hi = dneg | st;",
         "`endif",
         f"  wire olo = {ovx('lo')};",
         f"  wire ohi = {ovx('hi')};",
         f"  wire vlo = olo | ~((&Slo[{SW - 1}:31]) | ~(|Slo[{SW - 1}:31]));",
         f"  wire vhi = ohi | ~((&Shi[{SW - 1}:31]) | ~(|Shi[{SW - 1}:31]));",
         f"  wire glo = olo ? Dlo[32] : Slo[{SW - 1}];",
         f"  wire ghi = ohi ? Dhi[32] : Shi[{SW - 1}];",
         "  wire nz = |xc_hi[15:0];",
         "  wire inc = nz & ~(xc_hi[31:16] == 16'h7fff);",
         "  assign x_lo = xc_lo[31:16];"]
    v += m.body + ["endmodule", ""]
    return v, m


def time():
    m = Mod()
    E = lambda j: f"entry[{j}]" if 0 <= j <= 14 else '0'
    for j in range(18):
        m.lut(f"z1[{j}]", *mux4("gp[0]", "gp[1]", [E(j - t) for t in range(4)]))
    Z1 = lambda j: f"z1[{j}]" if 0 <= j <= 17 else '0'
    for j in range(30):
        m.lut(f"z[{j}]", *mux4("gp[2]", "gp[3]", [Z1(j - 4 * t) for t in range(4)]))
    Z = lambda j: f"z[{j}]" if 0 <= j <= 29 else '0'
    S = []
    for i in range(48):
        ins, f = mux4("gp[4]", "gp[5]", [Z(i), Z(i - 16), Z(i - 32), '0'])
        m.lut(f"ss[{i}]", ins + [f"t_p[{i}]"], lambda v, f=f: f(v[:6]) ^ v[6])
        S.append(f"ss[{i}]")
    m.chain(S, [f"t_p[{i}]" for i in range(48)], "1'b0", [f"sum[{i}]" for i in range(48)], "c48")
    for i in range(0, 48, 2):
        m.lut2(f"t_c[{i}]", f"t_c[{i + 1}]", [f"sum[{i}]", f"sum[{i + 1}]", "ovf"],
               lambda v: v[0] | v[2], lambda v: v[1] | v[2])
    S = []
    for i in range(48):
        m.lut(f"ds[{i}]", [f"tmax[{i}]", f"t_c[{i}]"], lambda v: v[0] ^ (1 - v[1]))
        S.append(f"ds[{i}]")
    m.chain(S, [f"tmax[{i}]" for i in range(48)], "1'b1", [f"d[{i}]" for i in range(48)], "nb")
    Dd = lambda j: f"d[{j}]" if j <= 47 else '0'
    for j in range(29):
        m.lut(f"A[{j}]", *mux4("gc[4]", "gc[5]", [Dd(j + 16 * t) for t in range(4)]))
    Af = lambda j: f"A[{j}]" if j <= 28 else '0'
    for j in range(17):
        m.lut(f"B[{j}]", *mux4("gc[2]", "gc[3]", [Af(j + 4 * t) for t in range(4)]))
    Bf = lambda j: f"B[{j}]" if j <= 16 else '0'
    S = []
    for j in range(14):
        m.lut(f"Dq[{j}]", *mux4("gc[0]", "gc[1]", [Bf(j + t) for t in range(4)]))
        S.append(f"Dq[{j}]")
    m.chain(S, ['0'] * 14, "st", [f"q[{j}]" for j in range(14)], "q14")
    for j in range(0, 14, 2):
        m.lut2(f"far_top[{j}]", f"far_top[{j + 1}]", [f"q[{j}]", f"q[{j + 1}]", "keep"],
               lambda v: v[0] & v[2], lambda v: v[1] & v[2])
    v = ["module carried_time_hand (",
         "  input  [14:0] entry,",
         "  input  [5:0]  gp,",
         "  input  [47:0] t_p, tmax,",
         "  input  [5:0]  gc,",
         "  output [47:0] t_c,",
         "  output [14:0] far_top,",
         "  output        empty);",
         "  wire [17:0] z1; wire [29:0] z; wire [47:0] ss, sum, ds, d; wire c48, nb;",
         "  wire [28:0] A; wire [16:0] B; wire [13:0] Dq, q; wire q14;",
         "  wire [1:0] g2 = gp[5:4], c2 = gc[5:4], c1 = gc[3:2], c0 = gc[1:0];",
         "  wire ovs = (g2 == 2'd3) ? (|entry) : (g2 == 2'd2) ? (|z[29:16]) : 1'b0;",
         "  wire ovf = ovs | c48;",
         "  assign empty = ~nb;",
         "  wire bA = (c2 == 2'd0) ? |d[47:29] : (c2 == 2'd1) ? |d[47:45] : 1'b0;",
         "  wire sA = (c2 == 2'd0) ? 1'b0 : (c2 == 2'd1) ? |d[15:0] : (c2 == 2'd2) ? |d[31:0] : |d;",
         "  wire bB = (c1 == 2'd0) ? |A[28:17] : (c1 == 2'd1) ? |A[28:21] : (c1 == 2'd2) ? |A[28:25] : 1'b0;",
         "  wire sB = (c1 == 2'd0) ? 1'b0 : (c1 == 2'd1) ? |A[3:0] : (c1 == 2'd2) ? |A[7:0] : |A[11:0];",
         "  wire bC = (c0 == 2'd0) ? |B[16:14] : (c0 == 2'd1) ? |B[16:15] : (c0 == 2'd2) ? B[16] : 1'b0;",
         "  wire sC = (c0 == 2'd0) ? 1'b0 : (c0 == 2'd1) ? B[0] : (c0 == 2'd2) ? |B[1:0] : |B[2:0];",
         "  wire big = bA | bB | bC;",
         "  wire keep = ~big & ~empty;",
         "  wire st = sA | sB | sC;",
         "  assign far_top[14] = keep ? q14 : (big & ~empty);"]
    v += m.body + ["endmodule", ""]
    return v, m


if __name__ == '__main__':
    va, ma = axis()
    va39, ma39 = axis(39, "carried_axis_hand39")
    vt, mt = time()
    with open("hand.v", "w") as f:
        f.write("// hand.v: written by gen_hand.py (see there); same function as carried.v\n")
        f.write("\n".join(va + va39 + vt))
    print(f"carried_axis_hand: {ma.nlut} LUT instances, {ma.ncarry} CARRY4 (+ Yosys logic)")
    print(f"carried_axis_hand39: {ma39.nlut} LUT instances, {ma39.ncarry} CARRY4 (+ Yosys logic)")
    print(f"carried_time_hand: {mt.nlut} LUT instances, {mt.ncarry} CARRY4 (+ Yosys logic)")
