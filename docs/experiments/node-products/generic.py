#!/usr/bin/env python3
# generic Verilog for Yosys's own mapping
shapes = [(8,8),(8,10),(9,10),(16,10),(16,24),(8,9),(8,7)]
with open("generic.v","w") as f:
    for n,m in shapes:
        f.write(f"module g_{n}x{m}(input [{n-1}:0] a, input [{m-1}:0] b, output [{n+m-1}:0] p);\n  assign p = a * b;\nendmodule\n")
    # two products sharing the factor s (q = 8, m+1 = 8, 10)
    for q,s in [(8,8),(8,10)]:
        f.write(f"module pair_{q}x{s}(input [{q-1}:0] x1, x2, input [{s-1}:0] s, output [{q+s-1}:0] p1, p2);\n  assign p1 = x1 * s;\n  assign p2 = x2 * s;\nendmodule\n")
        # packed for one DSP48E1: {x2, gap, x1} * s
        k = q + s
        f.write(f"module packed_{q}x{s}(input [{q-1}:0] x1, x2, input [{s-1}:0] s, output [{q+s-1}:0] p1, p2);\n"
                f"  wire [{k+q+s-1}:0] p = {{x2, {k-q}'b0, x1}} * s;\n  assign p1 = p[{k-1}:0];\n  assign p2 = p[{k+q+s-1}:{k}];\nendmodule\n")
    # 2q + s = 25: unsigned 25 bits in the signed 25-bit port
    f.write("module packed_8x9(input [7:0] x1, x2, input [8:0] s, output [16:0] p1, p2);\n"
            "  wire [33:0] p = {x2, 9'b0, x1} * s;\n  assign p1 = p[16:0];\n  assign p2 = p[33:17];\nendmodule\n")
