//! The `node` unit's model (docs/node.md §10, §12): the ray
//! **re-originated at the node** once per node, then every child in fixed
//! point without anchors. Began as a design study beside [`crate::node`]
//! (the window-and-anchors design, kept as the reference it was measured
//! against); the unit `node` is its hardware, bit for bit.
//!
//! **Inputs**: the ray of [`crate::node::Ray`] plus its direction `d` (raw
//! bits; `inv_d = RTZ(1/d)` as before) and `t_start`, a lower bound of the
//! `t` of every hit in the node (the parent's conservative entry for the
//! child; the root's from a box test). The node is [`NodeIn`].
//!
//! **Per node** (`q` box bits, `Q = 2^q − 1`; `g` position fraction bits,
//! `h` cell bits, `m` slope bits):
//! 1. `T = max(t_min, t_start)`, then rounded down to `p` significant bits
//!    ([`start_term`]: still a lower bound of every hit, and each per-node
//!    product `T·d` is `p × (F + 1)` bits, one DSP48E1 at `p = 17`); the
//!    ray's position at `T` in frame steps, `x = (o + T·d − O)/2^e` per axis, bounded below and above in `2^−g`
//!    steps from a window sum ([`window_sum`]: exact unless a term reaches
//!    below the window, then one step wider per such term; the window's
//!    lowest bit is `2^(e − g − f)` or above, `f` the window floor) and clamped to
//!    `±2^(q + 3)` (a clamp that never changes a cell);
//!    a zero `d` component gives `x = (o − O)/2^e` (parallel axis);
//! 2. the cell `u = 2^G`: `G = min over non-parallel axes of
//!    ⌊log2(a·2^e)⌋ − h` (the fastest axis crosses a step in `2^h` to
//!    `2^(h+1)` cells: exponent arithmetic only), `a = |inv_d|`;
//! 3. per axis the time per step in cells, `s_lo = RDN_m(a·2^e/u)`,
//!    `s_hi = RUP_m(b·2^e/u)` (`m` significant bits, `b` the successor of
//!    `a`), infinite for a parallel axis; the window end
//!    `far_top = min(C, ⌈(t_max − T)/u⌉)` (from a window sum whose lowest
//!    bit is `2^(G − f)` or above, so at least that), `C = 2^K`, `K = q + h + 2`.
//!
//! **Per child** (per axis, in `2^−g` steps): the distance to the entry plane
//! `Δn = lo − x_hi` (`x_lo − hi` when `d < 0`) and to the exit plane
//! `Δf = hi − x_lo` (`x_hi − lo`); `Δf < 0`: miss (the child is behind `T`);
//! `near = 0` if `Δn ≤ 0`, else `min(C, ⌊Δn·s_lo·2^−g⌋)` (a parallel axis:
//! miss); `far = min(C, ⌈Δf·s_hi·2^−g⌉)` (`C` for a parallel axis). `hit =
//! valid ∧ no axis missed ∧ max near ≤ min(min far, far_top)`, `entry =
//! max near`, standing for `T + entry·u`. A cell count at its cap `C`
//! stands for "`C` or more": every `near` is at most `C`, so a capped `far`
//! never rejects a child (docs/node.md §10 has the proof).

use crate::exact::ray_box::{decode, Exact};
use crate::float::FloatFormat;
use crate::node::{finite, Bound, Dyadic, NodeIn, NodeOut, Ray, SlotOut};
use dashu::base::{BitTest, UnsignedAbs};
use dashu::integer::IBig;
use std::cmp::Ordering;

/// The shape of a re-origin node test.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReoriginParams {
    /// ray format
    pub fmt: FloatFormat,
    /// slots N
    pub children: usize,
    /// box integer bits q
    pub box_bits: u32,
    /// fraction bits g of the position at `T` in frame steps
    pub pos_frac: u32,
    /// cells per step of the fastest axis: `2^h` to `2^(h+1)`
    pub cell_bits: u32,
    /// significant bits m of the per-axis time per step
    pub slope_bits: u32,
    /// significant bits p the start `T` is rounded down to
    pub start_bits: u32,
    /// the window floor f: a window sum's lowest bit is at most `f` bits below its grid
    /// (`2^(e − g − f)` for a position, `2^(G − f)` for the window end), so the grid
    /// conversion shifts by at most `f` bits more than its output's width
    pub window_floor: u32,
}

