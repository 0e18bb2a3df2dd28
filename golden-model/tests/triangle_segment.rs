//! The `segment=log` test of `outputs=hit|tnum` ([`segment_log`],
//! [`eval_tnum_with`] with [`Segment::Log`]) against exact rationals: it
//! never rejects a `t` within `[t_min, t_max]` nor lets a `|t| ≥ 2^(emax+1)`
//! through unflagged, and is tight (a looser margin would fail here); bit
//! for bit the Python model `docs/experiments/triangle-dsp24/segment_model.py`
//! at binary32; and on random triangles it loses no hit of the exact test.

mod common;

use common::Rng;
use dashu::integer::IBig;
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::triangle::{
    eval_tnum, eval_tnum_with, internal_format, log_segment_constants, segment_log, Segment, TriIn,
};
use std::cmp::Ordering::{self, *};

const F32: FloatFormat = FloatFormat::BINARY32;
const E5M10: FloatFormat = FloatFormat::BINARY16;
const E8M7: FloatFormat = FloatFormat::BFLOAT16;

/// The draws these tests make, on the shared generator.
trait Draws {
    /// uniform in `[lo, hi]`
    fn int(&mut self, lo: i64, hi: i64) -> i64;
    /// `n` uniform bits
    fn bits(&mut self, n: u32) -> u64;
    /// true with `percent` per cent
    fn chance(&mut self, percent: u64) -> bool;
    /// uniform in `[lo, hi)`
    fn real(&mut self, lo: f64, hi: f64) -> f64;
}

impl Draws for Rng {
    fn int(&mut self, lo: i64, hi: i64) -> i64 {
        self.range(lo, hi)
    }
    fn bits(&mut self, n: u32) -> u64 {
        if n == 0 {
            0
        } else {
            self.next() >> (64 - n)
        }
    }
    fn chance(&mut self, percent: u64) -> bool {
        self.below(100) < percent
    }
    fn real(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }
}

/// `2^−K` times the most by which a truncated Mitchell logarithm falls
/// below `log2`: `max(log2(1+f) − f) + 2^−K`.
fn delta(k: u32) -> f64 {
    let f = 1.0 / std::f64::consts::LN_2 - 1.0;
    (1.0 + f).log2() - f + (-(k as f64)).exp2()
}

// ---- exact values, decoded independently of the crate -------------------

/// A value of a float format: `±∞` or `m·2^e` (both zeros `m = 0`); NaN is
/// never generated.
#[derive(Debug, Clone, Copy)]
enum Val {
    NegInf,
    PosInf,
    Fin(i64, i64),
}

fn decode(fmt: FloatFormat, bits: u64) -> Val {
    let (f, eb) = (fmt.frac_bits(), fmt.exp_bits());
    let neg = (bits >> (eb + f)) & 1 == 1;
    let exp = ((bits >> f) & ((1 << eb) - 1)) as i64;
    let frac = (bits & ((1 << f) - 1)) as i64;
    let bias = fmt.bias() as i64;
    if exp == (1 << eb) - 1 {
        assert_eq!(frac, 0, "no NaN is generated");
        return if neg { Val::NegInf } else { Val::PosInf };
    }
    let (m, e) = if exp == 0 {
        (frac, 1 - bias - f as i64)
    } else {
        (frac | (1 << f), exp - bias - f as i64)
    };
    Val::Fin(if neg { -m } else { m }, e)
}

fn fin(fmt: FloatFormat, bits: u64) -> (i64, i64) {
    match decode(fmt, bits) {
        Val::Fin(m, e) => (m, e),
        v => panic!("{bits:#x} is {v:?}"),
    }
}

/// The order of `a·2^ea` and `b·2^eb`.
fn cmp_scaled(a: IBig, ea: i64, b: IBig, eb: i64) -> Ordering {
    if ea >= eb {
        (a << (ea - eb) as usize).cmp(&b)
    } else {
        a.cmp(&(b << (eb - ea) as usize))
    }
}

/// `t = T/D` exactly, against scaled bounds.
#[derive(Debug, Clone, Copy)]
struct Ratio {
    /// `T·sgn(D)` and `|D|`: `t = tm·2^te / (dm·2^de)`, `dm > 0`
    tm: i64,
    te: i64,
    dm: i64,
    de: i64,
}

