//! The one shared rounder: a raw result (sign, class, exponent, unnormalised
//! significand, sticky) → the packed encoding of a format, in one rounding
//! mode. Every rounding operator ends in an instance of this module.
//!
//! Raw format (the golden model's `RawFloat`, with hardware widths):
//!
//! | port     | type         | meaning                                                      |
//! |----------|--------------|--------------------------------------------------------------|
//! | `sign`   | Bool         | sign of the result (also of a zero or infinity)              |
//! | `cls`    | UInt(2)      | 0 zero, 1 finite, 2 infinity, 3 NaN                          |
//! | `exp`    | SInt(xw)     | weight exponent of bit 0 of `sig`                             |
//! | `sig`    | UInt(sw)     | unnormalised integer significand, sw >= F + 2                |
//! | `sticky` | Bool         | the exact magnitude exceeds `sig · 2^exp` by less than `2^exp` |
//!
//! A finite value is `(-1)^sign · (sig + s) · 2^exp` with `s = 0` if
//! `!sticky` and `0 < s < 1` if `sticky`. Producers guarantee
//! `sticky ⇒ sig >= 2^(F+1)` (the round bit is a real bit of `sig`), and
//! `sig == 0 ⇒ !sticky` (a finite raw value with `sig == 0` rounds to a zero
//! of `sign`). The table is checked by a unit test against the ports.
//!
//! Datapath, three steps: (1) leading-zero count of `sig` and
//! `d = exp + sw - 1 - emin`, the distance of `sig`'s top bit above the
//! smallest normal exponent; the left shift is `min(lz, d)` (subnormal
//! results stop at emin), for significands up to [`STOP_MASK_MAX_SIG`] bits
//! counted as the leading zeros of `sig` with a one set at bit `sw - 1 - d`
//! (a mask decoded from the exponent, which is ready first, so no comparison
//! follows the count), for wider ones by a comparison; a negative `d` is a right
//! shift with sticky; (2) the shift; (3) the increment by mode, added to
//! `{biased exponent - 1, significand}` so that a carry out of the
//! significand moves into the exponent (subnormal → normal, 1.11..1 → 10.0,
//! max → infinity), then the overflow choice per mode (the exponent field
//! all ones or a carry above it: bit tests) and the specials.

use super::bits::{add_const, lzc, lzc_width, shr_sticky, to_sint};
use super::unpack::{CLASS_INF, CLASS_NAN, CLASS_ZERO};
use super::{finish_operator, sint_width, spread, Format, Rm, RoundSel, Rounding};
use crate::arith::int::zext;
use crate::arith::ports::{call, rounded, DownUp, RawDownUp, RawValue, Rounded};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::ports::declare_inputs;
use std::sync::Arc;

/// The widest significand whose left shift is limited by a stop mask (a
/// one at bit `sw - 1 - d`, decoded from the exponent) rather than by a
/// comparison after the leading-zero count. The mask takes the comparison
/// off the count → shift path (`fadd` binary32 at 5 stages: 88.9 → 113.1
/// MHz routed on the ECP5-85F) but costs a decoder as wide as the
/// significand: for a binary32 product's 48 bits +20 % xc7 LUTs, so wide
/// significands keep the comparison.
pub const STOP_MASK_MAX_SIG: u32 = 32;

/// A raw result in the current module, to be rounded by [`round`].
#[derive(Debug, Clone, Copy)]
pub struct Raw {
    /// Bool
    pub sign: Sig,
    /// UInt(2) class code
    pub class: Sig,
    /// SInt: weight exponent of bit 0 of `sig`
    pub exp: Sig,
    /// UInt: unnormalised significand
    pub sig: Sig,
    /// Bool
    pub sticky: Sig,
}

