//! Golden model of the `node` unit (issue 36, step 2): one ray against one
//! compressed wide-BVH node ([`crate::wide`]), every child slot tested
//! **conservatively**, the slots returned sorted. The specification and the
//! proof are in `docs/node.md`; this is its bit-exact twin.
//!
//! **Ray** (raw bits of the ray format `fmt`): origin `o`, reciprocal
//! direction `inv_d = RTZ(1/d)` (the conservative slab's contract,
//! `docs/silhouette.md` §6.2: `±∞` iff `d = ±0`, and `|1/d| ∈ [a, b]` with
//! `a = |inv_d|`, `b` its successor, or `b = 1/min_subnormal` when
//! `a = max_finite`), `t_min`, `t_max`.
//!
//! **Per node, once** (per axis, mirrored by the sign `s` of `inv_d`, so
//! that `t(n) = c + s·n·step` is the parameter of the plane `O + n·2^e`,
//! `c = s·(O − o)·|1/d|`, `step = 2^e·|1/d|`):
//! 1. `D = s·(O − o)` rounded down and up to `P` significant bits
//!    (`node_bits`, default `F + q + 5`: the ray's precision and `q + 4`
//!    more; exponent unbounded: the hardware carries two more exponent bits,
//!    so nothing overflows);
//! 2. `c_lo = RDN_P(D_lo · (D_lo < 0 ? b : a))`, `c_hi = RUP_P(D_hi · (D_hi > 0 ? b : a))`;
//! 3. `st_lo = RDN_S(a)·2^e`, `st_hi = RUP_S(b)·2^e`: the step with a
//!    narrow `S`-bit mantissa (`step_bits`), which is what keeps the
//!    per-child products narrow (`q × S` bits);
//! 4. the whole node box `[0, 2^q − 1]` on each axis gives the node's
//!    entry and exit bounds, rounded outward to `P` bits; the **window**
//!    `T0 = max(t_min, entries)`, `T1 = min(t_max, exits)`; an axis with
//!    `inv_d = ±∞` (parallel) instead bounds the origin's position in frame
//!    steps, `[p_lo, p_hi]` (from `o − O` rounded outward to `P` bits);
//! 5. the **grid**: `2^G` with `G` the least integer such that
//!    `T1 − T0 < 2^(G + K)` (`K = grid_bits`).
//!
//! **Per child** (narrow: integers of `q`, `S` and `K + 2` bits): per
//! non-parallel axis the entry bound `near = c_lo + n_e·st` and exit bound
//! `far = c_hi + n_x·st` on the entry and exit planes (`lo`/`hi` swapped
//! when `s < 0`, the step bound that makes each a bound), brought onto the
//! grid: `near_q = clamp(⌊(near − T0)/2^G⌋, 0, 2^K + 1)`,
//! `far_q = clamp(⌈(far − T0)/2^G⌉, −1, 2^K)`; a parallel axis passes
//! (`0`, `2^K`) iff `lo ≤ p_hi` and `p_lo ≤ hi`, else (`2^K + 1`, `−1`).
//! `hit = valid ∧ T0 ≤ T1 ∧ max near_q ≤ min far_q`; the slot's **entry** is
//! `max near_q`, meaning the distance `T0 + entry·2^G`, a lower bound of the
//! exact entry parameter.
//!
//! **Sort**: hits first, smaller entry first, ties (and misses among
//! themselves) by slot index ascending; a miss reports the sentinel entry
//! [`NodeParams::miss_entry`] (all ones, `K + 1` bits).
//!
//! **Bad input** (`bad` set): NaN in `o`, `inv_d`, `t_min`, `t_max`; an
//! infinite `o`; `inv_d = ±0` (that is `d = ±∞`); a frame origin not finite or
//! a scale exponent outside `[emin, emax]`; a valid slot with `lo > hi` or an
//! integer above `2^q − 1`. Then every valid slot is reported a hit with
//! entry 0 (never a silent miss of a valid child) and `T0 = −∞`.