impl Ratio {
    fn new(w: FloatFormat, t: u64, d: u64) -> Ratio {
        let ((tm, te), (dm, de)) = (fin(w, t), fin(w, d));
        assert_ne!(dm, 0);
        Ratio {
            tm: if dm < 0 { -tm } else { tm },
            te,
            dm: dm.abs(),
            de,
        }
    }
    /// The order of `t` and `(num/den)·m·2^e` (`num, den > 0`).
    fn cmp(&self, num: i64, den: i64, m: i64, e: i64) -> Ordering {
        cmp_scaled(
            IBig::from(self.tm) * den,
            self.te,
            IBig::from(m) * num * self.dm,
            e + self.de,
        )
    }
    /// The order of `t` and `(num/den)·bound` (`num, den > 0`).
    fn cmp_bound(&self, num: i64, den: i64, bound: Val) -> Ordering {
        match bound {
            Val::NegInf => Greater,
            Val::PosInf => Less,
            Val::Fin(m, e) => self.cmp(num, den, m, e),
        }
    }
    /// The order of `|t|` and `(num/den)·2^e`.
    fn cmp_abs_pow2(&self, num: i64, den: i64, e: i64) -> Ordering {
        let abs = Ratio {
            tm: self.tm.abs(),
            ..*self
        };
        abs.cmp(num, den, 1, e)
    }
    /// `t / (m·2^e)` as an `f64` (for `t` and the bound within a few octaves).
    fn over(&self, m: i64, e: i64) -> f64 {
        self.tm as f64 / (self.dm as f64 * m as f64) * ((self.te - self.de - e) as f64).exp2()
    }
}

// ---- stimulus -----------------------------------------------------------

/// A value of `fmt` built from `m·2^e` (`m ≠ 0`), normal, exactly; `None`
/// when that needs more fraction bits or lies outside the normal range.
fn normal_from(fmt: FloatFormat, neg: bool, m: u64, e: i64) -> Option<u64> {
    let f = fmt.frac_bits() as i64;
    let (m, e) = (m >> m.trailing_zeros(), e + m.trailing_zeros() as i64);
    let len = 64 - m.leading_zeros() as i64;
    if len > f + 1 {
        return None;
    }
    let biased = e + len - 1 + fmt.bias() as i64;
    if biased < 1 || biased > (1 << fmt.exp_bits()) - 2 {
        return None;
    }
    let frac = (m << (f + 1 - len)) & fmt.frac_mask();
    Some(fmt.with_sign(neg, ((biased as u64) << f) | frac))
}

/// A bound of `fmt` near `±2^e` (random fraction): normal, subnormal, or
/// clamped to zero, the smallest subnormal, the largest finite value or ∞.
fn bound_near(rng: &mut Rng, fmt: FloatFormat, neg: bool, e: i64) -> u64 {
    let f = fmt.frac_bits() as i64;
    let biased = e + fmt.bias() as i64;
    let top = (1i64 << fmt.exp_bits()) - 2;
    let mag = if biased > top {
        if rng.chance(50) {
            fmt.max_finite(false)
        } else {
            fmt.inf(false)
        }
    } else if biased >= 1 {
        ((biased as u64) << f) | rng.bits(f as u32)
    } else {
        // subnormal: the leading bit at 2^e = 2^(emin − f + k)
        let k = e - (fmt.emin() as i64 - f);
        if k >= 0 {
            (1u64 << k) | (rng.bits(f as u32) & ((1u64 << k) - 1))
        } else if rng.chance(50) {
            fmt.min_subnormal(false)
        } else {
            0
        }
    };
    fmt.with_sign(neg, mag)
}

/// The special bounds: zeros, extreme subnormals and normals, infinities, 1.
fn special(rng: &mut Rng, fmt: FloatFormat) -> u64 {
    let neg = rng.chance(50);
    let mag = match rng.int(0, 6) {
        0 => 0,
        1 => fmt.min_subnormal(false),
        2 => fmt.max_subnormal(false),
        3 => fmt.min_normal(false),
        4 => fmt.max_finite(false),
        5 => fmt.inf(false),
        _ => fmt.one(false),
    };
    fmt.with_sign(neg, mag)
}

