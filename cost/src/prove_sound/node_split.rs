//! `--split` for the node tester (docs/proofs.md, "Splitting the proof";
//! docs/node.md §12): the unit cut at its per-node terms, in five stages
//! on the design as read (the cut wires keep their drivers and readers
//! there: prep's wreduce and opt would narrow and merge them), each lemma
//! its own `sat` call on its cone of influence, under the wrapper's
//! contract.
//!
//! Notation: `g` position bits, `h` cell bits, `m` slope bits, `kmin = h −
//! m + 1 − g`; `T_r` the output `t_base`, `u = 2^G` the cell (`G` the output
//! `grid_exp`), `C = 2^K` the cap, `L = 2^(q+3+g)` the clamp, `Q = 2^q − 1`;
//! `live` = neither every valid slot reported (`every_valid_slot`: bad
//! input, no start) nor the segment empty (`empty_segment_empty`). Per axis
//! the exact position at `T_r` in `2^−g` frame steps is `P = (o − O +
//! T_r·d)·2^(g − e)`, `P' = P` or `Q·2^g − P` when mirrored; the window sum
//! adds the terms `t0 = o`, `t1 = −O`, `t2 = T_r·d` (exact) in `2^B` units
//! (`B = sum_exp`), each term truncated to `kept` with `lost` set when it
//! lost bits; `from_lo`, `from_hi` are the position bounds on the grid
//! (mirrored); a slope is `S = sig·2^(shift + kmin)` cells per `2^−g` step
//! (`sig_down` rounded down, `sig_up_used` up, each flagged `over_cap`).
//!
//! **Stage 0** (nothing cut):
//! * **start**: live ⇒ `t_base` finite, `T_r ≤ max(t_min, t_start)`;
//! * **empty**: `empty` (not every slot reported) only for `t_min = +∞`,
//!   `t_start = +∞`, `t_max = −∞` or `t_max < max(t_min, t_start)`;
//! * **window_end**: live ⇒ `0 ≤ far_top ≤ C`, and `far_top = C` or `t_max`
//!   finite with `far_top·u ≥ t_max − T_r`;
//! * **flags_a**: live ⇒ `parallel` iff `d = 0`; a parallel axis is not
//!   mirrored, a slab axis mirrored iff `d < 0`;
//! * **term<i>_a**: live ⇒ a nonzero term has `B` in the window's range and
//!   `kept·2^B ≤ |t_i| ≤ (kept + lost)·2^B`; a zero term loses nothing and
//!   keeps nothing, except a zero start's significand times a nonzero `d`
//!   when `B` is the floor (every term zero; the unit summed it before the
//!   eighth session's fix, and the lemma still allows it);
//! * **slope_a**: live, slab axis, `A = |inv_d|·2^(e−g−G)`, `B' =
//!   next(|inv_d|)·2^(e−g−G)` (`2^(bias+F−1)·2^(e−g−G)` at the largest
//!   finite `inv_d`): unless `over_lo`, `S_lo ≤ A` and `shift_lo ≤ zmax`;
//!   with `over_lo`, `A > C`; unless `over_hi`, `S_hi ≥ B'`, `S_hi ≥
//!   2^(h−g)`, `shift_hi ≤ zmax`, `sig_hi ≥ 2^(m−1)`.
//!
//! **Stage 1** (`kept`, `lost` of every term cut): **sum_lo_a**,
//! **sum_hi_a**: live, the zero terms keeping and losing nothing, the
//! unit's sums are `lo = Σ ±kept − Σ_neg lost`, `hi = Σ ±kept + Σ_pos lost`
//! (signs of the exact terms).
//!
//! **Stage 2** (the sums cut, at the adders the unit's readers take their
//! bits from): **grid_lo_a**, **grid_hi_a** (one bound each, each proved
//! as one `sat` call per grid shift `s = B − e + g` and one for every `s`
//! out of range: a partition): live, `B` in range or the floor (then, on a
//! parallel axis, the sums zero): `−L ≤ from_lo, from_hi ≤ Q·2^g + L`, and
//! with the sums `lo`, `hi` (both read as 0 when `B` is the floor): a slab
//! axis has `from_lo ≤ lo·2^B` scaled (`Q·2^g
//! − hi` mirrored) or `from_lo ≤ Q·2^g − L`, `from_hi ≥ hi` (`Q·2^g − lo`)
//! or `from_hi ≥ Q·2^g`; a parallel axis `from_hi ≥ Q·2^g` or `from_hi >
//! hi − 1`, `from_lo ≤ 0` or `from_lo < lo + 1` (in steps).
//!
//! **Stage 3** (`from_lo`, `from_hi`, the slopes, `far_top` and every
//! slot's `near_max` cut): **cells<i>_a**: given the stage-0/1 lemmas'
//! internal parts (the ranges of `from_*` and `far_top`, the shifts,
//! `sig_hi`), slot i's cells on axis a: `near = 0` for `dn ≤ 0`, else `0 ≤
//! near ≤ C`, `near = C` with `over_lo`, else `near ≤ dn·S_lo`; for any
//! `0 ≤ near_max ≤ C`, the exit `admits` it, or `df < 0`, or the axis is a
//! slab axis without `df > 0` and `over_hi` and `near_max > df·S_hi` (the
//! unit forms no exit cells since 2026-12-07: only whether they reach
//! `near_max`); `misses` iff `df < 0` or a parallel axis with `dn > 0`.
//!
//! **Stage 4** (also every slot's cells cut; `near_max` is the unit's
//! maximum of the cut entries): **child_i**: if slot i is
//! valid and every valid slot is reported, or the segment is not empty, the
//! internal parts, `meet_i` and slot i's cells lemmas hold, the slot is
//! reported hit, and its entry is 0 or, live, for some slab axis with
//! `dn > 0`, at most `C` (`over_lo`) or at most `dn·S_lo`. With
//! `dn_a = entry_a·2^g − from_hi_a`, `df_a = exit_a·2^g − from_lo_a` (the
//! child's planes in the mirrored frame),
//! `meet_i`: `df_a ≥ 0` on every axis and `dn_a ≤ 0` on a parallel one; for
//! slab axes a, b: `dn_a ≤ 0`, or `df_b > 0` with `over_hi_b` or
//! `df_b·S_hi_b ≥ C`, or neither flag and `dn_a·S_lo_a ≤ df_b·S_hi_b`; and
//! `dn_a ≤ 0`, `far_top = C`, or `dn_a·S_lo_a ≤ far_top` without `over_lo_a`.
//!
//! **Why they imply the property.** Take a valid slot whose box the segment
//! meets: some real `t*`, `max(t_min, t_start) ≤ t* ≤ t_max`, in the box. If
//! every valid slot is reported, child_i gives the hit at entry 0. Else by
//! empty the segment is not empty, so live; by start `T_r ≤ t*`. Position:
//! by term<i> the exact sum `o − O + T_r·d` lies in `[lo, hi]·2^B` with
//! the sums of sum_lo, sum_hi (zero terms add nothing; `B` the floor only
//! when every term is zero, sum 0, and then on a parallel axis, `d = 0`,
//! every part is zero and so are the sums), so by grid `from_lo ≤ P'` or `from_lo ≤ Q·2^g − L`, `from_hi ≥ P'` or
//! `from_hi ≥ Q·2^g` (a parallel axis: `from_hi > P − 1`, `from_lo < P + 1`
//! or beyond the planes). Let `τ = (t* − T_r)/u ≥ 0` and per slab axis `R =
//! 2^(e−g)/(|d|·u)`; the contract `|inv_d| ≤ 1/|d| < next(|inv_d|)` (`1/|d|
//! ≤ 2^(bias+F−1)`) gives `A ≤ R < B'`. The mirrored position at `t` is `P' +
//! (t − T_r)/(u·R)`, so `(t_enter − T_r)/u = (entry·2^g − P')·R ≤ τ ≤
//! (exit·2^g − P')·R = (t_exit − T_r)/u`. `dn_a > 0` puts `from_hi_a` below
//! `Q·2^g`, so `dn_a ≤ entry·2^g − P'_a` and `τ ≥ dn_a·R_a > 0`, which is at
//! least `dn_a·S_lo_a` (`S_lo ≤ A ≤ R`), or above `C` with `over_lo`. On
//! axis b, `from_lo_b ≤ P'_b` gives `df_b ≥ τ/R_b > 0` and `df_b·S_hi_b ≥
//! τ` unless `over_hi_b`; a clamped `from_lo_b` gives `df_b ≥ L − Q·2^g` and
//! `df_b·S_hi_b ≥ (L − Q·2^g)·2^(h−g) > C`. So every pair holds and `df ≥
//! 0`; window_end gives `τ ≤ far_top` or `far_top = C` (with `over_lo`, `τ >
//! C ≥ far_top` forces `far_top = C`). A parallel axis: flags give `d = 0`,
//! the box `lo·2^g ≤ P ≤ hi·2^g` (integers), so `from_hi ≥ lo·2^g` and
//! `from_lo ≤ hi·2^g`. So `meet_i` and the internal parts hold, and the
//! cells lemmas hold of the unit's cells whatever they are; child_i gives
//! the hit, and its entry is 0 or at most `dn·S_lo ≤ dn·R ≤ (t_enter −
//! T_r)/u` (or `C < R ≤ (t_enter − T_r)/u`) for a slab axis: `T_r +
//! entry·u ≤ t_enter`, the reference's `entry_ok`. The extra cover: a hit of
//! slot 0 where `meet_0` holds on the unit's own terms.

