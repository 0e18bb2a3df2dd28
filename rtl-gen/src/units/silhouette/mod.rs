//! `silhouette`: the silhouette-edge ray / bundle versus box tester (seed
//! 000, issues #4 and #19). One transaction per clock.
//!
//! Two modes (`mode`):
//! - `bundle` (the default, the seed's contribution): a box, a bundle
//!   (direction bounds `d_lo..d_hi`, an origin `o_lo` or origin bounds
//!   `o_lo..o_hi`) and a segment `[t_min, t_max]` give AllHit and AnyHit in
//!   parallel (three-valued: AllHit / AllMiss / Mixed);
//! - `ray`: one ray (`o`, `d`, one origin) and the one conservative test a
//!   single ray needs, output `hit`. It is the bundle tester's AnyHit with
//!   coinciding bounds, bit for bit, at about half the logic.
//!
//! The specification is `docs/silhouette.md` and the bit-exact twin is
//! `golden_model::silhouette`: this generator performs the same steps with
//! the DSL's float operators.
//!
//! Hierarchy (each block its own Verilog module):
//! - the top classifies the inputs (NaN, invalid, empty segment or box, mixed
//!   direction signs) and combines the verdict;
//! - three `silhouette_axis_*` instances mirror one axis each so that its
//!   directions are `>= 0` and form the numerators (differences `plane −
//!   origin`, the only rounded values): `n_any`, `x_any`, `n_all`, `x_all` in
//!   bundle mode, `n`, `x` in ray mode;
//! - one `silhouette_tests_*` instance unpacks every factor once and
//!   evaluates, per test (AnyHit: best corner, AllHit: worst corner; ray
//!   mode: the one ray), the six silhouette-edge tests, three distance checks
//!   and three direction checks as exact comparisons of products
//!   (`arith::float::product_compare`: significand products and exponent
//!   sums, no rounder, no IEEE packing).
//!
//! Rounding rule per operand (conservative policy, §4.3 of the spec):
//! `n_any = near − ô_hi` rounded toward −∞ and `x_any = far − ô_lo` toward
//! +∞ (AnyHit, and the single-ray hit, can only gain hits); `n_all = near −
//! ô_lo` toward +∞ and `x_all = far − ô_hi` toward −∞ (AllHit can only lose
//! them). Shared-origin bundles: one exact sum per numerator pair, rounded
//! both ways by `add_down_up`; ray mode: one adder per plane, rounded in the
//! one direction the hit needs. Nearest policy: every difference rounded to
//! nearest even (charts only). Products and comparisons are exact.
//!
//! Pipelining: `stages` registers are spread over 11 logical steps: the
//! difference (6 steps: the adder's 3 and its rounder's 3), the factors'
//! normalisation (1), the significand multipliers (2), the comparisons and
//! the reduction. One register goes to the outputs first.

use super::ports::{self, Record, Visit, Walk};
use super::{Description, AXES};
use crate::arith::float::add::{add_module, ADD_RAW_STEPS};
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::classify::{
    all_of, any_of, is_any_inf, is_inf, is_nan, is_negative, is_positive,
};
use crate::arith::float::compare::compare;
use crate::arith::float::mul::MUL_RAW_STEPS;
use crate::arith::float::mul_exact::exact_product_format;
use crate::arith::float::product_compare::{
    factor, product_term, single_term, start_product, term_le, Factor, ProductStart, Term,
};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread_over, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;
use std::sync::Arc;

/// The `silhouette` unit.
pub struct Silhouette;

crate::params! {
    /// The silhouette unit's parameters.
    pub struct SilhouetteParams {
        /// exponent bits E of the input format (E + 2F <= 60)
        exp_bits: u32 [2..=9] = 8,
        /// fraction bits F of the input format
        frac_bits: u32 [1..=25] = 23,
        /// bundle: direction bounds d_lo..d_hi, outputs all_hit/any_hit/mixed_sign; ray: one
        /// ray (o, d), output hit
        mode: Mode = Mode::Bundle,
        /// shared: one origin o_lo; bounded: per-axis origin bounds o_lo..o_hi (bundle mode only)
        origin: Origin = Origin::Shared,
        /// conservative: directed differences (never a false miss); nearest: RNE (charts only)
        rounding: Policy = Policy::Conservative,
        /// pipeline stages (latency in cycles), spread over differences, normalisation,
        /// products, comparisons, reduction
        stages: u32 [0..=32] = 4,
    }
}