/// The class code of a result that is NaN if `nan`, else infinite if `inf`,
/// else finite (a finite raw value with a zero significand is a zero).
#[track_caller]
pub fn class_of(m: &mut ModuleBuilder, nan: Sig, inf: Sig) -> Sig {
    let special = m.or(nan, inf);
    let special = m.name(special, "class_hi");
    let not_inf = m.not(inf);
    let lo = m.or(nan, not_inf);
    let lo = m.name(lo, "class_lo");
    let hi = m.as_uint(special);
    let lo = m.as_uint(lo);
    let class = m.cat(&[hi, lo]);
    m.name(class, "class_code")
}

/// What the producer of a raw value guarantees to the rounder (HardFloat's
/// `flRoundOpt_neverUnderflows`/`neverOverflows`): the rounder builds no
/// logic for what cannot happen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Range {
    /// any value: subnormal results (a right shift with sticky), overflow
    Any,
    /// the exact value is zero or lies in the normal range of the format
    /// (no subnormal result, no overflow), and a nonzero significand has at
    /// most `lead` leading zeros (so the normalising shift is `lead` bits
    /// at most: 1 for a product of normal operands)
    Normal {
        /// the most leading zeros of a nonzero significand
        lead: u32,
    },
}

/// Module name of the rounder.
pub fn round_name(
    fmt: Format,
    sig_width: u32,
    exp_width: u32,
    mode: RoundSel,
    stages: u32,
) -> String {
    round_range_name(fmt, sig_width, exp_width, mode, Range::Any, stages)
}

/// Module name of the rounder for values in `range` (`_n<lead>` unless `Any`).
pub fn round_range_name(
    fmt: Format,
    sig_width: u32,
    exp_width: u32,
    mode: RoundSel,
    range: Range,
    stages: u32,
) -> String {
    let range = match range {
        Range::Any => String::new(),
        Range::Normal { lead } => format!("_n{lead}"),
    };
    format!(
        "fround_{}_w{sig_width}x{exp_width}_{mode}{range}_s{stages}",
        fmt.tag()
    )
}

/// Number of logical steps of the rounder (for stage planning).
pub const ROUND_STEPS: u32 = 3;

/// Builds the rounder for results of `fmt` from a raw value with a
/// `sig_width`-bit significand (>= F + 2) and an `exp_width`-bit exponent.
pub fn round_module(
    fmt: Format,
    sig_width: u32,
    exp_width: u32,
    mode: impl Into<RoundSel>,
    stages: u32,
) -> Arc<Module> {
    round_range_module(fmt, sig_width, exp_width, mode, Range::Any, stages)
}

/// [`round_module`] for raw values in `range` (the producer's guarantee;
/// outside it the result is unspecified).
pub fn round_range_module(
    fmt: Format,
    sig_width: u32,
    exp_width: u32,
    mode: impl Into<RoundSel>,
    range: Range,
    stages: u32,
) -> Arc<Module> {
    let mode: RoundSel = mode.into();
    let (e, f) = (fmt.exp_bits, fmt.frac_bits);
    let sw = sig_width;
    let range = match range {
        Range::Normal { lead } => Range::Normal {
            lead: lead.min(sw - 1),
        },
        Range::Any => Range::Any,
    };
    assert!(
        sw >= f + 2,
        "rounder needs a significand of at least F + 2 bits"
    );
    let mut m = ModuleBuilder::new(round_range_name(fmt, sw, exp_width, mode, range, stages));
    let promise = match range {
        Range::Any => String::new(),
        Range::Normal { lead } => format!(
            " The value is zero or normal (no subnormal result, no overflow) and a nonzero \
             significand has at most {lead} leading zeros: the producer guarantees it."
        ),
    };
    m.describe(format!(
        "Shared rounder: raw (sign, class, exp, {sw}-bit sig, sticky) to {} in mode {mode}.{promise}",
        fmt.tag()
    ));
    m.param("exp_bits", e)
        .param("frac_bits", f)
        .param("sig_width", sw)
        .param("exp_width", exp_width)
        .param("round", mode)
        .param("stages", stages);
    let plan = spread(stages, ROUND_STEPS);
    let ports = (Ty::SInt(exp_width), Ty::UInt(sw), mode.is_port());
    let RawValue {
        sign,
        cls: class,
        exp,
        sig,
        sticky: sticky_in,
        rm,
    } = declare_inputs(&mut m, &ports);
    let rm = Rm::new(mode, rm);
    let n = match range {
        Range::Any => shift_to_grid(&mut m, fmt, exp, sig, &plan),
        Range::Normal { lead } => shift_in_range(&mut m, fmt, exp, sig, lead, &plan),
    };
    let in_range = range != Range::Any;
    let z = round_and_pack(&mut m, fmt, &rm, sign, class, sticky_in, &n, in_range);
    finish_operator(m, plan[2], &fmt.ty(), &Rounded { z }, "rounder")
}

