//! `transform`: the two-step inverse transform (seed 003, issue #5). A world
//! ray goes to model space as `O_m = R⁻¹·fl(O_w − T)`, `D_m = R⁻¹·D_w`;
//! `t_min`, `t_max` and the id pass through. No `u = −R⁻¹·T` and no single
//! inverse matrix are formed. The specification is `docs/transform.md`, the
//! golden twin `golden_model::transform`.
//!
//! Datapath, built from the float operators of [`crate::arith::float`]:
//! three subtractors (the reverse translation), then matrix-vector engines,
//! each three row dot products in the chosen style (separate multiply and
//! add, chained FMA, or fused dot3). With `throughput=full` two engines
//! (origin and direction) take one ray per clock; with `throughput=half` one
//! engine takes one vector per clock, and a ray is two transactions (`is_origin`
//! selects whether the vector is translated first). `stages` pipeline
//! registers are spread over the operator chain ([`spread`]); the latency is
//! `stages`.
//!
//! `R⁻¹` is an input (`inverse=pre`, computed by the scene builder) or is
//! computed from `R` (`inverse=hw`): adjugate (2×2 determinants in the dot
//! style), determinant (a dot product), one reciprocal
//! ([`crate::arith::recip`]), nine multiplications; a `rot_hint` input
//! selects `Rᵀ` instead. A non-finite input entry, a zero or non-finite
//! determinant, a non-finite computed `R⁻¹` or a value of the inversion at
//! ±max finite (a directed mode's overflow) raises `singular` and every
//! vector output is the canonical NaN: the first component of each vector
//! entering an engine is replaced by NaN, and every row's dot product reads it.

use super::ports::{self, Record, Visit, Walk};
use super::Description;
use crate::arith::float::add::add_module;
use crate::arith::float::classify::{is_max_finite, is_special, is_zero};
use crate::arith::float::convert::convert_module;
use crate::arith::float::dot3::dot3_module;
use crate::arith::float::fma::fma_module;
use crate::arith::float::mul::mul_module;
use crate::arith::float::{negate, spread, Format, Rounding};
use crate::arith::ports::{rounded, DotTerms, Operand, Pair, Source, Triple};
use crate::arith::recip::recip_module;
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::ParamError;

/// The `transform` unit.
pub struct Transform;

crate::choice! {
    /// Where `R⁻¹` comes from.
    pub enum Inverse {
        /// an input, from the scene builder
        Pre = "pre",
        /// computed in hardware from `R`
        Hw = "hw",
    }
}

crate::choice! {
    /// Rays per clock.
    pub enum Throughput {
        /// two engines, one ray per clock
        Full = "full",
        /// one engine, one vector per clock
        Half = "half",
    }
}

crate::params! {
    /// The transform unit's parameters.
    pub struct TransformParams {
        /// exponent bits E of the float format
        exp_bits: u32 [2..=11] = 8,
        /// fraction bits F of the float format (1 + E + F <= 64)
        frac_bits: u32 [1..=52] = 23,
        /// rounding mode of every operation
        round: Rounding = Rounding::Rne,
        /// dot-product style: separate mul/add, chained fma, fused dot3, or wide (O - T and a
        /// fused dot product in e(E+1)m(2F+2), then rounded to the format: within one ulp of
        /// the correctly rounded result where O - T is exact; needs E <= 10 and E + 2F <= 60)
        dot: Dot = Dot::Fma,
        /// R^-1 source: pre (input, from the scene builder) or hw (adjugate, determinant,
        /// reciprocal, scaling)
        inverse: Inverse = Inverse::Pre,
        /// full: two engines, one ray per clock; half: one engine, one vector per clock
        throughput: Throughput = Throughput::Full,
        /// width of the ray id passed through
        id_bits: u32 [1..=64] = 32,
        /// pipeline stages (latency), spread over the subtract and dot-product operators
        stages: u32 [0..=48] = 8,
    }
}

crate::choice! {
    /// The dot-product style of the engines.
    pub enum Dot {
        /// `add(add(mul, mul), mul)`
        Separate = "separate",
        /// `fma(a2, b2, fma(a1, b1, mul(a0, b0)))`
        Fma = "fma",
        /// fused three-term dot product
        Dot3 = "dot3",
        /// every matrix-vector product in the wide format `(E + 1, 2F + 2)`:
        /// operands widened exactly, `O − T` subtracted there, a fused dot
        /// product rounded there, then rounded to the format
        /// (`golden_model::transform::DotStyle::Wide`); the inversion as `Dot3`
        Wide = "wide",
    }
}