use crate::exact::ray_box::{decode, Exact};
use crate::float::FloatFormat;
use crate::wide::MAX_CHILDREN;
use dashu::base::{BitTest, UnsignedAbs};
use dashu::integer::IBig;
use std::cmp::Ordering;

/// The shape of a node test: ray format, slots, box integers, grid and step
/// precision. Only [`NodeParams::new`] makes one, so every value is valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeParams {
    fmt: FloatFormat,
    children: usize,
    box_bits: u32,
    grid_bits: u32,
    step_bits: u32,
    node_bits: u32,
}

impl NodeParams {
    /// `children` 2, 4 or 8; `box_bits` (q) 4..=16; `fmt` with at most 10
    /// exponent bits (as [`crate::wide::WideFormat`]); the grid and step
    /// precision at their defaults ([`NodeParams::with_precision`]).
    pub fn new(fmt: FloatFormat, children: usize, box_bits: u32) -> Result<Self, String> {
        Self::with_precision(fmt, children, box_bits, box_bits + 6, box_bits + 8)
    }

    /// As [`NodeParams::new`] with the grid bits `K` (4..=30) and the step's
    /// significant bits `S` (2..=F + 1) given.
    pub fn with_precision(
        fmt: FloatFormat,
        children: usize,
        box_bits: u32,
        grid_bits: u32,
        step_bits: u32,
    ) -> Result<Self, String> {
        if ![2, 4, 8].contains(&children) {
            return Err(format!("children must be 2, 4 or 8, not {children}"));
        }
        if !(4..=16).contains(&box_bits) {
            return Err(format!("box_bits must be 4..=16, not {box_bits}"));
        }
        if fmt.exp_bits() > 10 {
            return Err(format!(
                "the ray format has {} exponent bits, at most 10",
                fmt.exp_bits()
            ));
        }
        if !(4..=30).contains(&grid_bits) {
            return Err(format!("grid_bits must be 4..=30, not {grid_bits}"));
        }
        let step_bits = step_bits.min(fmt.frac_bits() + 1);
        if step_bits < 2 {
            return Err(format!("step_bits must be at least 2, not {step_bits}"));
        }
        Ok(NodeParams {
            fmt,
            children,
            box_bits,
            grid_bits,
            step_bits,
            // the ray's precision, q + 4 bits more: the per-node part rounds
            // `O − o` whose magnitude exceeds the node's by up to the ray's
            // distance (docs/node.md §4)
            node_bits: fmt.frac_bits() + 1 + box_bits + 4,
        })
    }

    /// With the per-node precision `P` (the significant bits of `O − o`,
    /// `c` and the window; `F + 1 ..= 64`) given.
    pub fn with_node_bits(self, node_bits: u32) -> Result<Self, String> {
        if !(self.fmt.frac_bits() + 1..=64).contains(&node_bits) {
            return Err(format!("node_bits must be F + 1 ..= 64, not {node_bits}"));
        }
        Ok(NodeParams { node_bits, ..self })
    }

    /// The ray format.
    pub fn fmt(self) -> FloatFormat {
        self.fmt
    }
    /// Slots per node.
    pub fn children(self) -> usize {
        self.children
    }
    /// Bits per box integer (q).
    pub fn box_bits(self) -> u32 {
        self.box_bits
    }
    /// Bits of the grid (K): the window is at most `2^K` grid steps.
    pub fn grid_bits(self) -> u32 {
        self.grid_bits
    }
    /// Significant bits of the per-node step (S).
    pub fn step_bits(self) -> u32 {
        self.step_bits
    }
    /// Significant bits of the per-node values (P).
    pub fn node_bits(self) -> u32 {
        self.node_bits
    }
    /// The entry reported for a miss: all ones in `K + 1` bits (no hit's
    /// entry reaches it, as a hit's entry is at most `2^K`).
    pub fn miss_entry(self) -> u32 {
        (1 << (self.grid_bits + 1)) - 1
    }
}

