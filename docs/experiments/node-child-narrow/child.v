// The narrow per-child test in Ylitie's form (docs/experiments/node-child-narrow/README.md).
// Axis i in bits [8i+:8] / [W*i+:W] / [9i+:9] / [17i+:17] (x = 0, y = 1, z = 2).
// Per node (inputs): an, af (time at plane 0, near side rounded down, far side rounded up,
// W-bit two's complement), s (9-bit unsigned slope), neg (direction sign), t_start, t_end.
// Per child: lo, hi (8-bit), valid.  Near integer xn = neg ? ~hi : lo, far xf = neg ? ~lo : hi;
// near = an + floor(xn*s / 2^D), far = af + floor(xf*s / 2^D);
// t_near = max(near_x, near_y, near_z, t_start), hit = valid & t_near <= min(far_*, t_end);
// entry = t_near >>> (W - 16).
// Flavours: default W = 16, D = 4 (sums narrowed; the per-node part supplies an, t_start,
// t_end floored and af ceiled to units of 2^D); -DEXACT: W = 20, D = 0 (exact sums).
// Own logic: -DOWN=child_own_plain (default), child_own_plain4, child_own_hand.
// Far product: default xf*s (F1: the per-node part adds 2^q - 1 ulp to af); -DF2: xf*(s + 1)
// (s1 = s + 1 a per-node input of 10 bits; on a DSP48E1 the +xf enters by the C port).
`ifdef EXACT
  `define W 20
  `define D 0
  `define HLE hle_20
  `define HMAX hmax_20
`else
  `define W 16
  `define D 4
  `define HLE hle_16
  `define HMAX hmax_16
`endif
`ifndef OWN
  `define OWN child_own_plain
`endif
`define PB (17 - `D)

// ---- the child's own logic: products are inputs (pn = xn*s, pf = xf*s, 17 bits each) ----
`define OWN_PORTS \
  input [23:0] lo, hi, input [2:0] neg, input valid, \
  input [3*`W-1:0] an, af, input [`W-1:0] t_start, t_end, \
  input [50:0] pn, pf, \
  output [23:0] xn, xf, output hit, output [15:0] entry

// as the brief writes it: max tree, min tree, one comparison
module child_own_plain(`OWN_PORTS);
  wire [3*`W-1:0] nr, fr;
  genvar i;
  for (i = 0; i < 3; i = i + 1) begin : ax
    assign xn[8*i+:8] = neg[i] ? ~hi[8*i+:8] : lo[8*i+:8];
    assign xf[8*i+:8] = neg[i] ? ~lo[8*i+:8] : hi[8*i+:8];
    assign nr[`W*i+:`W] = an[`W*i+:`W] + pn[17*i+`D+:`PB];
    assign fr[`W*i+:`W] = af[`W*i+:`W] + pf[17*i+`D+:`PB];
  end
  wire signed [`W-1:0] n0 = nr[0+:`W], n1 = nr[`W+:`W], n2 = nr[2*`W+:`W];
  wire signed [`W-1:0] f0 = fr[0+:`W], f1 = fr[`W+:`W], f2 = fr[2*`W+:`W];
  wire signed [`W-1:0] ts = t_start, te = t_end;
  wire signed [`W-1:0] m1 = n0 > n1 ? n0 : n1;
  wire signed [`W-1:0] m2 = n2 > ts ? n2 : ts;
  wire signed [`W-1:0] tn = m1 > m2 ? m1 : m2;
  wire signed [`W-1:0] g1 = f0 < f1 ? f0 : f1;
  wire signed [`W-1:0] g2 = f2 < te ? f2 : te;
  wire signed [`W-1:0] tf = g1 < g2 ? g1 : g2;
  assign hit = valid & (tn <= tf);
  assign entry = tn[`W-1-:16];
endmodule

// the same function, t_far not formed: hit = valid & t_near <= each of the four far values
module child_own_plain4(`OWN_PORTS);
  wire [3*`W-1:0] nr, fr;
  genvar i;
  for (i = 0; i < 3; i = i + 1) begin : ax
    assign xn[8*i+:8] = neg[i] ? ~hi[8*i+:8] : lo[8*i+:8];
    assign xf[8*i+:8] = neg[i] ? ~lo[8*i+:8] : hi[8*i+:8];
    assign nr[`W*i+:`W] = an[`W*i+:`W] + pn[17*i+`D+:`PB];
    assign fr[`W*i+:`W] = af[`W*i+:`W] + pf[17*i+`D+:`PB];
  end
  wire signed [`W-1:0] n0 = nr[0+:`W], n1 = nr[`W+:`W], n2 = nr[2*`W+:`W];
  wire signed [`W-1:0] f0 = fr[0+:`W], f1 = fr[`W+:`W], f2 = fr[2*`W+:`W];
  wire signed [`W-1:0] ts = t_start, te = t_end;
  wire signed [`W-1:0] m1 = n0 > n1 ? n0 : n1;
  wire signed [`W-1:0] m2 = n2 > ts ? n2 : ts;
  wire signed [`W-1:0] tn = m1 > m2 ? m1 : m2;
  assign hit = valid & (tn <= f0) & (tn <= f1) & (tn <= f2) & (tn <= te);
  assign entry = tn[`W-1-:16];
