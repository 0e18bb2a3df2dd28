//! `node_child`: the per-child test of the node tester (`docs/node.md` §2
//! step 5, issue 36 step 2), bit-exact with `golden_model::node::child`.
//!
//! One slot's six box integers against the node's per-node integers (the
//! model's `NodeTerms`, computed once per node): per axis either the
//! origin's position range (an axis parallel to the ray) or the two
//! bounding lines anchored at the window start, in grid units `2^(G − f)`.
//! Per slab axis two products of `q` by `K + f + 2` bits (the entry cell
//! from the lower line, the exit cell from the upper), a floor or ceiling
//! by `2^f` as a bit slice, clamps; `hit = valid ∧ ¬miss ∧ max near ≤ min
//! far`, `entry = max near` (the sentinel `2^(K+1) − 1` on a miss). The
//! grid is the model's default, `K = q + 4`, `f = 4`. Signed ports are two's
//! complement in a `UInt` of their width. `stages` registers are placed by
//! the delay model ([`crate::retime::balance`]).

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::arith::float::bits::to_sint;
use crate::arith::int::{sext, zext};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `node_child` unit.
pub struct NodeChild;

/// Fraction bits below a grid step (the model's default `f`).
pub const GRID_FRAC: u32 = 4;

crate::params! {
    /// The per-child node test's parameters.
    pub struct NodeChildParams {
        /// bits per box integer q (grid K = q + 4, f = 4: the model's defaults)
        box_bits: u32 [4..=16] = 8,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=8] = 2,
    }
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// box integer bits q
    pub box_bits: u32,
    /// pipeline registers
    pub stages: u32,
}

impl Config {
    /// Grid bits K = q + 4.
    pub fn grid_bits(&self) -> u32 {
        self.box_bits + 4
    }
    /// Bits of a line value (`±2^(K + f + 1)`, two's complement): `K + f + 3`.
    pub fn at_bits(&self) -> u32 {
        self.grid_bits() + GRID_FRAC + 3
    }
    /// Bits of a slope (`0 ..= 2^(K + f + 1)`): `K + f + 2`.
    pub fn slope_bits(&self) -> u32 {
        self.grid_bits() + GRID_FRAC + 2
    }
    /// Bits of a parallel axis's position (`−1 ..= 2^q`, two's complement): `q + 2`.
    pub fn pos_bits(&self) -> u32 {
        self.box_bits + 2
    }
}

/// The inputs, in port order (`*` = x, y, z; docs/node.md §8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeChildIn<T> {
    /// the slot holds a child
    pub valid: T,
    /// every slot of the node misses
    pub miss: T,
    /// the window's end in grid steps, `0 ..= 2^K`
    pub far_top: T,
    /// the slot's lower integers
    pub lo: [T; 3],
    /// the slot's upper integers
    pub hi: [T; 3],
    /// the ray is parallel to the axis (`inv_d = ±∞`)
    pub parallel: [T; 3],
    /// plane indices mirrored (`inv_d < 0`)
    pub mirror: [T; 3],
    /// parallel axis: the origin's lowest frame step
    pub pos_lo: [T; 3],
    /// parallel axis: the origin's highest frame step
    pub pos_hi: [T; 3],
    /// the lower line's anchor plane
    pub near_n0: [T; 3],
    /// the lower line at `n0` minus `T0`
    pub near_at_n0: [T; 3],
    /// the lower line at `n0 + 1` minus `T0`
    pub near_at_next: [T; 3],
    /// `near_at_n0` is −∞
    pub near_inf_n0: [T; 3],
    /// `near_at_next` is −∞
    pub near_inf_next: [T; 3],
    /// the lower line's slope rounded down
    pub near_slope: [T; 3],
    /// the upper line's anchor plane
    pub far_n0: [T; 3],
    /// the upper line at `n0 − 1` minus `T0`
    pub far_at_prev: [T; 3],
    /// the upper line at `n0` minus `T0`
    pub far_at_n0: [T; 3],
    /// the upper line at `n0 + 1` minus `T0`
    pub far_at_next: [T; 3],
    /// `far_at_prev` is +∞
    pub far_inf_prev: [T; 3],
    /// `far_at_n0` is +∞
    pub far_inf_n0: [T; 3],
    /// `far_at_next` is +∞
    pub far_inf_next: [T; 3],
    /// the upper line's slope rounded down
    pub far_slope_dn: [T; 3],
    /// the upper line's slope rounded up
    pub far_slope_up: [T; 3],
    /// `far_slope_up` is above `2^(K + f + 1)`
    pub far_slope_up_inf: [T; 3],
}