/// One ray, raw bits of the ray format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Ray {
    /// origin
    pub o: [u64; 3],
    /// `RTZ(1/d)` per axis (`±∞` for a zero component)
    pub inv_d: [u64; 3],
    /// segment start
    pub t_min: u64,
    /// segment end
    pub t_max: u64,
}

/// One node as the unit sees it: the frame and the slots' integers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeIn {
    /// frame origin per axis, raw bits of the ray format
    pub origin: [u64; 3],
    /// frame scale per axis: the unbiased exponent `e` of the step `2^e`
    pub exp: [i32; 3],
    /// bit i: slot i holds a child
    pub valid: u8,
    /// per slot and axis the lower integer
    pub lo: [[u16; 3]; MAX_CHILDREN],
    /// per slot and axis the upper integer
    pub hi: [[u16; 3]; MAX_CHILDREN],
}

impl NodeIn {
    /// The unit's view of a [`crate::wide::Node`].
    pub fn from_wide(n: &crate::wide::Node) -> NodeIn {
        NodeIn {
            origin: n.frame.origin,
            exp: n.frame.exp,
            valid: n.valid,
            lo: n.lo,
            hi: n.hi,
        }
    }
}

/// One output slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlotOut {
    /// the ray may meet the child's decoded box with `t` in `[t_min, t_max]`
    pub hit: bool,
    /// grid steps from `T0` to a lower bound of the entry (`0..=2^K`), or
    /// [`NodeParams::miss_entry`]
    pub entry: u32,
    /// the slot index
    pub child: u8,
}

/// A dyadic rational `m · 2^e`, exact.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Dyadic {
    /// significand
    pub m: IBig,
    /// power of two
    pub e: i64,
}

/// A value or −∞ (the window start when every axis is parallel and
/// `t_min = −∞`, or after bad input).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Bound {
    /// −∞
    NegInf,
    /// a finite value
    Fin(Dyadic),
}

/// The result of one node test.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeOut {
    /// bad input (module doc): every valid slot is a hit with entry 0
    pub bad: bool,
    /// `T0`, the window start: a slot's entry distance is `T0 + entry·2^G`
    pub t_base: Bound,
    /// `G`, the grid's exponent
    pub grid_exp: i64,
    /// the slots, sorted (module doc); `children` of them
    pub slots: Vec<SlotOut>,
}

impl NodeOut {
    /// The entry distance a hit slot stands for: `T0 + entry·2^G`.
    pub fn entry_value(&self, slot: &SlotOut) -> Bound {
        match &self.t_base {
            Bound::NegInf => Bound::NegInf,
            Bound::Fin(t0) => {
                Bound::Fin(t0.add(&Dyadic::new(IBig::from(slot.entry), self.grid_exp)))
            }
        }
    }
}