endmodule

// plain4 with hand-placed select (hmux8), comparators and maxima (hand.v); adders as '+'
module child_own_hand(`OWN_PORTS);
  wire [3*`W-1:0] nr, fr;
  genvar i;
  for (i = 0; i < 3; i = i + 1) begin : ax
    hmux8 mx(.lo(lo[8*i+:8]), .hi(hi[8*i+:8]), .neg(neg[i]), .xn(xn[8*i+:8]), .xf(xf[8*i+:8]));
    assign nr[`W*i+:`W] = an[`W*i+:`W] + pn[17*i+`D+:`PB];
    assign fr[`W*i+:`W] = af[`W*i+:`W] + pf[17*i+`D+:`PB];
  end
  wire [`W-1:0] m1, m2, tn;
  wire [3:0] le;
  `HMAX x01(.a(nr[0+:`W]), .b(nr[`W+:`W]), .y(m1));
  `HMAX x2s(.a(nr[2*`W+:`W]), .b(t_start), .y(m2));
  `HMAX xn_(.a(m1), .b(m2), .y(tn));
  `HLE c0(.a(tn), .b(fr[0+:`W]), .le(le[0]));
  `HLE c1(.a(tn), .b(fr[`W+:`W]), .le(le[1]));
  `HLE c2(.a(tn), .b(fr[2*`W+:`W]), .le(le[2]));
  `HLE c3(.a(tn), .b(t_end), .le(le[3]));
  assign hit = valid & (&le);
  assign entry = tn[`W-1-:16];
endmodule

// ---- whole children: per node s (3 x 9 bits); the products four ways ----
`ifdef F2
  `define S1_PORT input [29:0] s1,
  `define SF(i) s1[10*i+:10]
  `define FAR_PROD(i) wire [17:0] pf18; hm_8x10 mf(.a(xf[8*i+:8]), .b(s1[10*i+:10]), .p(pf18)); assign pf[17*i+:17] = pf18[16:0];
  `define DSP2 dsp2f_8x9
`else
  `define S1_PORT
  `define SF(i) s[9*i+:9]
  `define FAR_PROD(i) hm_8x9 mf(.a(xf[8*i+:8]), .b(s[9*i+:9]), .p(pf[17*i+:17]));
  `define DSP2 dsp2_8x9
`endif
`define CHILD_PORTS \
  input [23:0] lo, hi, input [2:0] neg, input valid, \
  input [3*`W-1:0] an, af, input [26:0] s, `S1_PORT input [`W-1:0] t_start, t_end, \
  output hit, output [15:0] entry
`define OWN_INST \
  `OWN own(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .t_start(t_start), \
           .t_end(t_end), .pn(pn), .pf(pf), .xn(xn), .xf(xf), .hit(hit), .entry(entry));

// 1. products as '*' (Yosys: DSP48E1 by default, LUTs with -nodsp)
module child_mul(`CHILD_PORTS);
  wire [23:0] xn, xf; wire [50:0] pn, pf;
  genvar i;
  for (i = 0; i < 3; i = i + 1) begin : ax
    assign pn[17*i+:17] = xn[8*i+:8] * s[9*i+:9];
    assign pf[17*i+:17] = xf[8*i+:8] * `SF(i);
  end
  `OWN_INST
endmodule

// 2. hand-placed radix-4 Booth products (hm_8x9 from ../node-products/gen.py 8 9)
module child_booth(`CHILD_PORTS);
  wire [23:0] xn, xf; wire [50:0] pn, pf;
  genvar i;
  for (i = 0; i < 3; i = i + 1) begin : ax
    hm_8x9 mn(.a(xn[8*i+:8]), .b(s[9*i+:9]), .p(pn[17*i+:17]));
    `FAR_PROD(i)
  end
  `OWN_INST
endmodule

// 3. the two products of an axis in one DSP48E1 (dsp2_8x9 from ../node-products/dsp2.v) on
//    the first NDSP axes, hand-placed Booth products on the others
`define DSP_CHILD(NAME, NDSP) \
module NAME(`CHILD_PORTS); \
  wire [23:0] xn, xf; wire [50:0] pn, pf; \
  genvar i; \
  for (i = 0; i < 3; i = i + 1) begin : ax \
    if (i < NDSP) begin : d \
      `DSP2 m(.x1(xn[8*i+:8]), .x2(xf[8*i+:8]), .s(s[9*i+:9]), .p1(pn[17*i+:17]), .p2(pf[17*i+:17])); \
    end else begin : l \
      hm_8x9 mn(.a(xn[8*i+:8]), .b(s[9*i+:9]), .p(pn[17*i+:17])); \
      `FAR_PROD(i) \
    end \
  end \
  `OWN_INST \
endmodule

`DSP_CHILD(child_dsp3, 3)
`DSP_CHILD(child_dsp2, 2)
`DSP_CHILD(child_dsp1, 1)

// dsp2_8x9 (../node-products/dsp2.v) with p2 = x2*(s + 1): C = {x2[7] ? s : 0, x2, 17'b0}
// always added (the sign-bit correction and the +x2 of the far field), the AND in hand9
module dsp2f_8x9(input [7:0] x1, x2, input [8:0] s, output [16:0] p1, p2);
  wire [47:0] P;
  wire [8:0] sc;
  hand9 g(.s(s), .b(x2[7]), .y(sc));
  wire [29:0] A = {{5{x2[7]}}, x2, 9'b0, x1};
  wire [17:0] B = {9'b0, s};
  wire [47:0] C = {14'b0, sc, x2, 17'b0};
  DSP48E1 #(.AREG(0), .ACASCREG(0), .BREG(0), .BCASCREG(0), .CREG(0), .MREG(0), .PREG(0),
            .ADREG(0), .DREG(0), .OPMODEREG(0), .ALUMODEREG(0), .INMODEREG(0), .CARRYINREG(0),
            .CARRYINSELREG(0), .USE_MULT("MULTIPLY"), .USE_DPORT("FALSE"))
    dsp (.A(A), .B(B), .C(C), .D(25'b0), .OPMODE(7'b0110101), .ALUMODE(4'b0000), .INMODE(5'b00000),
         .CARRYIN(1'b0), .CARRYINSEL(3'b000), .P(P), .CLK(1'b0),
         .CEA1(1'b0), .CEA2(1'b0), .CEAD(1'b0), .CEALUMODE(1'b0), .CEB1(1'b0), .CEB2(1'b0),
         .CEC(1'b0), .CECARRYIN(1'b0), .CECTRL(1'b0), .CED(1'b0), .CEINMODE(1'b0), .CEM(1'b0), .CEP(1'b0),
         .RSTA(1'b0), .RSTALLCARRYIN(1'b0), .RSTALUMODE(1'b0), .RSTB(1'b0), .RSTC(1'b0), .RSTCTRL(1'b0),
         .RSTD(1'b0), .RSTINMODE(1'b0), .RSTM(1'b0), .RSTP(1'b0), .ACIN(30'b0), .BCIN(18'b0),
         .PCIN(48'b0), .CARRYCASCIN(1'b0), .MULTSIGNIN(1'b0));
  assign p1 = P[16:0];
  assign p2 = P[33:17];
endmodule