/// A normal or zero value of `w`: random sign and fraction (sometimes 0,
/// all ones, or Mitchell's worst `1/ln 2 − 1`), the biased exponent given.
fn w_value(rng: &mut Rng, w: FloatFormat, biased: i64) -> u64 {
    let f = w.frac_bits();
    let frac = match rng.int(0, 19) {
        0 => 0,
        1 => w.frac_mask(),
        2 => ((1.0 / std::f64::consts::LN_2 - 1.0) * (1u64 << f) as f64) as u64 + rng.bits(2),
        _ => rng.bits(f),
    };
    w.with_sign(rng.chance(50), ((biased as u64) << f) | frac)
}

/// One random case `(T, D, L, H)` for `fmt` (internal format `w`): the
/// exponents of T and D over the whole range of `w` (extremes included),
/// `t` mostly within `fmt`'s range and sometimes near `2^(emax+1)`, `T`
/// sometimes ±0; bounds near `t` (within a factor 2, either sign), equal
/// to `t` (a product `T = bound·D` built exactly), special, or random.
fn case(rng: &mut Rng, fmt: FloatFormat, w: FloatFormat) -> (u64, u64, u64, u64) {
    let top = (1i64 << w.exp_bits()) - 2;
    let (ff, bias_f) = (fmt.frac_bits() as i64, fmt.bias() as i64);
    let rand_exp = |rng: &mut Rng| match rng.int(0, 9) {
        0 => rng.int(1, 3),
        1 => rng.int(top - 2, top),
        _ => rng.int(1, top),
    };
    // t = bound exactly: a bound with `sig` significant bits times a D with
    // at most F + 1 − sig (the product T exact in w)
    if rng.chance(15) {
        let sig = rng.int(1, ff.min(8)) as u32;
        let bound = loop {
            let b = if rng.chance(25) {
                special(rng, fmt)
            } else {
                let (neg, e) = (
                    rng.chance(50),
                    rng.int(fmt.emin() as i64 - ff - 1, fmt.emax() as i64),
                );
                bound_near(rng, fmt, neg, e)
            };
            // a finite nonzero bound, cut to `sig` significant bits (a
            // subnormal's bits are its fraction: clearing low bits keeps it
            // subnormal)
            let mag = b & !fmt.sign_bit();
            if fmt.is_finite(b) && mag != 0 {
                let len = if mag < fmt.min_normal(false) {
                    64 - mag.leading_zeros()
                } else {
                    fmt.frac_bits() + 1
                };
                let cut = len.saturating_sub(sig);
                break b >> cut << cut;
            }
        };
        let (bm, be) = fin(fmt, bound);
        let j = rng.int(0, ff + 1 - sig as i64 - 1) as u32;
        let a = (1u64 << j) | rng.bits(j);
        let neg_d = rng.chance(50);
        let de = rand_exp(rng) - w.bias() as i64 - j as i64;
        if let Some(d) = normal_from(w, neg_d, a, de) {
            let (dm, de) = fin(w, d);
            let p = bm * dm;
            let t = normal_from(w, p < 0, p.unsigned_abs(), be + de);
            if let Some(t) = t {
                assert_eq!(
                    Ratio::new(w, t, d).cmp_bound(1, 1, decode(fmt, bound)),
                    Equal
                );
                let other = if rng.chance(50) {
                    bound
                } else {
                    special(rng, fmt)
                };
                return if rng.chance(50) {
                    (t, d, bound, other)
                } else {
                    (t, d, other, bound)
                };
            }
        }
    }
    let eb_d = rand_exp(rng);
    let d = w_value(rng, w, eb_d);
    let t = if rng.chance(5) {
        w.with_sign(rng.chance(50), 0)
    } else {
        // the unbiased exponent of t (before the fractions' ratio)
        let et = match rng.int(0, 9) {
            0..=5 => rng.int(fmt.emin() as i64 - ff - 2, fmt.emax() as i64 + 2),
            6 => rng.int(bias_f - 1, bias_f + 1),
            _ => rng.int(1, top) - eb_d,
        };
        w_value(rng, w, (eb_d + et).clamp(1, top))
    };
    // floor(log2 |t|), and t's sign
    let exp_field = |v: u64| ((v >> w.frac_bits()) & ((1 << w.exp_bits()) - 1)) as i64;
    let frac_field = |v: u64| v & w.frac_mask();
    let zero_t = exp_field(t) == 0;
    let log_t = exp_field(t) - exp_field(d) - (frac_field(t) < frac_field(d)) as i64;
    let neg_t = (t ^ d) & w.sign_bit() != 0;
    let bound = |rng: &mut Rng| match rng.int(0, 19) {
        0..=10 if !zero_t => {
            let neg = if rng.chance(80) { neg_t } else { !neg_t };
            let e = log_t + rng.int(-1, 1);
            bound_near(rng, fmt, neg, e)
        }
        0..=14 => special(rng, fmt),
        _ => {
            // random, not NaN
            let b = rng.bits(fmt.width());
            if fmt.is_nan(b) {
                fmt.inf(b & fmt.sign_bit() != 0)
            } else {
                b
            }
        }
    };
    let (l, h) = (bound(rng), bound(rng));
    (t, d, l, h)
}

