//! rustc_apfloat as an oracle for any (E, F) format in the test list.

use golden_model::float::{FloatFormat, RoundingMode};
use rustc_apfloat::ieee::{IeeeFloat, Semantics};
use rustc_apfloat::{Float, FloatConvert, Round};

/// IEEE 754 semantics with E exponent bits and F fraction bits.
pub struct Fmt<const E: usize, const F: usize>;

impl<const E: usize, const F: usize> Semantics for Fmt<E, F> {
    const BITS: usize = 1 + E + F;
    const EXP_BITS: usize = E;
}

pub type Ap<const E: usize, const F: usize> = IeeeFloat<Fmt<E, F>>;

pub fn round_of(m: RoundingMode) -> Round {
    match m {
        RoundingMode::NearestEven => Round::NearestTiesToEven,
        RoundingMode::TowardZero => Round::TowardZero,
        RoundingMode::Down => Round::TowardNegative,
        RoundingMode::Up => Round::TowardPositive,
    }
}

/// Runs `$body` with `$T` bound to the apfloat type of `$fmt`.
macro_rules! with_ap {
    ($fmt:expr, $T:ident => $body:expr) => {
        match ($fmt.exp_bits(), $fmt.frac_bits()) {
            (8, 23) => {
                type $T = Ap<8, 23>;
                $body
            }
            (5, 10) => {
                type $T = Ap<5, 10>;
                $body
            }
            (8, 7) => {
                type $T = Ap<8, 7>;
                $body
            }
            (8, 15) => {
                type $T = Ap<8, 15>;
                $body
            }
            (6, 9) => {
                type $T = Ap<6, 9>;
                $body
            }
            (11, 52) => {
                type $T = Ap<11, 52>;
                $body
            }
            (4, 3) => {
                type $T = Ap<4, 3>;
                $body
            }
            (3, 2) => {
                type $T = Ap<3, 2>;
                $body
            }
            (e, f) => panic!("no apfloat instance for ({e}, {f})"),
        }
    };
}

/// The oracle's result bits (NaNs may carry any payload: compare with `is_nan`).
pub fn add(fmt: FloatFormat, a: u64, b: u64, m: RoundingMode) -> u64 {
    with_ap!(fmt, T => T::from_bits(a as u128).add_r(T::from_bits(b as u128), round_of(m)).value.to_bits() as u64)
}

pub fn sub(fmt: FloatFormat, a: u64, b: u64, m: RoundingMode) -> u64 {
    with_ap!(fmt, T => T::from_bits(a as u128).sub_r(T::from_bits(b as u128), round_of(m)).value.to_bits() as u64)
}

pub fn mul(fmt: FloatFormat, a: u64, b: u64, m: RoundingMode) -> u64 {
    with_ap!(fmt, T => T::from_bits(a as u128).mul_r(T::from_bits(b as u128), round_of(m)).value.to_bits() as u64)
}

pub fn fma(fmt: FloatFormat, a: u64, b: u64, c: u64, m: RoundingMode) -> u64 {
    with_ap!(fmt, T => T::from_bits(a as u128)
        .mul_add_r(T::from_bits(b as u128), T::from_bits(c as u128), round_of(m))
        .value
        .to_bits() as u64)
}

pub fn convert(from: FloatFormat, to: FloatFormat, x: u64, m: RoundingMode) -> u64 {
    with_ap!(from, S => with_ap!(to, T => {
        let mut loses_info = false;
        let r: T = S::from_bits(x as u128).convert_r(round_of(m), &mut loses_info).value;
        r.to_bits() as u64
    }))
}
