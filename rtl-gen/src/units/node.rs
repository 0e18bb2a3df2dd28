//! `node`: the node tester (issue 36): one ray against one wide BVH node
//! of N compressed child boxes, the children returned sorted. Bit-exact
//! with `golden_model::node_reorigin::eval` (docs/node.md §10, §12).
//!
//! **Per node, once**: the segment's start `T = max(t_min, t_start)`
//! (`t_start`: a lower bound of every hit in the node, the parent's entry);
//! per axis the ray's position at `T` in `2^−g` frame steps, `o − O + T·d`
//! summed in a window of `W = q + g + 16` bits under the largest term but
//! with its lowest bit no lower than `2^(e − g − f)` (the window floor `f =
//! 8`; each term truncated, the bits it lost moving the sum's lower or upper
//! bound by one step), floored and ceiled to the frame's grid, clamped to
//! `±2^(q+3+g)`; the cell `2^G` from exponents (`G = min E − h`, `E = e +
//! ⌊log2 |inv_d|⌋` over the axes the ray is not parallel to); per axis the
//! time per frame step in cells as an `m`-bit significand rounded down and
//! up, shifted by `z = E − min E`; the window end `⌈(t_max − T)/2^G⌉` from a
//! window sum, capped at `C = 2^K`, `K = q + h + 2`.
//!
//! **Per child**: per axis the distances from the position to the entry and
//! exit planes (a q-bit integer against a fixed-point value), times the
//! slopes (a narrow product and a shift by `z`), the entry's floored to cells
//! and capped at `C`; an exit plane behind `T` or a parallel axis outside
//! the slab misses; `hit = max near ≤ min(min far, window end)`, `entry = max
//! near` (`T + entry·2^G` is a lower bound of the entry). The exit's cells
//! `far = min(C, ⌈p·2^kmin⌉)` are never formed: `max near ≤ far` is `p ≥
//! (max near − 1)·2^−kmin + 1`, the sign of one subtraction. Then Batcher's
//! network sorts the slots: hits first, nearer first, ties by slot index
//! ([`super::node_sort::sort_slots`]). Special inputs: `bad` (NaN, a
//! non-finite origin or frame, a frame exponent out of range, a zero
//! `inv_d` or an infinite one with a nonzero `d`, a child with `lo > hi`):
//! every valid slot a hit at entry 0; `T = −∞`: the same without `bad`;
//! `t_min` or `t_start` at `+∞`, `t_max = −∞` or `t_max < T`: every slot a
//! miss. `stages` registers are placed by the delay model
//! ([`crate::retime::balance`]).

use super::node_sort::sort_slots;
use super::ports::{self, Record, Visit, Walk};
use super::{Description, AXES};
use crate::arith::float::bits::{lzc, sadd, ssub, to_sint};
use crate::arith::float::classify::is_max_finite;
use crate::arith::float::compare::compare;
use crate::arith::float::unpack::{normalize, unpack, Unpacked};
use crate::arith::float::{sint_width, Format};
use crate::arith::int::{bits_for, sext, zext};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamSet};
use crate::retime::Products;

/// The `node` unit.
pub struct Node;

/// Fraction bits g of the position at `T`, in frame steps.
pub const POS_FRAC: u32 = 4;
/// Cells per frame step of the fastest axis: `2^h` to `2^(h+1)`.
pub const CELL_BITS: u32 = 4;
/// The window floor f: a window sum's lowest bit is at most this many bits
/// below its grid (`2^(e − g − f)` for a position, `2^(G − f)` for the window
/// end), so each grid conversion shifts by at most `f` bits beyond its width.
pub const WINDOW_FLOOR: u32 = 8;
/// Bits of the window sums beyond `q + g`.
pub const WINDOW_EXTRA: u32 = 16;

crate::params! {
    /// The node tester's parameters.
    pub struct NodeParams {
        /// child slots per node N: 2, 4 or 8
        children: u32 [2..=8] = 4,
        /// bits per child box integer q
        box_bits: u32 [4..=16] = 8,
        /// exponent bits E of the ray and frame format
        exp_bits: u32 [3..=8] = 8,
        /// fraction bits F of the ray and frame format
        frac_bits: u32 [2..=23] = 23,
        /// significant bits m of the per-axis time per frame step
        slope_bits: u32 [4..=16] = 9,
        /// significant bits p the start `T` is rounded down to before the per-node products
        /// `T·d`, formed as `d·2^(p−1)` plus `d` times the p − 1 bits below the leading one
        /// (18: one DSP48E1 and its post-adder each; a negative `T` becomes `−2^top`)
        start_bits: u32 [2..=24] = 18,
        /// pipeline stages (latency in cycles), placed by the delay model
        stages: u32 [0..=48] = 4,
        /// split (ECP5's 18x18 MULT18X18D): each child's distance clamped and shifted so its
        /// product fits one block, the per-node `T·d` cut into 18x18 blocks and their sum when
        /// stages are placed; whole (a 7-series DSP48E1 takes 25x18): the slope shifted once
        /// per node, each child's product one block, `T·d` one multiplication each
        /// (`xc7_products` says where whole stays one block)
        products: Products = Products::Split,
    }
}

/// Resolved parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// ray and frame format
    pub fmt: Format,
    /// slots N (2, 4 or 8)
    pub children: u32,
    /// box integer bits q
    pub box_bits: u32,
    /// slope significand bits m
    pub slope_bits: u32,
    /// significant bits p of the rounded start
    pub start_bits: u32,
    /// pipeline registers
    pub stages: u32,
    /// how the retimer flattens the per-node products
    pub products: Products,
}

impl Config {
    /// `K = q + h + 2`: cells counted up to `C = 2^K`.
    pub fn cap_bits(&self) -> u32 {
        self.box_bits + CELL_BITS + 2
    }
    /// Bits of an entry: `K + 1` (the miss sentinel is `2^(K+1) − 1`).
    pub fn entry_bits(&self) -> u32 {
        self.cap_bits() + 1
    }
    /// Bits of a slot index: `log2 N`.
    pub fn index_bits(&self) -> u32 {
        self.children.trailing_zeros()
    }
    /// The window of the position sums: `W = q + g + 16`.
    pub fn window_bits(&self) -> u32 {
        self.box_bits + POS_FRAC + WINDOW_EXTRA
    }
    /// The window of `t_max − T`: `K + 2`.
    pub fn end_window_bits(&self) -> u32 {
        self.cap_bits() + 2
    }
    /// Bits of a frame exponent port: `emin ..= emax` (other values are bad input).
    pub fn frame_exp_bits(&self) -> u32 {
        sint_width(self.fmt.emin(), self.fmt.emax())
    }
    /// The range of the grid exponent `G`: `2·emin − F − h ..= 2·emax − h`.
    pub fn grid_exp_range(&self) -> (i64, i64) {
        let (f, h) = (self.fmt.frac_bits as i64, CELL_BITS as i64);
        (2 * self.fmt.emin() - f - h, 2 * self.fmt.emax() - h)
    }
    /// Bits of the grid exponent output.
    pub fn grid_exp_bits(&self) -> u32 {
        let (lo, hi) = self.grid_exp_range();
        sint_width(lo, hi)
    }
}

/// The inputs (`*` = x, y, z): the ray, the start, the node.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeIn<T> {
    /// the ray's origin
    pub o: [T; 3],
    /// the ray's direction
    pub d: [T; 3],
    /// `RTZ(1/d)` per axis (`±∞` for a zero `d`)
    pub inv_d: [T; 3],
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
    /// a lower bound of every hit in the node (the parent's entry)
    pub t_start: T,
    /// the node frame's origin
    pub origin: [T; 3],
    /// the node frame's step exponent per axis
    pub exp: [T; 3],
    /// bit i: slot i holds a child
    pub valid: T,
    /// per slot the lower box integers
    pub lo: Vec<[T; 3]>,
    /// per slot the upper box integers
    pub hi: Vec<[T; 3]>,
}