/// Module name of the down/up rounder.
pub fn round_down_up_name(fmt: Format, sig_width: u32, exp_width: u32, stages: u32) -> String {
    format!(
        "fround_{}_w{sig_width}x{exp_width}_down_up_s{stages}",
        fmt.tag()
    )
}

/// The rounder of [`round_module`] with two outputs, `down` (RDN, sign
/// `sign_down`) and `up` (RUP, sign `sign_up`), of one raw value: the
/// leading-zero count and the shift are shared, only the increment and the
/// packing are built twice. The two signs differ only for an exact zero
/// whose sign depends on the mode (a sum of opposite-signed operands).
pub fn round_down_up_module(
    fmt: Format,
    sig_width: u32,
    exp_width: u32,
    stages: u32,
) -> Arc<Module> {
    let sw = sig_width;
    assert!(
        sw >= fmt.frac_bits + 2,
        "rounder needs a significand of at least F + 2 bits"
    );
    let mut m = ModuleBuilder::new(round_down_up_name(fmt, sw, exp_width, stages));
    m.describe(format!(
        "Shared rounder, two directions: raw (sign per direction, class, exp, {sw}-bit sig, sticky) \
         to {} rounded toward -inf (down) and toward +inf (up), one normalisation.",
        fmt.tag()
    ));
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("sig_width", sw)
        .param("exp_width", exp_width)
        .param("stages", stages);
    let plan = spread(stages, ROUND_STEPS);
    let RawDownUp {
        sign_down,
        sign_up,
        cls: class,
        exp,
        sig,
        sticky: sticky_in,
    } = declare_inputs(&mut m, &(Ty::SInt(exp_width), Ty::UInt(sw)));
    let n = shift_to_grid(&mut m, fmt, exp, sig, &plan);
    let rdn = Rm::fixed(Rounding::Rdn);
    let rup = Rm::fixed(Rounding::Rup);
    let down = m.scope("down", |m| {
        round_and_pack(m, fmt, &rdn, sign_down, class, sticky_in, &n, false)
    });
    let up = m.scope("up", |m| {
        round_and_pack(m, fmt, &rup, sign_up, class, sticky_in, &n, false)
    });
    finish_operator(
        m,
        plan[2],
        &fmt.ty(),
        &DownUp { down, up },
        "down/up rounder",
    )
}

/// A raw significand moved onto the result's grid (steps 1 and 2 of the
/// rounder), with what the packing needs.
struct OnGrid {
    /// the significand, kept bits at the top
    shifted: Sig,
    /// bits lost by a right shift (subnormal results)
    lost: Sig,
    /// biased exponent minus one of the result before the increment
    base: Sig,
    /// the raw significand is zero
    sig_zero: Sig,
}

