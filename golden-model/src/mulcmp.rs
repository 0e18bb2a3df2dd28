//! Golden model of the `mulcmp` demo unit: compares two unsigned products.

/// Outputs of one `mulcmp` transaction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MulCmpOut {
    /// `a·b < c·d`
    pub lt: bool,
    /// `a·b == c·d`
    pub eq: bool,
    /// the full product `a·b`
    pub ab: u128,
}

/// Evaluates `mulcmp` on operands `a`, `c` (each `a_width` bits) and `b`, `d`
/// (`b_width` bits). Products are exact: at most 64 × 64 bits fits `u128`.
pub fn eval(a: u64, b: u64, c: u64, d: u64) -> MulCmpOut {
    let ab = a as u128 * b as u128;
    let cd = c as u128 * d as u128;
    MulCmpOut {
        lt: ab < cd,
        eq: ab == cd,
        ab,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compares_products_not_operands() {
        let r = eval(2, 9, 3, 7);
        assert!(r.lt && !r.eq && r.ab == 18);
        let r = eval(u64::MAX, u64::MAX, u64::MAX, u64::MAX);
        assert!(!r.lt && r.eq);
        assert_eq!(r.ab, (u64::MAX as u128) * (u64::MAX as u128));
    }
}