impl<T: Copy> Record<T> for NodeIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let f = cfg.fmt.ty();
        let q = Ty::UInt(cfg.box_bits);
        let o = w.xyz("o", f, |r| r.o);
        let d = w.xyz("d", f, |r| r.d);
        let inv_d = w.xyz("inv_d", f, |r| r.inv_d);
        let t_min = w.one("t_min", f, |r| r.t_min);
        let t_max = w.one("t_max", f, |r| r.t_max);
        let t_start = w.one("t_start", f, |r| r.t_start);
        let origin = w.xyz("frame_origin", f, |r| r.origin);
        let exp = w.xyz("frame_exp", Ty::SInt(cfg.frame_exp_bits()), |r| r.exp);
        let valid = w.one("valid", Ty::UInt(cfg.children), |r| r.valid);
        let (mut lo, mut hi) = (Vec::new(), Vec::new());
        for i in 0..cfg.children as usize {
            lo.push(w.xyz(format_args!("slot{i}_lo"), q, move |r| r.lo[i]));
            hi.push(w.xyz(format_args!("slot{i}_hi"), q, move |r| r.hi[i]));
        }
        NodeIn {
            o,
            d,
            inv_d,
            t_min,
            t_max,
            t_start,
            origin,
            exp,
            valid,
            lo,
            hi,
        }
    }
}

/// The outputs: `bad`, `t_base`, `grid_exp`, then per sorted position `j`
/// `out{j}_hit`, `out{j}_entry`, `out{j}_child`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NodeOut<T> {
    /// bad input: every valid slot reported hit at entry 0
    pub bad: T,
    /// `T` (`+0` for a zero; `−∞` when there is none: bad input, no finite
    /// start, every slot a miss)
    pub t_base: T,
    /// `G`: a hit's entry is at least `t_base + entry·2^G` (0 without a `T`)
    pub grid_exp: T,
    /// per position: a hit
    pub hit: Vec<T>,
    /// per position: cells from `T` to the entry bound (`2^(K+1) − 1` on a miss)
    pub entry: Vec<T>,
    /// per position: the slot index
    pub child: Vec<T>,
}

impl<T: Copy> Record<T> for NodeOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let bad = w.one("bad", Ty::Bool, |r| r.bad);
        let t_base = w.one("t_base", cfg.fmt.ty(), |r| r.t_base);
        let grid_exp = w.one("grid_exp", Ty::SInt(cfg.grid_exp_bits()), |r| r.grid_exp);
        let (mut hit, mut entry, mut child) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..cfg.children as usize {
            hit.push(w.one(format_args!("out{j}_hit"), Ty::Bool, move |r| r.hit[j]));
            entry.push(w.one(
                format_args!("out{j}_entry"),
                Ty::UInt(cfg.entry_bits()),
                move |r| r.entry[j],
            ));
            child.push(w.one(
                format_args!("out{j}_child"),
                Ty::UInt(cfg.index_bits()),
                move |r| r.child[j],
            ));
        }
        NodeOut {
            bad,
            t_base,
            grid_exp,
            hit,
            entry,
            child,
        }
    }
}

/// The `products` that keeps each child's product on one DSP48E1 (xc7):
/// `whole` while the distance (`q + g + 4` bits) and the shifted slope
/// (`m + q + g + 3` bits) fit its unsigned 17 × 24, else `split` (at q = 16
/// a whole product would take four blocks).
pub fn xc7_products(box_bits: u32, slope_bits: u32) -> Products {
    let distance = box_bits + POS_FRAC + 4;
    let slope = slope_bits + box_bits + POS_FRAC + 3;
    if distance <= 17 && slope <= 24 {
        Products::Whole
    } else {
        Products::Split
    }
}

/// Module name: `node_n{N}_q{q}_m{m}[_p{p}]_{fmt}[_whole]_s{stages}` (`_p` unless
/// the default start bits).
pub fn node_name(cfg: &Config) -> String {
    let products = match cfg.products {
        Products::Split => "",
        Products::Whole => "_whole",
    };
    let start = if cfg.start_bits == NodeParams::defaults().start_bits {
        String::new()
    } else {
        format!("_p{}", cfg.start_bits)
    };
    format!(
        "node_n{}_q{}_m{}{start}_{}{products}_s{}",
        cfg.children,
        cfg.box_bits,
        cfg.slope_bits,
        cfg.fmt.tag(),
        cfg.stages
    )
}

/// Width of the `top` exponents of window terms: a product's is the sum of two.
fn top_bits(fmt: Format) -> u32 {
    position_top_bits(fmt.emin(), fmt.emax())
}

fn position_top_bits(emin: i64, emax: i64) -> u32 {
    sint_width(2 * (emin - 1), 2 * (emax + 1)) + 1
}

/// Width of a position's window exponent `B` (`axis_*_sum_exp`, SInt) for a
/// format's `emin ..= emax`: the terms' tops or the floor's window top (a
/// frame exponent plus a constant), whichever is wider, one bit for their
/// maximum and one for `B = top − W`. The split proof declares its copy of
/// the wire with it.
pub fn position_sum_exp_bits(emin: i64, emax: i64) -> u32 {
    let floor_top = sint_width(emin, emax) + LOWEST_TOP_HEADROOM;
    position_top_bits(emin, emax).max(floor_top) + 2
}

/// Bits a window's lowest top has beyond the exponent it is formed from.
const LOWEST_TOP_HEADROOM: u32 = 3;

/// The lowest top of a window of `w` bits whose lowest bit is at most `f`
/// (the window floor) below its grid `2^(exp − frac)`: `exp − frac − f + w`,
/// SInt (`exp` the frame exponent and `frac = g` for a position, the cell
/// exponent `G` and `frac = 0` for the window end).
fn lowest_window_top(m: &mut ModuleBuilder, exp: Sig, frac: u32, w: u32) -> Sig {
    let lw = exp.width() + LOWEST_TOP_HEADROOM;
    let e = sext(m, exp, lw);
    let above = i128::from(w) - i128::from(frac) - i128::from(WINDOW_FLOOR);
    let above = m.sint(lw, above);
    sadd(m, e, above, lw)
}

/// One term of a window sum: sign, magnitude, zero, and `top`: `|v| <
/// 2^top`, from the exponent field (the encoding's width, not the value).
#[derive(Clone, Copy)]
struct Term {
    negative: Sig,
    sig: Sig,
    zero: Sig,
    top: Sig,
    /// trailing zeros of `sig` (UInt)
    tz: Sig,
}

/// Trailing zeros of `x` (its width when `x` is zero): the leading zeros of
/// its bits reversed.
fn trailing_zeros(m: &mut ModuleBuilder, x: Sig) -> Sig {
    m.scope("trailing", |m| {
        let bits: Vec<Sig> = (0..x.width())
            .map(|i| {
                let b = m.bit_at(x, i);
                m.as_uint(b)
            })
            .collect();
        let reversed = m.cat(&bits);
        let reversed = m.name(reversed, "reversed");
        let tz = lzc(m, reversed);
        m.name(tz, "zeros")
    })
}

/// A finite float as a window term (in scope `what`), its sign flipped by
/// `negate`.
fn float_term(m: &mut ModuleBuilder, fmt: Format, u: &Unpacked, negate: bool, what: &str) -> Term {
    m.scope(what, |m| {
        // top = eff_exp − bias + 1
        let tw = top_bits(fmt);
        let e = to_sint(m, u.eff_exp, tw);
        let e = m.name(e, "eff_exp");
        let k = m.sint(tw, 1 - fmt.bias() as i128);
        let top = sadd(m, e, k, tw);
        let negative = if negate { m.not(u.sign) } else { u.sign };
        Term {
            negative: m.name(negative, "negative"),
            sig: u.sig,
            zero: u.zero,
            top: m.name(top, "top"),
            tz: trailing_zeros(m, u.sig),
        }
    })
}