crate::choice! {
    /// What one transaction tests.
    pub enum Mode {
        /// a bundle: ports `o_lo_*` (`o_hi_*` if bounded), `d_lo_*`, `d_hi_*`; outputs
        /// `all_hit`, `any_hit`, `mixed_sign`
        Bundle = "bundle",
        /// one ray: ports `o_*`, `d_*`; output `hit` (the conservative test)
        Ray = "ray",
    }
}

crate::choice! {
    /// Origin mode: one shared origin or per-axis origin bounds.
    pub enum Origin {
        /// one origin `o_lo`; there is no `o_hi` port
        Shared = "shared",
        /// per-axis bounds `o_lo <= o <= o_hi`
        Bounded = "bounded",
    }
}

crate::choice! {
    /// Rounding policy of the differences `plane − origin`.
    pub enum Policy {
        /// directed: AnyHit can only gain hits, AllHit only lose them
        Conservative = "conservative",
        /// round to nearest even (no guarantee; for accuracy charts)
        Nearest = "nearest",
    }
}

/// The parameters of one tester.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// input format
    pub fmt: Format,
    /// ray or bundle
    pub mode: Mode,
    /// origin mode (always `Shared` in ray mode)
    pub origin: Origin,
    /// rounding policy
    pub policy: Policy,
    /// pipeline stages (latency)
    pub stages: u32,
}

/// Logical steps of the numerators: the adder's exact part and its rounder.
pub const DIFF_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;
/// Logical steps of the factors' unpacking and normalisation.
pub const NORM_STEPS: u32 = 1;
/// Logical steps of the significand products (the integer multiplier).
pub const PRODUCT_STEPS: u32 = MUL_RAW_STEPS;
/// Logical steps per phase, in the order of [`StagePlan`]'s fields:
/// differences, normalisation, products, comparisons, reduction.
pub const PHASES: [u32; 5] = [DIFF_STEPS, NORM_STEPS, PRODUCT_STEPS, 1, 1];

/// How the `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// registers inside the difference operators (axis blocks)
    pub diff: u32,
    /// registers after the factors are normalised (tests block)
    pub norm: u32,
    /// registers inside the significand multipliers (tests block)
    pub product: u32,
    /// registers after the comparisons (tests block)
    pub compare: u32,
    /// registers after the reduction and verdict (top)
    pub reduce: u32,
}

impl StagePlan {
    /// The plan for `stages` registers ([`spread_over`] the [`PHASES`]).
    pub fn new(stages: u32) -> StagePlan {
        let [diff, norm, product, compare, reduce] = spread_over(stages, PHASES);
        StagePlan {
            diff,
            norm,
            product,
            compare,
            reduce,
        }
    }
}

impl Config {
    /// The parameter tags of module names, e.g. `e8m23_shared_cons_s4`
    /// (bundle) or `e8m23_ray_cons_s4`.
    pub fn tag(&self) -> String {
        let o = match (self.mode, self.origin) {
            (Mode::Ray, _) => "ray",
            (Mode::Bundle, Origin::Shared) => "shared",
            (Mode::Bundle, Origin::Bounded) => "bounded",
        };
        let r = match self.policy {
            Policy::Conservative => "cons",
            Policy::Nearest => "near",
        };
        format!("{}_{o}_{r}_s{}", self.fmt.tag(), self.stages)
    }

    fn ray(&self) -> bool {
        self.mode == Mode::Ray
    }

    fn bounded(&self) -> bool {
        self.origin == Origin::Bounded
    }

    fn describe_params(&self, m: &mut ModuleBuilder, stages: u32) {
        m.param("exp_bits", self.fmt.exp_bits)
            .param("frac_bits", self.fmt.frac_bits)
            .param("mode", self.mode)
            .param("origin", self.origin)
            .param("rounding", self.policy)
            .param("stages", stages);
    }
}

/// The six silhouette edges `(i, j)`: entry plane of axis `i` against the
/// exit plane of axis `j`, in the golden model's order.
pub const EDGES: [(usize, usize); 6] = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];

/// The sign bit of `fmt` as a constant of its width.
fn sign_bit(m: &mut ModuleBuilder, fmt: Format) -> Sig {
    m.uint(fmt.width(), 1u128 << (fmt.width() - 1))
}