use super::split::{extended_real, Cut, Stage};
use super::{magnitude_bits, AXES};
use golden_model::float::FloatFormat;
use rtl_gen::units::node::{
    position_sum_exp_bits, CELL_BITS, POS_FRAC, WINDOW_EXTRA, WINDOW_FLOOR,
};
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
    /// the window sum's exponent `B = max(top − W, e − g − f)` (`top ≤ 2·emax + 3`, the
    /// frame's `e` in `emin ..= emax`, `f` the window floor), widened by 2 each way
    fn sum_exp_range(&self) -> (i32, i32) {
        let ww = self.window_bits() as i32;
        let (emin, emax) = (self.fmt.emin(), self.fmt.emax());
        let below = (POS_FRAC + WINDOW_FLOOR) as i32;
        (emin - below - 2, (2 * emax + 3 - ww).max(emax - below) + 2)
    }
    /// the position windows' width `W = q + g + WINDOW_EXTRA`
    fn window_bits(&self) -> u32 {
        self.q + POS_FRAC + WINDOW_EXTRA
    }
    /// the grid shift `s = B − e + g`: at least `−f` (the window floor), at most over
    /// `B`'s range and `emin ..= emax`
    fn grid_shift_range(&self) -> (i32, i32) {
        let (_, b_max) = self.sum_exp_range();
        let g = POS_FRAC as i32;
        (-(WINDOW_FLOOR as i32), b_max - self.fmt.emin() + g)
    }
    /// the grid exponent's range `2·emin − F − h ..= 2·emax − h`
    fn grid_range(&self) -> (i32, i32) {
        let (f, h) = (self.fmt.frac_bits() as i32, CELL_BITS as i32);
        (2 * self.fmt.emin() - f - h, 2 * self.fmt.emax() - h)
    }
}