/// The start `T` (bits `t`, unpacked `u`) rounded down to `p` significant
/// bits, as a window term (the model's `start_term`): a positive normal `T`
/// keeps its top `p` significand bits, a subnormal one becomes zero, a
/// negative one `−2^top` (the term's `top` one more), so a live term's
/// leading bit is set. Returns the term, the rounded start's bits (`+0` when
/// zero) and whether a negative `T` rounded beyond the format (`top > emax`).
fn start_term(
    m: &mut ModuleBuilder,
    fmt: Format,
    p: u32,
    t: Sig,
    u: &Unpacked,
) -> (Term, Sig, Sig) {
    let fw = fmt.frac_bits + 1;
    let p = p.min(fw);
    let drop = fw - p;
    let exact = float_term(m, fmt, u, false, "exact");
    let not_zero = m.not(u.zero);
    let below = m.and(u.sign, not_zero);
    let below = m.name(below, "negative");
    // positive: the low `drop` bits cleared, in the significand and in the encoding
    let kept = m.slice(u.sig, fw - 1, drop);
    let power = m.uint(p, 1u128 << (p - 1));
    let sig = m.mux(below, power, kept);
    let sig = m.name(sig, "sig");
    let truncated = if drop == 0 {
        t
    } else {
        let high = m.slice(t, fmt.width() - 1, drop);
        let zeros = m.uint(drop, 0);
        m.cat(&[high, zeros])
    };
    let truncated = m.name(truncated, "truncated");
    // negative: −2^top, the exponent field one above T's effective one
    let ew = fmt.exp_bits;
    let one = m.uint(ew, 1);
    let field = m.add(u.eff_exp, one);
    let field = m.slice(field, ew - 1, 0);
    let sign = m.bool(true);
    let sign = m.as_uint(sign);
    let frac_zero = m.uint(fmt.frac_bits, 0);
    let power_bits = m.cat(&[sign, field, frac_zero]);
    let power_bits = m.name(power_bits, "power_of_two");
    let all_ones = m.uint(ew, (1u128 << ew) - 1);
    let to_inf = m.eq(field, all_ones);
    let overflow = m.and(below, to_inf);
    let bits = m.mux(below, power_bits, truncated);
    let not_below = m.not(below);
    let none = m.or(u.zero, u.sub);
    let zero = m.and(not_below, none);
    let tw = exact.top.width();
    let lift = m.as_uint(below);
    let lift = to_sint(m, lift, tw);
    let top = sadd(m, exact.top, lift, tw);
    let term = Term {
        negative: exact.negative,
        sig,
        zero: m.name(zero, "zero"),
        top: m.name(top, "top"),
        tz: trailing_zeros(m, sig),
    };
    (term, m.name(bits, "bits"), m.name(overflow, "overflow"))
}

/// `a·b` for an `a` whose leading bit is set (a zero start is flagged, not
/// formed): `b·2^(wa−1)` plus `b` times `a`'s lower `wa − 1` bits, a 17 × 24
/// multiplication for an 18-bit `a`, one DSP48E1 whose post-adder takes the
/// sum.
fn leading_one_product(m: &mut ModuleBuilder, a: Sig, b: Sig) -> Sig {
    let (wa, wb) = (a.width(), b.width());
    let w = wa + wb;
    if wa < 2 {
        return zext(m, b, w);
    }
    let lower = m.slice(a, wa - 2, 0);
    let lower = m.name(lower, "lower_bits");
    let partial = m.mul(lower, b);
    let partial = zext(m, partial, w);
    let partial = m.name(partial, "lower_product");
    let shifted = b;
    let low_zeros = m.uint(wa - 1, 0);
    let shifted = m.cat(&[shifted, low_zeros]);
    let shifted = zext(m, shifted, w);
    let shifted = m.name(shifted, "leading_product");
    let sum = m.add(partial, shifted);
    m.slice(sum, w - 1, 0)
}

impl Term {
    /// The same value negated.
    fn negated(&self, m: &mut ModuleBuilder) -> Term {
        let negative = m.not(self.negative);
        Term {
            negative: m.name(negative, "negated"),
            ..*self
        }
    }
}

/// `[lo, hi]·2^B ∋ Σ terms` in a window of `w` bits whose top is the largest
/// `top` of the nonzero terms or `lowest`, whichever is larger (`B = max(max
/// top, lowest) − w`): returns `(lo, hi, B)`, `lo` and `hi` SInt of `w + 3`
/// bits, `B` an SInt. The golden model's `window_sum` (its floor is `lowest −
/// w`).
fn window_sum(m: &mut ModuleBuilder, terms: &[Term], w: u32, lowest: Sig) -> (Sig, Sig, Sig) {
    let tw = terms[0].top.width().max(lowest.width()) + 1;
    // the largest of the floor's window top and the nonzero terms' tops: from the floor's
    // (known first), each term's raw top compared while its zero flag is formed
    let tops: Vec<Sig> = terms
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let top = sext(m, t.top, tw);
            m.name(top, &format!("term{i}_top"))
        })
        .collect();
    let lowest = sext(m, lowest, tw);
    let mut top = m.name(lowest, "lowest_top");
    for (i, (t, &t_top)) in terms.iter().zip(&tops).enumerate() {
        let below = m.lt(top, t_top);
        let live = m.not(t.zero);
        let above = m.and(below, live);
        let v = m.mux(above, t_top, top);
        top = m.name(v, &format!("top_through_term{i}"));
    }
    let top = m.name(top, "window_top");
    let sw = w + 3;
    // Σ ±kept as Σ (kept ^ negative) + #negative: one adder a term, the count of
    // negative terms added with the counts of lost bits
    let mut base = m.sint(sw, 0);
    let mut negatives = m.uint(2, 0);
    let mut down = m.uint(2, 0);
    let mut up = m.uint(2, 0);
    for (i, t) in terms.iter().enumerate() {
        (base, negatives, down, up) = m.scope(&format!("term{i}"), |m| {
            let wi = t.sig.width();
            let wt = wi.max(w);
            // the significand at the top of a wt-bit field, moved down by max top − top
            let padded = zext(m, t.sig, wt);
            let lift = m.uint(bits_for(u64::from(wt)), u64::from(wt - wi) as u128);
            let padded = m.shl(padded, lift);
            let padded = m.name(padded, "aligned_to_top");
            let gap = m.sub(top, tops[i]);
            let gap = m.name(gap, "top_gap");
            let gap = m.slice(gap, tw - 1, 0);
            let cap = bits_for(u64::from(wt));
            let limit = m.uint(tw, u128::from(wt));
            // a zero term is shifted out whole (its significand need not be zero: a start
            // rounded to +0 keeps its bits; its top is not one of the window's)
            let far = m.lt(limit, gap);
            let far = m.or(far, t.zero);
            let gap = m.slice(gap, cap - 1, 0);
            let limit = m.slice(limit, cap - 1, 0);
            let gap = m.mux(far, limit, gap);
            let gap = m.name(gap, "gap");
            let moved = m.shr(padded, gap);
            // the top w bits kept; bits were lost when the significand has a one below
            // weight gap + wi − w: gap + wi − w > trailing zeros (a comparison, not a mask)
            let kept = if wt > w {
                m.slice(moved, wt - 1, wt - w)
            } else {
                moved
            };
            let cw = gap.width().max(t.tz.width()) + 2;
            let reach = to_sint(m, gap, cw);
            let reach = m.name(reach, "gap_wide");
            let shift = m.sint(cw, i128::from(wi) - i128::from(w));
            let reach = sadd(m, reach, shift, cw);
            let reach = m.name(reach, "reach");
            let tz = to_sint(m, t.tz, cw);
            let tz = m.name(tz, "trailing_wide");
            let below = m.lt(tz, reach);
            let live = m.not(t.zero);
            let lost = m.and(below, live);
            let kept = m.name(kept, "kept");
            let lost = m.name(lost, "lost");
            let kept_s = to_sint(m, kept, sw);
            let kept_s = m.name(kept_s, "kept_wide");
            let flip = m.as_uint(t.negative);
            let flip = m.cat(&vec![flip; sw as usize]);
            let flip = m.as_sint(flip);
            let flip = m.name(flip, "sign_mask");
            let ones_complement = m.xor(kept_s, flip);
            let ones_complement = m.name(ones_complement, "ones_complement");
            let sum = m.add(base, ones_complement);
            let sum = m.name(sum, "sum_wide");
            let base = sext(m, sum, sw);
            let negatives = add_bit(m, negatives, t.negative, "negatives");
            let neg_lost = m.and(t.negative, lost);
            let neg_lost = m.name(neg_lost, "lost_negative");
            let not_neg = m.not(t.negative);
            let pos_lost = m.and(not_neg, lost);
            let pos_lost = m.name(pos_lost, "lost_positive");
            let down = add_bit(m, down, neg_lost, "down");
            let up = add_bit(m, up, pos_lost, "up");
            (m.name(base, "partial_sum"), negatives, down, up)
        });
    }
    let negatives = to_sint(m, negatives, 4);
    let negatives = m.name(negatives, "negative_terms");
    let down = to_sint(m, down, 4);
    let down = m.name(down, "lost_below");
    let up = to_sint(m, up, 4);
    let up = m.name(up, "lost_above");
    let lo_adjust = ssub(m, negatives, down, 4);
    let lo_adjust = m.name(lo_adjust, "low_adjust");
    let hi_adjust = sadd(m, negatives, up, 4);
    let hi_adjust = m.name(hi_adjust, "high_adjust");
    let lo = sadd(m, base, lo_adjust, sw);
    let lo = m.name(lo, "low_wide");
    let hi = sadd(m, base, hi_adjust, sw);
    let hi = m.name(hi, "high_wide");
    let bw = tw + 1;
    let top = sext(m, top, bw);
    let top = m.name(top, "top_wide");
    let wc = m.sint(bw, i128::from(w));
    let b = ssub(m, top, wc, bw);
    (
        m.name(lo, "sum_lo"),
        m.name(hi, "sum_hi"),
        m.name(b, "sum_exp"),
    )
}