impl Dyadic {
    /// `m · 2^e`.
    pub fn new(m: IBig, e: i64) -> Dyadic {
        Dyadic { m, e }
    }
    /// `self + other`, exact.
    pub fn add(&self, other: &Dyadic) -> Dyadic {
        let e = self.e.min(other.e);
        Dyadic::new(
            (&self.m << (self.e - e) as usize) + (&other.m << (other.e - e) as usize),
            e,
        )
    }
    /// `self − other`, exact.
    pub fn sub(&self, other: &Dyadic) -> Dyadic {
        self.add(&other.neg())
    }
    /// `−self`.
    pub fn neg(&self) -> Dyadic {
        Dyadic::new(-&self.m, self.e)
    }
    /// `self · other`, exact.
    pub fn mul(&self, other: &Dyadic) -> Dyadic {
        Dyadic::new(&self.m * &other.m, self.e + other.e)
    }
    /// `self · 2^k`, exact.
    pub fn scale(&self, k: i64) -> Dyadic {
        Dyadic::new(self.m.clone(), self.e + k)
    }
    /// The sign: −1, 0 or 1.
    pub fn signum(&self) -> i32 {
        match self.m.cmp(&IBig::ZERO) {
            Ordering::Less => -1,
            Ordering::Equal => 0,
            Ordering::Greater => 1,
        }
    }
    /// Exact comparison.
    pub fn cmp_exact(&self, other: &Dyadic) -> Ordering {
        self.sub(other).signum().cmp(&0)
    }
    /// `⌊self / 2^g⌋` (`up = false`) or `⌈self / 2^g⌉` (`up = true`).
    pub fn div_pow2_round(&self, g: i64, up: bool) -> IBig {
        let k = self.e - g;
        if k >= 0 {
            return &self.m << k as usize;
        }
        let sh = (-k) as usize;
        // `>>` on IBig floors (rounds toward −∞)
        let fl = &self.m >> sh;
        if up && (&fl << sh) != self.m {
            fl + IBig::ONE
        } else {
            fl
        }
    }
    /// Rounded down (`up = false`) or up to `p` significant bits, exponent
    /// unbounded.
    pub fn round(&self, p: u32, up: bool) -> Dyadic {
        let len = (&self.m).unsigned_abs().bit_len() as i64;
        if len <= p as i64 {
            return self.clone();
        }
        let g = self.e + len - p as i64;
        Dyadic::new(self.div_pow2_round(g, up), g)
    }
    /// `floor(log2 |self|)`; `self` nonzero.
    fn ilog2(&self) -> i64 {
        (&self.m).unsigned_abs().bit_len() as i64 - 1 + self.e
    }
    /// Approximately, as `f64` (for reports).
    pub fn to_f64(&self) -> f64 {
        let len = (&self.m).unsigned_abs().bit_len() as i64;
        let sh = (len - 60).max(0);
        let top: i64 = (&self.m >> sh as usize).try_into().unwrap_or(0);
        top as f64 * 2f64.powi((self.e + sh).clamp(-2000, 2000) as i32)
    }
}

/// A finite input decoded exactly; `None` for NaN and ±∞.
fn finite(fmt: FloatFormat, bits: u64) -> Option<Dyadic> {
    match decode(fmt, bits) {
        Exact::Fin { m, e } => Some(Dyadic::new(IBig::from(m), e as i64)),
        _ => None,
    }
}

/// Per-axis view of the ray after the node part.
enum Axis {
    /// `inv_d = ±∞`: the origin lies within frame steps `[lo, hi]` (clamped to `−1 ..= 2^q`)
    Parallel { lo: i64, hi: i64 },
    /// `t(n) ∈ [c_lo + s·n·st, c_hi + s·n·st]`, `st ∈ [st_lo, st_hi]`
    Slab {
        neg: bool,
        c_lo: Dyadic,
        c_hi: Dyadic,
        st_lo: Dyadic,
        st_hi: Dyadic,
    },
}

impl Axis {
    /// Lower bound of the entry and upper bound of the exit of the slab
    /// `[lo, hi]` (frame integers); `None` for a parallel axis.
    fn bounds(&self, lo: i64, hi: i64) -> Option<(Dyadic, Dyadic)> {
        match self {
            Axis::Parallel { .. } => None,
            Axis::Slab {
                neg,
                c_lo,
                c_hi,
                st_lo,
                st_hi,
            } => {
                let n = |k: i64| Dyadic::new(IBig::from(k), 0);
                Some(if *neg {
                    // t(n) = c − n·step: entry on `hi`, exit on `lo`
                    (c_lo.sub(&st_hi.mul(&n(hi))), c_hi.sub(&st_lo.mul(&n(lo))))
                } else {
                    (c_lo.add(&st_lo.mul(&n(lo))), c_hi.add(&st_hi.mul(&n(hi))))
                })
            }
        }
    }
}