/// IEEE quiet `a <= b` (false if either is NaN), its comparator's values
/// named in the scope `name`.
#[track_caller]
fn le(m: &mut ModuleBuilder, fmt: Format, a: Sig, b: Sig, name: &str) -> Sig {
    m.scope(name, |m| compare(m, fmt, a, b).1)
}

mod axis;
mod edge_tests;
mod records;

pub use axis::{axis_module, axis_name};
pub use edge_tests::{tests_module, tests_name};
pub use records::{AxisIn, AxisOut, Bounds, SilhouetteIn, SilhouetteOut, TestsIn, TestsOut};

/// Module name of the top.
pub fn silhouette_name(cfg: &Config) -> String {
    format!("silhouette_{}", cfg.tag())
}

/// Builds the tester.
pub fn build(cfg: &Config) -> Module {
    let f = cfg.fmt;
    let plan = StagePlan::new(cfg.stages);
    let mut m = ModuleBuilder::with_handshake(silhouette_name(cfg));
    m.describe(if cfg.ray() {
        "Silhouette-edge ray versus box tester (docs/silhouette.md), one ray per transaction: \
         hit = 0 only if the ray misses the box within [t_min, t_max] (conservative: never a \
         false miss); nan = a NaN input, invalid = an infinite origin or direction component."
    } else {
        "Silhouette-edge ray/bundle versus box tester (docs/silhouette.md): all_hit = every ray of \
         the bundle hits the box, any_hit = 0 only if every ray misses (a single ray's conservative \
         hit bit); nan = a NaN input, invalid = infinite or unordered origin/direction bounds, \
         mixed_sign = direction bounds straddle 0 on an axis (all_hit = 0, any_hit = nonempty)."
    });
    let bounded = cfg.bounded();
    let inputs: SilhouetteIn<Sig> = ports::declare_inputs(&mut m, cfg);
    let SilhouetteIn {
        p_min,
        p_max,
        o_lo,
        o_hi,
        d_lo,
        d_hi,
        t_min,
        t_max,
    } = inputs;

    // Step 1: classify the inputs (no arithmetic).
    let mut read: Vec<Sig> = Vec::new();
    read.extend(p_min.iter().chain(&p_max).chain(&o_lo).chain(&d_lo));
    if !cfg.ray() {
        read.extend(&d_hi);
    }
    if bounded {
        read.extend(&o_hi);
    }
    read.extend([t_min, t_max]);
    let nans: Vec<Sig> = read.iter().map(|&v| is_nan(&mut m, f, v)).collect();
    let nan = any_of(&mut m, &nans, "nan_in");
    let mut bad = Vec::new();
    for i in 0..3 {
        let mut vals = vec![o_lo[i], d_lo[i]];
        if !cfg.ray() {
            vals.push(d_hi[i]);
        }
        if bounded {
            vals.push(o_hi[i]);
        }
        for v in vals {
            bad.push(is_any_inf(&mut m, f, v));
        }
        if !cfg.ray() {
            // a ray's bounds coincide: d <= d holds for every non-NaN value
            let d_ok = le(&mut m, f, d_lo[i], d_hi[i], &format!("d_{}_order", AXES[i]));
            bad.push(m.not(d_ok));
        }
        if bounded {
            // shared mode: o_lo <= o_lo holds for every non-NaN value
            let o_ok = le(&mut m, f, o_lo[i], o_hi[i], &format!("o_{}_order", AXES[i]));
            bad.push(m.not(o_ok));
        }
    }
    let bad = any_of(&mut m, &bad, "bad_bounds");
    let not_nan = m.not(nan);
    let invalid = m.and(bad, not_nan);
    let invalid = m.name(invalid, "invalid_in");
    let t_ok = le(&mut m, f, t_min, t_max, "t_order");
    let mut empty = vec![m.not(t_ok)];
    empty.push(is_inf(&mut m, f, t_min, false));
    empty.push(is_inf(&mut m, f, t_max, true));
    for i in 0..3 {
        let p_ok = le(
            &mut m,
            f,
            p_min[i],
            p_max[i],
            &format!("p_{}_order", AXES[i]),
        );
        empty.push(m.not(p_ok));
        empty.push(is_inf(&mut m, f, p_min[i], false));
        empty.push(is_inf(&mut m, f, p_max[i], true));
    }
    let empty = any_of(&mut m, &empty, "empty");

    // Steps 2 and 3: per axis, mirror and form the numerators.
    let axis = axis_module(cfg, plan.diff);
    let axes: [AxisOut<Sig>; 3] = [0, 1, 2].map(|i| {
        let name = format!("u_axis_{}", AXES[i]);
        ports::instance(&mut m, &name, &axis, cfg, &inputs.axis(i), cfg)
    });
    for _ in 0..plan.diff {
        m.stage();
    }

    // Step 4: the tests (two corners of a bundle, or the ray's one).
    let tests = tests_module(cfg, &plan);
    let tests_in = TestsIn::from_axes(&axes, t_min, t_max);
    let passes: TestsOut<Sig> = ports::instance(&mut m, "u_tests", &tests, cfg, &tests_in, cfg);
    for _ in 0..plan.norm + plan.product + plan.compare {
        m.stage();
    }

    // Step 5: the verdict.
    let not_invalid = m.not(invalid);
    let valid = m.and(not_nan, not_invalid);
    let not_empty = m.not(empty);
    let ok = m.and(valid, not_empty);
    let outputs = if cfg.ray() {
        SilhouetteOut {
            all_hit: None,
            any_hit: m.and(ok, passes.pass_any),
            nan,
            invalid,
            mixed_sign: None,
        }
    } else {
        let TestsOut { pass_any, pass_all } = passes;
        let bundle_only = "a bundle's axes have their signs";
        let straddles: Vec<Sig> = axes
            .iter()
            .map(|ax| m.and(ax.neg.expect(bundle_only), ax.pos.expect(bundle_only)))
            .collect();
        let mixed = any_of(&mut m, &straddles, "mixed");
        let not_mixed = m.not(mixed);
        let all_hit = m.and(ok, not_mixed);
        let all_hit = m.and(all_hit, pass_all);
        let any_pass = m.or(mixed, pass_any);
        let any_hit = m.and(ok, any_pass);
        let mixed_sign = m.and(valid, mixed);
        SilhouetteOut {
            all_hit: Some(all_hit),
            any_hit,
            nan,
            invalid,
            mixed_sign: Some(mixed_sign),
        }
    };
    for _ in 0..plan.reduce {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &outputs);
    m.finish()
        .expect("silhouette generator is type-correct for every accepted configuration")
}