/// `2^q − 1`.
fn mask_of(q: u32) -> u128 {
    (1u128 << q) - 1
}

/// `count + bit`, a 2-bit count (at most 3 terms).
fn add_bit(m: &mut ModuleBuilder, count: Sig, bit: Sig, what: &str) -> Sig {
    let b = m.as_uint(bit);
    let b = zext(m, b, 2);
    let s = m.add(count, b);
    let s = m.name(s, &format!("{what}_sum"));
    let s = m.slice(s, 1, 0);
    m.name(s, what)
}

/// `⌊v·2^s⌋` (or `⌈v·2^s⌉` when `up`, a Bool), `v` and `s` SInt, `s ≥ −f`
/// (the window floor: the sum's lowest bit is at most `f` bits below the
/// grid), clamped to `±2^bits`: SInt of `bits + 2`. One right shifter: `v`
/// with `bits + 2` zeros below it, shifted right by `bits + 2 − s`, at most
/// `bits + 2 + f` (a larger `s` saturates any nonzero `v`); only `v`'s low
/// `f` bits can be shifted out.
fn to_grid(m: &mut ModuleBuilder, v: Sig, s: Sig, up: Sig, bits: u32, f: u32) -> Sig {
    let ow = bits + 2;
    let vw = v.width();
    assert!(f <= vw, "a window floor of {f} bits below a {vw}-bit sum");
    let lim = m.sint(ow, 1i128 << bits);
    let neg_lim = m.sint(ow, -(1i128 << bits));
    // the shift right: ow − s, from 0 (s = ow) to ow + f (s = −f)
    let rcap = bits_for(u64::from(ow + f));
    let sw = s.width().max(rcap + 1) + 1;
    let s = sext(m, s, sw);
    let s = m.name(s, "scale_wide");
    let headroom = m.sint(sw, i128::from(ow));
    let right = ssub(m, headroom, s, sw);
    let right = m.name(right, "right");
    let huge = m.msb(right);
    let huge = m.name(huge, "saturates");
    let amount = m.slice(right, rcap - 1, 0);
    let amount = m.name(amount, "shift");
    let zeros = m.uint(ow, 0);
    let ext = m.cat(&[v, zeros]);
    let ext = m.as_sint(ext);
    let ext = m.name(ext, "with_headroom");
    // only the low ow + 1 bits of the shift are formed: when v has significant bits at or
    // above `amount`, `ext >> amount` is outside [−2^ow, 2^ow) and beyond the clamp whatever
    // the rounding adds (found from v's leading sign bits, not from the shifted bits)
    let floor = m.shr(ext, amount);
    let floor = m.slice(floor, ow, 0);
    let floor = m.as_sint(floor);
    let floor = m.name(floor, "floor_low");
    let overflow = m.scope("beyond_low_bits", |m| {
        // v ∈ [−2^k, 2^k) for k = vw − 1 − (leading zeros of v's bits xor their upper
        // neighbours): the bits above k all equal the sign
        let upper = m.slice(v, vw - 1, 1);
        let lower = m.slice(v, vw - 2, 0);
        let changes = m.xor(upper, lower);
        let changes = m.as_uint(changes);
        let same = lzc(m, changes);
        let cw = same.width().max(amount.width()) + 1;
        let same = zext(m, same, cw);
        let amount_w = zext(m, amount, cw);
        let sum = m.add(same, amount_w);
        let sum = m.slice(sum, cw - 1, 0);
        let len = m.uint(cw, u128::from(vw - 1));
        let o = m.lt(sum, len);
        m.name(o, "overflow")
    });
    // a one shifted out: v's bit j (j < f) when the shift passes it, amount > ow + j
    let mut lost = m.bool(false);
    for j in 0..f {
        let bit = m.bit_at(v, j);
        let at = m.uint(rcap, u128::from(ow + j));
        let past = m.lt(at, amount);
        let out = m.and(bit, past);
        lost = m.or(lost, out);
    }
    let lost = m.name(lost, "shifted_out");
    let lost = m.and(lost, up);
    let lost = m.name(lost, "round_up");
    let l = m.as_uint(lost);
    let l = to_sint(m, l, 2);
    let l = m.name(l, "increment");
    let r = m.add(floor, l);
    let r = m.name(r, "rounded");
    let rw = r.width();
    let hi = sext(m, lim, rw);
    let lo = sext(m, neg_lim, rw);
    let above = m.lt(hi, r);
    let above = m.name(above, "above_limit");
    let below = m.lt(r, lo);
    let below = m.name(below, "below_limit");
    let r = m.slice(r, ow - 1, 0);
    let r = m.as_sint(r);
    let r = m.name(r, "rounded_low");
    let r = m.mux(above, lim, r);
    let r = m.name(r, "clamped_above");
    let r = m.mux(below, neg_lim, r);
    let r = m.name(r, "clamped");
    let zero_v = m.sint(vw, 0);
    let negative = m.lt(v, zero_v);
    let negative = m.name(negative, "negative");
    let beyond = m.mux(negative, neg_lim, lim);
    let beyond = m.name(beyond, "beyond_limit");
    let r = m.mux(overflow, beyond, r);
    let r = m.name(r, "clamped_or_beyond");
    // s beyond the headroom: any nonzero v is beyond the clamp
    let nonzero = m.ne(v, zero_v);
    let nonzero = m.name(nonzero, "nonzero");
    let zero_o = m.sint(ow, 0);
    let sat = m.mux(nonzero, beyond, zero_o);
    let sat = m.name(sat, "saturated_or_zero");
    let r = m.mux(huge, sat, r);
    m.name(r, "on_grid")
}

/// The per-node terms of one axis.
struct AxisTerms {
    parallel: Sig,
    mirror: Sig,
    x_lo: Sig,
    x_hi: Sig,
    /// `E = e + ⌊log2 |inv_d|⌋`
    e_sum: Sig,
    sig_lo: Sig,
    sig_hi: Sig,
}

/// The per-axis slope of the per-child test: significands rounded down and
/// up, the shift `z`, and whether each is above the cap.
struct Slope {
    /// cells per frame step rounded down, `sig · 2^z` in units of `2^kmin`
    down: Scaled,
    /// rounded up
    up: Scaled,
}

/// A slope `sig · 2^z` and how the product meets it. `products=split`: the
/// distance is clamped at `2^(sat − z)` (beyond it the product reaches the cap
/// anyway) and shifted by `z`, so the product is `(q + g + 3) × (m + 1)` bits,
/// one 18×18 block at q ≤ 11 and m ≤ 17. `products=whole`: the significand is shifted once per node
/// (`m + 1 + zmax` bits) and each child multiplies its distance by it, a
/// `(q + g + 4) × (m + 1 + zmax)` product that one DSP48E1 (25×18) takes whole,
/// with no shifter and no clamp per child.
#[derive(Clone, Copy)]
struct Scaled {
    /// the slope's factor of the product: `sig`, or `sig · 2^z` (whole)
    sig: Sig,
    /// `z` and `2^(sat − z)` when the distance is shifted (split)
    distance_shift: Option<(Sig, Sig)>,
    /// above the cap: every positive distance gives `C`
    over: Sig,
}