// ---- 1. the decision function against exact rationals ----------------

/// What the random test measured for one format.
#[derive(Debug)]
struct Measured {
    cases: u64,
    /// a bound equal to `t` exactly
    equal: u64,
    /// `t` within a bound rejected, or `|t| ≥ 2^(emax+1)` not `far`
    violations: u64,
    /// the largest `t/t_max` accepted for `t > t_max > 0` (normal), and
    /// `|t|/|t_min|` for `t < t_min < 0`: beyond a bound by a larger magnitude
    up_pos: f64,
    up_neg: f64,
    /// the smallest `t/t_min` accepted for `0 < t < t_min` (normal), and
    /// `|t|/|t_max|` for `t_max < t < 0`: beyond a bound by a smaller magnitude
    low_pos: f64,
    low_neg: f64,
    /// the smallest `|t|/2^(emax+1)` flagged `far` below `2^(emax+1)`
    far_low: f64,
    /// accepted `t ≥ up·t_max` (the theoretical factor, rounded up), `t ≤
    /// low·t_min` (rounded down), `far` for `|t| ≤ far·2^(emax+1)`
    beyond_up: u64,
    beyond_low: u64,
    beyond_far: u64,
    /// at binary32, the spec's factors: accepted `t ≥ 1.25·t_max` (0 <
    /// t_max), `t ≤ 0.8·t_min` (0 < t_min), `far` for `|t| < 2^128/1.25`
    spec_up: u64,
    spec_low: u64,
    spec_far: u64,
}

/// The theoretical looseness of the log test for `fmt`, in thousandths
/// rounded outward: `(2^(C/2^K + δ), 2^−(C/2^K + 2δ), 2^−(C/2^K + δ))`.
fn loose_factors(fmt: FloatFormat) -> (i64, i64, i64) {
    let (k, c) = log_segment_constants(fmt);
    let (m, d) = (c as f64 / (1u64 << k) as f64, delta(k));
    (
        ((m + d).exp2() * 1000.0).ceil() as i64,
        ((-(m + 2.0 * d)).exp2() * 1000.0).floor() as i64,
        ((-(m + d)).exp2() * 1000.0).floor() as i64,
    )
}