impl Dot {
    /// Operators on the longest path of one dot product (the wide one: the
    /// fused product, then the rounding to the format).
    fn depth(self) -> u32 {
        match self {
            Dot::Separate | Dot::Fma => 3,
            Dot::Dot3 => 1,
            Dot::Wide => 2,
        }
    }
    /// The style of the inversion's determinants and dot product.
    fn inversion(self) -> Dot {
        match self {
            Dot::Wide => Dot::Dot3,
            other => other,
        }
    }
    /// Operators on the longest path of one 2×2 determinant.
    fn det2_depth(self) -> u32 {
        match self.inversion() {
            Dot::Separate | Dot::Fma => 2,
            Dot::Dot3 | Dot::Wide => 1,
        }
    }
}

/// The format `dot=wide` computes in: `(E + 1, 2F + 2)`.
pub fn wide_format(fmt: Format) -> Result<Format, String> {
    Format::new(fmt.exp_bits + 1, 2 * fmt.frac_bits + 2).map_err(|e| {
        format!(
            "dot=wide computes in e{}m{}: {e}",
            fmt.exp_bits + 1,
            2 * fmt.frac_bits + 2
        )
    })
}

/// Resolved configuration of the unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// float format
    pub fmt: Format,
    /// rounding mode
    pub mode: Rounding,
    /// dot style
    pub dot: Dot,
    /// `R⁻¹` computed in hardware from `R` (else an input)
    pub hw: bool,
    /// one ray per clock (two engines) or one vector per clock (one engine)
    pub full: bool,
    /// id width
    pub id_bits: u32,
    /// latency
    pub stages: u32,
}

/// The data inputs: the world origin and direction `ow_* dw_*` (full
/// throughput) or one vector `v_*` and `is_origin` (half); `tmin_w tmax_w
/// id_w`; the matrix `rinv_RC` (pre-inverted) or `r_RC` (`inverse=hw`, R, C
/// in 0..3, row-major); the translation `t_*`; `rot_hint` with `inverse=hw`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TransformIn<T> {
    /// the origin (full throughput) or the one vector (half)
    pub origin_or_vector: [T; 3],
    /// the direction (full throughput)
    pub direction: Option<[T; 3]>,
    /// the one vector is the origin, not the direction (half throughput)
    pub is_origin: Option<T>,
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
    /// the ray's id
    pub id: T,
    /// the matrix, row-major: its inverse, or itself with `inverse=hw`
    pub linear: [T; 9],
    /// the translation
    pub translation: [T; 3],
    /// the matrix is a rotation (`inverse=hw`)
    pub rotation_hint: Option<T>,
}

impl<T: Copy> Record<T> for TransformIn<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        let (origin_or_vector, direction, is_origin) = if cfg.full {
            let o = w.xyz("ow", ty, |r| r.origin_or_vector);
            let d = w.xyz("dw", ty, |r| r.direction.expect("full throughput"));
            (o, Some(d), None)
        } else {
            let v = w.xyz("v", ty, |r| r.origin_or_vector);
            let is_origin = w.one("is_origin", Ty::Bool, |r| {
                r.is_origin.expect("half throughput")
            });
            (v, None, Some(is_origin))
        };
        let t_min = w.one("tmin_w", ty, |r| r.t_min);
        let t_max = w.one("tmax_w", ty, |r| r.t_max);
        let id = w.one("id_w", Ty::UInt(cfg.id_bits), |r| r.id);
        let matrix = cfg.matrix();
        let linear = std::array::from_fn(|k| {
            let name = format_args!("{matrix}_{}{}", k / 3, k % 3);
            w.one(name, ty, move |r| r.linear[k])
        });
        TransformIn {
            origin_or_vector,
            direction,
            is_origin,
            t_min,
            t_max,
            id,
            linear,
            translation: w.xyz("t", ty, |r| r.translation),
            rotation_hint: cfg.hw.then(|| {
                w.one("rot_hint", Ty::Bool, |r| {
                    r.rotation_hint.expect("inverse=hw")
                })
            }),
        }
    }
}

/// The data outputs: the model-space origin and direction `om_* dm_*` (full
/// throughput) or the one vector `vm_*` (half); `tmin_m tmax_m id_m
/// singular`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TransformOut<T> {
    /// the origin (full throughput) or the one vector (half)
    pub origin_or_vector: [T; 3],
    /// the direction (full throughput)
    pub direction: Option<[T; 3]>,
    /// the segment's start
    pub t_min: T,
    /// the segment's end
    pub t_max: T,
    /// the ray's id
    pub id: T,
    /// the instance cannot be inverted (its vectors are NaN)
    pub singular: T,
}

