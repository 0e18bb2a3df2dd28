//! Exact comparison of products without forming IEEE products.
//!
//! A test `a·b <= c·d` needs the order of two exact products, not their
//! encodings. Each factor is unpacked and normalised once ([`factor`],
//! subnormals included), each product is the (F+1)×(F+1) significand
//! product with the exponent sum ([`start_product`]), normalised by at most
//! one bit into a [`Term`] whose key orders magnitudes as unsigned integers
//! ([`product_term`], [`single_term`] for a factor compared on its own), and
//! [`term_le`] compares two terms. No rounder, no packing: every step is
//! exact, so the result equals IEEE `le` of the exactly rounded-free
//! products (the golden model's `mul_exact` + `le`) for every non-NaN input.
//!
//! Key layout, `1 + WE + 2F + 1` bits (see [`term_width`]):
//! `{inf, exponent + OFFSET (WE bits, >= 1 for every nonzero finite value),
//! fraction of the normalised significand product (2F + 1 bits)}`; zero is
//! all zeros, an infinity is `{1, 0...}`. A zero term (either factor zero)
//! is `+0` whatever the signs, as in the golden model (`±∞·0 = 0` there:
//! a zero direction bound makes the product zero).
//!
//! NaN factors give an unspecified term; callers mask their verdicts with a
//! NaN flag computed from the inputs.

use super::bits::{add_const, to_sint};
use super::unpack::{norm_exp_width, normalize, unpack, Normalized};
use super::{sint_width, Format};
use crate::arith::int::{sext, umul_module};
use crate::arith::ports::product;
use crate::builder::{ModuleBuilder, Sig};

/// One factor, unpacked and normalised once, shared by every product it
/// takes part in.
#[derive(Debug, Clone, Copy)]
pub struct Factor {
    /// sign bit, Bool
    pub sign: Sig,
    /// ±0, Bool
    pub zero: Sig,
    /// ±∞, Bool
    pub inf: Sig,
    /// unbiased exponent of the significand's top bit, SInt of [`norm_exp_width`]
    pub exp: Sig,
    /// significand, UInt(F + 1), top bit set unless zero (or not finite)
    pub sig: Sig,
}

/// Unpacks and normalises the `fmt` encoding `x` in the naming scope
/// `name`: `{name}_sign`, `{name}_zero`, `{name}_exp_norm`, `{name}_sig_norm`, ...
#[track_caller]
pub fn factor(m: &mut ModuleBuilder, fmt: Format, x: Sig, name: &str) -> Factor {
    m.scope(name, |m| {
        let u = unpack(m, fmt, x);
        let Normalized { sig, exp } = normalize(m, fmt, &u);
        Factor {
            sign: u.sign,
            zero: m.name(u.zero, "zero"),
            inf: m.name(u.inf, "inf"),
            exp,
            sig,
        }
    })
}

/// [`factor`] of an encoding that the caller guarantees to be zero or
/// normal (or not finite, where its verdicts are masked): the significand's
/// top bit is already the hidden bit, so no leading-zero count and no shift.
/// Equal to [`factor`] for every zero or normal `x`.
#[track_caller]
pub fn factor_normal(m: &mut ModuleBuilder, fmt: Format, x: Sig, name: &str) -> Factor {
    m.scope(name, |m| {
        let u = unpack(m, fmt, x);
        let exp = add_const(m, u.eff_exp, -fmt.bias(), norm_exp_width(fmt));
        Factor {
            sign: u.sign,
            zero: m.name(u.zero, "zero"),
            inf: m.name(u.inf, "inf"),
            exp: m.name(exp, "exp_norm"),
            sig: u.sig,
        }
    })
}

/// Lowest exponent of a term: two factors at `emin - F - 1` each.
fn term_exp_min(fmt: Format) -> i64 {
    2 * (fmt.emin() - fmt.frac_bits as i64 - 1)
}

/// Highest exponent of a term: two factors at `emax`, product in `[2, 4)`.
fn term_exp_max(fmt: Format) -> i64 {
    2 * fmt.emax() + 1
}

/// Added to a term's exponent so that every nonzero finite term has a
/// biased exponent of at least 1 (zero keeps the all-zero key).
fn term_offset(fmt: Format) -> i64 {
    1 - term_exp_min(fmt)
}

/// Width WE of a term's biased exponent.
pub fn term_exp_width(fmt: Format) -> u32 {
    let hi = (term_exp_max(fmt) + term_offset(fmt)) as u64;
    64 - hi.leading_zeros()
}

/// Width of a term's key: infinity flag, biased exponent, 2F + 1 fraction bits.
pub fn term_width(fmt: Format) -> u32 {
    1 + term_exp_width(fmt) + 2 * fmt.frac_bits + 1
}

/// A value compared by [`term_le`]: an exact product or a single factor.
#[derive(Debug, Clone, Copy)]
pub struct Term {
    /// negative and nonzero, Bool
    pub neg: Sig,
    /// magnitude key, UInt([`term_width`])
    pub key: Sig,
}

/// The part of a product formed before the significand multiplier's
/// registers: the multiplier instance and everything that does not wait
/// for it.
#[derive(Debug, Clone, Copy)]
pub struct ProductStart {
    /// significand product, UInt(2F + 2), from the multiplier instance
    pub sig: Sig,
    /// `exp_a + exp_b`, SInt
    pub exp_sum: Sig,
    /// a factor is zero, Bool
    pub zero: Sig,
    /// a factor is infinite (and none is zero), Bool
    pub inf: Sig,
    /// signs differ and the product is nonzero, Bool
    pub neg: Sig,
}