fn measure(fmt: FloatFormat, n: u64, seed: u64) -> Measured {
    let w = internal_format(fmt).expect("an internal format");
    let mut rng = Rng::new(seed);
    let emax1 = fmt.emax() as i64 + 1;
    let (up, low, far_f) = loose_factors(fmt);
    let mut m = Measured {
        cases: 0,
        equal: 0,
        violations: 0,
        up_pos: 1.0,
        up_neg: 1.0,
        low_pos: 1.0,
        low_neg: 1.0,
        far_low: 1.0,
        beyond_up: 0,
        beyond_low: 0,
        beyond_far: 0,
        spec_up: 0,
        spec_low: 0,
        spec_far: 0,
    };
    let normal = |b: u64| {
        let e = (b >> fmt.frac_bits()) & ((1 << fmt.exp_bits()) - 1);
        e != 0 && e != (1 << fmt.exp_bits()) - 1
    };
    for _ in 0..n {
        let (t, d, l, h) = case(&mut rng, fmt, w);
        let (after_min, before_max, far) = segment_log(fmt, t, d, l, h);
        let r = Ratio::new(w, t, d);
        let (lv, hv) = (decode(fmt, l), decode(fmt, h));
        m.cases += 1;
        let in_l = r.cmp_bound(1, 1, lv) != Less;
        let in_h = r.cmp_bound(1, 1, hv) != Greater;
        if r.cmp_bound(1, 1, lv) == Equal || r.cmp_bound(1, 1, hv) == Equal {
            m.equal += 1;
        }
        let huge = r.cmp_abs_pow2(1, 1, emax1) != Less;
        if (in_l && !after_min) || (in_h && !before_max) || (huge && !far) {
            m.violations += 1;
            if m.violations <= 5 {
                eprintln!(
                    "VIOLATION {fmt:?}: T {t:#x} D {d:#x} L {l:#x} H {h:#x}: t ≥ L {in_l} \
                     after_min {after_min}, t ≤ H {in_h} before_max {before_max}, \
                     |t| ≥ 2^(emax+1) {huge} far {far}"
                );
            }
        }
        let t_pos = r.tm > 0;
        let t_neg = r.tm < 0;
        // beyond t_max by a larger magnitude (t > H > 0), or t_min (t < L < 0)
        for (bits, v, accepted, inside, pos) in [
            (h, hv, before_max, in_h, true),
            (l, lv, after_min, in_l, false),
        ] {
            let Val::Fin(bm, be) = v else { continue };
            if !normal(bits) || !accepted || inside {
                continue;
            }
            // |t| / |bound|
            let ratio = r.over(bm, be);
            if pos && t_pos && bm > 0 {
                m.up_pos = m.up_pos.max(ratio);
                m.beyond_up += (r.cmp(up, 1000, bm, be) != Less) as u64;
                m.spec_up += (r.cmp(5, 4, bm, be) != Less) as u64;
            }
            if !pos && t_neg && bm < 0 {
                m.up_neg = m.up_neg.max(ratio);
                m.beyond_up += (r.cmp(up, 1000, bm, be) != Greater) as u64;
            }
            if !pos && t_pos && bm > 0 {
                m.low_pos = m.low_pos.min(ratio);
                m.beyond_low += (r.cmp(low, 1000, bm, be) != Greater) as u64;
                m.spec_low += (r.cmp(4, 5, bm, be) != Greater) as u64;
            }
            if pos && t_neg && bm < 0 {
                m.low_neg = m.low_neg.min(ratio);
                m.beyond_low += (r.cmp(low, 1000, bm, be) != Less) as u64;
            }
        }
        if far && !huge {
            m.far_low = m.far_low.min(r.over(1, emax1).abs());
            m.beyond_far += (r.cmp_abs_pow2(far_f, 1000, emax1) != Greater) as u64;
            m.spec_far += (r.cmp_abs_pow2(4, 5, emax1) == Less) as u64;
        }
    }
    m
}

/// Sound at binary32, e5m10 and e8m7: no `t` within the segment rejected,
/// no `|t| ≥ 2^(emax+1)` unflagged; and no looser than the derivation says
/// (`2^−K·r` minus the exact log ratio within `(−δ, 2δ)`), on either side.
#[test]
fn log_segment_is_sound_and_tight() {
    for (fmt, n, seed) in [(F32, 200_000, 1), (E5M10, 50_000, 2), (E8M7, 50_000, 3)] {
        let m = measure(fmt, n, seed);
        let (k, c) = log_segment_constants(fmt);
        let (up, low, far) = loose_factors(fmt);
        eprintln!(
            "{fmt:?} (K = {k}, C = {c}; theory: up < {up}/1000, low > {low}/1000, far above \
             {far}/1000): {m:?}"
        );
        assert_eq!(m.cases, n);
        assert_eq!(
            m.violations, 0,
            "{fmt:?}: the log test rejected a t it must accept"
        );
        assert!(m.equal > n / 20, "{fmt:?}: bounds equal to t: {}", m.equal);
        // the derivation's factors, on every side
        assert_eq!(
            (m.beyond_up, m.beyond_low, m.beyond_far),
            (0, 0, 0),
            "{fmt:?}"
        );
        // measured looseness: real (a margin C is needed), within theory
        assert!(m.up_pos > 1.05 && m.up_pos < up as f64 / 1000.0, "{fmt:?}");
        assert!(m.up_neg > 1.05 && m.up_neg < up as f64 / 1000.0, "{fmt:?}");
        assert!(
            m.low_pos < 0.9 && m.low_pos > low as f64 / 1000.0,
            "{fmt:?}"
        );
        assert!(
            m.low_neg < 0.9 && m.low_neg > low as f64 / 1000.0,
            "{fmt:?}"
        );
        assert!(
            m.far_low < 0.95 && m.far_low > far as f64 / 1000.0,
            "{fmt:?}"
        );
        if fmt == F32 {
            // the brief's figures (Python measured t/t_max up to 1.174)
            assert!(m.up_pos < 1.22, "{}", m.up_pos);
            assert_eq!((m.spec_up, m.spec_far), (0, 0));
            // t ≤ 0.8·t_min is NOT always rejected: the lower side is looser
            // (down to 2^−(C/2^K + 2δ) ≈ 0.777, see the explicit vectors);
            // reported, not asserted
            eprintln!("binary32: accepted t ≤ 0.8·t_min: {}", m.spec_low);
        }
    }
}