/// Builds `node` for a configuration.
pub fn build(cfg: &Config) -> Module {
    let mut m = ModuleBuilder::with_handshake(node_name(cfg));
    m.describe(
        "The node tester: one ray against a wide BVH node of N quantised child boxes, children sorted.",
    );
    let r: NodeIn<Sig> = ports::declare_inputs(&mut m, cfg);
    let fmt = cfg.fmt;
    let (q, g, h, mb) = (cfg.box_bits, POS_FRAC, CELL_BITS, cfg.slope_bits);
    let k_cap = cfg.cap_bits();
    let n = cfg.children as usize;
    let w = cfg.window_bits();
    let pos_bits = q + 3 + g;
    // inputs
    let un = |m: &mut ModuleBuilder, name: String, x: Sig| m.scope(&name, |m| unpack(m, fmt, x));
    let o: Vec<Unpacked> = (0..3)
        .map(|a| un(&mut m, format!("o_{}", AXES[a]), r.o[a]))
        .collect();
    let d: Vec<Unpacked> = (0..3)
        .map(|a| un(&mut m, format!("d_{}", AXES[a]), r.d[a]))
        .collect();
    let inv: Vec<Unpacked> = (0..3)
        .map(|a| un(&mut m, format!("inv_d_{}", AXES[a]), r.inv_d[a]))
        .collect();
    let org: Vec<Unpacked> = (0..3)
        .map(|a| un(&mut m, format!("frame_origin_{}", AXES[a]), r.origin[a]))
        .collect();
    let t_min = un(&mut m, "t_min".into(), r.t_min);
    let t_max = un(&mut m, "t_max".into(), r.t_max);
    let t_start = un(&mut m, "t_start".into(), r.t_start);
    let slot_valid: Vec<Sig> = (0..n)
        .map(|i| {
            let v = m.bit_at(r.valid, i as u32);
            m.name(v, &format!("slot{i}_valid"))
        })
        .collect();
    // bad input
    let bad = m.scope("bad_input", |m| {
        let mut flags = Vec::new();
        for a in 0..3 {
            let special = |m: &mut ModuleBuilder, u: &Unpacked| m.or(u.nan, u.inf);
            flags.push(special(m, &o[a]));
            flags.push(special(m, &d[a]));
            flags.push(special(m, &org[a]));
            flags.push(inv[a].nan);
            flags.push(inv[a].zero);
            let mismatch = m.ne(d[a].zero, inv[a].inf);
            flags.push(mismatch);
            let e = r.exp[a];
            let ew = e.width();
            let lo = m.sint(ew, i128::from(fmt.emin() as i32));
            let below = m.lt(e, lo);
            flags.push(below);
        }
        flags.push(t_min.nan);
        flags.push(t_max.nan);
        flags.push(t_start.nan);
        for (i, &valid) in slot_valid.iter().enumerate() {
            for a in 0..3 {
                let inverted = m.lt(r.hi[i][a], r.lo[i][a]);
                let wrong = m.and(valid, inverted);
                flags.push(wrong);
            }
        }
        crate::arith::float::classify::any_of(m, &flags, "is_bad")
    });
    // T = max(t_min, t_start): t_min unless t_start is strictly later
    let (t_bits, t_u) = m.scope("start", |m| {
        let (later, _, _) = compare(m, fmt, r.t_min, r.t_start);
        let t = m.mux(later, r.t_start, r.t_min);
        let t = m.name(t, "t");
        (t, unpack(m, fmt, t))
    });
    let t_neg_inf = m.and(t_u.inf, t_u.sign);
    let t_neg_inf = m.name(t_neg_inf, "no_start");
    let (t_term, t_rounded_bits, start_overflow) = m.scope("start_rounded", |m| {
        start_term(m, fmt, cfg.start_bits, t_bits, &t_u)
    });
    // every slot a miss: a start at +∞, an end at −∞ or before T
    let none = m.scope("empty_segment", |m| {
        let not_s = m.not(t_min.sign);
        let min_pos_inf = m.and(t_min.inf, not_s);
        let not_s = m.not(t_start.sign);
        let start_pos_inf = m.and(t_start.inf, not_s);
        let max_neg_inf = m.and(t_max.inf, t_max.sign);
        let (before, _, _) = compare(m, fmt, r.t_max, t_bits);
        let not_no_start = m.not(t_neg_inf);
        let before = m.and(before, not_no_start);
        let a = m.or(min_pos_inf, start_pos_inf);
        let b = m.or(max_neg_inf, before);
        let e = m.or(a, b);
        m.name(e, "empty")
    });
    // per axis: the position at T, E, the slope significands
    let axes: Vec<AxisTerms> = (0..3)
        .map(|a| {
            m.scope(&format!("axis_{}", AXES[a]), |m| {
                let parallel = m.name(inv[a].inf, "parallel");
                let not_parallel = m.not(parallel);
                let mirror = m.and(inv[a].sign, not_parallel);
                let mirror = m.name(mirror, "mirror");
                let ot = float_term(m, fmt, &o[a], false, "origin_term");
                let frame = float_term(m, fmt, &org[a], true, "frame_term");
                let dt = float_term(m, fmt, &d[a], false, "direction_term");
                let product = m.scope("t_times_d", |m| {
                    leading_one_product(m, t_term.sig, d[a].sig)
                });
                let product = m.name(product, "t_times_d");
                let sign = m.ne(t_term.negative, d[a].sign);
                let zero = m.or(t_term.zero, d[a].zero);
                let tw = t_term.top.width();
                let top = sadd(m, t_term.top, dt.top, tw);
                // a product's trailing zeros are its factors' together
                let tzw = t_term.tz.width().max(dt.tz.width()) + 1;
                let (ta, tb) = (zext(m, t_term.tz, tzw), zext(m, dt.tz, tzw));
                let tz = m.add(ta, tb);
                let pt = Term {
                    negative: sign,
                    sig: product,
                    zero,
                    top,
                    tz,
                };
                let lowest = lowest_window_top(m, r.exp[a], g, w);
                let (lo, hi, b) = window_sum(m, &[ot, frame, pt], w, lowest);
                assert_eq!(b.width(), position_sum_exp_bits(fmt.emin(), fmt.emax()));
                // s = B − (e − g); the frame exponent widened once for this and E
                let nz = m.scope("inv_d_normalised", |m| normalize(m, fmt, &inv[a]));
                let sw = b.width().max(r.exp[a].width()).max(nz.exp.width()) + 2;
                let frame_exp = sext(m, r.exp[a], sw);
                let frame_exp = m.name(frame_exp, "frame_exp_wide");
                let bs = sext(m, b, sw);
                let bs = m.name(bs, "sum_exp_wide");
                let s = ssub(m, bs, frame_exp, sw);
                let s = m.name(s, "grid_shift_less_g");
                let gc = m.sint(sw, i128::from(g));
                let s = sadd(m, s, gc, sw);
                let s = m.name(s, "grid_shift");
                // outward for a slab axis; inward for a parallel one (golden model)
                let x_lo = m.scope("x_lo", |m| {
                    to_grid(m, lo, s, parallel, pos_bits, WINDOW_FLOOR)
                });
                let x_hi = m.scope("x_hi", |m| {
                    to_grid(m, hi, s, not_parallel, pos_bits, WINDOW_FLOOR)
                });
                // in the frame of the child's entry and exit planes, once per node: mirrored
                // (Q·2^g − x) for a negative direction, so each child forms entry − x_hi and
                // exit − x_lo (for a parallel axis lo − x_hi > 0 or hi − x_lo < 0: outside)
                let (x_lo, x_hi) = m.scope("plane_frame", |m| {
                    let xw = x_lo.width() + 1;
                    let top = m.sint(xw, (mask_of(q) as i128) << g);
                    let lo_w = sext(m, x_lo, xw);
                    let lo_w = m.name(lo_w, "low_wide");
                    let hi_w = sext(m, x_hi, xw);
                    let hi_w = m.name(hi_w, "high_wide");
                    let mirrored_lo = ssub(m, top, hi_w, xw);
                    let mirrored_lo = m.name(mirrored_lo, "mirrored_low");
                    let mirrored_hi = ssub(m, top, lo_w, xw);
                    let mirrored_hi = m.name(mirrored_hi, "mirrored_high");
                    let lo = m.mux(mirror, mirrored_lo, lo_w);
                    let hi = m.mux(mirror, mirrored_hi, hi_w);
                    (m.name(lo, "from_lo"), m.name(hi, "from_hi"))
                });
                // E = e + ⌊log2 |inv_d|⌋
                let ew = sw;
                let e1 = sext(m, nz.exp, ew);
                let e1 = m.name(e1, "inv_d_exp_wide");
                let e_sum = sadd(m, e1, frame_exp, ew);
                // m-bit significands: rounded down, and up past inv_d's successor
                let fw = fmt.frac_bits + 1;
                let (sig_lo, sig_hi) = m.scope("slope", |m| {
                    let lo = if mb <= fw {
                        m.slice(nz.sig, fw - 1, fw - mb)
                    } else {
                        let z = m.uint(mb - fw, 0);
                        m.cat(&[nz.sig, z])
                    };
                    // the successor's step in units of lo: 2^max(0, lz + m − F − 1)
                    let lz = lzc(m, inv[a].sig);
                    let lzw = lz.width() + 2;
                    let lz_s = to_sint(m, lz, lzw.max(bits_for(u64::from(mb + fw)) + 2));
                    let xw = lz_s.width();
                    let off = m.sint(xw, i128::from(mb) - i128::from(fw));
                    let step_exp = sadd(m, lz_s, off, xw);
                    let neg = m.msb(step_exp);
                    let step_exp = m.as_uint(step_exp);
                    let zero_u = m.uint(xw, 0);
                    let step_exp = m.mux(neg, zero_u, step_exp);
                    let one = m.uint(mb + 1, 1);
                    let step = m.shl(one, step_exp);
                    let lo_w = zext(m, lo, mb + 1);
                    let hi = m.add(lo_w, step);
                    let hi = m.slice(hi, mb, 0);
                    (m.name(lo, "sig_down"), m.name(hi, "sig_up"))
                });
                AxisTerms {
                    parallel,
                    mirror,
                    x_lo,
                    x_hi,
                    e_sum: m.name(e_sum, "e_sum"),
                    sig_lo,
                    sig_hi,
                }
            })
        })
        .collect();
    // G = min E − h over the non-parallel axes (0 when every axis is parallel)
    let ew = axes[0].e_sum.width();
    let (e_min, any_slab) = m.scope("grid", |m| {
        let big = m.sint(ew, (1i128 << (ew - 1)) - 1);
        let mut e_min = big;
        let mut any = m.bool(false);
        for ax in &axes {
            let e = m.mux(ax.parallel, big, ax.e_sum);
            let smaller = m.lt(e, e_min);
            e_min = m.mux(smaller, e, e_min);
            let slab = m.not(ax.parallel);
            any = m.or(any, slab);
        }
        (m.name(e_min, "e_min"), m.name(any, "any_slab"))
    });
    let gw = cfg.grid_exp_bits();
    let grid_exp = m.scope("grid", |m| {
        let wide = ew.max(gw) + 1;
        let e = sext(m, e_min, wide);
        let hc = m.sint(wide, i128::from(h));
        let gexp = ssub(m, e, hc, wide);
        let gexp = m.slice(gexp, gw - 1, 0);
        let gexp = m.as_sint(gexp);
        let zero = m.sint(gw, 0);
        let gexp = m.mux(any_slab, gexp, zero);
        m.name(gexp, "grid_exp")
    });
    // slopes: z = E − min E; above the cap when z > zmax, or z = zmax and sig > 2^(m−1).
    // inv_d at the largest finite value bounds 1/|d| by 2^(F − emin): the upper
    // slope is 2^(m−1) shifted by z + F − 1.
    let zmax = q + 2 + g;
    let zbits = bits_for(u64::from(zmax));
    let slopes: Vec<Slope> = axes
        .iter()
        .enumerate()
        .map(|(a, ax)| {
            m.scope(&format!("slope_{}", AXES[a]), |m| {
                let at_max = is_max_finite(m, fmt, r.inv_d[a]);
                let at_max = m.name(at_max, "inv_d_at_max");
                let z = m.sub(ax.e_sum, e_min);
                let zw = z.width() + 1;
                let z = sext(m, z, zw);
                let lift = m.sint(zw, i128::from(fmt.frac_bits) - 1);
                let z_max = sadd(m, z, lift, zw);
                let z_hi = m.mux(at_max, z_max, z);
                let half = m.uint(mb + 1, 1u128 << (mb - 1));
                let sig_hi = m.mux(at_max, half, ax.sig_hi);
                let sig_hi = m.name(sig_hi, "sig_up_used");
                let lo_w = zext(m, ax.sig_lo, mb + 1);
                let zmax_c = m.sint(zw, i128::from(zmax));
                let over = |m: &mut ModuleBuilder, z: Sig, sig: Sig| {
                    let beyond = m.lt(zmax_c, z);
                    let at = m.eq(z, zmax_c);
                    let big = m.lt(half, sig);
                    let at_big = m.and(at, big);
                    m.or(beyond, at_big)
                };
                let lo_over = over(m, z, lo_w);
                let hi_over = over(m, z_hi, sig_hi);
                // an over-cap slope's shift does not matter
                let top = m.uint(zmax + 1, 1u128 << zmax);
                let whole = cfg.products == Products::Whole;
                let scaled = |m: &mut ModuleBuilder, sig: Sig, z: Sig, over: Sig, what: &str| {
                    m.scope(what, |m| {
                        let shift = m.slice(z, zbits - 1, 0);
                        let shift = m.name(shift, "shift");
                        let over = m.name(over, "over_cap");
                        if whole {
                            let wide = zext(m, sig, mb + 1 + zmax);
                            let sig = m.shl(wide, shift);
                            Scaled {
                                sig: m.name(sig, "shifted"),
                                distance_shift: None,
                                over,
                            }
                        } else {
                            let limit = m.shr(top, shift);
                            Scaled {
                                sig,
                                distance_shift: Some((shift, m.name(limit, "distance_limit"))),
                                over,
                            }
                        }
                    })
                };
                Slope {
                    down: scaled(m, lo_w, z, lo_over, "down"),
                    up: scaled(m, sig_hi, z_hi, hi_over, "up"),
                }
            })
        })
        .collect();
    // the window end: ⌈(t_max − T)/2^G⌉, capped at C (C for t_max = +∞)
    let cap_w = k_cap + 2;
    let far_top = m.scope("window_end", |m| {
        let end = float_term(m, fmt, &t_max, false, "end_term");
        let start = t_term.negated(m);
        let lowest = lowest_window_top(m, grid_exp, 0, cfg.end_window_bits());
        let (_, hi, b) = window_sum(m, &[end, start], cfg.end_window_bits(), lowest);
        let sw = b.width().max(gw) + 2;
        let bs = sext(m, b, sw);
        let gs = sext(m, grid_exp, sw);
        let s = ssub(m, bs, gs, sw);
        let round_up = m.bool(true);
        let v = to_grid(m, hi, s, round_up, k_cap, WINDOW_FLOOR);
        let v = sext(m, v, cap_w);
        let cap = m.sint(cap_w, 1i128 << k_cap);
        let open = m.or(t_max.inf, t_neg_inf);
        let v = m.mux(open, cap, v);
        m.name(v, "far_top")
    });
    // per child
    let zero_c = m.sint(cap_w, 0);
    let dist_bits = q + g + 5;
    let mut hits = Vec::new();
    let mut nears = Vec::new();
    for i in 0..n {
        let (hit, near) = m.scope(&format!("slot{i}"), |m| {
            let mut near_max = zero_c;
            let mut exits = Vec::new();
            let mut missed = m.bool(false);
            for a in 0..3 {
                let ax = &axes[a];
                let sl = &slopes[a];
                let (axis_miss, near, exit) = m.scope(&format!("axis_{}", AXES[a]), |m| {
                    // the entry and exit planes (mirrored: Q − hi, Q − lo)
                    let (not_hi, not_lo) = (m.not(r.hi[i][a]), m.not(r.lo[i][a]));
                    let entry = m.mux(ax.mirror, not_hi, r.lo[i][a]);
                    let exit = m.mux(ax.mirror, not_lo, r.hi[i][a]);
                    let gz = m.uint(g, 0);
                    let entry = m.cat(&[entry, gz]);
                    let exit = m.cat(&[exit, gz]);
                    let entry = to_sint(m, entry, dist_bits);
                    let exit = to_sint(m, exit, dist_bits);
                    let from_lo = sext(m, ax.x_lo, dist_bits);
                    let from_hi = sext(m, ax.x_hi, dist_bits);
                    let dn = m.sub(entry, from_hi);
                    let dn = m.name(dn, "entry_gap");
                    let dn = sext(m, dn, dist_bits);
                    let dn = m.name(dn, "entry_distance");
                    let df = m.sub(exit, from_lo);
                    let df = m.name(df, "exit_gap");
                    let df = sext(m, df, dist_bits);
                    let df = m.name(df, "exit_distance");
                    // an exit behind T misses; a parallel axis misses outside its slab
                    let behind = m.msb(df);
                    let zero_d = m.sint(dist_bits, 0);
                    let outside = m.lt(zero_d, dn);
                    let par_miss = m.and(ax.parallel, outside);
                    let axis_miss = m.or(par_miss, behind);
                    // a parallel axis's entry distance is at most 0 when it does not miss
                    let near = m.scope("entry_cells", |m| {
                        let product = slope_product(m, dn, sl.down);
                        near_cells(m, cfg, dn, product, sl.down.over)
                    });
                    // the exit's cells are never formed: only whether they admit the entry
                    let exit_product = m.scope("exit_cells", |m| slope_product(m, df, sl.up));
                    // over the cap only past T: an exit at T has 0 cells at any slope (a
                    // negative distance misses beside this, so `df ≠ 0` says `df > 0`)
                    let past = m.any_set(df);
                    let over = m.and(sl.up.over, past);
                    let always = m.or(ax.parallel, over);
                    (
                        m.name(axis_miss, "misses"),
                        m.name(near, "near_cells"),
                        (exit_product, always),
                    )
                });
                missed = m.or(missed, axis_miss);
                let larger = m.lt(near_max, near);
                near_max = m.mux(larger, near, near_max);
                exits.push(exit);
            }
            let near_max = m.name(near_max, "near_max");
            // near_max ≤ min far as four comparisons (no multiplexers for the minimum); an
            // exit's `min(C, ⌈p·2^kmin⌉) ≥ near_max` (near_max is at most C) is `p >
            // (near_max − 1)·2^−kmin`: one comparison per exit of the product's bits at and
            // above the cells' unit (and whether any below it is set) with `near_max − 1`,
            // with no rounding, cap or minimum of the exit's cells
            let before = m.le(near_max, far_top);
            let mut overlap = m.name(before, "window_admits");
            let least = least_exit_cells(m, near_max);
            for (a, (product, always)) in exits.into_iter().enumerate() {
                let admits = m.scope(&format!("axis_{}", AXES[a]), |m| {
                    let enough = exit_reaches(m, cfg, product, least);
                    let admits = m.or(always, enough);
                    m.name(admits, "exit_admits")
                });
                overlap = m.and(overlap, admits);
            }
            let overlap = m.name(overlap, "overlap");
            let not_missed = m.not(missed);
            let hit = m.and(overlap, not_missed);
            (m.name(hit, "box_hit"), near_max)
        });
        hits.push(hit);
        nears.push(near);
    }
    // special cases, then the sort
    let eb = cfg.entry_bits();
    let sentinel = m.uint(eb, (1u128 << eb) - 1);
    let zero_e = m.uint(eb, 0);
    // no start (T = −∞, or a negative one rounded beyond the format) unless the segment is
    // empty (the model checks t_max < T first; T = −∞ never makes it empty)
    let not_none = m.not(none);
    let overflow = m.and(start_overflow, not_none);
    let open = m.or(t_neg_inf, overflow);
    let all_in = m.or(bad, open);
    let all_in = m.name(all_in, "every_valid_slot");
    let good = m.not(bad);
    let none = m.and(none, good);
    let (slot_hit, slot_entry): (Vec<Sig>, Vec<Sig>) = (0..n)
        .map(|i| {
            m.scope(&format!("slot{i}"), |m| {
                let valid = slot_valid[i];
                let live = m.not(none);
                let tested = m.and(live, hits[i]);
                let yes = m.bool(true);
                let hit = m.mux(all_in, yes, tested);
                let hit = m.and(valid, hit);
                let entry = m.slice(nears[i], eb - 1, 0);
                let entry = m.mux(all_in, zero_e, entry);
                let entry = m.mux(hit, entry, sentinel);
                (m.name(hit, "slot_hit"), m.name(entry, "slot_entry"))
            })
        })
        .unzip();
    let sorted = m.scope("sort", |m| sort_slots(m, &slot_hit, &slot_entry));
    // T and G when there is a T
    let neg_inf = m.uint(fmt.width(), fmt.inf_bits() | 1u128 << (fmt.width() - 1));
    let no_t = m.or(all_in, none);
    let plus_zero = m.uint(fmt.width(), 0);
    let t_out = m.mux(t_term.zero, plus_zero, t_rounded_bits);
    let t_out = m.mux(no_t, neg_inf, t_out);
    let zero_g = m.sint(gw, 0);
    let g_out = m.mux(no_t, zero_g, grid_exp);
    let t_out = m.name(t_out, "t_base");
    let g_out = m.name(g_out, "grid_exp_out");
    ports::declare_outputs(
        &mut m,
        cfg,
        &NodeOut {
            bad,
            t_base: t_out,
            grid_exp: g_out,
            hit: sorted.hit,
            entry: sorted.entry,
            child: sorted.child,
        },
    );
    let datapath = m.finish().expect("node datapath is well formed");
    if cfg.stages == 0 {
        return datapath;
    }
    let (mut module, _) = crate::retime::balance_with(&datapath, cfg.stages, cfg.products)
        .expect("the node datapath is feed-forward");
    module.name = datapath.name.clone();
    module
}