/// The node's cut: the per-node terms (flattened names in `u_unit`), the
/// flags the lemmas read on both designs, the lemmas (module doc).
pub(super) fn node_cut(shape: NodeShape) -> Cut {
    let children = shape.children;
    let mut wires = Vec::new();
    let mut watched = Vec::new();
    let (mut parts, mut sums, mut terms) = (Vec::new(), Vec::new(), Vec::new());
    for a in AXES {
        for i in 0..3 {
            for part in ["kept", "lost"] {
                let name = format!("node_{part}{i}_{a}");
                wires.push((name.clone(), format!("u_unit.axis_{a}_term{i}_{part}")));
                parts.push(name);
            }
        }
        for part in ["lo", "hi"] {
            let end = if part == "lo" { "low" } else { "high" };
            let name = format!("node_sum_{part}_{a}");
            wires.push((
                name.clone(),
                format!("u_unit.add_axis_{a}_term2_partial_sum_{end}_adjust"),
            ));
            sums.push(name);
        }
        for (monitor, unit) in [
            ("sum_exp", format!("axis_{a}_sum_exp")),
            ("from_lo", format!("axis_{a}_plane_frame_from_lo")),
            ("from_hi", format!("axis_{a}_plane_frame_from_hi")),
            ("sig_down", format!("axis_{a}_slope_sig_down")),
            ("shift_down", format!("slope_{a}_down_shift")),
            ("over_down", format!("slope_{a}_down_over_cap")),
            ("sig_up", format!("slope_{a}_sig_up_used")),
            ("shift_up", format!("slope_{a}_up_shift")),
            ("over_up", format!("slope_{a}_up_over_cap")),
        ] {
            let name = format!("node_{monitor}_{a}");
            if monitor != "sum_exp" {
                terms.push(name.clone());
            }
            wires.push((name, format!("u_unit.{unit}")));
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
    terms.push("node_far_top".into());
    let mut cells = Vec::new();
    let mut near_maxes = Vec::new();
    for i in 0..children {
        let name = format!("node_near_max_{i}");
        wires.push((name.clone(), format!("u_unit.slot{i}_near_max")));
        near_maxes.push(name);
        for a in AXES {
            for (monitor, unit) in [
                ("near", format!("slot{i}_axis_{a}_near_cells")),
                ("admits", format!("slot{i}_axis_{a}_exit_admits")),
                ("misses", format!("slot{i}_axis_{a}_misses")),
            ] {
                let name = format!("node_{monitor}_{i}_{a}");
                wires.push((name.clone(), format!("u_unit.{unit}")));
                cells.push(name);
            }
        }
    }
    watched.push(("node_all_in".into(), "u_unit.every_valid_slot".into()));
    watched.push(("node_empty".into(), "u_unit.empty_segment_empty".into()));
    let stages = vec![
        Stage {
            cut: Vec::new(),
            lemmas: ["lemma_start", "lemma_empty", "lemma_window_end"]
                .iter()
                .map(|s| s.to_string())
                .chain(AXES.iter().map(|a| format!("lemma_flags_{a}")))
                .chain(
                    AXES.iter()
                        .flat_map(|a| (0..3).map(move |i| format!("lemma_term{i}_{a}"))),
                )
                .chain(AXES.iter().map(|a| format!("lemma_slope_{a}")))
                .collect(),
            cover: Some("-set child0_exact_hit 1 -set lemma_meet0 1".into()),
            cases: Vec::new(),
        },
        Stage {
            cut: parts,
            lemmas: AXES
                .iter()
                .flat_map(|a| [format!("lemma_sum_lo_{a}"), format!("lemma_sum_hi_{a}")])
                .collect(),
            cover: None,
            cases: Vec::new(),
        },
        Stage {
            cut: sums,
            lemmas: AXES
                .iter()
                .flat_map(|a| [format!("lemma_grid_lo_{a}"), format!("lemma_grid_hi_{a}")])
                .collect(),
            cover: None,
            // one case per grid shift s (then every shifter's amount is a constant), and one
            // for every s outside the range (where the sums are zero or the lemma vacuous)
            cases: AXES
                .iter()
                .flat_map(|a| {
                    let (lo, hi) = shape.grid_shift_range();
                    let cases: Vec<String> = (lo..=hi)
                        .map(|v| format!("-set grid_s_{a} 10'b{:010b}", (v as i64) & 0x3ff))
                        .chain([format!("-set grid_s_out_{a} 1")])
                        .collect();
                    [
                        (format!("lemma_grid_lo_{a}"), cases.clone()),
                        (format!("lemma_grid_hi_{a}"), cases),
                    ]
                })
                .collect(),
        },
        Stage {
            cut: terms.iter().cloned().chain(near_maxes).collect(),
            lemmas: (0..children)
                .flat_map(|i| AXES.iter().map(move |a| format!("lemma_cells{i}_{a}")))
                .collect(),
            cover: None,
            cases: Vec::new(),
        },
        Stage {
            cut: terms.into_iter().chain(cells).collect(),
            lemmas: (0..children).map(|i| format!("lemma_child{i}")).collect(),
            cover: None,
            cases: Vec::new(),
        },
    ];
    Cut {
        wires,
        lemmas: stages.iter().flat_map(|s| s.lemmas.clone()).collect(),
        combination: children,
        watched_after_cut: Vec::new(),
        watched,
        cover: String::new(),
        stages,
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
    // the window sums: [sum_lo, sum_hi]·2^B ∋ o − O + T_r·d, in units of 2^−(U + k2), U = 2·s1
    let ww = s.window_bits();
    let (b_min, b_max) = s.sum_exp_range();
    let k2 = (-(b_min + u2)).max(0);
    let bw = position_sum_exp_bits(emin.into(), emax.into());
    let sum_w = ww + 3;
    let vw = ((sum_w as i32 + b_max + u2 + k2).max(2 * nw as i32 + 2 + k2) + 3) as u32;
    // the grid: from·2^(−s) against sum·2^s's positive part, s = B − e + g
    let (s_min, s_max) = s.grid_shift_range();
    let gw2 = ((xw as i32 + 2 + (-s_min).max(0)).max(sum_w as i32 + 1 + s_max.max(0)) + 2) as u32;
    for a in AXES {
        for i in 0..3 {
            let _ = writeln!(
                v,
                "    (* keep *) wire [{k1}:0] node_kept{i}_{a};\n    (* keep *) wire node_lost{i}_{a};",
                k1 = ww - 1
            );
        }
        let _ = writeln!(
            v,
            "    // window {a}: the unit's sum bounds against o − O + T_r·d (exact), and its flags
                 (* keep *) wire signed [{b1}:0] node_sum_exp_{a};
                 (* keep *) wire signed [{sw}:0] node_sum_lo_{a}, node_sum_hi_{a};
                 wire signed [{sw1}:0] unit_sum_lo_{a} = node_sum_lo_{a}[{sw1}:0];
                 wire signed [{sw1}:0] unit_sum_hi_{a} = node_sum_hi_{a}[{sw1}:0];
                 wire node_sum_exp_ok_{a} = node_sum_exp_{a} >= {bmin} && node_sum_exp_{a} <= {bmax};
                 wire signed [{v1}:0] win_o_{a} = value(o_{a});
                 wire signed [{v1}:0] win_origin_{a} = value(frame_origin_{a});
                 wire signed [{v1}:0] win_d_{a} = value(d_{a});
                 wire signed [{v1}:0] win_t_{a} = value(unit_t_base);
                 wire signed [{v1}:0] win_v_{a} = ((win_o_{a} - win_origin_{a}) <<< {s1}) + win_t_{a} * win_d_{a};
                 wire signed [9:0] win_shift_{a} = node_sum_exp_{a} + 10'sd{bsh};
                 wire flags_ok_{a} = node_parallel_{a} ? (win_d_{a} == 0 && !node_mirror_{a})
                     : (win_d_{a} != 0 && node_mirror_{a} == d_{a}[{w1}]);
                 (* keep *) wire lemma_flags_{a} = !node_live || flags_ok_{a};
                 // the three terms o, −O, T_r·d (exact, in units of 2^−U): zero, sign, magnitude
                 wire signed [{v1}:0] ex_t0_{a} = win_o_{a} <<< {s1};
                 wire signed [{v1}:0] ex_t1_{a} = -(win_origin_{a} <<< {s1});
                 wire signed [{v1}:0] ex_t2_{a} = win_t_{a} * win_d_{a};
                 wire ex_zero0_{a} = o_{a}[{w2}:0] == 0;
                 wire ex_zero1_{a} = frame_origin_{a}[{w2}:0] == 0;
                 wire ex_zero2_{a} = unit_t_base[{w2}:0] == 0 || d_{a}[{w2}:0] == 0;
                 wire ex_neg0_{a} = o_{a}[{w1}];
                 wire ex_neg1_{a} = !frame_origin_{a}[{w1}];
                 wire ex_neg2_{a} = unit_t_base[{w1}] ^ d_{a}[{w1}];
                 // sum {a}: the unit's sum of the kept terms (cut), each with its sign, its lost bits outward
                 wire signed [{sw1}:0] sum_kept_lo_{a} = (ex_neg0_{a} ? -$signed({{1'b0, node_kept0_{a}}}) - node_lost0_{a} : $signed({{1'b0, node_kept0_{a}}}))
                     + (ex_neg1_{a} ? -$signed({{1'b0, node_kept1_{a}}}) - node_lost1_{a} : $signed({{1'b0, node_kept1_{a}}}))
                     + (ex_neg2_{a} ? -$signed({{1'b0, node_kept2_{a}}}) - node_lost2_{a} : $signed({{1'b0, node_kept2_{a}}}));
                 wire signed [{sw1}:0] sum_kept_hi_{a} = (ex_neg0_{a} ? -$signed({{1'b0, node_kept0_{a}}}) : $signed({{1'b0, node_kept0_{a}}}) + node_lost0_{a})
                     + (ex_neg1_{a} ? -$signed({{1'b0, node_kept1_{a}}}) : $signed({{1'b0, node_kept1_{a}}}) + node_lost1_{a})
                     + (ex_neg2_{a} ? -$signed({{1'b0, node_kept2_{a}}}) : $signed({{1'b0, node_kept2_{a}}}) + node_lost2_{a});
                 // the zero terms keep and lose nothing: the unit's sums are the kept terms'
                 wire parts_exact_{a} = (!ex_zero0_{a} || (!node_lost0_{a} && node_kept0_{a} == 0))
                     && (!ex_zero1_{a} || (!node_lost1_{a} && node_kept1_{a} == 0))
                     && (!ex_zero2_{a} || (!node_lost2_{a} && node_kept2_{a} == 0));
                 (* keep *) wire lemma_sum_lo_{a} = !node_live || !parts_exact_{a} || unit_sum_lo_{a} == sum_kept_lo_{a};
                 (* keep *) wire lemma_sum_hi_{a} = !node_live || !parts_exact_{a} || unit_sum_hi_{a} == sum_kept_hi_{a};
                 // grid {a}: the position bounds on the grid against the sum bounds (cut), in the
                 // unit's own alignment: from·2^(e − g) against sum·2^B as from·2^(−s) against sum,
                 // s = B − e + g (each side shifted by the other's share of s)
                 (* keep *) wire signed [9:0] grid_s_{a} = node_sum_exp_{a} - $signed(frame_exp_{a}) + 10'sd{g};
                 (* keep *) wire grid_s_out_{a} = grid_s_{a} < {smin} || grid_s_{a} > {smax};
                 wire [9:0] grid_from_shift_{a} = grid_s_{a} < 0 ? -grid_s_{a} : 10'd0;
                 wire [9:0] grid_sum_shift_{a} = grid_s_{a} < 0 ? 10'd0 : grid_s_{a};
                 wire signed [{g1}:0] grid_lo_{a} = unit_sum_lo_{a};
                 wire signed [{g1}:0] grid_hi_{a} = unit_sum_hi_{a};
                 wire signed [{g1}:0] grid_lo_s_{a} = grid_lo_{a} <<< grid_sum_shift_{a};
                 wire signed [{g1}:0] grid_hi_s_{a} = grid_hi_{a} <<< grid_sum_shift_{a};
                 wire [9:0] grid_x_shift_{a} = grid_from_shift_{a};
                 wire signed [{g1}:0] grid_from_lo_{a} = node_mirror_{a} ? {gw2}'sd{qg} - node_from_lo_{a} : node_from_lo_{a};
                 wire signed [{g1}:0] grid_from_hi_{a} = node_mirror_{a} ? {gw2}'sd{qg} - node_from_hi_{a} : node_from_hi_{a};
                 wire range_lo_{a} = node_from_lo_{a} >= {neg_l} && node_from_lo_{a} <= {x}'sd{top};
                 wire range_hi_{a} = node_from_hi_{a} >= {neg_l} && node_from_hi_{a} <= {x}'sd{top};
                 wire range_ok_{a} = range_lo_{a} && range_hi_{a};
                 // mirrored: from_lo = Q·2^g − x_hi ≤ Q·2^g − hi, from_hi = Q·2^g − x_lo ≥ Q·2^g − lo
                 wire slab_lo_{a} = node_from_lo_{a} <= {lo_clamp} || (node_mirror_{a}
                         ? (grid_from_lo_{a} <<< grid_x_shift_{a}) >= grid_hi_s_{a}
                         : (grid_from_lo_{a} <<< grid_x_shift_{a}) <= grid_lo_s_{a});
                 wire slab_hi_{a} = node_from_hi_{a} >= {x}'sd{qg} || (node_mirror_{a}
                         ? (grid_from_hi_{a} <<< grid_x_shift_{a}) <= grid_lo_s_{a}
                         : (grid_from_hi_{a} <<< grid_x_shift_{a}) >= grid_hi_s_{a});
                 wire signed [{g1}:0] grid_hi_plus_{a} = node_from_hi_{a} + 1;
                 wire signed [{g1}:0] grid_lo_minus_{a} = node_from_lo_{a} - 1;
                 wire parallel_hi_{a} = node_from_hi_{a} >= {x}'sd{qg} || (grid_hi_plus_{a} <<< grid_x_shift_{a}) > grid_hi_s_{a};
                 wire parallel_lo_{a} = node_from_lo_{a} <= 0 || (grid_lo_minus_{a} <<< grid_x_shift_{a}) < grid_lo_s_{a};
                 wire grid_hyp_{a} = node_live && node_sum_exp_ok_{a};
                 (* keep *) wire lemma_grid_lo_{a} = !grid_hyp_{a} || (range_lo_{a} && (node_parallel_{a} ? parallel_lo_{a} : slab_lo_{a}));
                 (* keep *) wire lemma_grid_hi_{a} = !grid_hyp_{a} || (range_hi_{a} && (node_parallel_{a} ? parallel_hi_{a} : slab_hi_{a}));",
            sw1 = sum_w - 1,
            sw = sum_w,
            w2 = w - 2,
            v1 = vw - 1,
            g1 = gw2 - 1,
            bmin = signed_literal(bw, b_min as i64),
            bmax = signed_literal(bw, b_max as i64),
            smin = signed_literal(10, s_min as i64),
            smax = signed_literal(10, s_max as i64),
            b1 = bw - 1,
            bsh = u2 + k2,
            w1 = w - 1,
            x = xw,
            top = qg + clamp,
            neg_l = signed_literal(xw, -clamp),
            lo_clamp = signed_literal(xw, qg - clamp),
        );
        for i in 0..3 {
            // a term's kept bits (and one more when it lost any) bound its magnitude in 2^B
            // units; a zero term keeps nothing and loses nothing
            let _ = writeln!(
                v,
                "    wire signed [{v1}:0] ex_mag{i}_{a} = ex_neg{i}_{a} ? -ex_t{i}_{a} : ex_t{i}_{a};\n    \
                 wire signed [{v1}:0] ex_kept{i}_{a} = {{1'b0, node_kept{i}_{a}}};\n    \
                 (* keep *) wire lemma_term{i}_{a} = !node_live || (ex_zero{i}_{a}\n        \
                 ? (!node_lost{i}_{a} && node_kept{i}_{a} == 0)\n        \
                 : (node_sum_exp_ok_{a} && (ex_t{i}_{a} < 0) == ex_neg{i}_{a}\n            \
                 && (ex_kept{i}_{a} <<< win_shift_{a}) <= (ex_mag{i}_{a} <<< {k2})\n            \
                 && (ex_mag{i}_{a} <<< {k2}) <= ((ex_kept{i}_{a} + node_lost{i}_{a}) <<< win_shift_{a})));",
                v1 = vw - 1,
            );
        }
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
                    "range_ok_{a} && (node_parallel_{a} || ((node_over_down_{a} || node_shift_down_{a} <= {zmax})\n            \
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
        let mut cells_ok = Vec::new();
        let _ = writeln!(
            v,
            "    // slot {i}: the largest entry (watched; cut in stage 3, where only its range is known)\n    \
             (* keep *) wire signed [{f1}:0] node_near_max_{i};\n    \
             wire signed [{n1}:0] near_max_wide_{i} = node_near_max_{i};\n    \
             wire near_max_in_range_{i} = node_near_max_{i} >= 0 && node_near_max_{i} <= {f2}'sd{cap};",
            f1 = k + 1,
            f2 = k + 2,
            n1 = nwp - 1,
        );
        for a in AXES {
            let _ = writeln!(
                v,
                "    // slot {i}, axis {a}: the unit's cells (watched, then cut) against the products\n    \
                 (* keep *) wire signed [{f1}:0] node_near_{i}_{a};\n    \
                 (* keep *) wire node_admits_{i}_{a}, node_misses_{i}_{a};\n    \
                 wire signed [{n1}:0] near_wide_{i}_{a} = node_near_{i}_{a};\n    \
                 wire near_ok_{i}_{a} = dn_{i}_{a} <= 0 ? node_near_{i}_{a} == 0\n        \
                 : (node_near_{i}_{a} >= 0 && node_near_{i}_{a} <= {f2}'sd{cap}\n           \
                 && (node_over_down_{a} ? node_near_{i}_{a} == {f2}'sd{cap} : (near_wide_{i}_{a} <<< {rs}) <= (na_{i}_{a} <<< {ls})));\n    \
                 wire admits_ok_{i}_{a} = !near_max_in_range_{i} || df_{i}_{a} < 0 || node_admits_{i}_{a}\n        \
                 || (!node_parallel_{a} && !(df_{i}_{a} > 0 && node_over_up_{a})\n           \
                 && (near_max_wide_{i} <<< {rs}) > (fb_{i}_{a} <<< {ls}));\n    \
                 wire misses_ok_{i}_{a} = node_misses_{i}_{a} == (df_{i}_{a} < 0 || (node_parallel_{a} && dn_{i}_{a} > 0));\n    \
                 wire cells_ok_{i}_{a} = near_ok_{i}_{a} && admits_ok_{i}_{a} && misses_ok_{i}_{a};\n    \
                 (* keep *) wire lemma_cells{i}_{a} = !node_internal || cells_ok_{i}_{a};",
                f1 = k + 1,
                f2 = k + 2,
                n1 = nwp - 1,
            );
            cells_ok.push(format!("cells_ok_{i}_{a}"));
        }
        let _ = writeln!(
            v,
            "    wire signed [{n1}:0] unit_entry_wide_{i} = $signed({{1'b0, unit_entry_{i}}});\n    \
             // what an exact hit of slot {i} implies for the per-node terms (module doc)\n    \
             (* keep *) wire lemma_meet{i} = !node_empty && node_internal\n        && {}\n        && {};\n    \
             wire entry_bound_{i} = unit_entry_{i} == 0 || (node_live && ({}));\n    \
             (* keep *) wire lemma_child{i} = !(child{i}_valid && (node_all_in || (lemma_meet{i} && {}))) || (unit_hit_{i} && entry_bound_{i});",
            axis_ok.join("\n        && "),
            pairs.join("\n        && "),
            entry_axes.join("\n            || "),
            cells_ok.join(" && "),
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