/// `(K, C)`: `K = min(8, F)`, `C = ⌈2^K · 0.1721427⌉ + 2`, at least
/// `2δ·2^K` for every `K` (the margin the derivation needs).
#[test]
fn log_segment_constants_follow_the_derivation() {
    let fmt = |e, f| FloatFormat::new(e, f).unwrap();
    assert_eq!(log_segment_constants(F32), (8, 47));
    assert_eq!(log_segment_constants(E5M10), (8, 47));
    assert_eq!(log_segment_constants(E8M7), (7, 25));
    assert_eq!(log_segment_constants(fmt(5, 6)), (6, 14));
    assert_eq!(log_segment_constants(fmt(4, 4)), (4, 5));
    assert_eq!(log_segment_constants(fmt(11, 52)), (8, 47));
    for f in 1..=10 {
        let (k, c) = log_segment_constants(fmt(5, f));
        assert_eq!(k, f.min(8));
        let need = 2.0 * delta(k) * (1u64 << k) as f64;
        assert!(
            c as f64 >= need && (c as f64) < need + 1.0,
            "K = {k}: C = {c}"
        );
    }
}

// ---- 2. agreement with the Python model ---------------------------------

/// Explicit binary32 vectors `(T, D, L, H)` (T, D in e11m23) and the triple
/// `(after_min, before_max, far)` the Python model gives, computed with
/// (in docs/experiments/triangle-dsp24)
/// `python3 -c 'exec(open("segment_model.py").read().split("random.seed(7)")[0]); print(seg(T, D, L, H)[:3])' 8 47`
/// (its `sL`-derived answers printed as `bool`).
#[test]
fn log_segment_matches_the_python_model() {
    // (T, D, L, H) and the triple (after_min, before_max, far)
    type Case = (u64, u64, u64, u64, (bool, bool, bool));
    #[rustfmt::skip]
    let vectors: [Case; 21] = [
        // t = 1.5 = t_min = t_max
        (0x200400000, 0x200000000, 0x3fc00000, 0x3fc00000, (true, true, false)),
        // t = 1.2574 accepted at 0.787 t_min
        (0x2000028f6, 0x1ffcbd70a, 0x3fcc7ae1, 0x7f800000, (true, true, false)),
        // t = 1.2574 rejected at 0.78 t_min
        (0x2000028f6, 0x1ffcbd70a, 0x3fce5a16, 0x7f800000, (false, true, false)),
        // t accepted at 1.182 t_max
        (0x200182ff9, 0x1ff80a320, 0x00000000, 0x40001b94, (true, true, false)),
        // t rejected at 1.25 t_max
        (0x200a00000, 0x200800000, 0x00000000, 0x3f800000, (true, false, false)),
        // T = +0, t_min = -0, t_max = +0
        (0x000000000, 0x200400000, 0x80000000, 0x00000000, (true, true, false)),
        // T = -0 over -det, subnormal bounds moved to 0
        (0x400000000, 0x600e00000, 0x00000001, 0x80000001, (true, true, false)),
        // T = 0, t_max = -1: before_max false
        (0x000000000, 0x200000000, 0xff800000, 0xbf800000, (true, false, false)),
        // t = -3 in [-inf, -inf]: before_max false
        (0x600400000, 0x1ff800000, 0xff800000, 0xff800000, (true, false, false)),
        // t = 3, t_min = +inf
        (0x200400000, 0x1ff800000, 0x7f800000, 0x7f800000, (false, true, false)),
        // t = 2^128: far
        (0x23f800000, 0x1ff800000, 0x00000000, 0x7f800000, (true, true, true)),
        // t = 2^128/1.1: far (flagged below 2^128)
        (0x23f68ba2f, 0x1ff800000, 0x00000000, 0x7f800000, (true, true, true)),
        // t = 2^128/1.2: not far
        (0x23f555555, 0x1ff800000, 0x00000000, 0x7f800000, (true, true, false)),
        // t = 2^128/1.25: not far
        (0x23f4ccccd, 0x1ff800000, 0x00000000, 0x7f800000, (true, true, false)),
        // t ~ 2^-2045 (extreme exponents), subnormal bounds
        (0x000923456, 0x3ff654321, 0x007fffff, 0x00000001, (true, true, false)),
        // t ~ 2^2045: far, above max_finite
        (0x3ff7fffff, 0x000800000, 0xff800000, 0x7f7fffff, (true, false, true)),
        // t = -3 in [-3.5, -2.5]
        (0x200400000, 0x5ff800000, 0xc0600000, 0xc0200000, (true, true, false)),
        // t = -1 against t_max = -1.15
        (0x5ff800000, 0x1ff800000, 0xff800000, 0xbf933333, (true, true, false)),
        // t = -1 against t_max = -1.4
        (0x1ff800000, 0x5ff800000, 0xff800000, 0xbfb33333, (true, false, false)),
        // t = 2 against t_max = -1, t_min = 3 (opposite signs)
        (0x200000000, 0x1ff800000, 0x40400000, 0xbf800000, (false, false, false)),
        // t = -2 against t_min = +1, t_max = +1
        (0x600000000, 0x1ff800000, 0x3f800000, 0x3f800000, (false, true, false)),
    ];
    for (t, d, l, h, want) in vectors {
        assert_eq!(
            segment_log(F32, t, d, l, h),
            want,
            "T {t:#x} D {d:#x} L {l:#x} H {h:#x}"
        );
    }
    // the vector accepted at 0.787·t_min: t < t_min exactly
    let w = internal_format(F32).unwrap();
    let (t, d, l) = (0x2000028f6, 0x1ffcbd70a, 0x3fcc7ae1);
    let r = Ratio::new(w, t, d);
    assert_eq!(r.cmp_bound(1, 1, decode(F32, l)), Less);
    assert_eq!(r.cmp_bound(4, 5, decode(F32, l)), Less);
    assert!(segment_log(F32, t, d, l, F32.inf(false)).0);
}