/// Steps 1-2: leading zeros, distance to emin, the shift (left to normalise,
/// right with sticky for subnormal results); `plan[0]` and `plan[1]`
/// registers after them.
fn shift_to_grid(m: &mut ModuleBuilder, fmt: Format, exp: Sig, sig: Sig, plan: &[u32]) -> OnGrid {
    let sw = sig.width();
    let exp_width = exp.width();
    // step 1: leading zeros, distance to emin, shift amounts, exponent base
    let cw = lzc_width(sw);
    let half = 1i64 << (exp_width - 1);
    let offset = sw as i64 - 1 - fmt.emin();
    let (d_lo, d_hi) = (-half + offset, half - 1 + offset);
    let dw = sint_width(d_lo.min(-1), d_hi.max(1i64 << cw)) + 1;
    let exp_w = to_sint(m, exp, dw);
    let off = m.sint(dw, offset as i128);
    let d = m.add(exp_w, off);
    let d = super::bits::to_sint(m, d, dw);
    let d = m.name(d, "d");
    let d_neg = m.msb(d);
    let d_bits = m.as_uint(d);
    let d_small = m.slice(d_bits, cw - 1, 0);
    let bw = (dw - 1).max(1);
    let base0 = m.uint(bw, 0);
    let (lshift, base) = if sw <= STOP_MASK_MAX_SIG {
        // min(lz, d) without a comparison after the count: for 0 <= d < sw
        // a one at bit sw-1-d stops the count at d. The mask depends on
        // the exponent alone, which is ready before the significand.
        let d_high = m.slice(d_bits, dw - 1, cw);
        let d_high_any = m.any_set(d_high);
        let top_one = m.uint(sw, 1u128 << (sw - 1));
        let stop = m.shr(top_one, d_small);
        let no_stop = m.uint(sw, 0);
        let stop = m.mux(d_high_any, no_stop, stop);
        let stop = m.name(stop, "lzc_stop");
        let counted = m.or(sig, stop);
        let lshift = lzc(m, counted);
        // d - min(lz, d): 0 for a subnormal result, and for a negative d
        let lshift_s = to_sint(m, lshift, dw);
        let base = m.sub(d, lshift_s);
        let base = m.slice(base, bw - 1, 0);
        (lshift, m.mux(d_neg, base0, base))
    } else {
        // min(lz, d) by a comparison after the count
        let lz = lzc(m, sig);
        let lz_s = to_sint(m, lz, dw);
        let d_lt_lz = m.lt(d, lz_s);
        let zero_cw = m.uint(cw, 0);
        let lshift_sub = m.mux(d_neg, zero_cw, d_small);
        let lshift = m.mux(d_lt_lz, lshift_sub, lz);
        let base = m.sub(d, lz_s);
        let base = m.slice(base, bw - 1, 0);
        (lshift, m.mux(d_lt_lz, base0, base))
    };
    let lshift = m.name(lshift, "lshift");
    let base = m.name(base, "exp_base");
    let zero_d = m.sint(dw, 0);
    let neg_d = m.sub(zero_d, d);
    let neg_d = m.name(neg_d, "d_neg");
    let rshift = m.slice(neg_d, dw - 1, 0);
    let rshift = m.name(rshift, "rshift");
    let sig_any = m.any_set(sig);
    let sig_zero = m.not(sig_any);
    let sig_zero = m.name(sig_zero, "sig_zero");
    for _ in 0..plan[0] {
        m.stage();
    }

    // step 2: normalise (left) or denormalise with sticky (right)
    let left = m.shl(sig, lshift);
    let (right, lost) = shr_sticky(m, sig, rshift);
    let shifted = m.mux(d_neg, right, left);
    let shifted = m.name(shifted, "sig_shifted");
    let no_loss = m.bool(false);
    let lost = m.mux(d_neg, lost, no_loss);
    let lost = m.name(lost, "lost");
    for _ in 0..plan[1] {
        m.stage();
    }
    OnGrid {
        shifted,
        lost,
        base,
        sig_zero,
    }
}

