//! One exact sum, rounded both toward -inf and toward +inf.

use super::add::add_raw;
use super::format::{FloatFormat, RoundingMode};
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
pub fn add_down_up(fmt: FloatFormat, a: u64, b: u64) -> DownUp {
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
