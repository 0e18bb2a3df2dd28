//! One exact sum, rounded both toward -inf and toward +inf.

use super::add::add_raw;
use super::format::{FloatFormat, RoundingMode};
use super::native::{add_down_up_f32, f32_bits};
use super::raw::Class;
use super::round::round;

/// The two directed roundings of one exact sum `a + b`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DownUp {
    /// `a + b` rounded toward -inf (RDN).
    pub down: u64,
    /// `a + b` rounded toward +inf (RUP).
    pub up: u64,
}

/// `a + b` rounded toward -inf and toward +inf, from one exact sum:
/// identical to `(add(.., Down), add(.., Up))`. `down <= a + b <= up`, with
/// `down == up` exactly when the sum is representable (NaN: both NaN).
///
/// Binary32 takes the native two-sum path (`native::add_down_up_f32`),
/// other formats [`add_down_up_generic`].
#[inline]
pub fn add_down_up(fmt: FloatFormat, a: u64, b: u64) -> DownUp {
    if fmt == FloatFormat::BINARY32 {
        let (d, u) = add_down_up_f32(f32::from_bits(a as u32), f32::from_bits(b as u32));
        return DownUp {
            down: f32_bits(d),
            up: f32_bits(u),
        };
    }
    add_down_up_generic(fmt, a, b)
}

/// The reference [`add_down_up`]: the generic exact sum and the shared
/// rounder, for every format and operand.
pub fn add_down_up_generic(fmt: FloatFormat, a: u64, b: u64) -> DownUp {
    let raw = add_raw(fmt, a, b, RoundingMode::Down);
    let down = round(fmt, raw, RoundingMode::Down);
    let up = if raw.class == Class::Zero {
        // The only mode-dependent part of an exact sum: the sign of an exact
        // zero (-0 in RDN, +0 in RUP, unless both operands are -0).
        round(fmt, add_raw(fmt, a, b, RoundingMode::Up), RoundingMode::Up)
    } else {
        round(fmt, raw, RoundingMode::Up)
    };
    DownUp { down, up }
}
