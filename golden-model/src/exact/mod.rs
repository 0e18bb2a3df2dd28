//! Exact references: the real-number answer on the same float inputs, in
//! big-integer arithmetic (`dashu`), with no float operator of this crate on
//! the path (only [`crate::float::FloatFormat`] to know the field widths).
//! Slow, simple and independent, so the bit-accurate models can be checked
//! against them.

pub mod extended;
pub mod ray_box;
