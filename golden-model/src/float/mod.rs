//! Bit-accurate IEEE-754-style floating point for any format
//! `(exp_bits, frac_bits)`, the golden model of the generated float units.
//! The specification is `docs/float.md`.
//!
//! Every operator computes an exact [`RawFloat`] (exact, or exact with a
//! sticky bit) and the one shared rounder, [`round`], rounds and packs it.
//! Values are raw bit patterns in the low bits of a `u64`; bits above the
//! format's width are ignored on input and zero on output.
//!
//! ```
//! use golden_model::float::{add, FloatFormat, RoundingMode};
//! let f = FloatFormat::BINARY32;
//! let r = add(f, 1.5f32.to_bits() as u64, 2.25f32.to_bits() as u64, RoundingMode::NearestEven);
//! assert_eq!(r, 3.75f32.to_bits() as u64);
//! ```

mod add;
mod add_down_up;
mod compare;
mod convert;
mod dot3;
mod dot3_floor;
mod fma;
mod format;
mod min_max;
mod mul;
mod mul_exact;
pub mod native;
mod order;
pub mod random;
mod raw;
mod round;
mod unpack;

pub use add::{add, add_generic, sub};
pub use add_down_up::{add_down_up, add_down_up_generic, DownUp};
pub use compare::{eq, le, lt};
pub use convert::convert;
pub use dot3::{dot3, dot3_accumulator_bits};
pub use dot3_floor::{dot3_floor, dot3_floor_generic};
pub(crate) use dot3_floor::{dot3_floor_operands, Operand as Dot3Operand};
pub use fma::{fma, fma_generic};
pub use format::{FloatFormat, FormatError, RoundingMode};
pub use min_max::{max, min};
pub use mul::{mul, mul_generic};
pub use mul_exact::{mul_exact, ExactProductFormat};
pub use order::{between, from_f64, from_total_key, nudge, ordered, to_f64, total_key};
pub use raw::{
    Class, RawFloat, RAW_CLASS_BITS, RAW_EXP_BITS, RAW_SIGN_BITS, RAW_SIG_BITS, RAW_STICKY_BITS,
    RAW_STICKY_MIN_EXTRA_BITS,
};
pub use round::{overflow, round};
pub use unpack::{classify, unpack};
