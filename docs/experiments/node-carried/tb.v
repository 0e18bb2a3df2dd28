// tb.v: Icarus check of node_carried_pernode against ref.py's vectors (vin.hex, vout.hex).
// iverilog -g2012 -DNV=<lines> [-DOPT] [-DFAULT] -o sim tb.v carried.v [opt.v hand.v cells_sim.v]
`timescale 1ns/1ps
module tb;
  reg [447:0] vin  [0:`NV-1];
  reg [351:0] vout [0:`NV-1];
  reg [443:0] i;
  wire [95:0] xp_lo, xp_hi; wire [23:0] lo_j; wire [8:0] k; wire [71:0] dsig; wire [2:0] dneg;
  wire [20:0] dsh; wire [14:0] entry; wire [5:0] gp, gc; wire [47:0] t_p, tmax;
  assign {xp_lo, xp_hi, lo_j, k, dsig, dneg, dsh, entry, gp, t_p, tmax, gc} = i;
  wire [95:0] xc_lo, xc_hi; wire [47:0] x_lo, x_hi, t_c; wire [14:0] far_top; wire empty;
  node_carried_pernode dut (.xp_lo(xp_lo), .xp_hi(xp_hi), .lo_j(lo_j), .k(k), .dsig(dsig),
    .dneg(dneg), .dsh(dsh), .entry(entry), .gp_minus_gunit(gp), .t_p(t_p), .tmax_fix(tmax),
    .gc_minus_gunit(gc), .xc_lo(xc_lo), .xc_hi(xc_hi), .x_lo(x_lo), .x_hi(x_hi), .t_c(t_c),
    .far_top(far_top), .empty(empty));
  wire [351:0] got = {xc_lo, xc_hi, x_lo, x_hi, t_c, far_top, empty};
  integer n, err, e_xc, e_x, e_t;
  initial begin
    $readmemh("vin.hex", vin);
    $readmemh("vout.hex", vout);
    err = 0; e_xc = 0; e_x = 0; e_t = 0;
    for (n = 0; n < `NV; n = n + 1) begin
      i = vin[n][443:0];
      #1;
      if (got !== vout[n]) begin
        err = err + 1;
        if (got[351:160] !== vout[n][351:160]) e_xc = e_xc + 1;
        if (got[159:64] !== vout[n][159:64]) e_x = e_x + 1;
        if (got[63:0] !== vout[n][63:0]) e_t = e_t + 1;
        if (err <= 3) $display("MISMATCH %0d\n in  %h\n got %h\n exp %h", n, i, got, vout[n]);
      end
    end
    $display("%0d vectors, %0d mismatches (xc %0d, x_lo/x_hi %0d, time %0d)", `NV, err, e_xc, e_x, e_t);
    $finish;
  end
endmodule
