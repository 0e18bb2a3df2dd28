//! The operators' unit tests compare against the golden models (a
//! dev-dependency only): the golden model's names for a format and a
//! rounding mode. The flow's own conversions are `rtl_flow::fstim`.

use crate::arith::float::{Format, Rounding};
use golden_model::float::{FloatFormat, RoundingMode};

/// The golden model's format for `fmt`.
pub fn golden_format(fmt: Format) -> FloatFormat {
    FloatFormat::new(fmt.exp_bits, fmt.frac_bits).expect("formats agree on validity")
}

/// The golden model's rounding mode for `mode`.
pub fn golden_mode(mode: Rounding) -> RoundingMode {
    match mode {
        Rounding::Rne => RoundingMode::NearestEven,
        Rounding::Rtz => RoundingMode::TowardZero,
        Rounding::Rup => RoundingMode::Up,
        Rounding::Rdn => RoundingMode::Down,
    }
}
