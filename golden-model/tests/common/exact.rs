//! The exact oracle: values as big integers times powers of two (dashu), and
//! a reference rounder that knows nothing about exponents or significands:
//! it binary-searches the monotonic encodings for the two representable
//! neighbours of the exact value and picks one per mode.

use dashu::base::BitTest;
use dashu::integer::UBig;
use golden_model::float::{FloatFormat, RoundingMode};
use std::cmp::Ordering;

/// An exact value. `Fin { neg, mag, exp }` is `(-1)^neg · mag · 2^exp`, mag > 0.
#[derive(Clone, Debug, PartialEq)]
pub enum V {
    NaN,
    Inf(bool),
    Zero(bool),
    Fin { neg: bool, mag: UBig, exp: i64 },
}

/// Decodes `bits` of `fmt` from the IEEE 754 definitions.
pub fn decode(fmt: FloatFormat, bits: u64) -> V {
    let (e, f) = (fmt.exp_bits(), fmt.frac_bits());
    let neg = (bits >> (e + f)) & 1 == 1;
    let field = (bits >> f) & ((1u64 << e) - 1);
    let frac = bits & ((1u64 << f) - 1);
    let bias = (1i64 << (e - 1)) - 1;
    if field == (1u64 << e) - 1 {
        return if frac == 0 { V::Inf(neg) } else { V::NaN };
    }
    if field == 0 {
        if frac == 0 {
            return V::Zero(neg);
        }
        return V::Fin {
            neg,
            mag: UBig::from(frac),
            exp: 1 - bias - f as i64,
        };
    }
    V::Fin {
        neg,
        mag: UBig::from(frac + (1u64 << f)),
        exp: field as i64 - bias - f as i64,
    }
}

/// Compares magnitudes `a·2^ea` and `b·2^eb`.
pub fn cmp_mag(a: &UBig, ea: i64, b: &UBig, eb: i64) -> Ordering {
    // Quick decision by the position of the leading one.
    let la = a.bit_len() as i64 + ea;
    let lb = b.bit_len() as i64 + eb;
    if a.is_zero() || b.is_zero() {
        return a.is_zero().cmp(&b.is_zero()).reverse();
    }
    if la != lb {
        return la.cmp(&lb);
    }
    if ea >= eb {
        (a << (ea - eb) as usize).cmp(b)
    } else {
        a.cmp(&(b << (eb - ea) as usize))
    }
}

/// IEEE order of two non-NaN values (-0 == +0).
pub fn cmp(x: &V, y: &V) -> Option<Ordering> {
    // Map to (rank, value): -inf < finite/zero < +inf.
    fn rank(v: &V) -> i8 {
        match v {
            V::Inf(true) => -1,
            V::Inf(false) => 1,
            _ => 0,
        }
    }
    if matches!(x, V::NaN) || matches!(y, V::NaN) {
        return None;
    }
    let (rx, ry) = (rank(x), rank(y));
    if rx != 0 || ry != 0 {
        return Some(rx.cmp(&ry));
    }
    let signed = |v: &V| -> (i8, UBig, i64) {
        match v {
            V::Zero(_) => (0, UBig::ZERO, 0),
            V::Fin { neg, mag, exp } => (if *neg { -1 } else { 1 }, mag.clone(), *exp),
            _ => unreachable!(),
        }
    };
    let (sx, mx, ex) = signed(x);
    let (sy, my, ey) = signed(y);
    if sx != sy {
        return Some(sx.cmp(&sy));
    }
    let m = cmp_mag(&mx, ex, &my, ey);
    Some(if sx < 0 { m.reverse() } else { m })
}

/// Exact product with IEEE special cases.
pub fn mul(x: &V, y: &V) -> V {
    let sign = |v: &V| match v {
        V::Inf(s) | V::Zero(s) => *s,
        V::Fin { neg, .. } => *neg,
        V::NaN => false,
    };
    let s = sign(x) != sign(y);
    match (x, y) {
        (V::NaN, _) | (_, V::NaN) => V::NaN,
        (V::Inf(_), V::Zero(_)) | (V::Zero(_), V::Inf(_)) => V::NaN,
        (V::Inf(_), _) | (_, V::Inf(_)) => V::Inf(s),
        (V::Zero(_), _) | (_, V::Zero(_)) => V::Zero(s),
        (
            V::Fin {
                mag: a, exp: ea, ..
            },
            V::Fin {
                mag: b, exp: eb, ..
            },
        ) => V::Fin {
            neg: s,
            mag: a * b,
            exp: ea + eb,
        },
    }
}