impl<T: Copy> Record<T> for NodeChildIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let b = Ty::Bool;
        let q = Ty::UInt(cfg.box_bits);
        let at = Ty::UInt(cfg.at_bits());
        let sl = Ty::UInt(cfg.slope_bits());
        let pos = Ty::UInt(cfg.pos_bits());
        NodeChildIn {
            valid: w.one("valid", b, |r| r.valid),
            miss: w.one("miss", b, |r| r.miss),
            far_top: w.one("far_top", Ty::UInt(cfg.grid_bits() + 1), |r| r.far_top),
            lo: w.xyz("lo", q, |r| r.lo),
            hi: w.xyz("hi", q, |r| r.hi),
            parallel: w.xyz("parallel", b, |r| r.parallel),
            mirror: w.xyz("mirror", b, |r| r.mirror),
            pos_lo: w.xyz("pos_lo", pos, |r| r.pos_lo),
            pos_hi: w.xyz("pos_hi", pos, |r| r.pos_hi),
            near_n0: w.xyz("near_n0", q, |r| r.near_n0),
            near_at_n0: w.xyz("near_at_n0", at, |r| r.near_at_n0),
            near_at_next: w.xyz("near_at_next", at, |r| r.near_at_next),
            near_inf_n0: w.xyz("near_inf_n0", b, |r| r.near_inf_n0),
            near_inf_next: w.xyz("near_inf_next", b, |r| r.near_inf_next),
            near_slope: w.xyz("near_slope", sl, |r| r.near_slope),
            far_n0: w.xyz("far_n0", q, |r| r.far_n0),
            far_at_prev: w.xyz("far_at_prev", at, |r| r.far_at_prev),
            far_at_n0: w.xyz("far_at_n0", at, |r| r.far_at_n0),
            far_at_next: w.xyz("far_at_next", at, |r| r.far_at_next),
            far_inf_prev: w.xyz("far_inf_prev", b, |r| r.far_inf_prev),
            far_inf_n0: w.xyz("far_inf_n0", b, |r| r.far_inf_n0),
            far_inf_next: w.xyz("far_inf_next", b, |r| r.far_inf_next),
            far_slope_dn: w.xyz("far_slope_dn", sl, |r| r.far_slope_dn),
            far_slope_up: w.xyz("far_slope_up", sl, |r| r.far_slope_up),
            far_slope_up_inf: w.xyz("far_slope_up_inf", b, |r| r.far_slope_up_inf),
        }
    }
}

/// The outputs: `hit entry`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeChildOut<T> {
    /// the ray may meet the child's box
    pub hit: T,
    /// grid steps from `T0` to the entry bound (`2^(K+1) − 1` on a miss)
    pub entry: T,
}

impl<T: Copy> Record<T> for NodeChildOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        NodeChildOut {
            hit: w.one("hit", Ty::Bool, |r| r.hit),
            entry: w.one("entry", Ty::UInt(cfg.grid_bits() + 1), |r| r.entry),
        }
    }
}

/// Module name: `node_child_q{q}_s{stages}`.
pub fn node_child_name(cfg: &Config) -> String {
    format!("node_child_q{}_s{}", cfg.box_bits, cfg.stages)
}

/// `a` (SInt) clamped to `[lo, hi]`, as an SInt of `w` bits.
fn clamp(m: &mut ModuleBuilder, a: Sig, lo: Sig, hi: Sig, w: u32) -> Sig {
    let ww = a.width().max(lo.width()).max(hi.width());
    let (a, lo, hi) = (sext(m, a, ww), sext(m, lo, ww), sext(m, hi, ww));
    let below = m.lt(a, lo);
    let below = m.name(below, "below");
    let above = m.lt(hi, a);
    let above = m.name(above, "above");
    let v = m.mux(above, hi, a);
    let v = m.mux(below, lo, v);
    let v = m.name(v, "limited");
    let v = m.slice(v, w - 1, 0);
    let v = m.as_sint(v);
    m.name(v, "cell")
}

