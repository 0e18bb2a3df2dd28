// Two products sharing the factor s in one DSP48E1 with 2q + m + 1 = 25 (q = 8, s = m + 1 = 9
// bits): A = {x2, 9'b0, x1} uses the 25-bit port's sign bit as x2's top bit; the signed product
// is then (A - 2^25 x2[7]) * s, corrected by the post-adder adding C = s * 2^25 (a per-node
// constant shift) selected by OPMODE's Z mux when x2[7] is set.
module dsp2_8x9(input [7:0] x1, x2, input [8:0] s, output [16:0] p1, p2);
  wire [47:0] P;
  wire [29:0] A = {{5{x2[7]}}, x2, 9'b0, x1};
  wire [17:0] B = {9'b0, s};
  wire [47:0] C = {14'b0, s, 25'b0};
  wire [6:0] OPMODE = {1'b0, x2[7], x2[7], 2'b01, 2'b01};
  DSP48E1 #(.AREG(0), .ACASCREG(0), .BREG(0), .BCASCREG(0), .CREG(0), .MREG(0), .PREG(0),
            .ADREG(0), .DREG(0), .OPMODEREG(0), .ALUMODEREG(0), .INMODEREG(0), .CARRYINREG(0),
            .CARRYINSELREG(0), .USE_MULT("MULTIPLY"), .USE_DPORT("FALSE"))
    dsp (.A(A), .B(B), .C(C), .D(25'b0), .OPMODE(OPMODE), .ALUMODE(4'b0000), .INMODE(5'b00000),
         .CARRYIN(1'b0), .CARRYINSEL(3'b000), .P(P), .CLK(1'b0),
         .CEA1(1'b0), .CEA2(1'b0), .CEAD(1'b0), .CEALUMODE(1'b0), .CEB1(1'b0), .CEB2(1'b0),
         .CEC(1'b0), .CECARRYIN(1'b0), .CECTRL(1'b0), .CED(1'b0), .CEINMODE(1'b0), .CEM(1'b0), .CEP(1'b0),
         .RSTA(1'b0), .RSTALLCARRYIN(1'b0), .RSTALUMODE(1'b0), .RSTB(1'b0), .RSTC(1'b0), .RSTCTRL(1'b0),
         .RSTD(1'b0), .RSTINMODE(1'b0), .RSTM(1'b0), .RSTP(1'b0), .ACIN(30'b0), .BCIN(18'b0),
         .PCIN(48'b0), .CARRYCASCIN(1'b0), .MULTSIGNIN(1'b0));
  assign p1 = P[16:0];
  assign p2 = P[33:17];
endmodule