/// Steps 1-2 for a value in the normal range whose nonzero significand has
/// at most `lead` leading zeros: the leading zeros of the top `lead + 1`
/// bits, the left shift, no distance to emin and no right shift.
fn shift_in_range(
    m: &mut ModuleBuilder,
    fmt: Format,
    exp: Sig,
    sig: Sig,
    lead: u32,
    plan: &[u32],
) -> OnGrid {
    let sw = sig.width();
    let cw = lzc_width(sw);
    let half = 1i64 << (exp.width() - 1);
    let offset = sw as i64 - 1 - fmt.emin();
    let (d_lo, d_hi) = (-half + offset, half - 1 + offset);
    let dw = sint_width(d_lo.min(-1), d_hi.max(1i64 << cw)) + 1;
    // the biased exponent minus one of the normalised value, exp + sw - 1 -
    // emin - lz (as in shift_to_grid, never below 0 here)
    let exp_w = to_sint(m, exp, dw);
    let off = m.sint(dw, offset as i128);
    let d = m.add(exp_w, off);
    let d = to_sint(m, d, dw);
    let top = m.slice(sig, sw - 1, sw - 1 - lead.min(sw - 1));
    let lz = lzc(m, top);
    let lshift = zext(m, lz, lz.width().max(1));
    let lshift = m.name(lshift, "lshift");
    let lz_s = to_sint(m, lshift, dw);
    let base = m.sub(d, lz_s);
    let bw = (dw - 1).max(1);
    let base = m.slice(base, bw - 1, 0);
    let base = m.name(base, "exp_base");
    let sig_any = m.any_set(sig);
    let sig_zero = m.not(sig_any);
    let sig_zero = m.name(sig_zero, "sig_zero");
    for _ in 0..plan[0] {
        m.stage();
    }
    let shifted = m.shl(sig, lshift);
    let shifted = m.name(shifted, "sig_shifted");
    let lost = m.bool(false);
    for _ in 0..plan[1] {
        m.stage();
    }
    OnGrid {
        shifted,
        lost,
        base,
        sig_zero,
    }
}

/// Step 3: round in mode `rm`, pack, overflow, specials; `in_range`: the
/// value is zero or finite and does not overflow (no saturation, no
/// infinity or NaN to select).
#[allow(clippy::too_many_arguments)]
fn round_and_pack(
    m: &mut ModuleBuilder,
    fmt: Format,
    rm: &Rm,
    sign: Sig,
    class: Sig,
    sticky_in: Sig,
    n: &OnGrid,
    in_range: bool,
) -> Sig {
    let (e, f) = (fmt.exp_bits, fmt.frac_bits);
    let (shifted, lost, base, sig_zero) = (n.shifted, n.lost, n.base, n.sig_zero);
    let sw = shifted.width();
    let bw = base.width();
    let top = m.slice(shifted, sw - 1, sw - f - 1);
    let top = m.name(top, "kept");
    let guard = m.bit_at(shifted, sw - f - 2);
    let rest = if sw >= f + 3 {
        let r = m.slice(shifted, sw - f - 3, 0);
        m.any_set(r)
    } else {
        m.bool(false)
    };
    let s1 = m.or(rest, lost);
    let sticky = m.or(s1, sticky_in);
    let sticky = m.name(sticky, "sticky_all");
    let lsb = m.bit_at(top, 0);
    let (inc, to_inf) = decide(m, rm, sign, guard, sticky, lsb);
    let inc = m.name(inc, "round_up");
    let pw = (bw + f + 2).max(e + f + 1);
    let zf = m.uint(f, 0);
    let base_hi = m.cat(&[base, zf]);
    let base_hi = zext(m, base_hi, pw);
    let top_w = zext(m, top, pw);
    let packed = m.add(base_hi, top_w);
    let inc_u = m.as_uint(inc);
    let inc_w = zext(m, inc_u, pw);
    let packed = m.add(packed, inc_w);
    let packed = zext(m, packed, pw);
    let packed = m.name(packed, "packed_mag");
    let mag_w = e + f;
    let zero_mag = m.uint(mag_w, 0);
    if in_range {
        let packed_mag = m.slice(packed, mag_w - 1, 0);
        let fin = m.mux(sig_zero, zero_mag, packed_mag);
        let k = m.uint(2, CLASS_ZERO);
        let is_zero = m.eq(class, k);
        let is_zero = m.name(is_zero, "class_zero");
        let mag = m.mux(is_zero, zero_mag, fin);
        let mag = m.name(mag, "mag");
        let sign_u = m.as_uint(sign);
        let z = m.cat(&[sign_u, mag]);
        return m.name(z, "result");
    }
    // packed >= the infinity's code: an exponent field of all ones or a carry
    // above it (bit tests, not a comparison after the addition)
    let exp_field = m.slice(packed, e + f - 1, f);
    let exp_all_ones = m.all_ones(exp_field);
    let above = m.slice(packed, pw - 1, e + f);
    let carried = m.any_set(above);
    let ovf = m.or(exp_all_ones, carried);
    let ovf = m.name(ovf, "overflow");
    let inf_mag = m.uint(mag_w, fmt.inf_bits());
    let max_mag = m.uint(mag_w, fmt.inf_bits() - 1);
    let sat = m.mux(to_inf, inf_mag, max_mag);
    let sat = m.name(sat, "saturated");
    let packed_mag = m.slice(packed, mag_w - 1, 0);
    let fin = m.mux(ovf, sat, packed_mag);
    let fin = m.mux(sig_zero, zero_mag, fin);
    let fin = m.name(fin, "finite_mag");
    let mut class_is = |code: u128, role: &str| {
        let k = m.uint(2, code);
        let is = m.eq(class, k);
        m.name(is, role)
    };
    let is_zero = class_is(CLASS_ZERO, "class_zero");
    let is_inf = class_is(CLASS_INF, "class_inf");
    let is_nan = class_is(CLASS_NAN, "class_nan");
    let mag = m.mux(is_inf, inf_mag, fin);
    let mag = m.mux(is_zero, zero_mag, mag);
    let mag = m.name(mag, "mag");
    let sign_u = m.as_uint(sign);
    let signed = m.cat(&[sign_u, mag]);
    let signed = m.name(signed, "with_sign");
    let nan = m.uint(fmt.width(), fmt.nan_bits());
    let z = m.mux(is_nan, nan, signed);
    m.name(z, "result")
}

