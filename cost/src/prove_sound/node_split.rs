//! `--split` for the node tester (docs/proofs.md, "Splitting the proof";
//! docs/node.md §12): the unit cut at its per-node terms, the ones every
//! child reads. Per axis the position bounds `from_lo`, `from_hi` (the
//! ray's position at the start `T` in `2^−g` frame steps, floored and ceiled
//! onto the grid, clamped, mirrored `Q·2^g − x` for a negative direction),
//! the slopes (cells per `2^−g` step rounded down and up: `sig_down`,
//! `sig_up_used`, each shifted by `shift` and flagged `over_cap` above the
//! cap) and, once per node, the window end `far_top`. With `g` the position
//! bits, `h` the cell bits, `m` the slope bits, `kmin = h − m + 1 − g`, a
//! slope is `S = sig·2^(shift + kmin)` cells per `2^−g` step; `u = 2^G` the
//! cell (`G` the output `grid_exp`), `T_r` the output `t_base`, `C = 2^K`
//! the cap, `L = 2^(q+3+g)` the clamp, `live` = neither every valid slot
//! reported (`every_valid_slot`: bad input, no start) nor the segment
//! empty (`empty_segment_empty`).
//!
//! Lemmas on the unit as instantiated (the per-node terms watched), each
//! its own `sat` call under the wrapper's contract:
//!
//! * **start**: when live, `t_base` is finite and `T_r ≤ max(t_min, t_start)`;
//! * **empty**: the unit's `empty` (unless every slot is reported) only for
//!   `t_min = +∞`, `t_start = +∞`, `t_max = −∞` or `t_max < max(t_min, t_start)`;
//! * **window_end**: when live, `0 ≤ far_top ≤ C` and `far_top = C` or
//!   `t_max` finite with `far_top·u ≥ t_max − T_r`;
//! * **position_a** (a = x, y, z): when live, with `P = (o − O + T_r·d)·2^(g − e)`
//!   the exact position in `2^−g` steps (`T_r·d` exact) and `P' = P`, or
//!   `Q·2^g − P` when mirrored: a slab axis has `d ≠ 0`, `mirror` the sign of
//!   `d`, `from_lo ≤ P'` or `from_lo ≤ Q·2^g − L` (clamped), `from_hi ≥ P'`
//!   or `from_hi ≥ Q·2^g`; a parallel axis `d = 0`, no mirror, `from_hi ≥
//!   Q·2^g` or `from_hi > P − 1`, `from_lo ≤ 0` or `from_lo < P + 1`;
//! * **slope_a**: when live, on a slab axis, with `A = |inv_d|·2^(e − g − G)`
//!   and `B = next(|inv_d|)·2^(e − g − G)` (`next` the successor; at the
//!   largest finite `inv_d`, `2^(bias + F − 1)`, the reciprocal of the
//!   smallest subnormal): `S_lo ≤ A` and `shift_lo ≤ zmax` unless
//!   `over_lo`, then `A > C`; unless `over_hi`, `S_hi ≥ B`, `S_hi ≥ 2^(h−g)`,
//!   `shift_hi ≤ zmax` and `sig_hi ≥ 2^(m−1)`;
//! * **child_i** (per slot, on the cut design: the per-node terms driven by
//!   free values): if slot i is valid and every valid slot is reported, or
//!   the segment is not empty, the per-node terms satisfy the lemmas'
//!   internal parts (`0 ≤ far_top ≤ C`, the shifts and `sig_hi` above) and
//!   `meet_i` holds, the slot is reported hit, and its entry is 0 or, live,
//!   for some slab axis with `dn > 0`, at most `C` (`over_lo`) or at most
//!   `dn·S_lo`. With `dn_a = entry_a·2^g − from_hi_a`, `df_a = exit_a·2^g −
//!   from_lo_a` (the child's entry and exit planes in the mirrored frame),
//!   `meet_i` is: `df_a ≥ 0` on every axis and `dn_a ≤ 0` on a parallel
//!   one; for slab axes a, b: `dn_a ≤ 0`, or `df_b > 0` with `over_hi_b` or
//!   `df_b·S_hi_b ≥ C`, or neither flag with `dn_a·S_lo_a ≤ df_b·S_hi_b`;
//!   and `dn_a ≤ 0`, `far_top = C` or `dn_a·S_lo_a ≤ far_top` without `over_lo_a`.
//!
//! Why they imply the property. Take a valid slot the segment meets
//! (exactly): some real `t*` with `max(t_min, t_start) ≤ t* ≤ t_max` puts
//! the ray in the child's box. If every valid slot is reported, child_i
//! gives the hit at entry 0. Else, by empty, the segment is not empty, so
//! live, and by start `T_r ≤ t*`; let `τ = (t* − T_r)/u ≥ 0`, and per slab
//! axis `R = 2^(e−g)/(|d|·u)` (cells per `2^−g` step): the contract `|inv_d|
//! ≤ 1/|d| < next(|inv_d|)` (`1/|d| ≤ 2^(bias+F−1)` at the largest `inv_d`)
//! gives `A ≤ R < B`. Along the axis the mirrored position at `t` is `P' +
//! (t − T_r)·u/R`, so the box gives `entry·2^g − P' ≤ τ/R` where... (with
//! `t_enter`, `t_exit` the axis's exact entry and exit parameters)
//! `(t_enter − T_r)/u = (entry·2^g − P')·R ≤ τ ≤ (exit·2^g − P')·R =
//! (t_exit − T_r)/u`. Now `dn_a > 0` puts `from_hi_a` below `Q·2^g`, so
//! `from_hi_a ≥ P'_a` (position) and `dn_a ≤ entry·2^g − P'_a`: `τ ≥
//! dn_a·R_a > 0`, above `dn_a·S_lo_a` (`S_lo ≤ A ≤ R`) or above `C` (`over_lo`:
//! `R ≥ A > C`, `dn_a ≥ 1`). On axis b, `from_lo_b ≤ P'_b` gives `df_b ≥
//! (exit·2^g − P'_b) ≥ τ/R_b ≥ 0` and, unless `over_hi_b`, `df_b·S_hi_b ≥
//! df_b·R_b ≥ τ`; a clamped `from_lo_b ≤ Q·2^g − L` gives `df_b ≥ L − Q·2^g`
//! and `df_b·S_hi_b ≥ (L − Q·2^g)·2^(h−g) > C`. So each pair holds (and `df ≥
//! 0`); the window end holds by window_end (`τ ≤ (t_max − T_r)/u`; with
//! `over_lo_a`, `τ > C`, so `far_top = C`). A parallel axis: `d = 0` and the
//! box gives `lo·2^g ≤ P ≤ hi·2^g`, integers, so `from_hi ≥ lo·2^g` and
//! `from_lo ≤ hi·2^g` by position. So `meet_i` and the internal parts hold,
//! child_i gives the hit, and its entry: 0, or for a slab axis with `dn > 0`
//! at most `dn·S_lo ≤ dn·R ≤ (t_enter − T_r)/u` (or at most `C < R ≤
//! (t_enter − T_r)/u`), so `T_r + entry·u ≤ t_enter`, the reference's
//! `entry_ok`. The extra cover: a hit of slot 0 where `meet_0` holds on the
//! unit's own terms.

