//! `mulcmp`: compares two unsigned products, `a·b < c·d` and `a·b == c·d`.
//!
//! The demo unit that proves the flow, and the pattern of the division-free
//! comparisons the intersection units are made of. Two multiplier instances
//! (hierarchy) feed a comparator; `stages` registers are spread over them.

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::arith::int::umul_module;
use crate::arith::ports::product;
use crate::builder::ModuleBuilder;
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `mulcmp` unit.
pub struct MulCmp;

crate::params! {
    /// A multiply-compare unit's parameters, which are its configuration.
    pub struct Config {
        /// width of a and c
        a_width: u32 [1..=32] = 16,
        /// width of b and d
        b_width: u32 [1..=32] = 16,
        /// pipeline stages (latency in cycles): the last registers the comparison, the others go to the multipliers
        stages: u32 [0..=8] = 2,
    }
}

/// The data inputs: `a` and `c` of `a_width` bits, `b` and `d` of
/// `b_width` bits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MulCmpIn<T> {
    /// first factor of the left product
    pub a: T,
    /// second factor of the left product
    pub b: T,
    /// first factor of the right product
    pub c: T,
    /// second factor of the right product
    pub d: T,
}

impl<T: Copy> Record<T> for MulCmpIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let (ta, tb) = (Ty::UInt(cfg.a_width), Ty::UInt(cfg.b_width));
        MulCmpIn {
            a: w.one("a", ta, |r| r.a),
            b: w.one("b", tb, |r| r.b),
            c: w.one("c", ta, |r| r.c),
            d: w.one("d", tb, |r| r.d),
        }
    }
}

/// The data outputs: `lt eq ab`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MulCmpOut<T> {
    /// `a*b < c*d`
    pub lt: T,
    /// `a*b == c*d`
    pub eq: T,
    /// `a*b`
    pub ab: T,
}

impl<T: Copy> Record<T> for MulCmpOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        MulCmpOut {
            lt: w.one("lt", Ty::Bool, |r| r.lt),
            eq: w.one("eq", Ty::Bool, |r| r.eq),
            ab: w.one("ab", Ty::UInt(cfg.a_width + cfg.b_width), |r| r.ab),
        }
    }
}

/// Builds `mulcmp` for `a`/`c` of `a_width` bits, `b`/`d` of `b_width` bits.
pub fn build(cfg: &Config) -> Module {
    let Config {
        a_width,
        b_width,
        stages,
    } = *cfg;
    let mut m = ModuleBuilder::with_handshake(format!("mulcmp_a{a_width}_b{b_width}_s{stages}"));
    m.describe("Compares two unsigned products: lt = a*b < c*d, eq = a*b == c*d; ab = a*b.");
    let MulCmpIn { a, b, c, d } = ports::declare_inputs(&mut m, cfg);
    let mul_stages = stages.saturating_sub(1);
    let mul = umul_module(a_width, b_width, mul_stages);
    let ab = product(&mut m, "u_mul_ab", &mul, a, b);
    let cd = product(&mut m, "u_mul_cd", &mul, c, d);
    for _ in 0..mul_stages {
        m.stage();
    }
    let lt = m.lt(ab, cd);
    let lt = m.name(lt, "ab_lt_cd");
    let eq = m.eq(ab, cd);
    let eq = m.name(eq, "ab_eq_cd");
    if stages > 0 {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &MulCmpOut { lt, eq, ab });
    m.finish()
        .expect("mulcmp generator is type-correct for every accepted width")
}

impl Description for MulCmp {
    type Params = Config;
    type Config = Config;
    const NAME: &'static str = "mulcmp";
    const SUMMARY: &'static str =
        "pipelined unsigned multiply-compare: lt = a*b < c*d, eq = a*b == c*d, ab = a*b";
    fn config(&self, p: &Config) -> Result<Config, ParamError> {
        Ok(*p)
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}