/// The exponent of a product's unit in cells, `kmin = h − m + 1 − g`: a
/// product `p` of a distance (`2^−g` steps) and a slope significand is
/// `p·2^kmin` cells. Negative for every `m` the parameters allow (`m ≥ 4`).
fn product_exp(cfg: &Config) -> u32 {
    let (g, h, mb) = (POS_FRAC, CELL_BITS, cfg.slope_bits);
    let kmin = h as i64 - mb as i64 + 1 - g as i64;
    assert!(
        kmin < 0,
        "slope_bits {mb} leaves the product's cells unrounded"
    );
    (-kmin) as u32
}

/// The product of a distance `dist` (frame steps in `2^−g` units, SInt) and a
/// slope, in units of `2^kmin` cells: the distance's magnitude bits times the
/// slope's factor (meaningful for a positive distance only; the callers
/// decide the others). With `split` the distance is first clamped at
/// `2^(sat − z)`, beyond which the product reaches the cap at this slope.
fn slope_product(m: &mut ModuleBuilder, dist: Sig, slope: Scaled) -> Sig {
    let dw = dist.width();
    let mag = m.slice(dist, dw - 2, 0);
    let mag = match slope.distance_shift {
        None => mag,
        Some((shift, limit)) => {
            let lw = limit.width();
            let mag = zext(m, mag, (dw - 1).max(lw));
            let limit = zext(m, limit, (dw - 1).max(lw));
            let big = m.lt(limit, mag);
            let mag = m.mux(big, limit, mag);
            let mag = m.name(mag, "limited");
            let mag = m.slice(mag, lw - 1, 0);
            m.shl(mag, shift)
        }
    };
    let mag = m.name(mag, "distance");
    let product = m.mul(mag, slope.sig);
    m.name(product, "product")
}