use super::split::{extended_real, Cut};
use super::{magnitude_bits, AXES};
use golden_model::float::FloatFormat;
use rtl_gen::units::node::{CELL_BITS, POS_FRAC};
use std::fmt::Write as _;

/// The node's shape, as the split reads it.
#[derive(Debug, Clone, Copy)]
pub(super) struct NodeShape {
    pub fmt: FloatFormat,
    pub q: u32,
    pub m: u32,
    pub children: usize,
}

impl NodeShape {
    fn zmax(&self) -> u32 {
        self.q + 2 + POS_FRAC
    }
    fn zbits(&self) -> u32 {
        32 - self.zmax().leading_zeros()
    }
    fn cap_bits(&self) -> u32 {
        self.q + CELL_BITS + 2
    }
    /// width of `from_lo`, `from_hi` (SInt): `q + g + 6`
    fn xw(&self) -> u32 {
        self.q + POS_FRAC + 6
    }
    fn kmin(&self) -> i32 {
        CELL_BITS as i32 - self.m as i32 + 1 - POS_FRAC as i32
    }
    /// the grid exponent's range `2·emin − F − h ..= 2·emax − h`
    fn grid_range(&self) -> (i32, i32) {
        let (f, h) = (self.fmt.frac_bits() as i32, CELL_BITS as i32);
        (2 * self.fmt.emin() - f - h, 2 * self.fmt.emax() - h)
    }
}

