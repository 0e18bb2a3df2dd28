//! Predicates on a float encoding, for units that test a value's class
//! without unpacking it: bit reductions over the fields, no comparison.

use super::Format;
use crate::builder::{ModuleBuilder, Sig};

/// `v` is ±0 (no magnitude bit set).
#[track_caller]
pub fn is_zero(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let mag = m.slice(v, fmt.width() - 2, 0);
    let any = m.any_set(mag);
    let zero = m.not(any);
    m.name_after(zero, v, "is_zero")
}

/// `v` is ±the largest finite value: where a directed rounding leaves an
/// overflow (it rounds to ±∞ only away from zero).
#[track_caller]
pub fn is_max_finite(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let mag = m.slice(v, fmt.width() - 2, 0);
    let max = m.uint(fmt.width() - 1, fmt.inf_bits() - 1);
    let at_max = m.eq(mag, max);
    m.name_after(at_max, v, "is_max_finite")
}

/// `v` is a NaN or an infinity (exponent field all ones).
#[track_caller]
pub fn is_special(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let e = m.slice(v, fmt.width() - 2, fmt.frac_bits);
    let special = m.all_ones(e);
    m.name_after(special, v, "is_special")
}

/// `v` is a NaN (exponent all ones, fraction not zero).
#[track_caller]
pub fn is_nan(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let special = is_special(m, fmt, v);
    let frac = m.slice(v, fmt.frac_bits - 1, 0);
    let any = m.any_set(frac);
    let nan = m.and(special, any);
    m.name_after(nan, v, "is_nan")
}

/// `v` is ±∞ (exponent all ones, fraction zero).
#[track_caller]
pub fn is_any_inf(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let special = is_special(m, fmt, v);
    let frac = m.slice(v, fmt.frac_bits - 1, 0);
    let any = m.any_set(frac);
    let none = m.not(any);
    let inf = m.and(special, none);
    m.name_after(inf, v, "is_inf")
}

/// `v` is +∞ (`negative = false`) or −∞.
#[track_caller]
pub fn is_inf(m: &mut ModuleBuilder, fmt: Format, v: Sig, negative: bool) -> Sig {
    let inf = is_any_inf(m, fmt, v);
    let sign = m.msb(v);
    let sign = if negative { sign } else { m.not(sign) };
    let inf = m.and(inf, sign);
    let role = if negative { "is_neg_inf" } else { "is_pos_inf" };
    m.name_after(inf, v, role)
}

/// `v < 0` by value: the sign bit set, not a zero (−0 is not negative),
/// not a NaN.
#[track_caller]
pub fn is_negative(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    strictly_signed(m, fmt, v, true)
}

/// `0 < v` by value: the sign bit clear, not a zero, not a NaN.
#[track_caller]
pub fn is_positive(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    strictly_signed(m, fmt, v, false)
}

/// [`is_negative`] (`negative`) or [`is_positive`].
#[track_caller]
fn strictly_signed(m: &mut ModuleBuilder, fmt: Format, v: Sig, negative: bool) -> Sig {
    let s = m.msb(v);
    let s = if negative { s } else { m.not(s) };
    let z = is_zero(m, fmt, v);
    let nz = m.not(z);
    let nan = is_nan(m, fmt, v);
    let ok = m.not(nan);
    let r = m.and(s, nz);
    let r = m.and(r, ok);
    let role = if negative { "is_neg" } else { "is_pos" };
    m.name_after(r, v, role)
}

/// OR of `flags` (Bool): one reduction over their concatenation `{name}_flags`, named `name`.
#[track_caller]
pub fn any_of(m: &mut ModuleBuilder, flags: &[Sig], name: &str) -> Sig {
    let v = flags_of(m, flags, name);
    let r = m.any_set(v);
    m.name(r, name)
}

/// AND of `flags` (Bool): one reduction over their concatenation `{name}_flags`, named `name`.
#[track_caller]
pub fn all_of(m: &mut ModuleBuilder, flags: &[Sig], name: &str) -> Sig {
    let v = flags_of(m, flags, name);
    let r = m.all_ones(v);
    m.name(r, name)
}

#[track_caller]
fn flags_of(m: &mut ModuleBuilder, flags: &[Sig], name: &str) -> Sig {
    let bits: Vec<Sig> = flags.iter().map(|&f| m.as_uint(f)).collect();
    let v = m.cat(&bits);
    m.name(v, &format!("{name}_flags"))
}