/// The increment and the overflow-to-infinity choice of mode `rm` for a
/// result of sign `sign` with round bit `guard`, `sticky` below it and
/// kept lsb `lsb`.
fn decide(
    m: &mut ModuleBuilder,
    rm: &Rm,
    sign: Sig,
    guard: Sig,
    sticky: Sig,
    lsb: Sig,
) -> (Sig, Sig) {
    let inexact = m.or(guard, sticky);
    let inexact = m.name(inexact, "inexact");
    let pos = m.not(sign);
    let tie_or_above = m.or(sticky, lsb);
    let rne_inc = m.and(guard, tie_or_above);
    let rup_inc = m.and(pos, inexact);
    let rdn_inc = m.and(sign, inexact);
    match rm.sel {
        RoundSel::Fixed(Rounding::Rne) => (rne_inc, m.bool(true)),
        RoundSel::Fixed(Rounding::Rtz) => (m.bool(false), m.bool(false)),
        RoundSel::Fixed(Rounding::Rup) => (rup_inc, pos),
        RoundSel::Fixed(Rounding::Rdn) => (rdn_inc, sign),
        RoundSel::Port => {
            let is_rne = rm.is(m, Rounding::Rne);
            let is_rup = rm.is(m, Rounding::Rup);
            let is_rdn = rm.is(m, Rounding::Rdn);
            let a = m.and(is_rne, rne_inc);
            let b = m.and(is_rup, rup_inc);
            let c = m.and(is_rdn, rdn_inc);
            let inc = m.or(a, b);
            let inc = m.or(inc, c);
            let up_inf = m.and(is_rup, pos);
            let dn_inf = m.and(is_rdn, sign);
            let to_inf = m.or(is_rne, up_inf);
            let to_inf = m.or(to_inf, dn_inf);
            (inc, to_inf)
        }
    }
}

/// Instantiates the rounder for `raw` (padding a significand narrower than
/// F + 2 bits with zeros) and returns the packed result, which belongs to
/// the stage `stages` cycles after the current one: the caller closes those
/// stages before reading it in its own logic.
#[track_caller]
pub fn round(
    m: &mut ModuleBuilder,
    fmt: Format,
    mode: Rounding,
    raw: &Raw,
    stages: u32,
    inst: &str,
) -> Sig {
    round_rm(m, fmt, &Rm::fixed(mode), raw, stages, inst)
}