impl Description for Silhouette {
    type Params = SilhouetteParams;
    type Config = Config;
    const NAME: &'static str = "silhouette";
    const SUMMARY: &'static str = "silhouette-edge box tester: bundles (all_hit, any_hit, three-valued) or single rays (hit); exact product comparisons, conservative differences";
    fn config(&self, p: &SilhouetteParams) -> Result<Config, ParamError> {
        let fmt = Format::new(p.exp_bits, p.frac_bits).map_err(ParamError::Combination)?;
        // the golden model's reference products need (E + 2, 2F + 1)
        exact_product_format(fmt).map_err(ParamError::Combination)?;
        if p.mode == Mode::Ray && p.origin == Origin::Bounded {
            return Err(ParamError::Combination(
                "origin=bounded needs mode=bundle: a ray (mode=ray) has one origin o".into(),
            ));
        }
        Ok(Config {
            fmt,
            mode: p.mode,
            origin: p.origin,
            policy: p.rounding,
            stages: p.stages,
        })
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::ParamSet;

    /// A block's name carries its own stages, not the unit's: two units of
    /// different depths whose axis blocks differ must not share a module name.
    #[test]
    fn the_axis_block_is_named_for_its_own_stages() {
        for stages in [0, 4, 12] {
            let p = SilhouetteParams {
                stages,
                ..SilhouetteParams::defaults()
            };
            let cfg = Silhouette.config(&p).expect("a valid silhouette");
            let unit = build(&cfg);
            let axis = &unit
                .instances
                .iter()
                .find(|i| i.name == "u_axis_x")
                .unwrap()
                .module;
            let diff = StagePlan::new(stages).diff;
            assert_eq!(axis.latency, diff, "stages={stages}");
            assert!(
                axis.name.ends_with(&format!("_s{diff}")),
                "stages={stages}: {}",
                axis.name
            );
        }
    }

    #[test]
    fn stage_plan_covers_every_register_and_registers_outputs_first() {
        for s in 0..=32 {
            let p = StagePlan::new(s);
            assert_eq!(p.diff + p.norm + p.product + p.compare + p.reduce, s);
        }
        assert_eq!(StagePlan::new(1).reduce, 1);
        let p4 = StagePlan::new(4);
        assert!(p4.diff >= 1 && p4.product >= 1 && p4.reduce == 1, "{p4:?}");
    }
}
