module tb_dsp2;
  reg [7:0] x1, x2; reg [8:0] s; wire [16:0] p1, p2;
  dsp2_8x9 dut(.x1(x1), .x2(x2), .s(s), .p1(p1), .p2(p2));
  longint errs = 0;
  initial begin
    for (longint i = 0; i < 20000; i++) begin
      if (i < 64) begin x1 = (i&1) ? 8'hff : (i&2) ? 1 : 0; x2 = (i&4) ? 8'hff : (i&8) ? 8'h80 : 0; s = (i&16) ? 9'h1ff : (i&32) ? 1 : 0; end
      else {x1, x2, s} = {$urandom, $urandom};
      #1;
      if (p1 !== x1 * s || p2 !== x2 * s) begin errs++; if (errs < 5) $display("BAD %0d %0d %0d: %0d %0d", x1, x2, s, p1, p2); end
    end
    $display("dsp2_8x9 random: 20000 cases, %0d errors", errs);
    $finish;
  end
endmodule