/// Evaluates one node test (module doc; `docs/node.md`).
pub fn eval(p: NodeParams, ray: &Ray, node: &NodeIn) -> NodeOut {
    let fmt = p.fmt;
    let n_slots = p.children;
    let q_max = (1i64 << p.box_bits) - 1;
    let prec = p.node_bits;
    let valid = |i: usize| node.valid >> i & 1 == 1;
    let bad_out = || {
        let mut slots: Vec<SlotOut> = (0..n_slots)
            .map(|i| SlotOut {
                hit: valid(i),
                entry: if valid(i) { 0 } else { p.miss_entry() },
                child: i as u8,
            })
            .collect();
        sort(&mut slots);
        NodeOut {
            bad: true,
            t_base: Bound::NegInf,
            grid_exp: 0,
            slots,
        }
    };
    // bad input (module doc)
    let slot_bad = (0..n_slots).any(|i| {
        valid(i) && (0..3).any(|a| node.lo[i][a] > node.hi[i][a] || node.hi[i][a] as i64 > q_max)
    });
    let frame_bad = (0..3).any(|a| {
        !fmt.is_finite(node.origin[a]) || !(fmt.emin()..=fmt.emax()).contains(&node.exp[a])
    });
    let ray_bad = (0..3).any(|a| {
        !fmt.is_finite(ray.o[a])
            || fmt.is_nan(ray.inv_d[a])
            || ray.inv_d[a] & !fmt.sign_bit() & fmt.mask() == 0
    }) || fmt.is_nan(ray.t_min)
        || fmt.is_nan(ray.t_max);
    if slot_bad || frame_bad || ray_bad {
        return bad_out();
    }
    let max_finite = finite(fmt, fmt.max_finite(false)).expect("finite");
    // 1/min_subnormal: the largest |1/d| of a nonzero d
    let recip_cap = Dyadic::new(IBig::ONE, (fmt.frac_bits() as i64) - fmt.emin() as i64);
    let mut axes = Vec::with_capacity(3);
    for a in 0..3 {
        let o = finite(fmt, ray.o[a]).expect("checked");
        let origin = finite(fmt, node.origin[a]).expect("checked");
        let e = node.exp[a] as i64;
        let c = ray.inv_d[a] & fmt.mask();
        let neg = c & fmt.sign_bit() != 0;
        let mag = c & !fmt.sign_bit();
        if mag == fmt.inf(false) {
            // position of the origin in frame steps, rounded outward
            let dp = o.sub(&origin);
            let lo = dp.round(prec, false).div_pow2_round(e, true);
            let hi = dp.round(prec, true).div_pow2_round(e, false);
            let clamp = |v: IBig| -> i64 {
                if v < IBig::from(-1) {
                    -1
                } else if v > IBig::from(q_max + 1) {
                    q_max + 1
                } else {
                    i64::try_from(v).expect("clamped")
                }
            };
            axes.push(Axis::Parallel {
                lo: clamp(lo),
                hi: clamp(hi),
            });
            continue;
        }
        let ra = finite(fmt, mag).expect("finite");
        let rb = if ra == max_finite {
            recip_cap.clone()
        } else {
            finite(fmt, mag + 1).expect("finite successor")
        };
        let dm = origin.sub(&o);
        let dm = if neg { dm.neg() } else { dm };
        let d_lo = dm.round(prec, false);
        let d_hi = dm.round(prec, true);
        let c_lo = d_lo
            .mul(if d_lo.signum() < 0 { &rb } else { &ra })
            .round(prec, false);
        let c_hi = d_hi
            .mul(if d_hi.signum() > 0 { &rb } else { &ra })
            .round(prec, true);
        let st_lo = ra.round(p.step_bits, false).scale(e);
        let st_hi = rb.round(p.step_bits, true).scale(e);
        axes.push(Axis::Slab {
            neg,
            c_lo,
            c_hi,
            st_lo,
            st_hi,
        });
    }
    // the window: the node box [0, 2^q − 1] on every axis and [t_min, t_max]
    let mut node_miss = false;
    let mut t0 = match decode(fmt, ray.t_min) {
        Exact::Fin { m, e } => Bound::Fin(Dyadic::new(IBig::from(m), e as i64)),
        Exact::NegInf => Bound::NegInf,
        _ => {
            node_miss = true; // t_min = +∞: nothing is reachable
            Bound::NegInf
        }
    };
    let mut t1: Option<Dyadic> = match decode(fmt, ray.t_max) {
        Exact::Fin { m, e } => Some(Dyadic::new(IBig::from(m), e as i64)),
        Exact::PosInf => None,
        _ => {
            node_miss = true; // t_max = −∞
            None
        }
    };
    for ax in &axes {
        match ax {
            Axis::Parallel { lo, hi } => node_miss |= *hi < 0 || *lo > q_max,
            Axis::Slab { .. } => {
                let (ne, nx) = ax.bounds(0, q_max).expect("slab");
                let (ne, nx) = (ne.round(prec, false), nx.round(prec, true));
                t0 = match t0 {
                    Bound::Fin(v) if v.cmp_exact(&ne) == Ordering::Greater => Bound::Fin(v),
                    _ => Bound::Fin(ne),
                };
                t1 = Some(match t1 {
                    Some(v) if v.cmp_exact(&nx) == Ordering::Less => v,
                    _ => nx,
                });
            }
        }
    }
    let k = p.grid_bits as i64;
    let grid_exp = match (&t0, &t1) {
        (Bound::Fin(a), Some(b)) => {
            let w = b.sub(a);
            match w.signum() {
                1 => w.ilog2() + 1 - k,
                0 => 0,
                _ => {
                    node_miss = true;
                    0
                }
            }
        }
        // every axis parallel: one grid cell, no distance information
        _ => 0,
    };
    let top = 1i64 << k;
    // the window's end on the grid, `ceil((T1 − T0)/2^G) ≤ 2^K`: no exit
    // needs to reach past it
    let far_top = match (&t0, &t1) {
        (Bound::Fin(a), Some(b)) if !node_miss => {
            i64::try_from(b.sub(a).div_pow2_round(grid_exp, true).min(IBig::from(top)))
                .expect("≤ 2^K")
        }
        _ => top,
    };
    let mut slots = Vec::with_capacity(n_slots);
    for i in 0..n_slots {
        let mut hit = valid(i) && !node_miss;
        let mut near_max = 0i64;
        let mut far_min = far_top;
        if hit {
            for (a, ax) in axes.iter().enumerate() {
                let (lo, hi) = (node.lo[i][a] as i64, node.hi[i][a] as i64);
                let (nq, fq) = match (ax, &t0) {
                    (Axis::Parallel { lo: pl, hi: ph }, _) => {
                        if lo <= *ph && *pl <= hi {
                            (0, far_top)
                        } else {
                            (top + 1, -1)
                        }
                    }
                    (Axis::Slab { .. }, Bound::Fin(t0v)) => {
                        let (near, far) = ax.bounds(lo, hi).expect("slab");
                        let nq = near.sub(t0v).div_pow2_round(grid_exp, false);
                        let fq = far.sub(t0v).div_pow2_round(grid_exp, true);
                        let clamp = |v: IBig, lo: i64, hi: i64| {
                            i64::try_from(v.clamp(IBig::from(lo), IBig::from(hi))).expect("clamped")
                        };
                        (clamp(nq, 0, top + 1), clamp(fq, -1, far_top))
                    }
                    (Axis::Slab { .. }, Bound::NegInf) => {
                        unreachable!("a slab axis makes T0 finite")
                    }
                };
                near_max = near_max.max(nq);
                far_min = far_min.min(fq);
            }
            hit = near_max <= far_min;
        }
        slots.push(SlotOut {
            hit,
            entry: if hit { near_max as u32 } else { p.miss_entry() },
            child: i as u8,
        });
    }
    sort(&mut slots);
    NodeOut {
        bad: false,
        t_base: if node_miss { Bound::NegInf } else { t0 },
        grid_exp,
        slots,
    }
}

/// The order of the outputs: hits first, smaller entry first, then slot index.
pub fn sort(slots: &mut [SlotOut]) {
    slots.sort_by_key(|s| (!s.hit, s.entry, s.child));
}
