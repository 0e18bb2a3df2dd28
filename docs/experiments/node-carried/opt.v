// opt.v: the same function as carried.v's carried_axis / carried_time (bit-exact, any VSAT),
// restructured in plain Verilog (no primitives). Selected in node_carried_pernode by -DOPT.
//
// carried_axis_opt:
//  - V's shift as three explicit 4:1 levels, coarse first, each keeping only the bits that can
//    still reach V[32:0]; the saturation flag (V >= 2^33) and the sticky bit (a dropped bit set)
//    from small ORs at each level instead of a 54-bit shifter, mask and OR;
//  - no negation and no ceiling adder: lower = (Vf ^ dneg) + (dneg & ~st), upper = (Vf ^ dneg) +
//    (dneg | st), so both bounds share the operand Vf ^ dneg and differ only by the carry-in
//    (written {a,1} + {b,cin} so that Yosys builds one carry chain with the carry-in);
//  - (xp - lo_j<<20) << k kept to VSAT + 2 bits plus an overflow flag (|V| <= 2^VSAT, so a shifted
//    value outside [-2^(VSAT+1), 2^(VSAT+1)) clamps by its own sign): at VSAT = 33 36-bit sums
//    instead of 41; at VSAT = 39 all 40 bits (no flag), 41-bit sums;
//  - x_hi's clamp folded into the increment: + (nz & ~(xc_hi[31:16] == 16'h7fff)).
// carried_time_opt:
//  - entry << gp as a 16-way shift (30 bits) then a 4-way shift by 16 (one candidate or two per
//    bit), its overflow from two small ORs; t_c's saturation an OR;
//  - (tmax - t_c) >> gc as three 4:1 levels keeping 29, 17, 14 bits, "big" (>= 2^14) and the
//    sticky bit from small ORs per level, the clamp and the empty case folded into the increment.
module carried_axis_opt #(parameter VSAT = `VSAT) (
  input  [14:0] entry,
  input  [31:0] xp_lo, xp_hi,
  input  [7:0]  lo_j,
  input  [2:0]  k,
  input  [23:0] dsig,
  input         dneg,
  input  [6:0]  dsh,
  output [31:0] xc_lo, xc_hi,
  output [15:0] x_lo, x_hi);
  // widths: V's shift keeps AW, BW, VSAT bits per level; (xp - lo_j<<20) << k keeps DKW bits
  // (40: all of it) and the sums are SW bits
  localparam AW  = (VSAT + 15 < 54) ? VSAT + 15 : 54;
  localparam BW  = VSAT + 3;
  localparam DKW = (VSAT + 2 < 40) ? VSAT + 2 : 40;
  localparam SW  = DKW + 1;

  wire [38:0] P = entry * dsig;
  wire [5:0]  r = 6'd15 - dsh[5:0];            // V = (P << 15) >> r
  wire [1:0]  r2 = r[5:4], r1 = r[3:2], r0 = r[1:0];
  wire [53:0] W = {P, 15'b0};
  // level A: >> 16*r2, keep [AW-1:0]
  wire [53:0] Af = W >> {r2, 4'b0};
  wire [AW-1:0] A = Af[AW-1:0];
  wire [54:0] Afx = {1'b0, Af};
  wire vA = |Afx[54:AW];                        // bits that stay >= 2^VSAT
  wire sA = (r2 == 2'd0) ? 1'b0 : (r2 == 2'd1) ? P[0] : (r2 == 2'd2) ? |P[16:0] : |P[32:0];
  // level B: >> 4*r1, keep [BW-1:0]
  wire [AW-1:0] Bf = A >> {r1, 2'b0};
  wire [BW-1:0] B = Bf[BW-1:0];
  wire vB = |Bf[AW-1:BW];
  wire sB = (r1 == 2'd0) ? 1'b0 : (r1 == 2'd1) ? |A[3:0] : (r1 == 2'd2) ? |A[7:0] : |A[11:0];
  // level C: >> r0, keep [VSAT-1:0]
  wire [BW-1:0] Cf = B >> r0;
  wire [VSAT-1:0] C = Cf[VSAT-1:0];
  wire vC = |Cf[BW-1:VSAT];
  wire sC = (r0 == 2'd0) ? 1'b0 : (r0 == 2'd1) ? B[0] : (r0 == 2'd2) ? |B[1:0] : |B[2:0];
  wire vsat = vA | vB | vC;
  wire st = (sA | sB | sC) & ~vsat;
  wire [VSAT:0] Vf = vsat ? {1'b1, {VSAT{1'b0}}} : {1'b0, C};
  wire [SW-1:0] Bop = {{(SW-VSAT-1){1'b0}}, Vf} ^ {SW{dneg}};
  wire cin_lo = dneg & ~st;
  wire cin_hi = dneg | st;
  // (xp - lo_j<<20) << k, DKW bits and an overflow flag
  wire [32:0] Lo  = {5'b0, lo_j, 20'b0};
  wire [32:0] Dlo = {xp_lo[31], xp_lo} - Lo;
  wire [32:0] Dhi = {xp_hi[31], xp_hi} - Lo;
  wire [40:0] Dlo_x = {{8{Dlo[32]}}, Dlo} << k;
  wire [40:0] Dhi_x = {{8{Dhi[32]}}, Dhi} << k;
  wire olo = ~((&Dlo_x[40:DKW-1]) | ~(|Dlo_x[40:DKW-1]));
  wire ohi = ~((&Dhi_x[40:DKW-1]) | ~(|Dhi_x[40:DKW-1]));
  wire [SW:0] Slo_x = {Dlo_x[DKW-1], Dlo_x[DKW-1:0], 1'b1} + {Bop, cin_lo};
  wire [SW:0] Shi_x = {Dhi_x[DKW-1], Dhi_x[DKW-1:0], 1'b1} + {Bop, cin_hi};
  wire [SW-1:0] Slo = Slo_x[SW:1], Shi = Shi_x[SW:1];
  wire vlo = olo | ~((&Slo[SW-1:31]) | ~(|Slo[SW-1:31]));
  wire vhi = ohi | ~((&Shi[SW-1:31]) | ~(|Shi[SW-1:31]));
  wire glo = olo ? Dlo[32] : Slo[SW-1];
  wire ghi = ohi ? Dhi[32] : Shi[SW-1];
  assign xc_lo = vlo ? {glo, {31{~glo}}} : Slo[31:0];
  assign xc_hi = vhi ? {ghi, {31{~ghi}}} : Shi[31:0];
  assign x_lo = xc_lo[31:16];
  wire nz = |xc_hi[15:0];
  wire top = (xc_hi[31:16] == 16'h7fff);
`ifdef FAULT
  assign x_hi = xc_hi[31:16];                // planted fault: floor instead of ceiling
`else
  assign x_hi = xc_hi[31:16] + {15'b0, nz & ~top};
`endif
endmodule

module carried_time_opt (
  input  [14:0] entry,
  input  [5:0]  gp,
  input  [47:0] t_p, tmax,
  input  [5:0]  gc,
  output [47:0] t_c,
  output [14:0] far_top,
  output        empty);
  wire [29:0] z = {15'b0, entry} << gp[3:0];
  wire [1:0]  g2 = gp[5:4];
  wire [47:0] es = (g2 == 2'd0) ? {18'b0, z} : (g2 == 2'd1) ? {2'b0, z, 16'b0} :
                   (g2 == 2'd2) ? {z[15:0], 32'b0} : 48'b0;
  wire ovs = (g2 == 2'd3) ? (|entry) : (g2 == 2'd2) ? (|z[29:16]) : 1'b0;
  wire [48:0] sum = {1'b0, t_p} + {1'b0, es};
  wire ovf = ovs | sum[48];
  assign t_c = sum[47:0] | {48{ovf}};
  wire [48:0] D = {1'b0, tmax} - {1'b0, t_c};
  assign empty = D[48];
  wire [47:0] d = D[47:0];
  wire [1:0] c2 = gc[5:4], c1 = gc[3:2], c0 = gc[1:0];
  wire [47:0] Af = d >> {c2, 4'b0};
  wire [28:0] A = Af[28:0];
  wire bA = (c2 == 2'd0) ? |d[47:29] : (c2 == 2'd1) ? |d[47:45] : 1'b0;
  wire sA = (c2 == 2'd0) ? 1'b0 : (c2 == 2'd1) ? |d[15:0] : (c2 == 2'd2) ? |d[31:0] : |d;
  wire [28:0] Bf = A >> {c1, 2'b0};
  wire [16:0] B = Bf[16:0];
  wire bB = (c1 == 2'd0) ? |A[28:17] : (c1 == 2'd1) ? |A[28:21] : (c1 == 2'd2) ? |A[28:25] : 1'b0;
  wire sB = (c1 == 2'd0) ? 1'b0 : (c1 == 2'd1) ? |A[3:0] : (c1 == 2'd2) ? |A[7:0] : |A[11:0];
  wire [16:0] Cf = B >> c0;
  wire [13:0] Dq = Cf[13:0];
  wire bC = (c0 == 2'd0) ? |B[16:14] : (c0 == 2'd1) ? |B[16:15] : (c0 == 2'd2) ? B[16] : 1'b0;
  wire sC = (c0 == 2'd0) ? 1'b0 : (c0 == 2'd1) ? B[0] : (c0 == 2'd2) ? |B[1:0] : |B[2:0];
  wire big = bA | bB | bC;
  wire keep = ~big & ~empty;
  assign far_top = {big & ~empty, 14'b0} | ({1'b0, Dq & {14{keep}}} + {14'b0, (sA | sB | sC) & keep});
endmodule
