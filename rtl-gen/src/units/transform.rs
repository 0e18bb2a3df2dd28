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
//! `R⁻¹` is an input (`inverse=pre`, computed by the scene builder). A
//! non-finite entry of `R⁻¹` or `T` raises `singular` (the scene builder
//! encodes a singular `R` as NaN entries) and every vector output is the
//! canonical NaN: the first component of each vector entering an engine is
//! replaced by NaN, and every row's dot product reads it.

use super::Unit;
use crate::arith::float::add::add_module;
use crate::arith::float::fma::fma_module;
use crate::arith::float::mul::mul_module;
use crate::arith::float::{spread, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};

/// The `transform` unit.
pub struct Transform;

/// Dot-product styles, in parameter order.
pub const DOT_WORDS: &[&str] = &["separate", "fma", "dot3"];
/// Sources of `R⁻¹`, in parameter order.
pub const INVERSE_WORDS: &[&str] = &["pre", "hw"];
/// Throughput choices, in parameter order.
pub const THROUGHPUT_WORDS: &[&str] = &["full", "half"];

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: "exp_bits",
        doc: "exponent bits E of the float format",
        kind: ParamKind::Int { min: 2, max: 11 },
        default: "8",
    },
    ParamSpec {
        name: "frac_bits",
        doc: "fraction bits F of the float format (1 + E + F <= 64)",
        kind: ParamKind::Int { min: 1, max: 52 },
        default: "23",
    },
    ParamSpec {
        name: "round",
        doc: "rounding mode of every operation",
        kind: ParamKind::Choice(Rounding::WORDS),
        default: "rne",
    },
    ParamSpec {
        name: "dot",
        doc: "dot-product style: separate mul/add, chained fma, fused dot3",
        kind: ParamKind::Choice(DOT_WORDS),
        default: "fma",
    },
    ParamSpec {
        name: "inverse",
        doc: "R^-1 source: pre (input, from the scene builder) or hw (computed; not built yet)",
        kind: ParamKind::Choice(INVERSE_WORDS),
        default: "pre",
    },
    ParamSpec {
        name: "throughput",
        doc: "full: two engines, one ray per clock; half: one engine, one vector per clock",
        kind: ParamKind::Choice(THROUGHPUT_WORDS),
        default: "full",
    },
    ParamSpec {
        name: "id_bits",
        doc: "width of the ray id passed through",
        kind: ParamKind::Int { min: 1, max: 64 },
        default: "32",
    },
    ParamSpec {
        name: "stages",
        doc: "pipeline stages (latency), spread over the subtract and dot-product operators",
        kind: ParamKind::Int { min: 0, max: 32 },
        default: "8",
    },
];

/// The dot-product style of the engines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dot {
    /// `add(add(mul, mul), mul)`
    Separate,
    /// `fma(a2, b2, fma(a1, b1, mul(a0, b0)))`
    Fma,
    /// fused three-term dot product
    Dot3,
}

impl Dot {
    fn parse(w: &str) -> Dot {
        match w {
            "separate" => Dot::Separate,
            "fma" => Dot::Fma,
            _ => Dot::Dot3,
        }
    }
    /// Operators on the longest path of one dot product.
    fn depth(self) -> u32 {
        match self {
            Dot::Separate | Dot::Fma => 3,
            Dot::Dot3 => 1,
        }
    }
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
    /// one ray per clock (two engines) or one vector per clock (one engine)
    pub full: bool,
    /// id width
    pub id_bits: u32,
    /// latency
    pub stages: u32,
}

impl Config {
    /// The configuration of resolved parameters, or why it cannot be built.
    pub fn from_params(p: &Params) -> Result<Config, ParamError> {
        let fmt = Format::new(p.u32("exp_bits"), p.u32("frac_bits"))
            .map_err(|e| ParamError::Combination(format!("transform: {e}")))?;
        if p.word("inverse") == "hw" {
            return Err(ParamError::Combination(
                "transform: inverse=hw (R^-1 computed in hardware) is specified and modelled \
                 (docs/transform.md) but not built yet; use inverse=pre"
                    .into(),
            ));
        }
        Ok(Config {
            fmt,
            mode: Rounding::parse(p.word("round")).expect("declared choice"),
            dot: Dot::parse(p.word("dot")),
            full: p.word("throughput") == "full",
            id_bits: p.u32("id_bits"),
            stages: p.u32("stages"),
        })
    }

    /// Module name, carrying every parameter.
    pub fn name(&self) -> String {
        let dot = match self.dot {
            Dot::Separate => "sep",
            Dot::Fma => "fma",
            Dot::Dot3 => "dot3",
        };
        format!(
            "xform_{}_{}_{dot}_pre_{}_id{}_s{}",
            self.fmt.tag(),
            self.mode,
            if self.full { "full" } else { "half" },
            self.id_bits,
            self.stages
        )
    }
}