/// Exact sum of any number of terms with IEEE special cases: NaN if any term
/// is NaN or infinities of both signs meet; an infinity wins; an exact zero
/// is -0 if all terms are -0, +0 if all are +0, else -0 only in RDN.
pub fn sum(terms: &[V], mode: RoundingMode) -> V {
    if terms.iter().any(|t| matches!(t, V::NaN)) {
        return V::NaN;
    }
    let pinf = terms.iter().any(|t| matches!(t, V::Inf(false)));
    let ninf = terms.iter().any(|t| matches!(t, V::Inf(true)));
    if pinf && ninf {
        return V::NaN;
    }
    if pinf || ninf {
        return V::Inf(ninf);
    }
    // Sum of positive and of negative parts on a common grid.
    let fins: Vec<(bool, &UBig, i64)> = terms
        .iter()
        .filter_map(|t| match t {
            V::Fin { neg, mag, exp } => Some((*neg, mag, *exp)),
            _ => None,
        })
        .collect();
    let zero = || {
        let all_neg = terms.iter().all(|t| matches!(t, V::Zero(true)));
        let all_pos = terms.iter().all(|t| matches!(t, V::Zero(false)));
        V::Zero(if all_neg {
            true
        } else if all_pos {
            false
        } else {
            mode == RoundingMode::Down
        })
    };
    let Some(e0) = fins.iter().map(|t| t.2).min() else {
        return zero();
    };
    let (mut pos, mut neg) = (UBig::ZERO, UBig::ZERO);
    for (n, m, e) in &fins {
        let aligned = *m << (*e - e0) as usize;
        if *n {
            neg += aligned;
        } else {
            pos += aligned;
        }
    }
    match pos.cmp(&neg) {
        Ordering::Equal => zero(),
        Ordering::Greater => V::Fin {
            neg: false,
            mag: pos - neg,
            exp: e0,
        },
        Ordering::Less => V::Fin {
            neg: true,
            mag: neg - pos,
            exp: e0,
        },
    }
}

/// `v` rounded to `fmt` in `mode`, by searching the encodings.
pub fn round(fmt: FloatFormat, v: &V, mode: RoundingMode) -> u64 {
    let (neg, mag, exp) = match v {
        V::NaN => return fmt.canonical_nan(),
        V::Inf(s) => return fmt.inf(*s),
        V::Zero(s) => return fmt.zero(*s),
        V::Fin { neg, mag, exp } => (*neg, mag, *exp),
    };
    let max = fmt.max_finite(false);
    let value_of = |p: u64| match decode(fmt, p) {
        V::Fin { mag, exp, .. } => (mag, exp),
        V::Zero(_) => (UBig::ZERO, 0),
        _ => unreachable!(),
    };
    // lo = the largest encoding whose magnitude is <= |v|.
    let (mut lo, mut hi) = (0u64, max);
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        let (m, e) = value_of(mid);
        if cmp_mag(&m, e, mag, exp) != Ordering::Greater {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    let (lm, le) = value_of(lo);
    if cmp_mag(&lm, le, mag, exp) == Ordering::Equal {
        return fmt.with_sign(neg, lo);
    }
    // Next magnitude up: the next encoding, or 2^(emax+1) above the largest.
    let (um, ue) = if lo < max {
        value_of(lo + 1)
    } else {
        (UBig::ONE, fmt.emax() as i64 + 1)
    };
    let away = match mode {
        RoundingMode::TowardZero => false,
        RoundingMode::Up => !neg,
        RoundingMode::Down => neg,
        RoundingMode::NearestEven => {
            // Compare 2|v| with lo + up on a common grid.
            let e = le.min(ue).min(exp) - 1;
            let mid2 = (&lm << (le - e) as usize) + (&um << (ue - e) as usize);
            let v2 = mag << (exp - e + 1) as usize;
            match v2.cmp(&mid2) {
                Ordering::Less => false,
                Ordering::Greater => true,
                Ordering::Equal => lo & 1 == 1,
            }
        }
    };
    let bits = if !away {
        lo
    } else if lo == max {
        fmt.inf(false)
    } else {
        lo + 1
    };
    fmt.with_sign(neg, bits)
}