impl ReoriginParams {
    /// The defaults, the `node` unit's: g = 4, h = 4, m = 9, p = 18, f = 8
    /// (docs/node.md §10, §12: m = 8 with an unrounded start is within the tightness
    /// ceiling, m = 9 keeps it with the start rounded to 18 bits; m = 12 is 5 %
    /// tighter; f = 8 leaves whole renders as they were).
    pub fn new(fmt: FloatFormat, children: usize, box_bits: u32) -> ReoriginParams {
        ReoriginParams {
            fmt,
            children,
            box_bits,
            pos_frac: 4,
            cell_bits: 4,
            slope_bits: 9,
            start_bits: 18,
            window_floor: 8,
        }
    }

    /// `K = q + h + 2`: cells are counted up to `C = 2^K`.
    pub fn cell_cap_bits(&self) -> u32 {
        self.box_bits + self.cell_bits + 2
    }

    /// Bits of the window the positions are summed in:
    /// `q + g + 16` (docs/node.md §10, §12; 20 until 2026-12-07).
    pub fn window_bits(&self) -> u32 {
        self.box_bits + self.pos_frac + 16
    }

    /// Bits of the window the window end `t_max − T` is summed in: `K + 2`
    /// (6 until 2026-12-07). A count capped at `2^K` cells needs no more while
    /// the terms are within a few times the cap, where the window sits at its
    /// floor; larger terms that cancel leave the end looser, never wrong (whole
    /// renders and the CI pairs did not change from `K + 6`).
    pub fn end_window_bits(&self) -> u32 {
        self.cell_cap_bits() + 2
    }

    /// The sentinel entry of a miss: `2^(K+1) − 1`.
    pub fn miss_entry(&self) -> u32 {
        (1 << (self.cell_cap_bits() + 1)) - 1
    }
}

/// `⌊v⌋` or `⌈v⌉` of a dyadic, as an integer.
fn round_int(v: &Dyadic, up: bool) -> IBig {
    v.div_pow2_round(0, up)
}

/// Per-axis terms of one node.
enum AxisTerms {
    /// `d = 0`: the position never changes
    Parallel { x_lo: i64, x_hi: i64 },
    Slab {
        mirror: bool,
        x_lo: i64,
        x_hi: i64,
        /// `None`: above the cap (every nonzero distance saturates)
        s_lo: Option<i64>,
        s_hi: Option<i64>,
    },
}

/// A term of a window sum: its exact value and `top`, a power of two its
/// magnitude is below, taken from its encoding's width (not its value), as
/// the hardware knows it from exponent fields alone.
#[derive(Debug, Clone)]
struct Term {
    v: Dyadic,
    top: i64,
}

impl Term {
    /// A finite float: `|v| < 2^(lsb exponent + F + 1)`.
    fn float(fmt: FloatFormat, bits: u64) -> Term {
        let v = finite(fmt, bits).expect("a finite input");
        Term {
            top: v.e + i64::from(fmt.frac_bits()) + 1,
            v,
        }
    }
    /// A value of the design study's extra axes: its own magnitude.
    fn exact(v: &Dyadic) -> Term {
        Term {
            top: if v.signum() == 0 { v.e } else { v.ilog2() + 1 },
            v: v.clone(),
        }
    }
    fn neg(&self) -> Term {
        Term {
            v: self.v.neg(),
            top: self.top,
        }
    }
    /// The exact product; its top is the sum of the tops.
    fn mul(&self, other: &Term) -> Term {
        Term {
            v: self.v.mul(&other.v),
            top: self.top + other.top,
        }
    }
}

/// The start `T` rounded down to `p` significant bits of its encoding, as a
/// window term: a positive normal `T` keeps the bits at or above `2^(top −
/// p)` (and its `top`), a subnormal one becomes `+0`, a negative one `−2^top`
/// (the term's `top` one more), so that every nonzero start has its leading
/// bit at `2^(top − 1)` and `T·d` is `d·2^(top−1)` plus a `(p − 1)`-bit
/// product. `None` when `−2^top` is not a float (`top > emax`): the caller
/// then has no start. An earlier start is still a lower bound of every hit;
/// what it costs is tightness (distances from it are longer, and so are the
/// slopes' rounding errors on them).
fn start_term(fmt: FloatFormat, p: u32, bits: u64) -> Option<Term> {
    let t = Term::float(fmt, bits);
    match t.v.signum() {
        0 => Some(t),
        1 if t.v.ilog2() < i64::from(fmt.emin()) => Some(Term {
            v: Dyadic::new(IBig::ZERO, 0),
            top: t.top,
        }),
        1 => {
            let lsb = t.top - i64::from(p);
            Some(Term {
                v: Dyadic::new(t.v.div_pow2_round(lsb, false), lsb),
                top: t.top,
            })
        }
        _ => (t.top <= i64::from(fmt.emax())).then(|| Term {
            v: Dyadic::new(IBig::from(-1), t.top),
            top: t.top + 1,
        }),
    }
}

