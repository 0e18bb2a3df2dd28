// Icarus check of child.v against a behavioural reference in 64-bit integers.
// iverilog -g2012 [-DEXACT] [-DF2] [-DFULL -DOWN=<own module>] -DNV=<vectors> -o sim \
//   child.v tb.sv hand.v hm_8x9.v hm_8x10.v dsp2.v cells_sim.v      (child.v first: its macros)
// Checks, per vector: xn/xf and hit/entry of the three own-logic modules (fed the exact
// products) and of the five whole children, bit for bit against the reference in the same
// flavour; in the narrow flavour also conservativeness against the exact sums (W = 20, D = 0):
// an exact hit is a narrow hit and the narrow entry is at most floor(exact t_near / 16).
`ifndef NV
  `define NV 200000
`endif
module tb;
  localparam int W = `W, D = `D;
`ifdef F2
  localparam int F2 = 1;   // far product xf*(s + 1), s1 = s + 1 a per-node input
  `define S1C .s1(s1),
`else
  localparam int F2 = 0;
  `define S1C
`endif
  reg [29:0] s1;
  localparam longint AMAX = (64'sd1 << 19) - (64'sd1 << 17);   // contract on every A (20-bit unit)
  reg [23:0] lo, hi; reg [2:0] neg; reg valid;
  reg [3*W-1:0] an, af; reg [26:0] s; reg [W-1:0] ts, te;
  reg [50:0] pn, pf;
  longint an20[3], af20[3], ts20, te20;
  int si[3], xn[3], xf[3];

  // own-logic modules, fed the products of the reference's integers
  wire [23:0] oxn[3], oxf[3]; wire ohit[3]; wire [15:0] oent[3];
  child_own_plain  o0(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .t_start(ts), .t_end(te),
                      .pn(pn), .pf(pf), .xn(oxn[0]), .xf(oxf[0]), .hit(ohit[0]), .entry(oent[0]));
  child_own_plain4 o1(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .t_start(ts), .t_end(te),
                      .pn(pn), .pf(pf), .xn(oxn[1]), .xf(oxf[1]), .hit(ohit[1]), .entry(oent[1]));
  child_own_hand   o2(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .t_start(ts), .t_end(te),
                      .pn(pn), .pf(pf), .xn(oxn[2]), .xf(oxf[2]), .hit(ohit[2]), .entry(oent[2]));
  // whole children (-DFULL; slow in Icarus: the DSP48E1 model)
  wire chit[5]; wire [15:0] cent[5];
`ifdef FULL
  child_mul   c0(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .s(s), `S1C .t_start(ts), .t_end(te), .hit(chit[0]), .entry(cent[0]));
  child_booth c1(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .s(s), `S1C .t_start(ts), .t_end(te), .hit(chit[1]), .entry(cent[1]));
  child_dsp3  c2(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .s(s), `S1C .t_start(ts), .t_end(te), .hit(chit[2]), .entry(cent[2]));
  child_dsp2  c3(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .s(s), `S1C .t_start(ts), .t_end(te), .hit(chit[3]), .entry(cent[3]));
  child_dsp1  c4(.lo(lo), .hi(hi), .neg(neg), .valid(valid), .an(an), .af(af), .s(s), `S1C .t_start(ts), .t_end(te), .hit(chit[4]), .entry(cent[4]));
  localparam int NC = 5;