/// An entry's cells from `T`: 0 for a distance at most 0 (an entry already
/// crossed), else `⌊product·2^kmin⌋` capped at `C`; `C` when the slope is over
/// the cap. SInt of `K + 2`.
fn near_cells(m: &mut ModuleBuilder, cfg: &Config, dist: Sig, product: Sig, over: Sig) -> Sig {
    let k_cap = cfg.cap_bits();
    let cap_w = k_cap + 2;
    let cap = m.sint(cap_w, 1i128 << k_cap);
    let zero = m.sint(cap_w, 0);
    let dw = dist.width();
    let zero_d = m.sint(dw, 0);
    let positive = m.lt(zero_d, dist);
    let pw = product.width();
    let value = m.slice(product, pw - 1, product_exp(cfg));
    let value = m.name(value, "cells");
    let vw = value.width().max(k_cap + 1);
    let cap_u = m.uint(vw, 1u128 << k_cap);
    let value = zext(m, value, vw);
    let capped = m.lt(cap_u, value);
    let v = m.slice(value, k_cap, 0);
    let v = to_sint(m, v, cap_w);
    let at_cap = m.or(capped, over);
    let v = m.mux(at_cap, cap, v);
    let not_pos = m.not(positive);
    m.mux(not_pos, zero, v)
}