/// Per-operator stage counts along the chain: subtract, then the dot's operators.
fn plan(cfg: &Config) -> Vec<u32> {
    spread(cfg.stages, 1 + cfg.dot.depth())
}

/// Instantiates a two-input operator module, returns its `z`.
fn op2(m: &mut ModuleBuilder, module: &std::sync::Arc<Module>, inst: &str, a: Sig, b: Sig) -> Sig {
    m.instance(inst, module, &[("a", a), ("b", b)])
        .get("z")
        .expect("float operator has output z")
}

fn close(m: &mut ModuleBuilder, n: u32) {
    for _ in 0..n {
        m.stage();
    }
}

/// Matrix-vector engines `r · v` for each `(tag, v)`, built side by side from
/// the current stage; closes the dot's stages (`plan` without the subtract's
/// entry), so every result belongs to the stage after the last operator.
fn engines(
    m: &mut ModuleBuilder,
    cfg: &Config,
    r: &[Sig; 9],
    vs: &[(&str, [Sig; 3])],
    plan: &[u32],
) -> Vec<[Sig; 3]> {
    let (fmt, mode) = (cfg.fmt, cfg.mode);
    let fma3 = |m: &mut ModuleBuilder, module, name: String, a, b, c| {
        m.instance(&name, module, &[("a", a), ("b", b), ("c", c)])
            .get("z")
            .expect("fma has output z")
    };
    match cfg.dot {
        Dot::Separate => {
            let mul = mul_module(fmt, mode, plan[0]);
            let p: Vec<[[Sig; 3]; 3]> = vs
                .iter()
                .map(|(tag, v)| {
                    [0, 1, 2].map(|i| {
                        [0, 1, 2].map(|j| {
                            op2(m, &mul, &format!("u_{tag}_mul{i}{j}"), r[3 * i + j], v[j])
                        })
                    })
                })
                .collect();
            close(m, plan[0]);
            let add1 = add_module(fmt, mode, false, plan[1]);
            let s: Vec<[Sig; 3]> = vs
                .iter()
                .zip(&p)
                .map(|((tag, _), p)| {
                    [0, 1, 2].map(|i| op2(m, &add1, &format!("u_{tag}_add{i}a"), p[i][0], p[i][1]))
                })
                .collect();
            close(m, plan[1]);
            let add2 = add_module(fmt, mode, false, plan[2]);
            let out = vs
                .iter()
                .zip(p.iter().zip(&s))
                .map(|((tag, _), (p, s))| {
                    [0, 1, 2].map(|i| op2(m, &add2, &format!("u_{tag}_add{i}b"), s[i], p[i][2]))
                })
                .collect();
            close(m, plan[2]);
            out
        }
        Dot::Fma => {
            let mul = mul_module(fmt, mode, plan[0]);
            let p: Vec<[Sig; 3]> = vs
                .iter()
                .map(|(tag, v)| {
                    [0, 1, 2].map(|i| op2(m, &mul, &format!("u_{tag}_mul{i}"), r[3 * i], v[0]))
                })
                .collect();
            close(m, plan[0]);
            let fma1 = fma_module(fmt, mode, plan[1]);
            let s: Vec<[Sig; 3]> = vs
                .iter()
                .zip(&p)
                .map(|((tag, v), p)| {
                    [0, 1, 2].map(|i| {
                        fma3(
                            m,
                            &fma1,
                            format!("u_{tag}_fma{i}a"),
                            r[3 * i + 1],
                            v[1],
                            p[i],
                        )
                    })
                })
                .collect();
            close(m, plan[1]);
            let fma2 = fma_module(fmt, mode, plan[2]);
            let out = vs
                .iter()
                .zip(&s)
                .map(|((tag, v), s)| {
                    [0, 1, 2].map(|i| {
                        fma3(
                            m,
                            &fma2,
                            format!("u_{tag}_fma{i}b"),
                            r[3 * i + 2],
                            v[2],
                            s[i],
                        )
                    })
                })
                .collect();
            close(m, plan[2]);
            out
        }
        Dot::Dot3 => {
            let d = crate::arith::float::dot3::dot3_module(fmt, mode, plan[0]);
            let out = vs
                .iter()
                .map(|(tag, v)| {
                    [0, 1, 2].map(|i| {
                        m.instance(
                            &format!("u_{tag}_dot{i}"),
                            &d,
                            &[
                                ("a0", r[3 * i]),
                                ("a1", r[3 * i + 1]),
                                ("a2", r[3 * i + 2]),
                                ("b0", v[0]),
                                ("b1", v[1]),
                                ("b2", v[2]),
                            ],
                        )
                        .get("z")
                        .expect("dot3 has output z")
                    })
                })
                .collect();
            close(m, plan[0]);
            out
        }
    }
}