// ---- 3. eval_tnum_with(Log) against eval_tnum on random triangles ------

fn bits(x: f32) -> u64 {
    x.to_bits() as u64
}

/// A random triangle in `[−1, 1]^3` and a ray from a sphere of radius 2-8
/// aimed at it (barycentrics in `[−0.2, 1.2]`, so t ≈ 1 at the aim), the
/// direction scaled by `scale`.
fn random_ray(rng: &mut Rng, scale: f64) -> TriIn {
    let tri = [0; 3].map(|_| [0; 3].map(|_| rng.real(-1.0, 1.0) as f32));
    let radius = rng.real(2.0, 8.0);
    let o = loop {
        let v = [0; 3].map(|_| rng.real(-1.0, 1.0));
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if n > 0.1 && n <= 1.0 {
            break v.map(|x| (x / n * radius) as f32);
        }
    };
    let (b1, b2) = (rng.real(-0.2, 1.2), rng.real(-0.2, 1.2));
    let aim: [f64; 3] = [0, 1, 2].map(|i| {
        let (a, b, c) = (tri[0][i] as f64, tri[1][i] as f64, tri[2][i] as f64);
        a + b1 * (b - a) + b2 * (c - a)
    });
    let d = [0, 1, 2].map(|i| ((aim[i] - o[i] as f64) * scale) as f32);
    common::triangle_ray(o, d, tri)
}

