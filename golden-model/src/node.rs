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
//! **Per node, once** (per axis, with `Q = 2^q − 1`, the frame plane
//! `O + n·2^e`, and mirrored plane indices `m = n`, or `m = Q − n` when
//! `inv_d < 0`, so that `t` grows with `m`):
//! 1. `D = ±(O − o)` rounded down and up to `P` significant bits
//!    (`node_bits`, default `F + q + 5`: the ray's precision and `q + 4`
//!    more; exponent unbounded, nothing overflows);
//!    `c_lo = RDN_P(D_lo · (D_lo < 0 ? b : a))`, `c_hi = RUP_P(D_hi · (D_hi > 0 ? b : a))`;
//!    the plane `m` is crossed at a `t` in `[A_lo + m·σ_lo, A_hi + m·σ_hi]`
//!    (two lines: `A = c`, `σ_lo = a·2^e`, `σ_hi = b·2^e`, or when mirrored
//!    `A_lo = c_lo − Q·b·2^e`, `σ_lo = b·2^e`, `A_hi = c_hi − Q·a·2^e`,
//!    `σ_hi = a·2^e`);
//! 2. the **window** `T0 = max(t_min, RDN_P(A_lo))` over the axes,
//!    `T1 = min(t_max, RUP_P(A_hi + Q·σ_hi))` (the node box on every axis);
//!    an axis with `inv_d = ±∞` (parallel) instead bounds the origin's
//!    position in frame steps, `[p_lo, p_hi]` (`o − O` rounded outward to
//!    `P` bits); `T0 > T1` or a parallel axis outside `[0, Q]`: every slot
//!    misses;
//! 3. the **grid** `2^G`, `G` the least integer with `T1 − T0 < 2^(G + K)`
//!    (`K = grid_bits`, default `q + 4`); per-node integers are in units
//!    `2^(G − f)` (`f = grid_frac`, default 4) and saturate at
//!    `±Z = ±2^(K + f + 1)`;
//! 4. per line an **anchor** `n0`, the last plane at or before `T0`
//!    (`⌊(T0 − A)/σ⌋` clamped to `[0, Q]`, from a short division corrected
//!    by one exact sign), and the line at `n0 − 1`, `n0`, `n0 + 1` minus
//!    `T0`, and `σ`, in grid units rounded outward (down for the lower
//!    line, up for the upper; the slope both ways).
//!
//! **Per child** (integers of `q + 1` and `K + f + 2` bits, one small
//! product per bound): for the entry plane `me` and exit plane `mx` of each
//! non-parallel axis, `d = me − n0`: `near = 0` if `d < 0`, else
//! `⌊(L[n0 + min(d, 1)] + max(d − 1, 0)·σ_dn) / 2^f⌋`, clamped to
//! `[0, 2^K + 1]`; `far` likewise from the upper line with `ceil`, the slope
//! rounded to make it an upper bound, clamped to `[−1, ⌈(T1 − T0)/2^G⌉]`; a
//! parallel axis passes (`0`, top) iff `lo ≤ p_hi` and `p_lo ≤ hi`, else
//! (`2^K + 1`, `−1`). `hit = valid ∧ max near ≤ min far`; the slot's
//! **entry** is `max near`, standing for the distance `T0 + entry·2^G`, a
//! lower bound of the exact entry parameter.
//!
//! [`terms`] computes steps 1-4 (the per-node integers, [`NodeTerms`]) and
//! [`child`] step 5 for one slot: the boundary of the RTL blocks
//! `node_child` and `node_sort` (`docs/node.md` §7-8); [`eval`] is both and
//! the sort.
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

/// The shape of a node test: ray format, slots, box integers, grid and
/// per-node precision. Only [`NodeParams::new`] makes one, so every value is valid.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct NodeParams {
    fmt: FloatFormat,
    children: usize,
    box_bits: u32,
    grid_bits: u32,
    grid_frac: u32,
    node_bits: u32,
}