/// The node's cut: the per-node terms (flattened names in `u_unit`), the
/// flags the lemmas read on both designs, the lemmas (module doc).
pub(super) fn node_cut(children: usize) -> Cut {
    let mut wires = Vec::new();
    let mut watched = Vec::new();
    for a in AXES {
        for (monitor, unit) in [
            ("from_lo", format!("axis_{a}_plane_frame_from_lo")),
            ("from_hi", format!("axis_{a}_plane_frame_from_hi")),
            ("sig_down", format!("axis_{a}_slope_sig_down")),
            ("shift_down", format!("slope_{a}_down_shift")),
            ("over_down", format!("slope_{a}_down_over_cap")),
            ("sig_up", format!("slope_{a}_sig_up_used")),
            ("shift_up", format!("slope_{a}_up_shift")),
            ("over_up", format!("slope_{a}_up_over_cap")),
        ] {
            wires.push((format!("node_{monitor}_{a}"), format!("u_unit.{unit}")));
        }
        watched.push((
            format!("node_parallel_{a}"),
            format!("u_unit.axis_{a}_parallel"),
        ));
        watched.push((
            format!("node_mirror_{a}"),
            format!("u_unit.axis_{a}_mirror"),
        ));
    }
    wires.push(("node_far_top".into(), "u_unit.window_end_far_top".into()));
    watched.push(("node_all_in".into(), "u_unit.every_valid_slot".into()));
    watched.push(("node_empty".into(), "u_unit.empty_segment_empty".into()));
    let lemmas: Vec<String> = ["lemma_start", "lemma_empty", "lemma_window_end"]
        .iter()
        .map(|s| s.to_string())
        .chain(AXES.iter().map(|a| format!("lemma_position_{a}")))
        .chain(AXES.iter().map(|a| format!("lemma_slope_{a}")))
        .chain((0..children).map(|i| format!("lemma_child{i}")))
        .collect();
    Cut {
        wires,
        lemmas,
        combination: children,
        watched_after_cut: Vec::new(),
        watched,
        cover: "-set child0_exact_hit 1 -set lemma_meet0 1".into(),
        raw: true,
    }
}