/// What the log test did differently from the exact one.
#[derive(Debug, Default)]
struct Compared {
    exact_hits: u64,
    /// log hits the exact test rejects (t outside the segment)
    extra: u64,
    /// log `invalid` (far) where the exact test is not
    extra_far: u64,
}

/// Both tests on `x`: the log one never loses a hit (same `T`, `det`) nor
/// an `invalid`, and differs in `invalid` only through `far`.
fn compare(x: &TriIn, c: &mut Compared) {
    let mode = RoundingMode::NearestEven;
    let exact = eval_tnum(F32, mode, x);
    let log = eval_tnum_with(F32, mode, Segment::Log, x);
    assert_eq!(exact, eval_tnum_with(F32, mode, Segment::Exact, x));
    assert!(!(log.hit && log.invalid), "{x:?}");
    if exact.hit {
        c.exact_hits += 1;
        assert!(log.hit || log.invalid, "a hit lost: {x:?}");
        if log.hit {
            assert_eq!((log.t_num, log.t_den), (exact.t_num, exact.t_den), "{x:?}");
        } else {
            // flagged: through far only
            let (_, _, far) = segment_log(F32, exact.t_num, exact.t_den, x.t_min, x.t_max);
            assert!(far, "{x:?}");
            c.extra_far += 1;
        }
    } else if exact.invalid {
        assert!(log.invalid && !log.hit, "an invalid lost: {x:?}");
    } else if log.hit {
        c.extra += 1;
    } else if log.invalid {
        // the log test accepted the segment and flagged far: with the
        // whole line as segment it flags the same transaction
        let open = TriIn {
            t_min: F32.inf(true),
            t_max: F32.inf(false),
            ..*x
        };
        let whole = eval_tnum_with(F32, mode, Segment::Log, &open);
        assert!(whole.invalid && !whole.hit, "{x:?}");
        // and where the exact test hits the whole line, far is set
        let line = eval_tnum(F32, mode, &open);
        if line.hit {
            let (_, _, far) = segment_log(F32, line.t_num, line.t_den, x.t_min, x.t_max);
            assert!(far, "{x:?}");
        }
        c.extra_far += 1;
    }
}

/// On random binary32 triangles: the log test keeps every hit of the exact
/// one (same `T`, `det`); with `t_max` (or `t_min`) log-uniform over
/// `[2^−4, 2^4]` (hits at t ≈ 1) its extra accepts are a small fraction of
/// the exact hits; with `t` near `2^128` its only other difference is
/// `far`.
#[test]
fn log_segment_keeps_every_exact_hit() {
    let mut rng = Rng::new(77);
    let (mut upper, mut lower, mut far) = (
        Compared::default(),
        Compared::default(),
        Compared::default(),
    );
    for _ in 0..100_000 {
        // random t_max, t_min = 0
        let mut x = random_ray(&mut rng, 1.0);
        x.t_max = bits(rng.real(-4.0, 4.0).exp2() as f32);
        compare(&x, &mut upper);
        // random t_min, t_max = ∞
        x.t_min = x.t_max;
        x.t_max = bits(f32::INFINITY);
        compare(&x, &mut lower);
    }
    for _ in 0..20_000 {
        // t ≈ c·2^127, c in [1, 2): around the far threshold 2^128
        let scale = (-127.0f64).exp2() / rng.real(1.0, 2.0);
        let x = random_ray(&mut rng, scale);
        compare(&x, &mut far);
    }
    eprintln!("t_max random: {upper:?}\nt_min random: {lower:?}\nt near 2^128: {far:?}");
    for c in [&upper, &lower] {
        assert!(c.exact_hits > 10_000, "{c:?}");
        assert_eq!(c.extra_far, 0, "{c:?}");
        assert!(c.extra > 0, "{c:?}");
    }
    // extra accepts: under 5 % of the exact hits with t_max random (beyond
    // t_max accepted up to ~1.2x); the t_min side is looser (~1.29x)
    assert!(upper.extra * 20 < upper.exact_hits, "{upper:?}");
    assert!(lower.extra * 10 < lower.exact_hits, "{lower:?}");
    assert!(far.exact_hits > 2_000 && far.extra_far > 200, "{far:?}");
}
