// carried.v: the per-node part of "carried positions" (docs/node.md §12), plain Verilog,
// combinational. g = 4, F = 16, q = 8, K = q + 6 = 14. See README.md for the function.
//
//   carried_axis          one axis: P = entry*dsig (one DSP48E1), V = P*2^dsh floored/ceiled and
//                         saturated at 2^VSAT, negated for dneg, xc = ((xp - lo_j<<20) << k) + V
//                         clamped to signed 32 bit, x_lo = floor(xc_lo/2^16), x_hi = ceil(xc_hi/2^16)
//   carried_time          t_c = t_p + (entry << gp) (saturated at 2^48 - 1),
//                         far_top = min(2^14, ceil((tmax - t_c)/2^gc)), empty = tmax < t_c
//   node_carried_pernode  three axes + time
//
// Contract (the testbench drives only this): dsh in -48..15, dsig 0 or in [2^23, 2^24) (the
// plain modules are exact for any dsig; carried_axis_opt uses the leading one, see there).
// -DFAULT plants a fault (x_hi floored instead of ceiled) for the negative control.
// -DOPT / -DHAND / -DHAND39 (with -DVSAT=39) select opt.v's / hand.v's modules in node_carried_pernode.
// -DVSAT=39 saturates V at 2^39 instead of 2^33 (see README: soundness of the 2^33 threshold).
`ifndef VSAT
`define VSAT 33
`endif

module carried_axis #(parameter VSAT = `VSAT) (
  input  [14:0] entry,
  input  [31:0] xp_lo, xp_hi,     // signed, units 2^-20 parent steps
  input  [7:0]  lo_j,
  input  [2:0]  k,
  input  [23:0] dsig,
  input         dneg,
  input  [6:0]  dsh,              // signed
  output [31:0] xc_lo, xc_hi,     // signed, units 2^-20 of this node's steps
  output [15:0] x_lo, x_hi);      // signed, units 2^-4 of this node's steps

  // 1. the product, exact
  wire [38:0] P = entry * dsig;
  // 2. V = P*2^dsh: P*2^15 shifted right by r = 15 - dsh (0..63); floor, ceiling, saturation
  wire [5:0]  r  = 6'd15 - dsh[5:0];
  wire [53:0] W  = {P, 15'b0};
  wire [53:0] Vs = W >> r;
  wire [53:0] lowmask = ~({54{1'b1}} << r);
  wire        sticky = |(W & lowmask);
  wire        vsat = |Vs[53:VSAT];
  wire [VSAT:0] Vf = vsat ? ({{VSAT{1'b0}}, 1'b1} << VSAT) : {1'b0, Vs[VSAT-1:0]};
  wire [VSAT:0] Vc = vsat ? ({{VSAT{1'b0}}, 1'b1} << VSAT) : {1'b0, Vs[VSAT-1:0]} + sticky;
  localparam VW = VSAT + 2;
  wire signed [VW-1:0] Vfs = $signed({1'b0, Vf});
  wire signed [VW-1:0] Vcs = $signed({1'b0, Vc});
  wire signed [VW-1:0] Vlo = dneg ? -Vcs : Vfs;
  wire signed [VW-1:0] Vhi = dneg ? -Vfs : Vcs;
  // 3. into this node's frame, clamped to signed 32 bit
  wire signed [32:0] Lo  = $signed({5'b0, lo_j, 20'b0});
  wire signed [32:0] Dlo = $signed(xp_lo) - Lo;
  wire signed [32:0] Dhi = $signed(xp_hi) - Lo;
  wire signed [39:0] Dlok = Dlo <<< k;
  wire signed [39:0] Dhik = Dhi <<< k;
  localparam SW = (VW > 40 ? VW : 40) + 1;
  wire signed [SW-1:0] Slo = Dlok + Vlo;
  wire signed [SW-1:0] Shi = Dhik + Vhi;
  function [31:0] clamp32(input [SW-1:0] s);
    if (s[SW-1] == 1'b0 && |s[SW-2:31]) clamp32 = 32'h7fffffff;
    else if (s[SW-1] == 1'b1 && ~&s[SW-2:31]) clamp32 = 32'h80000000;
    else clamp32 = s[31:0];
  endfunction
  assign xc_lo = clamp32(Slo);
  assign xc_hi = clamp32(Shi);
  // 4. grid values
  assign x_lo = xc_lo[31:16];
`ifdef FAULT
  assign x_hi = xc_hi[31:16];
`else
  wire [16:0] xh = {xc_hi[31], xc_hi[31:16]} + {16'b0, |xc_hi[15:0]};
  assign x_hi = (xh[16] != xh[15]) ? 16'h7fff : xh[15:0];
`endif
endmodule

module carried_time (
  input  [14:0] entry,
  input  [5:0]  gp,               // gp_minus_gunit
  input  [47:0] t_p, tmax,
  input  [5:0]  gc,               // gc_minus_gunit
  output [47:0] t_c,
  output [14:0] far_top,
  output        empty);
  wire [77:0] es  = {63'b0, entry} << gp;
  wire [48:0] sum = {1'b0, t_p} + {1'b0, es[47:0]};
  wire        ovf = (|es[77:48]) | sum[48];
  assign t_c = ovf ? {48{1'b1}} : sum[47:0];
  wire [48:0] D  = {1'b0, tmax} - {1'b0, t_c};
  assign empty = D[48];
  wire [47:0] Dq = D[47:0] >> gc;
  wire [47:0] m  = ~({48{1'b1}} << gc);
  wire        st = |(D[47:0] & m);
  wire        big = |Dq[47:14];
  assign far_top = empty ? 15'd0 : big ? 15'h4000 : {1'b0, Dq[13:0]} + {14'b0, st};
endmodule

module node_carried_pernode (
  input  [95:0] xp_lo, xp_hi,     // axis a at [32a+31:32a]
  input  [23:0] lo_j,
  input  [8:0]  k,
  input  [71:0] dsig,
  input  [2:0]  dneg,
  input  [20:0] dsh,
  input  [14:0] entry,
  input  [5:0]  gp_minus_gunit,
  input  [47:0] t_p, tmax_fix,
  input  [5:0]  gc_minus_gunit,
  output [95:0] xc_lo, xc_hi,
  output [47:0] x_lo, x_hi,
  output [47:0] t_c,
  output [14:0] far_top,
  output        empty);
`ifdef HAND39
`define AXIS_MOD carried_axis_hand39
`define TIME_MOD carried_time_hand
`elsif HAND
`define AXIS_MOD carried_axis_hand
`define TIME_MOD carried_time_hand
`elsif OPT
`define AXIS_MOD carried_axis_opt
`define TIME_MOD carried_time_opt
`else
`define AXIS_MOD carried_axis
`define TIME_MOD carried_time
`endif
  genvar a;
  generate for (a = 0; a < 3; a = a + 1) begin : ax
    `AXIS_MOD u (
      .entry(entry), .xp_lo(xp_lo[32*a+31:32*a]), .xp_hi(xp_hi[32*a+31:32*a]),
      .lo_j(lo_j[8*a+7:8*a]), .k(k[3*a+2:3*a]), .dsig(dsig[24*a+23:24*a]), .dneg(dneg[a]),
      .dsh(dsh[7*a+6:7*a]), .xc_lo(xc_lo[32*a+31:32*a]), .xc_hi(xc_hi[32*a+31:32*a]),
      .x_lo(x_lo[16*a+15:16*a]), .x_hi(x_hi[16*a+15:16*a]));
  end endgenerate
  `TIME_MOD ut (
    .entry(entry), .gp(gp_minus_gunit), .t_p(t_p), .tmax(tmax_fix),
    .gc(gc_minus_gunit), .t_c(t_c), .far_top(far_top), .empty(empty));
endmodule

// the product alone (for the iCE40 figures, where it is built from LUTs)
module carried_prod (input [14:0] entry, input [23:0] dsig, output [38:0] p);
  assign p = entry * dsig;
endmodule