/// `2·(near_max − 1) + 1`, SInt of `K + 3` bits (`near_max` is `0 ..= C =
/// 2^K`): the key an exit's product reaches when its cells reach `near_max`
/// ([`exit_reaches`]). Formed once per child.
fn least_exit_cells(m: &mut ModuleBuilder, near_max: Sig) -> Sig {
    let w = near_max.width() + 1;
    let n = sext(m, near_max, w);
    let one = m.sint(w, 1);
    let below = m.sub(n, one);
    let below = sext(m, below, w);
    let below = m.name(below, "near_max_less_one");
    // `2·(C − 1) + 1 < 2^(K+1)`: one sign bit above it
    let below = m.slice(below, w - 2, 0);
    let odd = m.bool(true);
    let key = m.cat(&[below, odd]);
    let key = m.as_sint(key);
    m.name(key, "least_exit_cells")
}

/// Whether an exit product `p` (UInt, units of `2^kmin` cells) has
/// `⌈p·2^kmin⌉ ≥ near_max`, that is `p > (near_max − 1)·2^−kmin`: with `p =
/// hi·2^−kmin + lo` (`lo` the bits below the cells' unit), `2·hi + [lo ≠ 0] ≥
/// 2·(near_max − 1) + 1` (`least`, [`least_exit_cells`]). Only `hi`'s low `K`
/// bits are compared: `near_max − 1 < 2^K`, so a larger `hi` reaches it.
fn exit_reaches(m: &mut ModuleBuilder, cfg: &Config, product: Sig, least: Sig) -> Sig {
    let k = product_exp(cfg);
    let k_cap = cfg.cap_bits();
    let pw = product.width();
    assert!(pw > k, "a product has bits at the cells' unit");
    let low = m.slice(product, k - 1, 0);
    let below_unit = m.any_set(low);
    let (cells, beyond) = if pw > k + k_cap {
        let cells = m.slice(product, k + k_cap - 1, k);
        let high = m.slice(product, pw - 1, k + k_cap);
        (cells, m.any_set(high))
    } else {
        let cells = m.slice(product, pw - 1, k);
        (zext(m, cells, k_cap), m.bool(false))
    };
    let key = m.cat(&[cells, below_unit]);
    let lw = least.width();
    let key = zext(m, key, lw);
    let key = m.as_sint(key);
    let key = m.name(key, "exit_key");
    let short = m.lt(key, least);
    let enough = m.not(short);
    m.or(beyond, enough)
}

impl Description for Node {
    type Params = NodeParams;
    type Config = Config;
    const NAME: &'static str = "node";
    const SUMMARY: &'static str =
        "node tester: one ray against a wide BVH node of N quantised child boxes, hits sorted by entry";
    fn config(&self, p: &NodeParams) -> Result<Config, ParamError> {
        if ![2, 4, 8].contains(&p.children) {
            return Err(ParamError::Combination(format!(
                "children={} (N must be 2, 4 or 8)",
                p.children
            )));
        }
        Ok(Config {
            fmt: Format::new(p.exp_bits, p.frac_bits).map_err(ParamError::Combination)?,
            children: p.children,
            box_bits: p.box_bits,
            slope_bits: p.slope_bits,
            start_bits: p.start_bits,
            stages: p.stages,
            products: p.products,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;

    /// An exit admits `near_max` exactly when its product `p` is above
    /// `(near_max − 1)·2^−kmin` ([`exit_reaches`]): for every `near_max` of `0
    /// ..= C`, products at the boundary and one step either side (at the
    /// cells' unit and below it) and beyond the compared bits, for products
    /// narrower than, as wide as and wider than the compared bits. The node
    /// tests' random rays rarely land an exit exactly on a cell boundary.
    /// `products=split` exists so that each child product fits one 18×18
    /// block: the clamped, shifted distance is `q + g + 3` bits and the slope
    /// `m + 1` (a wider wire holds the same values on a bigger multiplier,
    /// which no evaluator test sees).
    #[test]
    fn every_split_child_product_fits_one_18x18_block() {
        fn products(m: &Module, out: &mut Vec<(String, u32, u32)>) {
            for n in &m.nodes {
                if let crate::ir::Op::Mul(a, b) = n.op {
                    let w = |id: crate::ir::NodeId| m.nodes[id.0 as usize].ty.width();
                    out.push((n.name.clone(), w(a), w(b)));
                }
            }
            for i in &m.instances {
                products(&i.module, out);
            }
        }
        for (q, mb) in [(4, 4), (8, 9), (11, 12)] {
            let p = NodeParams {
                box_bits: q,
                slope_bits: mb,
                stages: 0,
                ..NodeParams::defaults()
            };
            let cfg = Node.config(&p).expect("a valid node");
            assert_eq!(cfg.products, Products::Split);
            let mut found = Vec::new();
            products(&build(&cfg), &mut found);
            let children: Vec<_> = found
                .iter()
                .filter(|(n, ..)| n.ends_with("product"))
                .collect();
            assert_eq!(children.len(), 6 * cfg.children as usize, "{found:?}");
            for (name, wa, wb) in children {
                assert_eq!(
                    (*wa, *wb),
                    (q + POS_FRAC + 3, mb + 1),
                    "q = {q}, m = {mb}: {name}"
                );
                assert!(*wa <= 18 && *wb <= 18, "{name}");
            }
        }
    }

    #[test]
    fn an_exit_admits_exactly_the_entries_its_product_passes() {
        let p = NodeParams {
            box_bits: 4,
            slope_bits: 4,
            ..NodeParams::defaults()
        };
        let cfg = Node.config(&p).expect("a valid node");
        let (k, k_cap) = (product_exp(&cfg), cfg.cap_bits());
        let mut checked = 0;
        // products narrower than, as wide as and wider than the compared bits
        for pw in [k + k_cap - 1, k + k_cap, k + k_cap + 3] {
            let mut m = ModuleBuilder::new(format!("exit_test_{pw}"));
            let product = m.input("product", Ty::UInt(pw));
            let near_max = m.input("near_max", Ty::SInt(k_cap + 2));
            let least = least_exit_cells(&mut m, near_max);
            let admits = exit_reaches(&mut m, &cfg, product, least);
            m.output("admits", admits);
            let module = m.finish().expect("a well-formed test module");
            let mut ev = Evaluator::new(&module);
            for n in 0..=1u128 << k_cap {
                let boundary = n.saturating_sub(1) << k;
                let products = [
                    0,
                    1,
                    boundary.wrapping_sub(1),
                    boundary,
                    boundary + 1,
                    boundary + (1 << k),
                    1 << (k + k_cap),
                    (1u128 << pw) - 1,
                ];
                for p in products.into_iter().filter(|&p| p < 1 << pw) {
                    let want = n == 0 || p > (n - 1) << k;
                    let got = ev.eval(&[p, n])[0] == 1;
                    assert_eq!(got, want, "{pw}-bit product {p:#x}, near_max {n}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 18 << k_cap, "{checked} cases");
    }
}