/// True if the encoding `x` is an infinity or a NaN (exponent all ones).
fn not_finite(m: &mut ModuleBuilder, fmt: Format, x: Sig) -> Sig {
    let e = m.slice(x, fmt.exp_bits + fmt.frac_bits - 1, fmt.frac_bits);
    m.all_ones(e)
}

/// Builds the unit for `cfg`.
pub fn build(cfg: &Config) -> Module {
    let fmt = cfg.fmt;
    let w = fmt.width();
    let ty = Ty::UInt(w);
    let mut m = ModuleBuilder::with_handshake(cfg.name());
    m.describe(if cfg.full {
        "Two-step inverse transform, one ray per clock: om = Rinv * (ow - t), dm = Rinv * dw; \
         tmin, tmax, id pass through; singular = a non-finite entry of Rinv or t (outputs NaN)."
    } else {
        "Two-step inverse transform, one vector per clock (a ray is two transactions): \
         vm = Rinv * (v - t) if is_origin, else Rinv * v; tmin, tmax, id pass through; \
         singular = a non-finite entry of Rinv or t (outputs NaN)."
    });
    m.param("exp_bits", fmt.exp_bits)
        .param("frac_bits", fmt.frac_bits)
        .param("round", cfg.mode)
        .param("dot", DOT_WORDS[cfg.dot as usize])
        .param("inverse", "pre")
        .param("throughput", if cfg.full { "full" } else { "half" })
        .param("id_bits", cfg.id_bits)
        .param("stages", cfg.stages);
    let axes = ["x", "y", "z"];
    let (vw, dw, is_origin) = if cfg.full {
        let o = axes.map(|a| m.input(&format!("ow_{a}"), ty));
        let d = axes.map(|a| m.input(&format!("dw_{a}"), ty));
        (o, Some(d), None)
    } else {
        let v = axes.map(|a| m.input(&format!("v_{a}"), ty));
        (v, None, Some(m.input("is_origin", Ty::Bool)))
    };
    let tmin = m.input("tmin_w", ty);
    let tmax = m.input("tmax_w", ty);
    let id = m.input("id_w", Ty::UInt(cfg.id_bits));
    let r: [Sig; 9] = std::array::from_fn(|k| m.input(&format!("rinv_{}{}", k / 3, k % 3), ty));
    let t = axes.map(|a| m.input(&format!("t_{a}"), ty));

    // the flag, and NaN forced into the first component of every engine input
    let mut bad = m.bool(false);
    for x in r.iter().chain(t.iter()) {
        let nf = not_finite(&mut m, fmt, *x);
        bad = m.or(bad, nf);
    }
    let singular = m.name(bad, "singular_flag");
    let nan = m.uint(w, fmt.nan_bits());
    let v0 = m.mux(singular, nan, vw[0]);
    let vw = [v0, vw[1], vw[2]];

    // step 1: reverse translation
    let plan = plan(cfg);
    let sub = add_module(fmt, cfg.mode, true, plan[0]);
    let x = [0, 1, 2].map(|k| op2(&mut m, &sub, &format!("u_sub_{}", axes[k]), vw[k], t[k]));
    close(&mut m, plan[0]);

    // step 2: inverse linear map
    let dot_plan = &plan[1..];
    match (dw, is_origin) {
        (Some(dw), _) => {
            let d0 = m.mux(singular, nan, dw[0]);
            let dw = [d0, dw[1], dw[2]];
            let out = engines(&mut m, cfg, &r, &[("o", x), ("d", dw)], dot_plan);
            let (om, dm) = (out[0], out[1]);
            for k in 0..3 {
                m.output(&format!("om_{}", axes[k]), om[k]);
            }
            for k in 0..3 {
                m.output(&format!("dm_{}", axes[k]), dm[k]);
            }
        }
        (None, Some(is_origin)) => {
            let sel = [0, 1, 2].map(|k| m.mux(is_origin, x[k], vw[k]));
            let vm = engines(&mut m, cfg, &r, &[("v", sel)], dot_plan)[0];
            for k in 0..3 {
                m.output(&format!("vm_{}", axes[k]), vm[k]);
            }
        }
        (None, None) => unreachable!("half throughput has is_origin"),
    }
    m.output("tmin_m", tmin);
    m.output("tmax_m", tmax);
    m.output("id_m", id);
    m.output("singular", singular);
    m.finish()
        .expect("transform generator is type-correct for every accepted configuration")
}

impl Unit for Transform {
    fn name(&self) -> &'static str {
        "transform"
    }
    fn summary(&self) -> &'static str {
        "two-step inverse transform: world ray to model space, Rinv * (O - T) and Rinv * D (seed 003)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        Ok(build(&Config::from_params(p)?))
    }
}