/// The common end of a rounding operator's module: rounds `raw` into `fmt`
/// in mode `rm` with `stages` registers inside the rounder, carries the
/// pipeline over them, outputs the result as `z` and finishes the module.
#[track_caller]
pub fn finish_rounded(
    m: ModuleBuilder,
    fmt: Format,
    rm: &Rm,
    raw: &Raw,
    stages: u32,
    what: &str,
) -> Arc<Module> {
    finish_rounded_range(m, fmt, rm, raw, Range::Any, stages, what)
}

/// [`finish_rounded`] for a raw value in `range`.
#[track_caller]
pub fn finish_rounded_range(
    mut m: ModuleBuilder,
    fmt: Format,
    rm: &Rm,
    raw: &Raw,
    range: Range,
    stages: u32,
    what: &str,
) -> Arc<Module> {
    let z = round_rm_range(&mut m, fmt, rm, raw, range, stages, "u_round");
    finish_operator(m, stages, &fmt.ty(), &Rounded { z }, what)
}

/// [`round`] in the mode `rm` (fixed, or the module's `rm` port, which is
/// connected to the rounder's).
#[track_caller]
pub fn round_rm(
    m: &mut ModuleBuilder,
    fmt: Format,
    rm: &Rm,
    raw: &Raw,
    stages: u32,
    inst: &str,
) -> Sig {
    round_rm_range(m, fmt, rm, raw, Range::Any, stages, inst)
}

/// [`round_rm`] for a raw value in `range` ([`round_range_module`]).
#[track_caller]
pub fn round_rm_range(
    m: &mut ModuleBuilder,
    fmt: Format,
    rm: &Rm,
    raw: &Raw,
    range: Range,
    stages: u32,
    inst: &str,
) -> Sig {
    let (sig, exp) = padded(m, fmt, raw);
    let module = round_range_module(fmt, sig.width(), exp.width(), rm.sel, range, stages);
    let value = RawValue {
        sign: raw.sign,
        cls: raw.class,
        exp,
        sig,
        sticky: raw.sticky,
        rm: rm.port,
    };
    rounded(m, inst, &module, &value)
}

/// The raw significand and exponent, the significand padded with zeros to
/// at least F + 2 bits (the rounder's minimum).
#[track_caller]
fn padded(m: &mut ModuleBuilder, fmt: Format, raw: &Raw) -> (Sig, Sig) {
    let f = fmt.frac_bits;
    if raw.sig.width() < f + 2 {
        let pad = f + 2 - raw.sig.width();
        let zeros = m.uint(pad, 0);
        let sig = m.cat(&[raw.sig, zeros]);
        let half = 1i64 << (raw.exp.width() - 1);
        let xw = sint_width(-half - pad as i64, half);
        (sig, add_const(m, raw.exp, -(pad as i64), xw))
    } else {
        (raw.sig, raw.exp)
    }
}

/// Instantiates the down/up rounder ([`round_down_up_module`]) for `raw`
/// with the sign `sign_down` toward −∞ and `sign_up` toward +∞ and returns
/// `(down, up)`, which belong to the stage `stages` cycles after the
/// current one (as [`round`]).
#[track_caller]
pub fn round_down_up(
    m: &mut ModuleBuilder,
    fmt: Format,
    raw: &Raw,
    sign_down: Sig,
    sign_up: Sig,
    stages: u32,
    inst: &str,
) -> (Sig, Sig) {
    let (sig, exp) = padded(m, fmt, raw);
    let module = round_down_up_module(fmt, sig.width(), exp.width(), stages);
    let value = RawDownUp {
        sign_down,
        sign_up,
        cls: raw.class,
        exp,
        sig,
        sticky: raw.sticky,
    };
    let DownUp { down, up } = call(m, inst, &module, &value, &fmt.ty());
    (down, up)
}