/// The entry and exit cells of one axis: `(near, far)`, SInt of `K + 3` bits.
/// A plane's offset `d = plane − anchor` from its line's anchor plane (q + 1
/// bits, signed), whether the plane is before the anchor (`d < 0`), and
/// whether it is the anchor (`d = 0`).
#[track_caller]
fn anchor_offset(m: &mut ModuleBuilder, plane: Sig, anchor: Sig, q: u32) -> (Sig, Sig, Sig) {
    let d = m.sub(plane, anchor);
    let d = m.name(d, "plane_offset");
    let before = m.msb(d);
    let zero_d = m.sint(q + 1, 0);
    let at_anchor = m.eq(d, zero_d);
    let at_anchor = m.name(at_anchor, "at_anchor");
    (d, before, at_anchor)
}

fn axis_cells(
    m: &mut ModuleBuilder,
    cfg: &Config,
    r: &NodeChildIn<Sig>,
    far_top: Sig,
    a: usize,
) -> (Sig, Sig) {
    let q = cfg.box_bits;
    let k = cfg.grid_bits();
    let f = GRID_FRAC;
    let cell_bits = k + 3;
    let top_plus = m.sint(cell_bits, (1i128 << k) + 1);
    let zero = m.sint(cell_bits, 0);
    let minus_one = m.sint(cell_bits, -1);
    let (lo, hi) = (r.lo[a], r.hi[a]);
    // parallel axis: the origin's steps against [lo, hi]
    let (par_near, par_far) = m.scope("parallel", |m| {
        let pw = cfg.pos_bits();
        let p_lo = m.as_sint(r.pos_lo[a]);
        let p_hi = m.as_sint(r.pos_hi[a]);
        let (lo_s, hi_s) = (to_sint(m, lo, pw), to_sint(m, hi, pw));
        let lo_in = m.le(lo_s, p_hi);
        let hi_in = m.le(p_lo, hi_s);
        let inside = m.and(lo_in, hi_in);
        let inside = m.name(inside, "inside");
        let near = m.mux(inside, zero, top_plus);
        let far = m.mux(inside, far_top, minus_one);
        (near, far)
    });
    // entry and exit planes in mirrored indices: Q − x is ~x
    let mirror = r.mirror[a];
    let (not_hi, not_lo) = (m.not(hi), m.not(lo));
    let me = m.mux(mirror, not_hi, lo);
    let me = m.name(me, "entry_plane");
    let mx = m.mux(mirror, not_lo, hi);
    let mx = m.name(mx, "exit_plane");
    let near = m.scope("entry_bound", |m| {
        let (d, before, at_anchor) = anchor_offset(m, me, r.near_n0[a], q);
        // d − 1 for d > 0: q bits
        let one = m.sint(q + 1, 1);
        let steps = m.sub(d, one);
        let steps = zext(m, steps, q);
        let steps = m.name(steps, "steps");
        let product = m.mul(steps, r.near_slope[a]);
        let product = m.name(product, "product");
        let vw = product.width() + 2;
        let next = sext(m, r.near_at_next[a], vw);
        let product = to_sint(m, product, vw);
        let after = m.add(next, product);
        let n0v = sext(m, r.near_at_n0[a], vw + 1);
        let v = m.mux(at_anchor, n0v, after);
        let v = m.name(v, "value");
        // ⌊v / 2^f⌋: the bits above f
        let cell = m.slice(v, v.width() - 1, f);
        let cell = m.as_sint(cell);
        let cell = m.name(cell, "floor_cell");
        let cell = m.scope("clamp", |m| clamp(m, cell, zero, top_plus, cell_bits));
        let inf = m.mux(at_anchor, r.near_inf_n0[a], r.near_inf_next[a]);
        let no_bound = m.or(before, inf);
        let no_bound = m.name(no_bound, "no_bound");
        m.mux(no_bound, zero, cell)
    });
    let far = m.scope("exit_bound", |m| {
        let (d, before, at_anchor) = anchor_offset(m, mx, r.far_n0[a], q);
        // planes beyond the line's point: −d − 1 = ~d before it, d − 1 after
        let one = m.sint(q + 1, 1);
        let after_steps = m.sub(d, one);
        let after_steps = zext(m, after_steps, q);
        let before_steps = m.not(d);
        let before_steps = zext(m, before_steps, q);
        let steps = m.mux(before, before_steps, after_steps);
        let steps = m.name(steps, "steps");
        let slope = m.mux(before, r.far_slope_dn[a], r.far_slope_up[a]);
        let product = m.mul(steps, slope);
        let product = m.name(product, "product");
        let vw = product.width() + 2;
        let base = m.mux(before, r.far_at_prev[a], r.far_at_next[a]);
        let base = sext(m, base, vw);
        let product = to_sint(m, product, vw);
        let below = m.sub(base, product);
        let above = m.add(base, product);
        let above = sext(m, above, vw + 1);
        let moved = m.mux(before, below, above);
        let n0v = sext(m, r.far_at_n0[a], vw + 1);
        let v = m.mux(at_anchor, n0v, moved);
        let v = m.name(v, "value");
        // ⌈v / 2^f⌉ = ⌊(v + 2^f − 1) / 2^f⌋
        let round_up = m.sint(vw + 1, (1i128 << f) - 1);
        let v_up = m.add(v, round_up);
        let cell = m.slice(v_up, v_up.width() - 1, f);
        let cell = m.as_sint(cell);
        let cell = m.name(cell, "ceil_cell");
        let cell = m.scope("clamp", |m| clamp(m, cell, minus_one, far_top, cell_bits));
        // an exit before the window start misses, even within one cell of it
        let exits_before = m.msb(v);
        let exits_before = m.name(exits_before, "exits_before");
        let cell = m.mux(exits_before, minus_one, cell);
        let inf_moved = m.mux(before, r.far_inf_prev[a], r.far_inf_next[a]);
        let inf_base = m.mux(at_anchor, r.far_inf_n0[a], inf_moved);
        let any_steps = m.any_set(steps);
        let not_after = m.or(before, at_anchor);
        let after = m.not(not_after);
        let slope_inf = m.and(after, r.far_slope_up_inf[a]);
        let slope_inf = m.and(slope_inf, any_steps);
        let unbounded = m.or(inf_base, slope_inf);
        let unbounded = m.name(unbounded, "unbounded");
        m.mux(unbounded, far_top, cell)
    });
    let parallel = r.parallel[a];
    let near = m.mux(parallel, par_near, near);
    let far = m.mux(parallel, par_far, far);
    (m.name(near, "near_cell"), m.name(far, "far_cell"))
}

