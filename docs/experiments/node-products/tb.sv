// usage: iverilog -g2012 -DN=8 -DM=10 -DDUT=hm_8x10 -DW=18 tb.sv hm_8x10.v cells_sim.v
module tb;
  reg [`N-1:0] a; reg [`M-1:0] b; wire [`W-1:0] p;
  `DUT dut(.a(a), .b(b), .p(p));
  longint errs = 0, cases = 0;
  reg [63:0] want;
  initial begin
    if (`N + `M <= 20) begin
      for (longint i = 0; i < (64'd1 << (`N + `M)); i++) begin
        {a, b} = i[`N+`M-1:0]; #1;
        want = a * b;
        if (p !== want[`W-1:0]) begin errs++; if (errs < 5) $display("BAD a=%0d b=%0d p=%0d want=%0d", a, b, p, want); end
        cases++;
      end
      $display("%0dx%0d exhaustive: %0d cases, %0d errors", `N, `M, cases, errs);
    end else begin
      // corners first, then random
      for (longint i = 0; i < 1000000; i++) begin
        if (i < 16) begin a = (i & 1) ? '1 : (i & 2) ? 1 : 0; b = (i & 4) ? '1 : (i & 8) ? 1 : 0; end
        else begin a = $urandom; b = $urandom; end
        #1; want = a * b;
        if (p !== want[`W-1:0]) begin errs++; if (errs < 5) $display("BAD a=%0d b=%0d p=%0d want=%0d", a, b, p, want); end
        cases++;
      end
      $display("%0dx%0d random: %0d cases, %0d errors", `N, `M, cases, errs);
    end
    $finish;
  end
endmodule
