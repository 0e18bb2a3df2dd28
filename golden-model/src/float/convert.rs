//! Conversion between any two formats, rounded once.

use super::format::{FloatFormat, RoundingMode};
use super::round::round;
use super::unpack::unpack;

/// `bits` of format `from` as the nearest value of format `to` (per `mode`).
/// NaN → the canonical NaN of `to`; infinities and signed zeros are kept;
/// widening conversions are exact.
pub fn convert(from: FloatFormat, to: FloatFormat, bits: u64, mode: RoundingMode) -> u64 {
    round(to, unpack(from, bits), mode)
}