/// `[lo, hi]·2^B ∋ Σ terms`, summed in a window of `w` bits under the
/// largest `top` of the nonzero terms but no lower than `floor` (`B =
/// max(max top − w, floor)`): each term's
/// magnitude truncated at `2^B`, summed with its sign; a term that lost
/// bits moves `lo` down one step if negative, `hi` up one if positive. Zero
/// terms take no part; all zero gives `(0, 0, floor)`. One aligned adder in the
/// hardware, exact whenever no term reaches below `2^B`.
fn window_sum(terms: &[Term], w: u32, floor: i64) -> (IBig, IBig, i64) {
    let live: Vec<&Term> = terms.iter().filter(|t| t.v.signum() != 0).collect();
    let Some(top) = live.iter().map(|t| t.top).max() else {
        return (IBig::ZERO, IBig::ZERO, floor);
    };
    let b = (top - i64::from(w)).max(floor);
    let (mut base, mut down, mut up) = (IBig::ZERO, 0i32, 0i32);
    for t in live {
        let mag = (&t.v.m).unsigned_abs();
        let (kept, lost) = if t.v.e >= b {
            (IBig::from(mag << (t.v.e - b) as usize), false)
        } else {
            let sh = (b - t.v.e) as usize;
            let kept = &mag >> sh;
            let lost = (&kept << sh) != mag;
            (IBig::from(kept), lost)
        };
        if t.v.signum() < 0 {
            base -= kept;
            down += i32::from(lost);
        } else {
            base += kept;
            up += i32::from(lost);
        }
    }
    (&base - IBig::from(down), base + IBig::from(up), b)
}

/// Evaluates one node test (module doc). `bad` as in [`crate::node::eval`],
/// and also for a NaN `t_start`, a NaN or infinite `d`, or a zero `d`
/// component whose `inv_d` is finite (and the reverse).
pub fn eval(p: &ReoriginParams, ray: &Ray, d: [u64; 3], t_start: u64, node: &NodeIn) -> NodeOut {
    eval_with(p, ray, d, t_start, node, &[])
}

/// An extra axis of the node (a k-DOP direction `n`, for the cull-plane
/// study of docs/node.md §11): the ray's `n·o` and `n·d` (exact), the node's
/// frame `U + [0, Q]·2^e` along `n`, and per slot the extent along `n`.
#[derive(Debug, Clone)]
pub struct ExtraAxis {
    /// `n·o`
    pub o: Dyadic,
    /// `n·d`
    pub d: Dyadic,
    /// frame origin `U`
    pub origin: Dyadic,
    /// frame step exponent `e`
    pub exp: i64,
    /// per slot the lower integer
    pub lo: [u16; crate::wide::MAX_CHILDREN],
    /// per slot the upper integer
    pub hi: [u16; crate::wide::MAX_CHILDREN],
}

/// `[a, b] ∋ 1/|v|` (`v ≠ 0`), `b/a − 1 < 2^−bits`.
fn reciprocal_interval(v: &Dyadic, bits: u32) -> (Dyadic, Dyadic) {
    let m = v.m.clone().unsigned_abs();
    let k = bits as usize + m.bit_len();
    let q = IBig::from((dashu::integer::UBig::ONE << k) / m);
    (
        Dyadic::new(q.clone(), -v.e - k as i64),
        Dyadic::new(q + IBig::ONE, -v.e - k as i64),
    )
}

/// [`eval`] with extra axes tested like the box's three, in the same cells.
pub fn eval_with(
    p: &ReoriginParams,
    ray: &Ray,
    d: [u64; 3],
    t_start: u64,
    node: &NodeIn,
    extra: &[ExtraAxis],
) -> NodeOut {
    eval_inner(p, ray, d, t_start, node, extra, None)
}

