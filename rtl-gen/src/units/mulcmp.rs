//! `mulcmp`: compares two unsigned products, `a·b < c·d` and `a·b == c·d`.
//!
//! The demo unit that proves the flow, and the pattern of the division-free
//! comparisons the intersection units are made of. Two multiplier instances
//! (hierarchy) feed a comparator; `stages` registers are spread over them.

use super::Description;
use crate::arith::int::umul_module;
use crate::builder::ModuleBuilder;
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};

/// The `mulcmp` unit.
pub struct MulCmp;

/// A multiply-compare unit's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// width of `a` and `c`
    pub a_width: u32,
    /// width of `b` and `d`
    pub b_width: u32,
    /// pipeline stages
    pub stages: u32,
}

const PARAMS: &[ParamSpec] = &[
    ParamSpec { name: "a_width", doc: "width of a and c", kind: ParamKind::Int { min: 1, max: 32 }, default: "16" },
    ParamSpec { name: "b_width", doc: "width of b and d", kind: ParamKind::Int { min: 1, max: 32 }, default: "16" },
    ParamSpec {
        name: "stages",
        doc: "pipeline stages (latency in cycles): the last registers the comparison, the others go to the multipliers",
        kind: ParamKind::Int { min: 0, max: 8 },
        default: "2",
    },
];

/// The data inputs in port order: `a` and `c` of `a_width` bits, `b` and
/// `d` of `b_width` bits; the module and the testbench both read it.
pub const INPUT_NAMES: [&str; 4] = ["a", "b", "c", "d"];

/// The data outputs in port order.
pub const OUTPUT_NAMES: [&str; 3] = ["lt", "eq", "ab"];

/// Builds `mulcmp` for `a`/`c` of `a_width` bits, `b`/`d` of `b_width` bits.
pub fn build(a_width: u32, b_width: u32, stages: u32) -> Module {
    let mut m = ModuleBuilder::with_handshake(format!("mulcmp_a{a_width}_b{b_width}_s{stages}"));
    m.describe("Compares two unsigned products: lt = a*b < c*d, eq = a*b == c*d; ab = a*b.");
    m.param("a_width", a_width)
        .param("b_width", b_width)
        .param("stages", stages);
    let [a, b, c, d] = INPUT_NAMES.map(|n| {
        let w = if matches!(n, "a" | "c") {
            a_width
        } else {
            b_width
        };
        m.input(n, Ty::UInt(w))
    });
    let mul_stages = stages.saturating_sub(1);
    let mul = umul_module(a_width, b_width, mul_stages);
    let ab = m
        .instance("u_mul_ab", &mul, &[("a", a), ("b", b)])
        .get("p")
        .expect("multiplier has output p");
    let cd = m
        .instance("u_mul_cd", &mul, &[("a", c), ("b", d)])
        .get("p")
        .expect("multiplier has output p");
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
    for (name, v) in OUTPUT_NAMES.into_iter().zip([lt, eq, ab]) {
        m.output(name, v);
    }
    m.finish()
        .expect("mulcmp generator is type-correct for every accepted width")
}

impl Description for MulCmp {
    type Config = Config;
    const NAME: &'static str = "mulcmp";
    const SUMMARY: &'static str =
        "pipelined unsigned multiply-compare: lt = a*b < c*d, eq = a*b == c*d, ab = a*b";
    const PARAMS: &'static [ParamSpec] = PARAMS;
    fn config(&self, p: &Params) -> Result<Config, ParamError> {
        Ok(Config {
            a_width: p.u32("a_width"),
            b_width: p.u32("b_width"),
            stages: p.u32("stages"),
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg.a_width, cfg.b_width, cfg.stages)
    }
}