impl<T: Copy> Record<T> for TransformOut<T> {
    type Config = Config;
    fn walk<V: Visit<T>>(cfg: &Config, w: &mut Walk<'_, T, Self, V>) -> Self {
        let ty = Ty::UInt(cfg.fmt.width());
        let (origin_or_vector, direction) = if cfg.full {
            let o = w.xyz("om", ty, |r| r.origin_or_vector);
            let d = w.xyz("dm", ty, |r| r.direction.expect("full throughput"));
            (o, Some(d))
        } else {
            (w.xyz("vm", ty, |r| r.origin_or_vector), None)
        };
        TransformOut {
            origin_or_vector,
            direction,
            t_min: w.one("tmin_m", ty, |r| r.t_min),
            t_max: w.one("tmax_m", ty, |r| r.t_max),
            id: w.one("id_m", Ty::UInt(cfg.id_bits), |r| r.id),
            singular: w.one("singular", Ty::Bool, |r| r.singular),
        }
    }
}

impl Config {
    /// The matrix inputs' name: `r` (`inverse=hw`) or `rinv` (pre-inverted).
    fn matrix(&self) -> &'static str {
        if self.hw {
            "r"
        } else {
            "rinv"
        }
    }

    /// Module name, carrying every parameter.
    pub fn name(&self) -> String {
        let dot = match self.dot {
            Dot::Separate => "sep",
            Dot::Fma => "fma",
            Dot::Dot3 => "dot3",
            Dot::Wide => "wide",
        };
        format!(
            "xform_{}_{}_{dot}_{}_{}_id{}_s{}",
            self.fmt.tag(),
            self.mode,
            if self.hw { "hw" } else { "pre" },
            if self.full { "full" } else { "half" },
            self.id_bits,
            self.stages
        )
    }

    /// Operators along the longest path: the inversion (adjugate,
    /// determinant, reciprocal, scaling) if any, then the engine's dot; the
    /// subtraction runs beside the first of them.
    fn chain(&self) -> u32 {
        let inversion = if self.hw {
            self.dot.det2_depth() + self.dot.inversion().depth() + 2
        } else {
            1 // the subtraction alone
        };
        inversion + self.dot.depth()
    }
}

mod arithmetic;

use arithmetic::{close, dots, invert};

/// Builds the unit for `cfg`.
pub fn build(cfg: &Config) -> Module {
    let fmt = cfg.fmt;
    let mut m = ModuleBuilder::with_handshake(cfg.name());
    let lin = if cfg.hw {
        "Rinv computed from r (adjugate, det, 1/det; rot_hint: transpose)"
    } else {
        "Rinv given"
    };
    m.describe(if cfg.full {
        format!(
            "Two-step inverse transform, one ray per clock: om = Rinv * (ow - t), dm = Rinv * dw; \
             {lin}; tmin, tmax, id pass through; singular: non-finite or singular transform (outputs NaN)."
        )
    } else {
        format!(
            "Two-step inverse transform, one vector per clock (a ray is two transactions): \
             vm = Rinv * (v - t) if is_origin, else Rinv * v; {lin}; tmin, tmax, id pass through; \
             singular: non-finite or singular transform (outputs NaN)."
        )
    });
    let axes = ["x", "y", "z"];
    let TransformIn {
        origin_or_vector: vw,
        direction: dw,
        is_origin,
        t_min: tmin,
        t_max: tmax,
        id,
        linear: lin,
        translation: t,
        rotation_hint: hint,
    } = ports::declare_inputs(&mut m, cfg);

    let mut bad_in = m.bool(false);
    for x in lin.iter().chain(t.iter()) {
        let nf = is_special(&mut m, fmt, *x);
        bad_in = m.or(bad_in, nf);
    }
    let plan = spread(cfg.stages, cfg.chain());

    // the engines' format: the format, or the wide one (operands widened exactly)
    let (ef, widen) = match cfg.dot {
        Dot::Wide => {
            let w = wide_format(fmt).expect("checked with the parameters");
            (w, Some(convert_module(fmt, w, cfg.mode, 0)))
        }
        _ => (fmt, None),
    };
    let up = |m: &mut ModuleBuilder, name: String, x: Sig| match &widen {
        Some(c) => rounded(m, &name, c, &Source::new(x)),
        None => x,
    };

    // step 1: reverse translation, beside the first operator of the inversion if any
    let sub = add_module(ef, cfg.mode, true, plan[0]);
    let x = [0, 1, 2].map(|k| {
        let a = up(&mut m, format!("u_widen_v_{}", axes[k]), vw[k]);
        let b = up(&mut m, format!("u_widen_t_{}", axes[k]), t[k]);
        rounded(
            &mut m,
            &format!("u_sub_{}", axes[k]),
            &sub,
            &Pair::new(a, b),
        )
    });
    let (r, singular, dot_plan) = match hint {
        Some(hint) => {
            let n = (cfg.chain() - cfg.dot.depth()) as usize;
            let (r, failed) = invert(&mut m, cfg, &lin, hint, &plan[..n]);
            let singular = m.or(bad_in, failed);
            (r, singular, &plan[n..])
        }
        None => {
            close(&mut m, plan[0]);
            (lin, bad_in, &plan[1..])
        }
    };
    let singular = m.name(singular, "singular_flag");

    // step 2: inverse linear map, NaN forced into the x component when singular
    let nan = m.uint(ef.width(), ef.nan_bits());
    let r: [Sig; 9] =
        std::array::from_fn(|k| up(&mut m, format!("u_widen_r{}{}", k / 3, k % 3), r[k]));
    let row = |i: usize| [r[3 * i], r[3 * i + 1], r[3 * i + 2]];
    let vectors = match (dw, is_origin) {
        (Some(dw), _) => {
            let dw = [0, 1, 2].map(|k| up(&mut m, format!("u_widen_d_{}", axes[k]), dw[k]));
            let x0 = m.mux(singular, nan, x[0]);
            let x = [x0, x[1], x[2]];
            let d0 = m.mux(singular, nan, dw[0]);
            let dw = [d0, dw[1], dw[2]];
            let mut items = Vec::new();
            for (tag, v) in [("o", x), ("d", dw)] {
                for i in 0..3 {
                    items.push((format!("{tag}{i}"), row(i), v));
                }
            }
            dots(&mut m, cfg, &items, dot_plan)
        }
        (None, Some(is_origin)) => {
            let vw = [0, 1, 2].map(|k| up(&mut m, format!("u_widen_d_{}", axes[k]), vw[k]));
            let sel = [0, 1, 2].map(|k| m.mux(is_origin, x[k], vw[k]));
            let s0 = m.mux(singular, nan, sel[0]);
            let sel = [s0, sel[1], sel[2]];
            let items: Vec<_> = (0..3).map(|i| (format!("v{i}"), row(i), sel)).collect();
            dots(&mut m, cfg, &items, dot_plan)
        }
        (None, None) => unreachable!("half throughput has is_origin"),
    };
    let outputs = TransformOut {
        origin_or_vector: [vectors[0], vectors[1], vectors[2]],
        direction: cfg.full.then(|| [vectors[3], vectors[4], vectors[5]]),
        t_min: tmin,
        t_max: tmax,
        id,
        singular,
    };
    ports::declare_outputs(&mut m, cfg, &outputs);
    m.finish()
        .expect("transform generator is type-correct for every accepted configuration")
}