/// The ray's position bounds on the box axes given from outside, for the carried-position
/// study (docs/node.md §12): for the start `T` the node test uses and axis `a` (`parallel`:
/// the ray's direction component is zero), `(x_lo, x_hi)` in `2^−g` steps of the node's
/// frame, rounded outward (inward for a parallel axis), before the clamp.
pub type Positions<'a> = &'a dyn Fn(&Dyadic, usize, bool) -> (IBig, IBig);

/// [`eval`] with the box axes' positions from `at` instead of the window sums: the rest of
/// the test (cells, slopes, window end, children) as [`eval`]'s. A design study, not a unit.
pub fn eval_carried(
    p: &ReoriginParams,
    ray: &Ray,
    d: [u64; 3],
    t_start: u64,
    node: &NodeIn,
    at: Positions,
) -> NodeOut {
    eval_inner(p, ray, d, t_start, node, &[], Some(at))
}

fn eval_inner(
    p: &ReoriginParams,
    ray: &Ray,
    d: [u64; 3],
    t_start: u64,
    node: &NodeIn,
    extra: &[ExtraAxis],
    at: Option<Positions>,
) -> NodeOut {
    let fmt = p.fmt;
    let q = p.box_bits;
    let q_max = (1i64 << q) - 1;
    let g = p.pos_frac as i64;
    let cap = 1i64 << p.cell_cap_bits();
    let valid = |i: usize| node.valid >> i & 1 == 1;
    let all = |hit: bool, entry: u32| {
        let mut slots: Vec<SlotOut> = (0..p.children)
            .map(|i| SlotOut {
                hit: hit && valid(i),
                entry: if hit && valid(i) {
                    entry
                } else {
                    p.miss_entry()
                },
                child: i as u8,
            })
            .collect();
        crate::node::sort(&mut slots);
        slots
    };
    let bad_out = || NodeOut {
        bad: true,
        t_base: Bound::NegInf,
        grid_exp: 0,
        slots: all(true, 0),
    };
    // bad input
    let slot_bad = (0..p.children).any(|i| {
        valid(i) && (0..3).any(|a| node.lo[i][a] > node.hi[i][a] || node.hi[i][a] as i64 > q_max)
    });
    let frame_bad = (0..3).any(|a| {
        !fmt.is_finite(node.origin[a]) || !(fmt.emin()..=fmt.emax()).contains(&node.exp[a])
    });
    let ray_bad = (0..3).any(|a| {
        let zero_d = d[a] & !fmt.sign_bit() & fmt.mask() == 0;
        let inf_inv = ray.inv_d[a] & !fmt.sign_bit() & fmt.mask() == fmt.inf(false);
        !fmt.is_finite(ray.o[a])
            || !fmt.is_finite(d[a])
            || fmt.is_nan(ray.inv_d[a])
            || ray.inv_d[a] & !fmt.sign_bit() & fmt.mask() == 0
            || zero_d != inf_inv
    }) || fmt.is_nan(ray.t_min)
        || fmt.is_nan(ray.t_max)
        || fmt.is_nan(t_start);
    if slot_bad || frame_bad || ray_bad {
        return bad_out();
    }
    let miss_out = || NodeOut {
        bad: false,
        t_base: Bound::NegInf,
        grid_exp: 0,
        slots: all(false, 0),
    };
    // step 1: T
    let lower = |bits: u64| match decode(fmt, bits) {
        Exact::Fin { m, e } => Ok(Some(Dyadic::new(IBig::from(m), e as i64))),
        Exact::NegInf => Ok(None),
        _ => Err(()), // +∞
    };
    let (Ok(t_a), Ok(t_b)) = (lower(ray.t_min), lower(t_start)) else {
        return miss_out(); // a segment starting at +∞
    };
    // T and its bits (t_min unless t_start is strictly later)
    let (t, t_bits) = match (t_a, t_b) {
        (Some(a), Some(b)) if a.cmp_exact(&b) == Ordering::Less => (Some(b), t_start),
        (Some(a), _) => (Some(a), ray.t_min),
        (None, b) => (b, t_start),
    };
    // no start: nothing to re-originate at; every valid slot may be hit
    let open_out = || NodeOut {
        bad: false,
        t_base: Bound::NegInf,
        grid_exp: 0,
        slots: all(true, 0),
    };
    let Some(t) = t else {
        return open_out(); // no finite start
    };
    let t_max = match decode(fmt, ray.t_max) {
        Exact::Fin { .. } => Some(Term::float(fmt, ray.t_max)),
        Exact::PosInf => None,
        _ => return miss_out(),
    };
    if t_max
        .as_ref()
        .is_some_and(|v| v.v.cmp_exact(&t) == Ordering::Less)
    {
        return miss_out();
    }
    let Some(t_term) = start_term(fmt, p.start_bits, t_bits) else {
        return open_out(); // a negative start in the largest binade: no float below it
    };
    // clamped beyond ±2^(q + 3) steps: a distance from a clamped position is then at least
    // 2^(q + 3) − Q steps of at least 2^h cells, above the cap C = 2^(q + h + 2)
    let x_range = 1i64 << (q + 3 + p.pos_frac);
    let clamp = |v: IBig| -> i64 {
        i64::try_from(v.clamp(IBig::from(-x_range), IBig::from(x_range))).expect("clamped")
    };
    let w = p.window_bits();
    struct Raw {
        mirror: bool,
        x_lo: i64,
        x_hi: i64,
        ra: Dyadic,
        rb: Dyadic,
        e: i64,
    }
    // every axis as `n·o`, `n·d`, the frame `origin + [0, Q]·2^e` and, unless the ray is
    // parallel to it, the reciprocal interval of `|n·d|` and its sign: the box's three from
    // the ray's bits, then the extra ones
    struct AxisRay {
        o: Term,
        d: Term,
        origin: Term,
        e: i64,
        recip: Option<(Dyadic, Dyadic, bool)>,
    }
    let box_axes = (0..3).map(|a| {
        let inv = ray.inv_d[a] & fmt.mask();
        let mag = inv & !fmt.sign_bit();
        AxisRay {
            o: Term::float(fmt, ray.o[a]),
            d: Term::float(fmt, d[a]),
            origin: Term::float(fmt, node.origin[a]),
            e: node.exp[a] as i64,
            recip: (mag != fmt.inf(false)).then(|| {
                let (ra, rb) = crate::node::reciprocal_bounds(fmt, mag);
                (ra, rb, inv & fmt.sign_bit() != 0)
            }),
        }
    });
    let extra_axes = extra.iter().map(|x| AxisRay {
        o: Term::exact(&x.o),
        d: Term::exact(&x.d),
        origin: Term::exact(&x.origin),
        e: x.exp,
        recip: (x.d.signum() != 0).then(|| {
            let (ra, rb) = reciprocal_interval(&x.d, fmt.frac_bits() + 1);
            (ra, rb, x.d.signum() < 0)
        }),
    });
    let mut raws: Vec<Option<Raw>> = Vec::new();
    let mut axes: Vec<Option<AxisTerms>> = Vec::new();
    for (a, ax) in box_axes.chain(extra_axes).enumerate() {
        let parallel = ax.recip.is_none();
        let (x_lo, x_hi) = match at {
            Some(at) if a < 3 => at(&t_term.v, a, parallel),
            _ => {
                // the position at T in units 2^(e − g), outward: o − O + T·d in the
                // window (a parallel axis's product is zero)
                let floor = ax.e - g - i64::from(p.window_floor);
                let terms = [ax.o, ax.origin.neg(), t_term.mul(&ax.d)];
                let (lo, hi, b) = window_sum(&terms, w, floor);
                // outward for a slab axis (⌊lo⌋, ⌈hi⌉); inward for a parallel one (⌈lo⌉,
                // ⌊hi⌋): there an integer plane p is certainly beyond x when p > ⌊hi⌋ or
                // p < ⌈lo⌉
                (
                    Dyadic::new(lo, b).div_pow2_round(ax.e - g, parallel),
                    Dyadic::new(hi, b).div_pow2_round(ax.e - g, !parallel),
                )
            }
        };
        let (x_lo, x_hi) = (clamp(x_lo), clamp(x_hi));
        let Some((ra, rb, mirror)) = ax.recip else {
            axes.push(Some(AxisTerms::Parallel { x_lo, x_hi }));
            raws.push(None);
            continue;
        };
        axes.push(None);
        raws.push(Some(Raw {
            mirror,
            x_lo,
            x_hi,
            ra,
            rb,
            e: ax.e,
        }));
    }
    // step 2: the cell, from the fastest axis's time per step (exponents only)
    let grid_exp = raws
        .iter()
        .flatten()
        .map(|r| r.e + r.ra.ilog2())
        .min()
        .map_or(0, |v| v - p.cell_bits as i64);
    // step 3: slopes in cells per step, with pos_frac fraction bits kept in the product
    let slope_cap = cap << g; // above it any distance of 2^−g saturates
    for (a, r) in raws.into_iter().enumerate() {
        let Some(r) = r else { continue };
        let slope = |v: &Dyadic, up: bool| -> Option<i64> {
            // cells per step with m significant bits (at least 2^h: no fraction
            // bits below 2^−32 are needed), or None above the cap
            let s = v.scale(r.e - grid_exp).round(p.slope_bits, up);
            if s.cmp_exact(&Dyadic::new(IBig::from(slope_cap), 0)) == Ordering::Greater {
                None
            } else {
                Some(i64::try_from(round_int(&s.scale(32), up)).expect("≤ cap·2^32"))
            }
        };
        axes[a] = Some(AxisTerms::Slab {
            mirror: r.mirror,
            x_lo: r.x_lo,
            x_hi: r.x_hi,
            s_lo: slope(&r.ra, false),
            s_hi: slope(&r.rb, true),
        });
    }
    let far_top = match &t_max {
        None => cap,
        Some(v) => {
            let floor = grid_exp - i64::from(p.window_floor);
            let (_, hi, b) = window_sum(&[v.clone(), t_term.neg()], p.end_window_bits(), floor);
            let c = Dyadic::new(hi, b).div_pow2_round(grid_exp, true);
            i64::try_from(c.min(IBig::from(cap))).expect("≤ cap")
        }
    };
    // per child
    let child = |i: usize| -> Option<u32> {
        if !valid(i) {
            return None;
        }
        let mut near_max = 0i64;
        let mut far_min = far_top;
        for (a, ax) in axes.iter().enumerate() {
            let (lo, hi) = match a.checked_sub(3) {
                None => (node.lo[i][a], node.hi[i][a]),
                Some(j) => (extra[j].lo[i], extra[j].hi[i]),
            };
            let (lo, hi) = ((lo as i64) << g, (hi as i64) << g);
            match ax.as_ref().expect("every axis has terms") {
                AxisTerms::Parallel { x_lo, x_hi } => {
                    // outside: above ⌊hi⌋ or below ⌈lo⌉ (exact when the window sum
                    // is: then both are ⌊x⌋ and ⌈x⌉)
                    if lo > *x_hi || hi < *x_lo {
                        return None;
                    }
                }
                AxisTerms::Slab {
                    mirror,
                    x_lo,
                    x_hi,
                    s_lo,
                    s_hi,
                } => {
                    let (dn, df) = if *mirror {
                        (x_lo - hi, x_hi - lo)
                    } else {
                        (lo - x_hi, hi - x_lo)
                    };
                    if df < 0 {
                        return None; // the exit plane is behind T
                    }
                    // distance in 2^−g steps × cells per step in 2^−32 units
                    let near = if dn <= 0 {
                        0
                    } else {
                        match s_lo {
                            None => cap,
                            Some(s) => {
                                let v = dn as i128 * *s as i128; // 2^−(g+32) cells
                                ((v >> (g + 32)) as i64).min(cap)
                            }
                        }
                    };
                    let far = match s_hi {
                        None if df > 0 => cap,
                        None => 0,
                        Some(s) => {
                            let v = df as i128 * *s as i128;
                            (-((-v) >> (g + 32)) as i64).min(cap)
                        }
                    };
                    near_max = near_max.max(near);
                    far_min = far_min.min(far);
                }
            }
        }
        (near_max <= far_min).then_some(near_max as u32)
    };
    let mut slots: Vec<SlotOut> = (0..p.children)
        .map(|i| {
            let e = child(i);
            SlotOut {
                hit: e.is_some(),
                entry: e.unwrap_or(p.miss_entry()),
                child: i as u8,
            }
        })
        .collect();
    crate::node::sort(&mut slots);
    NodeOut {
        bad: false,
        t_base: Bound::Fin(t_term.v),
        grid_exp,
        slots,
    }
}