/// The node wrapper's part for the lemmas (inside `node_wrapper`, after the
/// contract's decode functions and `inv_d_<a>_next`; module doc).
pub(super) fn node_wrapper_part(s: NodeShape) -> String {
    let fmt = s.fmt;
    let (w, q, m) = (fmt.width(), s.q, s.m);
    let (g, h) = (POS_FRAC, CELL_BITS);
    let s1 = fmt.bias() + fmt.frac_bits() as i32 - 1;
    let u2 = 2 * s1;
    let k = s.cap_bits();
    let cap = 1u64 << k;
    let xw = s.xw();
    let zmax = s.zmax();
    let zb = s.zbits();
    let nw = magnitude_bits(fmt) + 1;
    let qg = ((1i64 << q) - 1) << g;
    let clamp = 1i64 << (q + 3 + g);
    let (gmin, gmax) = s.grid_range();
    let (emin, emax) = (fmt.emin(), fmt.emax());
    let mut v = String::from(
        "    // --split (node): the unit's per-node terms, driven by the proof script (prove.ys)\n",
    );
    for a in AXES {
        let _ = writeln!(
            v,
            "    (* keep *) wire signed [{x1}:0] node_from_lo_{a}, node_from_hi_{a};\n    \
             (* keep *) wire [{m1}:0] node_sig_down_{a};\n    (* keep *) wire [{m}:0] node_sig_up_{a};\n    \
             (* keep *) wire [{z1}:0] node_shift_down_{a}, node_shift_up_{a};\n    \
             (* keep *) wire node_over_down_{a}, node_over_up_{a}, node_parallel_{a}, node_mirror_{a};",
            x1 = xw - 1,
            m1 = m - 1,
            z1 = zb - 1,
        );
    }
    let _ = writeln!(
        v,
        "    (* keep *) wire signed [{f1}:0] node_far_top;\n    (* keep *) wire node_all_in, node_empty;\n    \
         wire node_live = !node_all_in && !node_empty;",
        f1 = k + 1
    );
    for x in ["unit_t_base", "t_min", "t_start", "t_max"] {
        v.push_str(&extended_real(fmt, x));
    }
    // start and empty
    let _ = writeln!(
        v,
        "    (* keep *) wire lemma_start = !node_live || (!unit_t_base_up && !unit_t_base_down && !unit_t_base_nan\n        \
         && (unit_t_base_key <= t_min_key || unit_t_base_key <= t_start_key));\n    \
         (* keep *) wire lemma_empty = !node_empty || node_all_in || t_min_up || t_start_up || t_max_down\n        \
         || t_max_key < t_min_key || t_max_key < t_start_key;"
    );
    // the window end: far_top·2^G ≥ t_max − T_r, scaled by 2^(s1 + lg) to integers
    let lg = (-(gmin + s1)).max(0);
    let ft_top = gmax + s1 + lg;
    let ew = ((k + 3) as i32 + ft_top).max(nw as i32 + 2 + lg) as u32 + 2;
    let _ = writeln!(
        v,
        "    // the window end in units of 2^−{sc}\n    \
         wire signed [7:0] ft_shift = $signed(unit_grid_exp) + 8'sd{sh};\n    \
         wire signed [{e1}:0] ft_wide = node_far_top;\n    \
         wire signed [{e1}:0] tmax_wide = value(t_max);\n    \
         wire signed [{e1}:0] tbase_wide = value(unit_t_base);\n    \
         wire signed [{e1}:0] ft_scaled = ft_wide <<< ft_shift;\n    \
         wire signed [{e1}:0] span_scaled = (tmax_wide - tbase_wide) <<< {lg};\n    \
         (* keep *) wire lemma_window_end = !node_live || (node_far_top >= 0 && node_far_top <= {f2}'sd{cap}\n        \
         && (node_far_top == {f2}'sd{cap} || (!t_max_up && ft_scaled >= span_scaled)));",
        sc = s1 + lg,
        sh = s1 + lg,
        e1 = ew - 1,
        f2 = k + 2,
    );
    // positions, in units of 2^−U (U = 2·s1): x·2^(e − g + U) against o − O + T_r·d
    let sh_max = emax - g as i32 + u2;
    let pw = [
        xw as i32 + sh_max + 2,
        2 * nw as i32 + 2,
        q as i32 + emax + u2 + g as i32 + 2,
        nw as i32 + s1 + 2,
    ]
    .into_iter()
    .max()
    .unwrap() as u32
        + 2;
    for a in AXES {
        let _ = writeln!(
            v,
            "    // position {a}: x·2^(e − g + {u2}) against (o − O + T_r·d)·2^{u2}\n    \
             wire signed [7:0] pos_shift_{a} = $signed(frame_exp_{a}) + 8'sd{psh};\n    \
             wire signed [{p1}:0] pos_o_{a} = value(o_{a});\n    \
             wire signed [{p1}:0] pos_origin_{a} = value(frame_origin_{a});\n    \
             wire signed [{p1}:0] pos_d_{a} = value(d_{a});\n    \
             wire signed [{p1}:0] pos_t_{a} = value(unit_t_base);\n    \
             wire signed [{p1}:0] pos_v_{a} = ((pos_o_{a} - pos_origin_{a}) <<< {s1}) + pos_t_{a} * pos_d_{a};\n    \
             wire signed [{p1}:0] pos_q_{a} = {pw}'sd{qg} <<< pos_shift_{a};\n    \
             wire signed [{p1}:0] pos_m_{a} = node_mirror_{a} ? pos_q_{a} - pos_v_{a} : pos_v_{a};\n    \
             wire signed [{p1}:0] pos_lo_{a} = node_from_lo_{a};\n    \
             wire signed [{p1}:0] pos_hi_{a} = node_from_hi_{a};\n    \
             wire slab_ok_{a} = pos_d_{a} != 0 && node_mirror_{a} == d_{a}[{w1}]\n        \
             && ((pos_lo_{a} <<< pos_shift_{a}) <= pos_m_{a} || node_from_lo_{a} <= {lo_clamp})\n        \
             && ((pos_hi_{a} <<< pos_shift_{a}) >= pos_m_{a} || node_from_hi_{a} >= {x}'sd{qg});\n    \
             wire parallel_ok_{a} = pos_d_{a} == 0 && !node_mirror_{a}\n        \
             && (node_from_hi_{a} >= {x}'sd{qg} || ((pos_hi_{a} + 1) <<< pos_shift_{a}) > pos_v_{a})\n        \
             && (node_from_lo_{a} <= 0 || ((pos_lo_{a} - 1) <<< pos_shift_{a}) < pos_v_{a});\n    \
             (* keep *) wire lemma_position_{a} = !node_live || (node_parallel_{a} ? parallel_ok_{a} : slab_ok_{a});",
            psh = u2 - g as i32,
            p1 = pw - 1,
            w1 = w - 1,
            x = xw,
            lo_clamp = signed_literal(xw, qg - clamp),
        );
    }
    // slopes, scaled by 2^k1: S = sig << (shift + kmin + k1), A = mag << (e − G − g − s1 + k1)
    let kmin = s.kmin();
    let k1 = [0, -kmin, -(emin - g as i32 - gmax - s1)]
        .into_iter()
        .max()
        .unwrap();
    let right_max = emax - g as i32 - gmin - s1 + k1;
    let left_max = (1 << zb) - 1 + kmin + k1;
    let sw = [
        m as i32 + 1 + left_max,
        2 * s1 + 2 + right_max,
        magnitude_bits(fmt) as i32 + right_max,
        k as i32 + k1 + 2,
    ]
    .into_iter()
    .max()
    .unwrap() as u32
        + 2;
    let max_mag = fmt.max_finite(false);
    for a in AXES {
        let _ = writeln!(
            v,
            "    // slope {a}: S = sig·2^(shift + {kmin}) cells per 2^−g step against |inv_d|·2^(e − g − G), scaled by 2^{k1}\n    \
             wire [7:0] slope_lo_shift_{a} = node_shift_down_{a} + 8'd{kk};\n    \
             wire [7:0] slope_hi_shift_{a} = node_shift_up_{a} + 8'd{kk};\n    \
             wire signed [9:0] slope_r_shift_{a} = $signed(frame_exp_{a}) - $signed(unit_grid_exp) + 10'sd{rs};\n    \
             wire [{s_1}:0] slope_lo_{a} = {{{pad_lo}'d0, node_sig_down_{a}}} << slope_lo_shift_{a};\n    \
             wire [{s_1}:0] slope_hi_{a} = {{{pad_hi}'d0, node_sig_up_{a}}} << slope_hi_shift_{a};\n    \
             wire [{s_1}:0] slope_a_mag_{a} = mag(inv_d_{a});\n    \
             wire [{s_1}:0] slope_a_{a} = slope_a_mag_{a} << slope_r_shift_{a};\n    \
             wire inv_d_{a}_at_max = inv_d_{a}[{w2}:0] == {w1}'h{max_mag:x};\n    \
             wire [{s_1}:0] slope_b_mag_{a} = inv_d_{a}_at_max ? ({sw}'d1 << {u2}) : mag(inv_d_{a}_next);\n    \
             wire [{s_1}:0] slope_b_{a} = slope_b_mag_{a} << slope_r_shift_{a};\n    \
             wire slope_ok_{a} = (node_over_down_{a} ? slope_a_{a} > ({sw}'d1 << {ck})\n            \
             : (slope_lo_{a} <= slope_a_{a} && node_shift_down_{a} <= {zmax}))\n        \
             && (node_over_up_{a} || (slope_hi_{a} >= slope_b_{a} && slope_hi_{a} >= ({sw}'d1 << {mk})\n            \
             && node_shift_up_{a} <= {zmax} && node_sig_up_{a} >= {m1}'d{half}));\n    \
             (* keep *) wire lemma_slope_{a} = !node_live || node_parallel_{a} || slope_ok_{a};",
            kk = kmin + k1,
            rs = k1 - g as i32 - s1,
            s_1 = sw - 1,
            pad_lo = sw - m,
            pad_hi = sw - m - 1,
            w1 = w - 1,
            w2 = w - 2,
            ck = k as i32 + k1,
            mk = h as i32 - g as i32 + k1,
            m1 = m + 1,
            half = 1u32 << (m - 1),
        );
    }
    // per child: the combination over the cut terms
    let dw = q + g + 8;
    let nwp = dw + m + 2 + (1 << zb) + 2;
    let (ls, rs) = (kmin.max(0), (-kmin).max(0));
    let c_scaled = format!("{nwp}'sd{}", (cap as u128) << rs);
    for i in 0..s.children {
        let mut axis_ok = Vec::new();
        let mut internal = Vec::new();
        let mut entry_axes = Vec::new();
        for a in AXES {
            let _ = writeln!(
                v,
                "    // slot {i}, axis {a}: distances to the entry and exit planes (mirrored frame), products with the slopes\n    \
                 wire [{q1}:0] plane_in_{i}_{a} = node_mirror_{a} ? ~slot{i}_hi_{a} : slot{i}_lo_{a};\n    \
                 wire [{q1}:0] plane_out_{i}_{a} = node_mirror_{a} ? ~slot{i}_lo_{a} : slot{i}_hi_{a};\n    \
                 wire signed [{d1}:0] dn_{i}_{a} = $signed({{1'b0, plane_in_{i}_{a}, {g}'d0}}) - node_from_hi_{a};\n    \
                 wire signed [{d1}:0] df_{i}_{a} = $signed({{1'b0, plane_out_{i}_{a}, {g}'d0}}) - node_from_lo_{a};\n    \
                 wire signed [{n1}:0] na_{i}_{a} = (dn_{i}_{a} * $signed({{1'b0, node_sig_down_{a}}})) <<< node_shift_down_{a};\n    \
                 wire signed [{n1}:0] fb_{i}_{a} = (df_{i}_{a} * $signed({{1'b0, node_sig_up_{a}}})) <<< node_shift_up_{a};",
                q1 = q - 1,
                d1 = dw - 1,
                n1 = nwp - 1,
            );
            axis_ok.push(format!(
                "(node_parallel_{a} ? (dn_{i}_{a} <= 0 && df_{i}_{a} >= 0) : df_{i}_{a} >= 0)"
            ));
            if i == 0 {
                internal.push(format!(
                    "(node_parallel_{a} || ((node_over_down_{a} || node_shift_down_{a} <= {zmax})\n            \
                     && (node_over_up_{a} || (node_shift_up_{a} <= {zmax} && node_sig_up_{a} >= {m1}'d{half}))))",
                    m1 = m + 1,
                    half = 1u32 << (m - 1)
                ));
            }
            entry_axes.push(format!(
                "(!node_parallel_{a} && dn_{i}_{a} > 0 && (node_over_down_{a} ? unit_entry_wide_{i} <= {c_scaled}\n            \
                 : (unit_entry_wide_{i} <<< {rs}) <= (na_{i}_{a} <<< {ls})))"
            ));
        }
        let mut pairs = Vec::new();
        for a in AXES {
            for b in AXES {
                pairs.push(format!(
                    "(node_parallel_{a} || node_parallel_{b} || dn_{i}_{a} <= 0\n            \
                     || (df_{i}_{b} > 0 && (node_over_up_{b} || (fb_{i}_{b} <<< {ls}) >= {c_scaled}))\n            \
                     || (!node_over_down_{a} && !node_over_up_{b} && na_{i}_{a} <= fb_{i}_{b}))"
                ));
            }
            pairs.push(format!(
                "(node_parallel_{a} || dn_{i}_{a} <= 0 || node_far_top == {f2}'sd{cap}\n            \
                 || (!node_over_down_{a} && (na_{i}_{a} <<< {ls}) <= (far_top_wide <<< {rs})))",
                f2 = k + 2
            ));
        }
        if i == 0 {
            let _ = writeln!(
                v,
                "    wire signed [{n1}:0] far_top_wide = node_far_top;\n    \
                 // what the lemmas give the per-node terms alone\n    \
                 wire node_internal = node_far_top >= 0 && node_far_top <= {f2}'sd{cap}\n        && {};",
                internal.join("\n        && "),
                n1 = nwp - 1,
                f2 = k + 2
            );
        }
        let _ = writeln!(
            v,
            "    wire signed [{n1}:0] unit_entry_wide_{i} = $signed({{1'b0, unit_entry_{i}}});\n    \
             // what an exact hit of slot {i} implies for the per-node terms (module doc)\n    \
             (* keep *) wire lemma_meet{i} = !node_empty && node_internal\n        && {}\n        && {};\n    \
             wire entry_bound_{i} = unit_entry_{i} == 0 || (node_live && ({}));\n    \
             (* keep *) wire lemma_child{i} = !(child{i}_valid && (node_all_in || lemma_meet{i})) || (unit_hit_{i} && entry_bound_{i});",
            axis_ok.join("\n        && "),
            pairs.join("\n        && "),
            entry_axes.join("\n            || "),
            n1 = nwp - 1,
        );
    }
    v
}

/// A signed Verilog literal of `width` bits: `N'sdV` or `-N'sdV`.
fn signed_literal(width: u32, value: i64) -> String {
    if value < 0 {
        format!("-{width}'sd{}", -value)
    } else {
        format!("{width}'sd{value}")
    }
}
