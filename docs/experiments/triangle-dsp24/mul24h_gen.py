# Hand-mapped 24x24 unsigned product: one DSP48E1 (a * signed(b[17:0]) + C) and
# a 24x7 rest R = 32a + d0*a + 4*d1*a + 16*d2*a in LUT6 + CARRY4, with Booth digits
# d0 = (b19,b18,b17), d1 = (b21,b20,b19), d2 = (~b23,b22,b21); exact for every b.
def lut_init(f, n):
    v = 0
    for i in range(1 << n):
        bits = [(i >> k) & 1 for k in range(n)]
        if f(*bits): v |= 1 << i
    return v
def booth_bit(aj, ajm1, x2, x1, x0):
    d = -2*x2 + x1 + x0
    neg = 1 if d < 0 else 0
    m = abs(d)
    v = aj if m == 1 else (ajm1 if m == 2 else 0)
    return v ^ neg
def emit(name="mul24h"):
    W = 30
    L = []
    L.append(f"module {name}(input [23:0] a, input [23:0] b, output [47:0] p);")
    L.append("  wire [25:0] az = {2'b0, a};")
    L.append("  wire [2:0] x0 = {b[19], b[18], b[17]};")
    L.append("  wire [2:0] x1 = {b[21], b[20], b[19]};")
    L.append("  wire [2:0] x2 = {~b[23], b[22], b[21]};")
    ninit = lut_init(lambda u0, u1, u2: 1 if (u2 and not (u1 and u0)) else 0, 3)
    for k in range(3):
        L.append(f"  wire n{k}; LUT3 #(.INIT(8'h{ninit:02x})) ln{k} (.O(n{k}), .I0(x{k}[0]), .I1(x{k}[1]), .I2(x{k}[2]));")
    # adders: stage k adds row k at offset 2k to prev (stage 0: prev = 32a)
    prev = None
    for k in range(3):
        off = 2 * k
        L.append(f"  wire [{W-1}:0] s{k};")
        nb = W - off
        nc = (nb + 3) // 4
        L.append(f"  wire [{4*nc-1}:0] S{k}, D{k}, O{k}, C{k};")
        for j in range(4 * nc):
            i = off + j  # bit position in R
            if j >= nb:
                L.append(f"  assign S{k}[{j}] = 1'b0; assign D{k}[{j}] = 1'b0;")
                continue
            # row bit index within row: j (row value d*a at offset off); a index j, j-1
            aj = f"az[{j}]" if j <= 25 else "1'b0"
            ajm1 = f"az[{j-1}]" if 1 <= j <= 26 else "1'b0"
            if k == 0:
                pv = f"a[{i-5}]" if 5 <= i <= 28 else None
            else:
                pv = f"s{k-1}[{i}]"
            if pv is None:
                f = lambda aj_, am_, a, b_, c: booth_bit(aj_, am_, a, b_, c)
                init = lut_init(lambda I0, I1, I2, I3, I4: booth_bit(I0, I1, I4, I3, I2), 5)
                L.append(f"  LUT5 #(.INIT(32'h{init:08x})) l{k}_{j} (.O(S{k}[{j}]), .I0({aj}), .I1({ajm1}), .I2(x{k}[0]), .I3(x{k}[1]), .I4(x{k}[2]));")
                L.append(f"  assign D{k}[{j}] = 1'b0;")
            else:
                init = lut_init(lambda I0, I1, I2, I3, I4, I5: I5 ^ booth_bit(I0, I1, I4, I3, I2), 6)
                L.append(f"  LUT6 #(.INIT(64'h{init:016x})) l{k}_{j} (.O(S{k}[{j}]), .I0({aj}), .I1({ajm1}), .I2(x{k}[0]), .I3(x{k}[1]), .I4(x{k}[2]), .I5({pv}));")
                L.append(f"  assign D{k}[{j}] = {pv};")
        for c in range(nc):
            ci = "1'b0" if c > 0 else "1'b0"
            cyinit = f"n{k}" if c == 0 else "1'b0"
            cin = ".CI(1'b0), " if c == 0 else f".CI(C{k}[{4*c-1}]), "
            L.append(f"  CARRY4 c{k}_{c} ({cin}.CYINIT({cyinit if c == 0 else '1' + chr(39) + 'b0'}), .DI(D{k}[{4*c+3}:{4*c}]), .S(S{k}[{4*c+3}:{4*c}]), .O(O{k}[{4*c+3}:{4*c}]), .CO(C{k}[{4*c+3}:{4*c}]));")
        if k == 0:
            L.append(f"  assign s0 = O0[{W-1}:0];")
        else:
            L.append(f"  assign s{k} = {{O{k}[{nb-1}:0], s{k-1}[{off-1}:0]}};")
    L.append("  wire signed [24:0] sa = {1'b0, a};")
    L.append("  wire signed [17:0] sb = b[17:0];")
    L.append("  wire signed [47:0] m = sa * sb;")
    L.append(f"  assign p = m + {{s2[29:0], 18'd0}};")
    L.append("endmodule")
    return "\n".join(L) + "\n"
open("mul24h.v", "w").write(emit())