/// Starts `a · b`: the (F+1)×(F+1) significand multiplier instance `inst`
/// with `mul_stages` registers (the caller closes those stages before
/// [`product_term`]) and the exponent sum and class beside it.
#[track_caller]
pub fn start_product(
    m: &mut ModuleBuilder,
    fmt: Format,
    a: &Factor,
    b: &Factor,
    mul_stages: u32,
    inst: &str,
) -> ProductStart {
    let f = fmt.frac_bits;
    let mul = umul_module(f + 1, f + 1, mul_stages);
    let sig = product(m, inst, &mul, a.sig, b.sig);
    m.scope(inst, |m| {
        let w = sint_width(term_exp_min(fmt), term_exp_max(fmt));
        let ea = sext(m, a.exp, w);
        let eb = sext(m, b.exp, w);
        let exp_sum = m.add(ea, eb);
        let exp_sum = sext(m, exp_sum, w);
        let zero = m.or(a.zero, b.zero);
        let not_zero = m.not(zero);
        let any_inf = m.or(a.inf, b.inf);
        let inf = m.and(any_inf, not_zero);
        let differ = m.xor(a.sign, b.sign);
        let neg = m.and(differ, not_zero);
        ProductStart {
            sig,
            exp_sum: m.name(exp_sum, "exp_sum"),
            zero: m.name(zero, "zero"),
            inf: m.name(inf, "inf"),
            neg: m.name(neg, "neg"),
        }
    })
}

/// The key of a term from its class, unbiased exponent (SInt) and the
/// 2F + 1 fraction bits below the leading one.
#[track_caller]
fn key_of(m: &mut ModuleBuilder, fmt: Format, zero: Sig, inf: Sig, exp: Sig, frac: Sig) -> Sig {
    let we = term_exp_width(fmt);
    let biased = add_const(m, exp, term_offset(fmt), we + 1);
    let biased = m.slice(biased, we - 1, 0);
    let finite_flag = m.uint(1, 0);
    let finite = m.cat(&[finite_flag, biased, frac]);
    let finite = m.name(finite, "finite_key");
    let tw = term_width(fmt);
    let inf_key = m.uint(tw, 1u128 << (tw - 1));
    let zero_key = m.uint(tw, 0);
    let k = m.mux(inf, inf_key, finite);
    let k = m.mux(zero, zero_key, k);
    m.name(k, "key")
}

/// Finishes a product started by [`start_product`]: normalise the
/// significand product by at most one bit and form the key.
#[track_caller]
pub fn product_term(m: &mut ModuleBuilder, fmt: Format, p: &ProductStart, name: &str) -> Term {
    m.scope(name, |m| product_key(m, fmt, p))
}

#[track_caller]
fn product_key(m: &mut ModuleBuilder, fmt: Format, p: &ProductStart) -> Term {
    let f = fmt.frac_bits;
    // the product of two normalised significands lies in [2^2F, 2^(2F+2))
    let top = m.bit_at(p.sig, 2 * f + 1);
    let high = m.slice(p.sig, 2 * f, 0);
    let low = m.slice(p.sig, 2 * f - 1, 0);
    let zero_bit = m.uint(1, 0);
    let low = m.cat(&[low, zero_bit]);
    let low = m.name(low, "frac_if_low");
    let frac = m.mux(top, high, low);
    let w = p.exp_sum.width() + 1;
    let es = sext(m, p.exp_sum, w);
    let top_u = m.as_uint(top);
    let top_s = to_sint(m, top_u, w);
    let exp = m.add(es, top_s);
    let exp = m.name(exp, "exp");
    let key = key_of(m, fmt, p.zero, p.inf, exp, frac);
    Term { neg: p.neg, key }
}

/// A factor as a term of its own (compared against products).
#[track_caller]
pub fn single_term(m: &mut ModuleBuilder, fmt: Format, a: &Factor, name: &str) -> Term {
    m.scope(name, |m| {
        let f = fmt.frac_bits;
        let frac = m.slice(a.sig, f - 1, 0);
        let pad = m.uint(f + 1, 0);
        let frac = m.cat(&[frac, pad]);
        let key = key_of(m, fmt, a.zero, a.inf, a.exp, frac);
        let not_zero = m.not(a.zero);
        let neg = m.and(a.sign, not_zero);
        Term {
            neg: m.name(neg, "neg"),
            key,
        }
    })
}

/// `a <= b` for two terms (±0 equal), Bool.
#[track_caller]
pub fn term_le(m: &mut ModuleBuilder, a: &Term, b: &Term) -> Sig {
    let lt = m.lt(a.key, b.key);
    let lt = m.name(lt, "key_lt");
    let eq = m.eq(a.key, b.key);
    let mag_le = m.or(lt, eq);
    let mag_ge = m.not(lt);
    // a negative: b positive, or b negative with no larger magnitude than a
    let b_pos = m.not(b.neg);
    let if_a_neg = m.or(b_pos, mag_ge);
    // a nonnegative: b must be nonnegative with no smaller magnitude
    let if_a_pos = m.and(b_pos, mag_le);
    m.mux(a.neg, if_a_neg, if_a_pos)
}
