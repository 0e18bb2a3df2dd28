module tb;
  reg [23:0] a, b; wire [47:0] p; integer i, bad;
  mul24h dut(.a(a), .b(b), .p(p));
  initial begin
    bad = 0;
    for (i = 0; i < 200000; i = i + 1) begin
      a = $random; b = $random;
      if (i % 4 == 1) b = 0; if (i % 4 == 2) b[23] = 1; if (i%7==3) a = 24'hffffff; if (i%11==5) b = 24'hffffff;
      #1;
      if (p !== a * b) begin bad = bad + 1; if (bad < 5) $display("BAD %h %h %h %h", a, b, p, a*b); end
    end
    $display("done bad=%0d", bad); $finish;
  end
endmodule