`else
  localparam int NC = 0;
`endif

  function automatic longint rnd(longint lo_, longint hi_);   // uniform in [lo_, hi_]
    longint r = {$urandom, $urandom};
    if (r < 0) r = -r;
    return lo_ + r % (hi_ - lo_ + 1);
  endfunction
  function automatic longint fl(longint x, int d); return x >>> d; endfunction      // floor(x / 2^d)
  function automatic longint ce(longint x, int d); return -((-x) >>> d); endfunction // ceil(x / 2^d)
  function automatic longint sx(longint x, int w); return (x << (64 - w)) >>> (64 - w); endfunction

  // reference: t_near, hit in the unit 2^dd of the 20-bit domain, inputs already in that unit
  longint ra_n[3], ra_f[3];   // ref_eval's A inputs (Icarus: no array arguments)
  task automatic ref_eval(input longint t0, t1, input int dd, output longint tn, output bit h);
    longint nr, fr, tf;
    tn = t0; tf = t1;
    for (int i = 0; i < 3; i++) begin
      nr = ra_n[i] + ((xn[i] * si[i]) >> dd);
      fr = ra_f[i] + ((xf[i] * (si[i] + F2)) >> dd);
      if (nr > tn) tn = nr;
      if (fr < tf) tf = fr;
    end
    h = valid && tn <= tf;
  endtask

  longint errs = 0, cons = 0, hits = 0, exact_hits = 0, ties = 0, ovf = 0;
  longint a_n[3], a_f[3], t0, t1, tn, tne, tf20, fr; bit h, he, bad; int mode, l, hh, c, xa, xb; longint tau, jit;
  function automatic longint ext(int k);   // extreme A / t values
    case (k % 8)
      0: return -(64'sd1 << 19); 1: return AMAX; 2: return 0; 3: return -1; 4: return 1;
      5: return -(64'sd1 << 19) + 1; 6: return AMAX - 1; default: return 64'sd1 << 17;
    endcase
  endfunction
  function automatic int sext_(int k);     // extreme slopes
    case (k % 6) 0: return 0; 1: return 1; 2: return 255; 3: return 256; 4: return 510; default: return 511; endcase
  endfunction
  initial begin
    for (longint v = 0; v < `NV; v++) begin
      mode = v < 4096 ? 4 : $urandom % 8;
      valid = ($urandom % 16) != 0;
      tau = rnd(-(64'sd1 << 16), 64'sd1 << 16); jit = ($urandom % 4) ? 512 : 16384;
      for (int i = 0; i < 3; i++) begin
        neg[i] = $urandom % 2;
        case (mode)
          3: begin l = $urandom % 256; hh = $urandom % 256; si[i] = $urandom % 512;
                   an20[i] = rnd(-(64'sd1 << 19), AMAX); af20[i] = rnd(-(64'sd1 << 19), AMAX); end
          4: begin l = ($urandom % 2) ? 255 : ($urandom % 3); hh = ($urandom % 2) ? 255 : ($urandom % 3);
                   si[i] = sext_($urandom % 6); an20[i] = ext($urandom % 8); af20[i] = ext($urandom % 8); end
          5: begin l = $urandom % 4; hh = l + $urandom % 4; si[i] = sext_($urandom % 6);
                   an20[i] = rnd(-200, 200); af20[i] = an20[i] + rnd(0, 40); end
          default: begin   // aimed: the ray at time tau in cell c of this axis, jittered
                   c = $urandom % 256; xa = c - rnd(0, c); xb = c + rnd(0, 255 - c);
                   if (neg[i]) begin l = 255 - xb; hh = 255 - xa; end else begin l = xa; hh = xb; end
                   si[i] = ($urandom % 4) ? 256 + $urandom % 256 : $urandom % 512;
                   an20[i] = tau - c * si[i] + rnd(-jit, jit); af20[i] = an20[i] + rnd(0, 300);
                   if (an20[i] < -(64'sd1 << 19)) an20[i] = -(64'sd1 << 19);
                   if (af20[i] > AMAX) af20[i] = AMAX; end
        endcase
        lo[8*i+:8] = l; hi[8*i+:8] = hh;
        xn[i] = neg[i] ? 255 - hh : l; xf[i] = neg[i] ? 255 - l : hh;
        s[9*i+:9] = si[i]; s1[10*i+:10] = si[i] + 1;
      end
      case (mode)
        3: begin ts20 = rnd(-(64'sd1 << 19), (64'sd1 << 19) - 1); te20 = rnd(-(64'sd1 << 19), (64'sd1 << 19) - 1); end
        4: begin ts20 = ext($urandom % 8); te20 = ($urandom % 2) ? (64'sd1 << 19) - 1 : ext($urandom % 8); end
        5: begin ts20 = rnd(-300, 300); te20 = ts20 + rnd(-50, 2000); end
        default: begin ts20 = ($urandom % 4) ? tau - rnd(0, 64'sd1 << 16) : -(64'sd1 << 19);
                       te20 = ($urandom % 4) ? tau + rnd(-4096, 64'sd1 << 17) : (64'sd1 << 19) - 1; end
      endcase
      // exact t_near / t_far in the 20-bit domain; tie modes put t_end or t_start on them
      for (int i = 0; i < 3; i++) begin ra_n[i] = an20[i]; ra_f[i] = af20[i]; end
      ref_eval(ts20, te20, 0, tne, he);
      if (mode >= 6) begin
        tf20 = te20;
        for (int i = 0; i < 3; i++) begin fr = af20[i] + xf[i] * (si[i] + F2); if (fr < tf20) tf20 = fr; end
        if (mode == 6) te20 = tne + rnd(-20, 20); else ts20 = tf20 + rnd(-20, 20);
        if (te20 > (64'sd1 << 19) - 1) te20 = (64'sd1 << 19) - 1;
        if (te20 < -(64'sd1 << 19)) te20 = -(64'sd1 << 19);
        if (ts20 > (64'sd1 << 19) - 1) ts20 = (64'sd1 << 19) - 1;
        if (ts20 < -(64'sd1 << 19)) ts20 = -(64'sd1 << 19);
        ref_eval(ts20, te20, 0, tne, he);
      end
      // the DUT's inputs in its own unit 2^D
      for (int i = 0; i < 3; i++) begin
        a_n[i] = fl(an20[i], D); a_f[i] = ce(af20[i], D);
        an[W*i+:W] = a_n[i]; af[W*i+:W] = a_f[i];
        pn[17*i+:17] = xn[i] * si[i]; pf[17*i+:17] = xf[i] * (si[i] + F2);
      end
      t0 = fl(ts20, D); t1 = fl(te20, D); ts = t0; te = t1;
      for (int i = 0; i < 3; i++) begin ra_n[i] = a_n[i]; ra_f[i] = a_f[i]; end
      ref_eval(t0, t1, D, tn, h);
      // contract: every sum fits W bits
      for (int i = 0; i < 3; i++)
        if (a_n[i] + ((xn[i] * si[i]) >> D) >= (64'sd1 << (W - 1)) || a_f[i] + ((xf[i] * (si[i] + F2)) >> D) >= (64'sd1 << (W - 1))) ovf++;
      #1;
      hits += h; exact_hits += he;
      if (tn == t1) ties++;
      for (int k = 0; k < 3; k++) begin
        bad = ohit[k] !== h || (h && oent[k] !== 16'(tn >>> (W - 16)));
        for (int i = 0; i < 3; i++) bad |= oxn[k][8*i+:8] !== 8'(xn[i]) || oxf[k][8*i+:8] !== 8'(xf[i]);
        if (bad) begin errs++; if (errs < 10) $display("BAD own%0d mode %0d: hit %b/%b entry %h/%h", k, mode, ohit[k], h, oent[k], 16'(tn >>> (W - 16))); end
      end
      for (int k = 0; k < NC; k++)
        if (chit[k] !== h || (h && cent[k] !== 16'(tn >>> (W - 16)))) begin
          errs++; if (errs < 10) $display("BAD child%0d mode %0d: hit %b/%b entry %h/%h", k, mode, chit[k], h, cent[k], 16'(tn >>> (W - 16)));
        end
      // conservative against the exact sums: an exact hit is a hit, entry a lower bound
      if (he && (!h || sx(tn >>> (W - 16), 16) > fl(tne, 4))) begin
        cons++; if (cons < 10) $display("NOT CONSERVATIVE mode %0d: exact t_near %0d, narrow hit %b entry %0d", mode, tne, h, tn);
      end
    end
    $display("W=%0d D=%0d: %0d vectors, %0d hits (exact %0d), %0d t_near == t_end, %0d contract overflows, %0d mismatches, %0d not conservative",
             W, D, `NV, hits, exact_hits, ties, ovf, errs, cons);
    $finish;
  end
endmodule