/// Builds `node_child` for a configuration.
pub fn build(cfg: &Config) -> Module {
    let mut m = ModuleBuilder::with_handshake(node_child_name(cfg));
    m.describe("The node tester's per-child test: one slot's box integers against the node's per-node integers.");
    let r: NodeChildIn<Sig> = ports::declare_inputs(&mut m, cfg);
    let k = cfg.grid_bits();
    let cell_bits = k + 3;
    let far_top = to_sint(&mut m, r.far_top, cell_bits);
    let far_top = m.name(far_top, "far_top_cell");
    let cells: Vec<(Sig, Sig)> = (0..3)
        .map(|a| {
            m.scope(&format!("axis_{}", ports::AXES[a]), |m| {
                axis_cells(m, cfg, &r, far_top, a)
            })
        })
        .collect();
    let mut near_max = m.sint(cell_bits, 0);
    let mut far_min = far_top;
    for (a, &(near, far)) in cells.iter().enumerate() {
        let axis = ports::AXES[a];
        (near_max, far_min) = m.scope(&format!("fold_{axis}"), |m| {
            let larger = m.lt(near_max, near);
            let nm = m.mux(larger, near, near_max);
            let smaller = m.lt(far, far_min);
            let fm = m.mux(smaller, far, far_min);
            (m.name(nm, "near_max"), m.name(fm, "far_min"))
        });
    }
    let overlap = m.le(near_max, far_min);
    let overlap = m.name(overlap, "overlap");
    let live = m.not(r.miss);
    let slot = m.and(r.valid, live);
    let hit = m.and(slot, overlap);
    let hit = m.name(hit, "slot_hit");
    let entry = m.slice(near_max, k, 0);
    let sentinel = m.uint(k + 1, (1u128 << (k + 1)) - 1);
    let entry = m.mux(hit, entry, sentinel);
    let entry = m.name(entry, "slot_entry");
    ports::declare_outputs(&mut m, cfg, &NodeChildOut { hit, entry });
    let datapath = m.finish().expect("node_child datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance(&datapath, cfg.stages)
        .expect("the node_child datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

impl Description for NodeChild {
    type Params = NodeChildParams;
    type Config = Config;
    const NAME: &'static str = "node_child";
    const SUMMARY: &'static str =
        "node tester's per-child test: one slot's box integers against the per-node integers, hit and entry cell";
    fn config(&self, p: &NodeChildParams) -> Result<Config, ParamError> {
        Ok(Config {
            box_bits: p.box_bits,
            stages: p.stages,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}