impl Description for Transform {
    type Params = TransformParams;
    type Config = Config;
    const NAME: &'static str = "transform";
    const SUMMARY: &'static str = "two-step inverse transform: world ray to model space, Rinv * (O - T) and Rinv * D (seed 003)";
    fn config(&self, p: &TransformParams) -> Result<Config, ParamError> {
        let fmt = super::float_ops::format(p.exp_bits, p.frac_bits, Self::NAME)?;
        if p.dot == Dot::Wide {
            wide_format(fmt).map_err(|e| ParamError::Combination(format!("transform: {e}")))?;
        }
        Ok(Config {
            fmt,
            mode: p.round,
            dot: p.dot,
            hw: p.inverse == Inverse::Hw,
            full: p.throughput == Throughput::Full,
            id_bits: p.id_bits,
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
    use crate::golden_twin::golden_format;

    /// `dot=wide`'s format is the golden model's (written apart from it):
    /// `(E + 1, 2F + 2)`, refused where that exceeds 64 bits. Four fraction
    /// bits fewer changed no result of the evaluator's 2,000 vectors (the
    /// first rounding only matters near a tie of the second), so it is
    /// compared here directly.
    #[test]
    fn the_wide_format_is_the_golden_models() {
        for (e, f) in [
            (8, 23),
            (5, 10),
            (2, 1),
            (4, 3),
            (10, 25),
            (8, 26),
            (11, 52),
        ] {
            let fmt = Format::new(e, f).expect("format");
            let golden = golden_model::transform::wide_format(golden_format(fmt));
            match wide_format(fmt) {
                Ok(w) => {
                    let g = golden.unwrap_or_else(|| panic!("e{e}m{f}: the model refuses"));
                    assert_eq!((w.exp_bits, w.frac_bits), (g.exp_bits(), g.frac_bits()));
                }
                Err(_) => assert!(golden.is_none(), "e{e}m{f}: the model accepts"),
            }
        }
        let w = wide_format(Format::new(8, 23).unwrap()).unwrap();
        assert_eq!((w.exp_bits, w.frac_bits), (9, 48));
    }
}