impl NodeParams {
    /// `children` 2, 4 or 8; `box_bits` (q) 4..=16; `fmt` with at most 10
    /// exponent bits (as [`crate::wide::WideFormat`]); the grid at its
    /// default, `K = q + 4`, `f = 4` (`docs/node.md` §4 measures others).
    pub fn new(fmt: FloatFormat, children: usize, box_bits: u32) -> Result<Self, String> {
        Self::with_precision(fmt, children, box_bits, box_bits + 4, 4)
    }

    /// As [`NodeParams::new`] with the grid bits `K` (4..=24) and the
    /// fraction bits `f` below a grid step (0..=16) given.
    pub fn with_precision(
        fmt: FloatFormat,
        children: usize,
        box_bits: u32,
        grid_bits: u32,
        grid_frac: u32,
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
        if !(4..=24).contains(&grid_bits) {
            return Err(format!("grid_bits must be 4..=24, not {grid_bits}"));
        }
        if grid_frac > 16 {
            return Err(format!("grid_frac must be 0..=16, not {grid_frac}"));
        }
        Ok(NodeParams {
            fmt,
            children,
            box_bits,
            grid_bits,
            grid_frac,
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
    /// Fraction bits below a grid step (f) of the per-node integers.
    pub fn grid_frac(self) -> u32 {
        self.grid_frac
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
    /// `⌊log2 |v|⌋` of a nonzero value.
    pub fn ilog2(&self) -> i64 {
        (&self.m).unsigned_abs().bit_len() as i64 - 1 + self.e
    }
}

/// A finite input decoded exactly; `None` for NaN and ±∞.
pub(crate) fn finite(fmt: FloatFormat, bits: u64) -> Option<Dyadic> {
    match decode(fmt, bits) {
        Exact::Fin { m, e } => Some(Dyadic::new(IBig::from(m), e as i64)),
        _ => None,
    }
}

/// `[a, b]`, the bounds of `|1/d|` given `a = |inv_d|` (raw magnitude bits
/// `mag`, finite and nonzero): `b` the successor of `a`, or `1/min_subnormal`
/// (the largest `|1/d|` of a nonzero `d`) when `a` is the largest finite value.
pub(crate) fn reciprocal_bounds(fmt: FloatFormat, mag: u64) -> (Dyadic, Dyadic) {
    let a = finite(fmt, mag).expect("finite");
    let b = if mag == fmt.max_finite(false) {
        Dyadic::new(IBig::ONE, (fmt.frac_bits() as i64) - fmt.emin() as i64)
    } else {
        finite(fmt, mag + 1).expect("finite successor")
    };
    (a, b)
}

/// Per-axis view of the ray after the first node step.
enum Axis {
    /// `inv_d = ±∞`: the origin lies within frame steps `[lo, hi]` (clamped to `−1 ..= 2^q`)
    Parallel { lo: i64, hi: i64 },
    /// In mirrored plane indices `m = n` (or `2^q − 1 − n` when `inv_d < 0`),
    /// the plane `m` is crossed at `t ∈ [a_lo + m·s_lo, a_hi + m·s_hi]`.
    Slab {
        mirror: bool,
        a_lo: Dyadic,
        a_hi: Dyadic,
        s_lo: Dyadic,
        s_hi: Dyadic,
    },
}

/// A lower bound in grid units `2^(G − f)`, or −∞ (below `−Z`).
#[derive(Debug, Clone, Copy)]
enum Low {
    NegInf,
    V(i64),
}

/// An upper bound in grid units, or +∞ (above `Z`).
#[derive(Debug, Clone, Copy)]
enum High {
    PosInf,
    V(i64),
}

/// The per-node integers of one bounding line, anchored at the plane `n0`
/// where the line crosses the window start (`line(n0) ≤ T0 < line(n0 + 1)`
/// unless clamped to `0` or `2^q − 1`): the line at planes `n0 − 1`, `n0`,
/// `n0 + 1` minus `T0`, and its slope rounded down and up, all in grid units
/// `2^(G − f)`, saturated at `±Z` (`docs/node.md` §2).
struct Line<B> {
    n0: i64,
    at: [B; 3],
    slope_dn: i64,
    slope_up: Option<i64>,
}

/// The per-node part of one non-parallel axis.
struct SlabAxis {
    mirror: bool,
    near: Line<Low>,
    far: Line<High>,
}

/// `⌊num/den⌋` clamped to `0 ..= max` (`den > 0`).
fn floor_div_clamped(num: &Dyadic, den: &Dyadic, max: i64) -> i64 {
    if num.signum() <= 0 {
        return 0;
    }
    if num.ilog2() - den.ilog2() > 62 {
        return max;
    }
    let k = num.e - den.e;
    let (n, d) = if k >= 0 {
        (&num.m << k as usize, den.m.clone())
    } else {
        (num.m.clone(), &den.m << (-k) as usize)
    };
    i64::try_from(n / d).map_or(max, |v| v.min(max))
}

/// Evaluates one node test (module doc; `docs/node.md`).
pub fn eval(p: NodeParams, ray: &Ray, node: &NodeIn) -> NodeOut {
    let valid = |i: usize| node.valid >> i & 1 == 1;
    let Some((terms, t_base, grid_exp)) = analyse(p, ray, node) else {
        // bad input: every valid slot a hit with entry 0
        let mut slots: Vec<SlotOut> = (0..p.children)
            .map(|i| SlotOut {
                hit: valid(i),
                entry: if valid(i) { 0 } else { p.miss_entry() },
                child: i as u8,
            })
            .collect();
        sort(&mut slots);
        return NodeOut {
            bad: true,
            t_base: Bound::NegInf,
            grid_exp: 0,
            slots,
        };
    };
    // step 5: per child, integers only
    let mut slots: Vec<SlotOut> = (0..p.children)
        .map(|i| {
            let entry = child(p, &terms, valid(i), node.lo[i], node.hi[i]);
            SlotOut {
                hit: entry.is_some(),
                entry: entry.unwrap_or(p.miss_entry()),
                child: i as u8,
            }
        })
        .collect();
    sort(&mut slots);
    NodeOut {
        bad: false,
        t_base,
        grid_exp,
        slots,
    }
}

/// The per-node integers the per-child test reads (steps 1-4 of
/// `docs/node.md` §2), or `None` on bad input.
pub fn terms(p: NodeParams, ray: &Ray, node: &NodeIn) -> Option<NodeTerms> {
    analyse(p, ray, node).map(|(t, _, _)| t)
}

/// Steps 1-4: the per-node integers, `T0` (−∞ on a node miss) and `G`;
/// `None` on bad input.
fn analyse(p: NodeParams, ray: &Ray, node: &NodeIn) -> Option<(NodeTerms, Bound, i64)> {
    let fmt = p.fmt;
    let n_slots = p.children;
    let q_max = (1i64 << p.box_bits) - 1;
    let prec = p.node_bits;
    let valid = |i: usize| node.valid >> i & 1 == 1;
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
        return None;
    }
    let q_int = Dyadic::new(IBig::from(q_max), 0);

    // step 1: the ray in the node's frame, per axis
    let mut axes = Vec::with_capacity(3);
    for a in 0..3 {
        let o = finite(fmt, ray.o[a]).expect("checked");
        let origin = finite(fmt, node.origin[a]).expect("checked");
        let e = node.exp[a] as i64;
        let c = ray.inv_d[a] & fmt.mask();
        let mirror = c & fmt.sign_bit() != 0;
        let mag = c & !fmt.sign_bit();
        if mag == fmt.inf(false) {
            // position of the origin in frame steps, rounded outward
            let dp = o.sub(&origin);
            let lo = dp.round(prec, false).div_pow2_round(e, true);
            let hi = dp.round(prec, true).div_pow2_round(e, false);
            let clamp = |v: IBig| {
                i64::try_from(v.clamp(IBig::from(-1), IBig::from(q_max + 1))).expect("clamped")
            };
            axes.push(Axis::Parallel {
                lo: clamp(lo),
                hi: clamp(hi),
            });
            continue;
        }
        // |1/d| ∈ [ra, rb]
        let (ra, rb) = reciprocal_bounds(fmt, mag);
        // t(n) = s·(O − o)·|1/d| + s·n·2^e·|1/d|, s = −1 when mirrored
        let dm = origin.sub(&o);
        let dm = if mirror { dm.neg() } else { dm };
        let d_lo = dm.round(prec, false);
        let d_hi = dm.round(prec, true);
        let c_lo = d_lo
            .mul(if d_lo.signum() < 0 { &rb } else { &ra })
            .round(prec, false);
        let c_hi = d_hi
            .mul(if d_hi.signum() > 0 { &rb } else { &ra })
            .round(prec, true);
        let (st_lo, st_hi) = (ra.scale(e), rb.scale(e));
        axes.push(if mirror {
            // t = c − n·st = (c − Q·st) + m·st, m = Q − n: the lower line
            // takes the larger step, the upper line the smaller
            Axis::Slab {
                mirror,
                a_lo: c_lo.sub(&q_int.mul(&st_hi)),
                a_hi: c_hi.sub(&q_int.mul(&st_lo)),
                s_lo: st_hi,
                s_hi: st_lo,
            }
        } else {
            Axis::Slab {
                mirror,
                a_lo: c_lo,
                a_hi: c_hi,
                s_lo: st_lo,
                s_hi: st_hi,
            }
        });
    }

    // step 2: the window, the node box `[0, 2^q − 1]` on every axis within [t_min, t_max]
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
            Axis::Slab {
                a_lo, a_hi, s_hi, ..
            } => {
                let ne = a_lo.round(prec, false);
                let nx = a_hi.add(&q_int.mul(s_hi)).round(prec, true);
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
    // step 3: the grid
    let k = p.grid_bits as i64;
    let f = p.grid_frac as i64;
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

    // step 4: per axis the plane n0 at the window start and the lines' integers
    let z = 1i64 << (k + f + 1);
    let unit = grid_exp - f;
    let slabs: Vec<Option<SlabAxis>> = axes
        .iter()
        .map(|ax| {
            let Axis::Slab {
                mirror,
                a_lo,
                a_hi,
                s_lo,
                s_hi,
            } = ax
            else {
                return None;
            };
            let Bound::Fin(t0v) = &t0 else {
                unreachable!("a slab axis makes T0 finite")
            };
            let at = |base: &Dyadic, slope: &Dyadic, m: i64, up: bool| {
                let v = base
                    .add(&slope.mul(&Dyadic::new(IBig::from(m), 0)))
                    .sub(t0v);
                v.div_pow2_round(unit, up)
            };
            // the anchor: ⌊(T0 − base)/slope⌋ from operands rounded to q + 4
            // bits (low by at most one), then corrected by the sign of the
            // line at the next plane
            let anchor = |base: &Dyadic, slope: &Dyadic| {
                let short = p.box_bits + 4;
                let num = t0v.sub(base).round(short, false);
                let n0 = floor_div_clamped(&num, &slope.round(short, true), q_max);
                if n0 < q_max && at(base, slope, n0 + 1, false) < IBig::ZERO {
                    n0 + 1
                } else {
                    n0
                }
            };
            let low = |v: IBig| {
                if v < IBig::from(-z) {
                    Low::NegInf
                } else {
                    Low::V(i64::try_from(v.min(IBig::from(z))).expect("clamped"))
                }
            };
            let high = |v: IBig| {
                if v > IBig::from(z) {
                    High::PosInf
                } else {
                    High::V(i64::try_from(v.max(IBig::from(-z))).expect("clamped"))
                }
            };
            let slope = |s: &Dyadic, up: bool| -> Option<i64> {
                let v = s.div_pow2_round(unit, up);
                (v <= IBig::from(z)).then(|| i64::try_from(v).expect("≤ Z"))
            };
            let (n_lo, n_hi) = (anchor(a_lo, s_lo), anchor(a_hi, s_hi));
            Some(SlabAxis {
                mirror: *mirror,
                near: Line {
                    n0: n_lo,
                    at: [-1, 0, 1].map(|d| low(at(a_lo, s_lo, n_lo + d, false))),
                    slope_dn: slope(s_lo, false).unwrap_or(z),
                    slope_up: slope(s_lo, true),
                },
                far: Line {
                    n0: n_hi,
                    at: [-1, 0, 1].map(|d| high(at(a_hi, s_hi, n_hi + d, true))),
                    slope_dn: slope(s_hi, false).unwrap_or(z),
                    slope_up: slope(s_hi, true),
                },
            })
        })
        .collect();

    let axes = [0, 1, 2].map(|a| match (&axes[a], &slabs[a]) {
        (Axis::Parallel { lo, hi }, _) => ChildAxis::Parallel { lo: *lo, hi: *hi },
        (Axis::Slab { .. }, Some(sa)) => ChildAxis::Slab(SlabTerms {
            mirror: sa.mirror,
            near_n0: sa.near.n0,
            near_at: [sa.near.at[1], sa.near.at[2]].map(|v| match v {
                Low::NegInf => None,
                Low::V(v) => Some(v),
            }),
            near_slope: sa.near.slope_dn,
            far_n0: sa.far.n0,
            far_at: sa.far.at.map(|v| match v {
                High::PosInf => None,
                High::V(v) => Some(v),
            }),
            far_slope_dn: sa.far.slope_dn,
            far_slope_up: sa.far.slope_up,
        }),
        (Axis::Slab { .. }, None) => unreachable!("every slab axis has its integers"),
    });
    let terms = NodeTerms {
        miss: node_miss,
        far_top,
        axes,
    };
    let t_base = if node_miss { Bound::NegInf } else { t0 };
    Some((terms, t_base, grid_exp))
}

/// The per-node integers of one axis that the per-child test reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChildAxis {
    /// `inv_d = ±∞`: the origin lies within frame steps `[lo, hi]` (`−1 ..= 2^q`)
    Parallel {
        /// lowest step
        lo: i64,
        /// highest step
        hi: i64,
    },
    /// a slab axis
    Slab(SlabTerms),
}

/// One slab axis's lines in grid units `2^(G − f)` (`docs/node.md` §2 step
/// 4), each within `±Z = ±2^(K + f + 1)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlabTerms {
    /// plane indices mirrored (`inv_d < 0`)
    pub mirror: bool,
    /// the lower line's anchor plane (`0 ..= 2^q − 1`)
    pub near_n0: i64,
    /// the lower line at `n0`, `n0 + 1` minus `T0`, rounded down; `None` is −∞
    pub near_at: [Option<i64>; 2],
    /// the lower line's slope rounded down (`0 ..= Z`)
    pub near_slope: i64,
    /// the upper line's anchor plane
    pub far_n0: i64,
    /// the upper line at `n0 − 1`, `n0`, `n0 + 1` minus `T0`, rounded up; `None` is +∞
    pub far_at: [Option<i64>; 3],
    /// the upper line's slope rounded down (`0 ..= Z`)
    pub far_slope_dn: i64,
    /// the upper line's slope rounded up; `None` above `Z`
    pub far_slope_up: Option<i64>,
}

/// What the per-child test reads of a node: computed once per node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NodeTerms {
    /// every slot misses (empty window, or a parallel axis outside the node)
    pub miss: bool,
    /// `⌈(T1 − T0)/2^G⌉ ≤ 2^K`, the grid cell of the window's end
    pub far_top: i64,
    /// per axis
    pub axes: [ChildAxis; 3],
}

/// Step 5, one slot: its entry in grid steps if it may be hit, `None` if
/// it misses (integers only; `docs/node.md` §2).
pub fn child(p: NodeParams, t: &NodeTerms, valid: bool, lo: [u16; 3], hi: [u16; 3]) -> Option<u32> {
    if !valid || t.miss {
        return None;
    }
    let q_max = (1i64 << p.box_bits) - 1;
    let f = p.grid_frac as i64;
    let top = 1i64 << p.grid_bits;
    let mut near_max = 0i64;
    let mut far_min = t.far_top;
    for (a, ax) in t.axes.iter().enumerate() {
        let (lo, hi) = (lo[a] as i64, hi[a] as i64);
        let (nq, fq) = match ax {
            ChildAxis::Parallel { lo: pl, hi: ph } => {
                if lo <= *ph && *pl <= hi {
                    (0, t.far_top)
                } else {
                    (top + 1, -1)
                }
            }
            ChildAxis::Slab(sa) => {
                // entry and exit planes in mirrored indices
                let (me, mx) = if sa.mirror {
                    (q_max - hi, q_max - lo)
                } else {
                    (lo, hi)
                };
                (
                    near_cell(sa, me - sa.near_n0, f, top),
                    far_cell(sa, mx - sa.far_n0, f, t.far_top),
                )
            }
        };
        near_max = near_max.max(nq);
        far_min = far_min.min(fq);
    }
    (near_max <= far_min).then_some(near_max as u32)
}

/// The entry bound's grid cell `clamp(⌊v / 2^f⌋, 0, 2^K + 1)` for the plane
/// `d` planes after the anchor: `0` for `d < 0` (the line is at or before
/// the window start there), `v = at[n0]` for `d = 0`, and
/// `v = at[n0 + 1] + (d − 1)·slope_dn` after it (never −∞: the anchor puts
/// the next plane at or after the window start).
fn near_cell(l: &SlabTerms, d: i64, f: i64, top: i64) -> i64 {
    let v = match (d, l.near_at[0], l.near_at[1]) {
        (..=-1, _, _) | (0, None, _) | (1.., _, None) => return 0,
        (0, Some(b), _) => b as i128,
        (1.., _, Some(b)) => b as i128 + (d - 1) as i128 * l.near_slope as i128,
    };
    (v >> f).clamp(0, top as i128 + 1) as i64
}

/// The exit bound's grid cell `clamp(⌈v / 2^f⌉, −1, far_top)`, or −1 when
/// `v < 0` (the exit is before the window start), with
/// `v = at[n0 − 1] + (d + 1)·slope_dn`, `at[n0]` or `at[n0 + 1] + (d − 1)·slope_up`.
fn far_cell(l: &SlabTerms, d: i64, f: i64, far_top: i64) -> i64 {
    let (base, k, slope) = match d {
        ..=-1 => (l.far_at[0], d + 1, Some(l.far_slope_dn)),
        0 => (l.far_at[1], 0, Some(0)),
        _ => (l.far_at[2], d - 1, l.far_slope_up),
    };
    let v = match (base, slope) {
        (None, _) => return far_top,
        (_, None) if k > 0 => return far_top,
        (Some(b), None) => b as i128,
        (Some(b), Some(s)) => b as i128 + k as i128 * s as i128,
    };
    if v < 0 {
        // the exit is before the window start: no `t` of the window is in the
        // child, however close (rays leaving a surface start just past its box)
        return -1;
    }
    // ⌈v / 2^f⌉ = −⌊−v / 2^f⌋
    (-((-v) >> f)).clamp(-1, far_top as i128) as i64
}

/// The order of the outputs: hits first, smaller entry first, then slot index.
pub fn sort(slots: &mut [SlotOut]) {
    slots.sort_by_key(|s| (!s.hit, s.entry, s.child));
}
