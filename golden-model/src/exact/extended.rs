//! The extended line the exact references clip parameter intervals on
//! (the slab test in [`super::ray_box`], the cull region test in
//! [`crate::cull::exact`]): `−∞ <` every finite value `< +∞`, one ordering
//! and one emptiness rule for both.

use std::cmp::Ordering;

/// Exact comparison of finite values. Not `Ord`: the rationals are kept
/// unreduced, so equal values may have different representations.
pub trait ExactCmp {
    /// The order of the values `self` and `other`.
    fn exact_cmp(&self, other: &Self) -> Ordering;
}

/// −∞, a finite value, or +∞.
#[derive(Debug, Clone)]
pub enum Extended<T> {
    /// −infinity
    NegInf,
    /// a finite value
    Fin(T),
    /// +infinity
    PosInf,
}

impl<T: ExactCmp> Extended<T> {
    /// Exact comparison.
    pub fn exact_cmp(&self, other: &Self) -> Ordering {
        match (self, other) {
            (Self::NegInf, Self::NegInf) | (Self::PosInf, Self::PosInf) => Ordering::Equal,
            (Self::NegInf, _) | (_, Self::PosInf) => Ordering::Less,
            (_, Self::NegInf) | (Self::PosInf, _) => Ordering::Greater,
            (Self::Fin(a), Self::Fin(b)) => a.exact_cmp(b),
        }
    }
    /// The larger value (`self` when they are equal).
    pub fn max(self, other: Self) -> Self {
        if self.exact_cmp(&other) == Ordering::Less {
            other
        } else {
            self
        }
    }
    /// The smaller value (`self` when they are equal).
    pub fn min(self, other: Self) -> Self {
        if self.exact_cmp(&other) == Ordering::Greater {
            other
        } else {
            self
        }
    }
    /// `[lo, hi]` holds a real parameter: `lo ≤ hi` with `lo < +∞` and
    /// `hi > −∞` (so `[+∞, +∞]` and `[−∞, −∞]` are empty).
    pub fn interval_nonempty(lo: &Self, hi: &Self) -> bool {
        lo.exact_cmp(hi) != Ordering::Greater
            && !matches!(lo, Self::PosInf)
            && !matches!(hi, Self::NegInf)
    }
}
