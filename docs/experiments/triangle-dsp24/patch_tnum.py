import re, sys
# conservative Mitchell-log segment test (k = 8 fraction bits), replacing the exact one
src, dst = sys.argv[1], sys.argv[2]
opts = dict(a.split("=", 1) if "=" in a else (a, "1") for a in sys.argv[3:])
t = open(src).read()
rests = opts.get("rests", "").split(",") if opts.get("rests") else []
pat = re.compile(r"assign (\w+_product) = (\w+) \*\s*(\w+);")
cnt = [0]
def rep(m):
    x, a, b = m.groups()
    if any(r and r in x for r in rests):
        cnt[0] += 1
        return f"mul24h u_hm_{x} (.a({a}), .b({b}), .p({x}));"
    return m.group(0)
if "zero" in opts:
    zc = 0
    for m in pat.finditer(t):
        x, a, b = m.groups()
        if a.startswith("24'h") or b.startswith("24'h"): continue
        pre = x[:-len("_u_mul_product")] if x.endswith("_u_mul_product") else None
        if pre is None: continue
        p2 = re.compile(r"assign " + pre + r"_u_round_sig_zero = ~\(\|" + x + r"\);")
        if p2.search(t):
            t = p2.sub(f"assign {pre}_u_round_sig_zero = ~({a}[23] & {b}[23]);", t); zc += 1
    print("sig_zero from hidden bits:", zc)
t = pat.sub(rep, t)
def setexpr(name, val):
    global t
    p = re.compile(r"assign " + name + r" = [^;]*;", re.S)
    assert len(p.findall(t)) == 1, name
    t = p.sub(f"assign {name} = {val};", t)
K = int(opts.get('k', 8))
C = {8: 47, 4: 5, 6: 14}[K]
if "sin" in opts:
    for ax in "xyz":
        setexpr(f"u_widen_s_{ax}_u_round_result", f"{{s_{ax}[31], 3'b000, s_{ax}[30:0]}}")
if "nosz" in opts:
    setexpr("u_t_num_u_round_result", "u_t_weighted_u_round_result")
    W, SZ = "u_t_weighted_u_round_result", "u_widen_s_z_u_round_result_s7"
    lt = f"({{2'b0, {W}[33:{23-K}]}} + {{2'b0, {SZ}[33:{23-K}]}} - 21'd{1023 << K})"
    st = f"({W}[34] ^ {SZ}[34])"
    zt = f"(~(|{W}[33:23]))"
else:
    T = "u_t_num_u_round_result"
    lt = f"{{2'b0, {T}[33:{23-K}]}}"
    st = f"{T}[34]"
    zt = f"(~(|{T}[33:23]))"
D, L, H = "u_det_u_round_result", "t_min", "t_max"
decl = f"""
    // raw binary32 bounds: a subnormal bound replaced outward (t_max up to 2^-126 or to 0,
    // t_min down to 0 or to -2^-126): conservative
    wire seg_dH = ~(|{H}[30:23]), seg_dL = ~(|{L}[30:23]);
    wire [{7+K}:0] seg_lH = seg_dH ? {8+K}'d{1 << K} : {H}[30:{23-K}];
    wire [{7+K}:0] seg_lL = seg_dL ? {8+K}'d{1 << K} : {L}[30:{23-K}];
    wire seg_sH = {H}[31], seg_zH = seg_dH & ((~(|{H}[22:0])) | {H}[31]);
    wire seg_sL = {L}[31], seg_zL = seg_dL & ((~(|{L}[22:0])) | ~{L}[31]);
    wire [20:0] seg_q = {lt} - {{2'b0, {D}[33:{23-K}]}} ;
    wire [20:0] seg_rH = seg_q + 21'd{127 << K} - {{{13-K}'b0, seg_lH}};
    wire [20:0] seg_rL = seg_q + 21'd{127 << K} - {{{13-K}'b0, seg_lL}};
    wire seg_sT = {st} ^ {D}[34];
    wire seg_zT = {zt};
    wire seg_gtH = $signed(seg_rH) > $signed(21'd{C});
    wire seg_ltH = $signed(seg_rH) < -$signed(21'd{C});
    wire seg_gtL = $signed(seg_rL) > $signed(21'd{C});
    wire seg_ltL = $signed(seg_rL) < -$signed(21'd{C});
    wire seg_before_max = seg_zT ? (~seg_sH | seg_zH) : seg_zH ? seg_sT :
        (~seg_sT & ~seg_sH) ? ~seg_gtH : (seg_sT & seg_sH) ? ~seg_ltH : seg_sT;
    wire seg_after_min = seg_zT ? (seg_sL | seg_zL) : seg_zL ? ~seg_sT :
        (~seg_sT & ~seg_sL) ? ~seg_ltL : (seg_sT & seg_sL) ? ~seg_gtL : ~seg_sT;
    wire seg_iH = &{H}[30:23], seg_iL = &{L}[30:23];
    wire seg_bm = seg_iH ? ~seg_sH : seg_before_max;
    wire seg_am = seg_iL ? seg_sL : seg_after_min;
    wire seg_far = ~seg_zT & ($signed(seg_q) >= $signed(21'd{(128 << K) - C}));
"""
setexpr("t_from_min_mux_neg_lt_key", "seg_am")
setexpr("t_to_max_mux_neg_lt_key", "seg_bm")
setexpr("t_beyond_format", "seg_far")
i = t.index("    assign and_not_invalid_input_inside_edges")
t = t[:i] + decl + t[i:]
open(dst, "w").write(t + open(opts.get("mul", "mul24h.v")).read())
print(cnt[0], "hand-mapped", opts)
