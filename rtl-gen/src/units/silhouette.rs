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

use super::Description;
use crate::arith::float::add::{add_module, ADD_RAW_STEPS};
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::classify::{all_of, any_of, is_any_inf, is_inf, is_nan, is_zero};
use crate::arith::float::compare::compare;
use crate::arith::float::mul::MUL_RAW_STEPS;
use crate::arith::float::mul_exact::exact_product_format;
use crate::arith::float::product_compare::{
    factor, product_term, single_term, start_product, term_le, Factor, ProductStart, Term,
};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread_over, Format, Rounding};
use crate::builder::{InstanceOutputs, ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

/// The `silhouette` unit.
pub struct Silhouette;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: "exp_bits",
        doc: "exponent bits E of the input format (E + 2F <= 60)",
        kind: ParamKind::Int { min: 2, max: 9 },
        default: "8",
    },
    ParamSpec {
        name: "frac_bits",
        doc: "fraction bits F of the input format",
        kind: ParamKind::Int { min: 1, max: 25 },
        default: "23",
    },
    ParamSpec {
        name: "mode",
        doc: "bundle: direction bounds d_lo..d_hi, outputs all_hit/any_hit/mixed_sign; ray: one ray (o, d), output hit",
        kind: ParamKind::Choice(&["bundle", "ray"]),
        default: "bundle",
    },
    ParamSpec {
        name: "origin",
        doc: "shared: one origin o_lo; bounded: per-axis origin bounds o_lo..o_hi (bundle mode only)",
        kind: ParamKind::Choice(&["shared", "bounded"]),
        default: "shared",
    },
    ParamSpec {
        name: "rounding",
        doc: "conservative: directed differences (never a false miss); nearest: RNE (charts only)",
        kind: ParamKind::Choice(&["conservative", "nearest"]),
        default: "conservative",
    },
    ParamSpec {
        name: "stages",
        doc: "pipeline stages (latency in cycles), spread over differences, normalisation, products, comparisons, reduction",
        kind: ParamKind::Int { min: 0, max: 32 },
        default: "4",
    },
];

/// What one transaction tests.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// one ray: ports `o_*`, `d_*`; output `hit` (the conservative test)
    Ray,
    /// a bundle: ports `o_lo_*` [`o_hi_*`], `d_lo_*`, `d_hi_*`; outputs
    /// `all_hit`, `any_hit`, `mixed_sign`
    Bundle,
}

/// Origin mode: one shared origin or per-axis origin bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Origin {
    /// one origin `o_lo`; there is no `o_hi` port
    Shared,
    /// per-axis bounds `o_lo <= o <= o_hi`
    Bounded,
}

/// Rounding policy of the differences `plane − origin`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Policy {
    /// directed: AnyHit can only gain hits, AllHit only lose them
    Conservative,
    /// round to nearest even (no guarantee; for accuracy charts)
    Nearest,
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
    /// The data inputs in port order, by name: the module's ports, its
    /// `ports.json` and the testbench's packing all come from this list.
    /// Ray: `p_min_* p_max_* o_* d_* t_min t_max`; bundle: `p_min_* p_max_*
    /// o_lo_* [o_hi_*] d_lo_* d_hi_* t_min t_max` (`*` = x, y, z).
    pub fn input_names(&self) -> Vec<String> {
        let groups: &[&str] = match (self.ray(), self.bounded()) {
            (true, _) => &["p_min", "p_max", "o", "d"],
            (false, false) => &["p_min", "p_max", "o_lo", "d_lo", "d_hi"],
            (false, true) => &["p_min", "p_max", "o_lo", "o_hi", "d_lo", "d_hi"],
        };
        let mut names: Vec<String> = groups
            .iter()
            .flat_map(|g| AXES.iter().map(move |a| format!("{g}_{a}")))
            .collect();
        names.extend(["t_min".to_string(), "t_max".to_string()]);
        names
    }

    /// The data outputs in port order, by name: ray `hit nan invalid`;
    /// bundle `all_hit any_hit nan invalid mixed_sign`.
    pub fn output_names(&self) -> &'static [&'static str] {
        if self.ray() {
            &["hit", "nan", "invalid"]
        } else {
            &["all_hit", "any_hit", "nan", "invalid", "mixed_sign"]
        }
    }

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
            .param("mode", format!("{:?}", self.mode).to_lowercase())
            .param("origin", format!("{:?}", self.origin).to_lowercase())
            .param("rounding", format!("{:?}", self.policy).to_lowercase())
            .param("stages", stages);
    }
}

const AXES: [&str; 3] = ["x", "y", "z"];

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

/// Module name of the axis block.
pub fn axis_name(cfg: &Config, stages: u32) -> String {
    let c = Config { stages, ..*cfg };
    format!("silhouette_axis_{}", c.tag())
}

/// The axis block: mirrors one axis so that its directions are `>= 0`
/// (sign flips only) and forms the numerators; `stages` registers inside
/// the difference operators.
///
/// Bundle mode: inputs `p_min p_max o_lo [o_hi] d_lo d_hi`; outputs (all
/// `stages` cycles later) `neg` (`d_lo < 0`: the axis is mirrored), `pos`
/// (`d_hi > 0`), `a`/`b` (smallest / largest `|d|`), `n_any x_any n_all
/// x_all`. Ray mode: inputs `p_min p_max o d`; outputs `a` (`|d|`), `n`
/// (entry numerator, rounded down) and `x` (exit numerator, rounded up).
pub fn axis_module(cfg: &Config, stages: u32) -> Arc<Module> {
    let f = cfg.fmt;
    let mut m = ModuleBuilder::new(axis_name(cfg, stages));
    m.describe(if cfg.ray() {
        "One axis of the silhouette ray tester: mirror so that the direction is >= 0, then the \
         entry numerator n = near - o (rounded down) and the exit numerator x = far - o (rounded up)."
    } else {
        "One axis of the silhouette tester: mirror so that directions are >= 0, then the entry \
         numerators n = near - o and exit numerators x = far - o for AnyHit (n down, x up) and \
         AllHit (n up, x down)."
    });
    cfg.describe_params(&mut m, stages);
    let ty = Ty::UInt(f.width());
    let p_min = m.input("p_min", ty);
    let p_max = m.input("p_max", ty);
    let (o_lo, o_hi, d_lo, d_hi) = if cfg.ray() {
        let o = m.input("o", ty);
        let d = m.input("d", ty);
        (o, o, d, d)
    } else {
        let o_lo = m.input("o_lo", ty);
        let o_hi = if cfg.bounded() {
            m.input("o_hi", ty)
        } else {
            o_lo
        };
        (o_lo, o_hi, m.input("d_lo", ty), m.input("d_hi", ty))
    };

    // Classify the direction interval (by value: -0 is not negative).
    // d_lo < +0: negative sign bit, nonzero, not NaN; +0 < d_hi likewise
    let strictly = |m: &mut ModuleBuilder, v: Sig, negative: bool| {
        let s = m.msb(v);
        let s = if negative { s } else { m.not(s) };
        let z = is_zero(m, f, v);
        let nz = m.not(z);
        let n = is_nan(m, f, v);
        let nn = m.not(n);
        let r = m.and(s, nz);
        m.and(r, nn)
    };
    let neg = strictly(&mut m, d_lo, true);
    let neg = m.name(neg, "neg");

    // Mirror: sign flips and swaps only, exact.
    let sb = sign_bit(&mut m, f);
    let abs_mask = m.uint(f.width(), (1u128 << (f.width() - 1)) - 1);
    let p_max_n = m.xor(p_max, sb);
    let p_min_n = m.xor(p_min, sb);
    let near = m.mux(neg, p_max_n, p_min);
    let near = m.name(near, "plane_near");
    let far = m.mux(neg, p_min_n, p_max);
    let far = m.name(far, "plane_far");
    let o_lo_n = m.xor(o_lo, sb);
    let o_hi_n = m.xor(o_hi, sb);
    // m = -ô: the negated origin bounds in mirrored coordinates
    let m_lo = m.mux(neg, o_hi, o_lo_n);
    let m_lo = m.name(m_lo, "m_lo");
    let m_hi = m.mux(neg, o_lo, o_hi_n);
    let m_hi = m.name(m_hi, "m_hi");
    let d_lo_abs = m.and(d_lo, abs_mask);
    let d_hi_abs = m.and(d_hi, abs_mask);
    let a = m.mux(neg, d_hi_abs, d_lo_abs);

    // The numerators (the only rounded values).
    let z = |io: InstanceOutputs| io.get("z").expect("adder has output z");
    let outputs = if cfg.ray() {
        let (entry, exit) = match cfg.policy {
            Policy::Conservative => (Rounding::Rdn, Rounding::Rup),
            Policy::Nearest => (Rounding::Rne, Rounding::Rne),
        };
        let entry = add_module(f, entry, false, stages);
        let exit = add_module(f, exit, false, stages);
        let n = z(m.instance("u_entry", &entry, &[("a", near), ("b", m_lo)]));
        let x = z(m.instance("u_exit", &exit, &[("a", far), ("b", m_lo)]));
        vec![("a", a), ("n", n), ("x", x)]
    } else {
        let pos = strictly(&mut m, d_hi, false);
        let pos = m.name(pos, "pos");
        let b = m.mux(neg, d_lo_abs, d_hi_abs);
        let (n_any, x_any, n_all, x_all) = match (cfg.origin, cfg.policy) {
            (Origin::Shared, Policy::Conservative) => {
                // one exact sum per plane, rounded both ways
                let adu = add_down_up_module(f, stages);
                let n = m.instance("u_entry", &adu, &[("a", near), ("b", m_lo)]);
                let x = m.instance("u_exit", &adu, &[("a", far), ("b", m_lo)]);
                let n_any = n.get("down").expect("down");
                let n_all = n.get("up").expect("up");
                let x_any = x.get("up").expect("up");
                let x_all = x.get("down").expect("down");
                (n_any, x_any, n_all, x_all)
            }
            (Origin::Bounded, Policy::Conservative) => {
                let dn = add_module(f, Rounding::Rdn, false, stages);
                let up = add_module(f, Rounding::Rup, false, stages);
                let n_any = z(m.instance("u_n_any", &dn, &[("a", near), ("b", m_hi)]));
                let x_any = z(m.instance("u_x_any", &up, &[("a", far), ("b", m_lo)]));
                let n_all = z(m.instance("u_n_all", &up, &[("a", near), ("b", m_lo)]));
                let x_all = z(m.instance("u_x_all", &dn, &[("a", far), ("b", m_hi)]));
                (n_any, x_any, n_all, x_all)
            }
            (Origin::Shared, Policy::Nearest) => {
                let rne = add_module(f, Rounding::Rne, false, stages);
                let n = z(m.instance("u_entry", &rne, &[("a", near), ("b", m_lo)]));
                let x = z(m.instance("u_exit", &rne, &[("a", far), ("b", m_lo)]));
                (n, x, n, x)
            }
            (Origin::Bounded, Policy::Nearest) => {
                let rne = add_module(f, Rounding::Rne, false, stages);
                let n_any = z(m.instance("u_n_any", &rne, &[("a", near), ("b", m_hi)]));
                let x_any = z(m.instance("u_x_any", &rne, &[("a", far), ("b", m_lo)]));
                let n_all = z(m.instance("u_n_all", &rne, &[("a", near), ("b", m_lo)]));
                let x_all = z(m.instance("u_x_all", &rne, &[("a", far), ("b", m_hi)]));
                (n_any, x_any, n_all, x_all)
            }
        };
        vec![
            ("neg", neg),
            ("pos", pos),
            ("a", a),
            ("b", b),
            ("n_any", n_any),
            ("x_any", x_any),
            ("n_all", n_all),
            ("x_all", x_all),
        ]
    };
    for _ in 0..stages {
        m.stage();
    }
    for (name, value) in outputs {
        m.output(name, value);
    }
    Arc::new(
        m.finish()
            .expect("silhouette axis generator is type-correct for every accepted format"),
    )
}

/// Module name of the tests block.
pub fn tests_name(cfg: &Config, plan: &StagePlan) -> String {
    let mode = match cfg.mode {
        Mode::Ray => "ray",
        Mode::Bundle => "bundle",
    };
    format!(
        "silhouette_tests_{mode}_{}_n{}_p{}_c{}",
        cfg.fmt.tag(),
        plan.norm,
        plan.product,
        plan.compare
    )
}

/// The factor whose fields are those of `b` where `sel`, else of `a`.
#[track_caller]
fn pick(m: &mut ModuleBuilder, sel: Sig, b: &Factor, a: &Factor) -> Factor {
    let mut field = |name: &str, b: Sig, a: Sig| {
        let v = m.mux(sel, b, a);
        m.name(v, name)
    };
    Factor {
        sign: field("d_sign", b.sign, a.sign),
        zero: field("d_zero", b.zero, a.zero),
        inf: field("d_inf", b.inf, a.inf),
        exp: field("d_exp", b.exp, a.exp),
        sig: field("d_sig", b.sig, a.sig),
    }
}

/// One side of a comparison before the multipliers' registers.
enum Side {
    /// a product `v · |d_k|`
    Product(ProductStart),
    /// a factor on its own (the numerator of a distance or direction check)
    Single(Factor),
}

/// The tests block: every factor unpacked and normalised once, then per
/// test the twelve comparisons `N_i·|d_j| <= X_j·|d_i|` (six silhouette
/// edges), `N_i <= t_max·|d_i|` (distance) and `t_min·|d_i| <= X_i`
/// (direction) as exact comparisons of products.
///
/// Bundle mode: AnyHit (each side at its best corner of the bundle) and
/// AllHit (worst corner); for each product `v·|d_k|` the bound of `|d_k|`
/// (`a_k` smallest, `b_k` largest) is picked by the sign bit of `v`.
/// Inputs `n_any_* x_any_* n_all_* x_all_* a_* b_* t_min t_max`, outputs
/// `pass_any`, `pass_all`. Ray mode: inputs `n_* x_* d_* t_min t_max`,
/// output `pass`. A zero factor gives `+0` (so `±∞·0 = 0`).
pub fn tests_module(cfg: &Config, plan: &StagePlan) -> Arc<Module> {
    let f = cfg.fmt;
    let mut m = ModuleBuilder::new(tests_name(cfg, plan));
    m.describe(if cfg.ray() {
        "Silhouette ray test: six silhouette-edge tests N_i*|d_j| <= X_j*|d_i|, three distance \
         checks N_i <= t_max*|d_i| and three direction checks t_min*|d_i| <= X_i, as exact \
         comparisons of significand products and exponent sums (no rounding)."
    } else {
        "Silhouette bundle tests, AnyHit (best corner) and AllHit (worst corner): six \
         silhouette-edge tests N_i*|d_j| <= X_j*|d_i|, three distance checks N_i <= t_max*|d_i| \
         and three direction checks t_min*|d_i| <= X_i each, as exact comparisons of \
         significand products and exponent sums (no rounding)."
    });
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("mode", format!("{:?}", cfg.mode).to_lowercase())
        .param("norm_stages", plan.norm)
        .param("product_stages", plan.product)
        .param("compare_stages", plan.compare);
    let ty = Ty::UInt(f.width());
    let tests: &[&str] = if cfg.ray() { &[""] } else { &["any", "all"] };
    let prefix = |t: &str, v: &str| {
        if t.is_empty() {
            v.to_string()
        } else {
            format!("{v}_{t}")
        }
    };
    // Inputs, then every factor unpacked once.
    let mut nx: Vec<(Vec<Sig>, Vec<Sig>)> = Vec::new();
    for t in tests {
        let n: Vec<Sig> = AXES
            .iter()
            .map(|ax| m.input(&format!("{}_{ax}", prefix(t, "n")), ty))
            .collect();
        let x: Vec<Sig> = AXES
            .iter()
            .map(|ax| m.input(&format!("{}_{ax}", prefix(t, "x")), ty))
            .collect();
        nx.push((n, x));
    }
    let bound = |m: &mut ModuleBuilder, name: &str| -> Vec<Sig> {
        AXES.iter()
            .map(|ax| m.input(&format!("{name}_{ax}"), ty))
            .collect()
    };
    let (a_in, b_in) = if cfg.ray() {
        let d = bound(&mut m, "d");
        (d.clone(), d)
    } else {
        (bound(&mut m, "a"), bound(&mut m, "b"))
    };
    let t_min = m.input("t_min", ty);
    let t_max = m.input("t_max", ty);

    let fa: Vec<Factor> = (0..3)
        .map(|i| {
            let name = if cfg.ray() { "d" } else { "a" };
            factor(&mut m, f, a_in[i], &format!("{name}_{}", AXES[i]))
        })
        .collect();
    let fb: Vec<Factor> = if cfg.ray() {
        fa.clone()
    } else {
        (0..3)
            .map(|i| factor(&mut m, f, b_in[i], &format!("b_{}", AXES[i])))
            .collect()
    };
    let ft_min = factor(&mut m, f, t_min, "t_min");
    let ft_max = factor(&mut m, f, t_max, "t_max");
    let fnx: Vec<(Vec<Factor>, Vec<Factor>)> = tests
        .iter()
        .zip(&nx)
        .map(|(t, (n, x))| {
            let fac = |m: &mut ModuleBuilder, v: &[Sig], which: &str| -> Vec<Factor> {
                (0..3)
                    .map(|i| factor(m, f, v[i], &format!("{}_{}", prefix(t, which), AXES[i])))
                    .collect()
            };
            (fac(&mut m, n, "n"), fac(&mut m, x, "x"))
        })
        .collect();
    for _ in 0..plan.norm {
        m.stage();
    }

    // `v · |d_k|`, with |d_k| the bound that makes the product largest
    // (`want_max`) or smallest: sgn(v) != want_max picks b (the largest).
    let product_of = |m: &mut ModuleBuilder, v: &Factor, k: usize, want_max: bool, inst: &str| {
        let d = if cfg.ray() {
            fa[k]
        } else {
            let pick_b = if want_max { m.not(v.sign) } else { v.sign };
            m.scope(inst, |m| pick(m, pick_b, &fb[k], &fa[k]))
        };
        Side::Product(start_product(m, f, v, &d, plan.product, inst))
    };
    let mut sides: Vec<Vec<(Side, Side, String)>> = Vec::new();
    for (t, (n, x)) in tests.iter().zip(&fnx) {
        let all = *t == "all";
        let tag = |s: &str| prefix(t, s);
        let mut cmp = Vec::new();
        for &(i, j) in EDGES.iter() {
            let e = format!("{}{}", AXES[i], AXES[j]);
            let l = product_of(&mut m, &n[i], j, all, &format!("u_{}_{e}_l", tag("edge")));
            let r = product_of(&mut m, &x[j], i, !all, &format!("u_{}_{e}_r", tag("edge")));
            cmp.push((l, r, format!("{}_{e}_ok", tag("edge"))));
        }
        for i in 0..3 {
            let r = product_of(
                &mut m,
                &ft_max,
                i,
                !all,
                &format!("u_{}_{}_r", tag("dist"), AXES[i]),
            );
            cmp.push((
                Side::Single(n[i]),
                r,
                format!("{}_{}_ok", tag("dist"), AXES[i]),
            ));
        }
        for i in 0..3 {
            let l = product_of(
                &mut m,
                &ft_min,
                i,
                all,
                &format!("u_{}_{}_l", tag("dir"), AXES[i]),
            );
            cmp.push((
                l,
                Side::Single(x[i]),
                format!("{}_{}_ok", tag("dir"), AXES[i]),
            ));
        }
        sides.push(cmp);
    }
    for _ in 0..plan.product {
        m.stage();
    }
    let term = |m: &mut ModuleBuilder, s: &Side, name: &str| -> Term {
        match s {
            Side::Product(p) => product_term(m, f, p, name),
            Side::Single(v) => single_term(m, f, v, name),
        }
    };
    let mut oks: Vec<Vec<Sig>> = Vec::new();
    for cmp in &sides {
        let mut ok = Vec::new();
        for (l, r, label) in cmp {
            let base = label.trim_end_matches("_ok");
            let lt = term(&mut m, l, &format!("{base}_lhs"));
            let rt = term(&mut m, r, &format!("{base}_rhs"));
            let v = m.scope(base, |m| term_le(m, &lt, &rt));
            ok.push(m.name(v, label));
        }
        oks.push(ok);
    }
    for _ in 0..plan.compare {
        m.stage();
    }
    for (t, ok) in tests.iter().zip(&oks) {
        let name = prefix(t, "pass");
        let pass = all_of(&mut m, ok, &name);
        m.output(&name, pass);
    }
    Arc::new(
        m.finish()
            .expect("silhouette tests generator is type-correct for every accepted format"),
    )
}

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
    cfg.describe_params(&mut m, cfg.stages);
    let ty = Ty::UInt(f.width());
    let bounded = cfg.bounded();
    let names = cfg.input_names();
    let ins: Vec<Sig> = names.iter().map(|n| m.input(n, ty)).collect();
    let port = |name: &str| ins[super::port_at(&names, name)];
    let vec3 = |group: &str| -> Vec<Sig> {
        super::port_at3(&names, group)
            .iter()
            .map(|&k| ins[k])
            .collect()
    };
    let (p_min, p_max) = (vec3("p_min"), vec3("p_max"));
    let (o_lo, o_hi, d_lo, d_hi) = match (cfg.ray(), bounded) {
        (true, _) => (vec3("o"), vec3("o"), vec3("d"), vec3("d")),
        (false, false) => (vec3("o_lo"), vec3("o_lo"), vec3("d_lo"), vec3("d_hi")),
        (false, true) => (vec3("o_lo"), vec3("o_hi"), vec3("d_lo"), vec3("d_hi")),
    };
    let (t_min, t_max) = (port("t_min"), port("t_max"));

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
    let mut axis_out = Vec::new();
    for i in 0..3 {
        let mut ins = vec![("p_min", p_min[i]), ("p_max", p_max[i])];
        if cfg.ray() {
            ins.push(("o", o_lo[i]));
            ins.push(("d", d_lo[i]));
        } else {
            ins.push(("o_lo", o_lo[i]));
            ins.push(("d_lo", d_lo[i]));
            ins.push(("d_hi", d_hi[i]));
            if bounded {
                ins.push(("o_hi", o_hi[i]));
            }
        }
        axis_out.push(m.instance(&format!("u_axis_{}", AXES[i]), &axis, &ins));
    }
    for _ in 0..plan.diff {
        m.stage();
    }
    let g = |i: usize, p: &str| axis_out[i].get(p).expect("axis block output");

    // Step 4: the tests (two corners of a bundle, or the ray's one).
    let tests = tests_module(cfg, &plan);
    // (tests block port, axis block output) per axis
    let wiring: &[(&str, &str)] = if cfg.ray() {
        &[("n", "n"), ("x", "x"), ("d", "a")]
    } else {
        &[
            ("n_any", "n_any"),
            ("x_any", "x_any"),
            ("n_all", "n_all"),
            ("x_all", "x_all"),
            ("a", "a"),
            ("b", "b"),
        ]
    };
    let names: Vec<(String, Sig)> = (0..3)
        .flat_map(|i| wiring.iter().map(move |&(to, from)| (i, to, from)))
        .map(|(i, to, from)| (format!("{to}_{}", AXES[i]), g(i, from)))
        .collect();
    let mut ins: Vec<(&str, Sig)> = names.iter().map(|(n, s)| (n.as_str(), *s)).collect();
    ins.push(("t_min", t_min));
    ins.push(("t_max", t_max));
    let passes = m.instance("u_tests", &tests, &ins);
    for _ in 0..plan.norm + plan.product + plan.compare {
        m.stage();
    }

    // Step 5: the verdict.
    let not_invalid = m.not(invalid);
    let valid = m.and(not_nan, not_invalid);
    let not_empty = m.not(empty);
    let ok = m.and(valid, not_empty);
    let outputs = if cfg.ray() {
        let pass = passes.get("pass").expect("tests block has output pass");
        let hit = m.and(ok, pass);
        vec![("hit", hit), ("nan", nan), ("invalid", invalid)]
    } else {
        let pass_any = passes
            .get("pass_any")
            .expect("tests block has output pass_any");
        let pass_all = passes
            .get("pass_all")
            .expect("tests block has output pass_all");
        let straddles: Vec<Sig> = (0..3)
            .map(|i| {
                let (neg, pos) = (g(i, "neg"), g(i, "pos"));
                m.and(neg, pos)
            })
            .collect();
        let mixed = any_of(&mut m, &straddles, "mixed");
        let not_mixed = m.not(mixed);
        let all_hit = m.and(ok, not_mixed);
        let all_hit = m.and(all_hit, pass_all);
        let any_pass = m.or(mixed, pass_any);
        let any_hit = m.and(ok, any_pass);
        let mixed_sign = m.and(valid, mixed);
        vec![
            ("all_hit", all_hit),
            ("any_hit", any_hit),
            ("nan", nan),
            ("invalid", invalid),
            ("mixed_sign", mixed_sign),
        ]
    };
    for _ in 0..plan.reduce {
        m.stage();
    }
    for &name in cfg.output_names() {
        let value = outputs.iter().find(|(n, _)| *n == name).map(|(_, v)| *v);
        m.output(name, value.expect("every output is computed"));
    }
    m.finish()
        .expect("silhouette generator is type-correct for every accepted configuration")
}

/// The configuration of resolved parameters, or why it cannot be built.
pub fn config(p: &Params) -> Result<Config, ParamError> {
    let fmt =
        Format::new(p.u32("exp_bits"), p.u32("frac_bits")).map_err(ParamError::Combination)?;
    // the golden model's reference products need (E + 2, 2F + 1)
    exact_product_format(fmt).map_err(ParamError::Combination)?;
    let mode = match p.word("mode") {
        "ray" => Mode::Ray,
        "bundle" => Mode::Bundle,
        other => unreachable!("mode choice checked by the parameter table: {other}"),
    };
    let origin = match p.word("origin") {
        "bounded" => Origin::Bounded,
        "shared" => Origin::Shared,
        other => unreachable!("origin choice checked by the parameter table: {other}"),
    };
    if mode == Mode::Ray && origin == Origin::Bounded {
        return Err(ParamError::Combination(
            "origin=bounded needs mode=bundle: a ray (mode=ray) has one origin o".into(),
        ));
    }
    let policy = match p.word("rounding") {
        "nearest" => Policy::Nearest,
        "conservative" => Policy::Conservative,
        other => unreachable!("rounding choice checked by the parameter table: {other}"),
    };
    Ok(Config {
        fmt,
        mode,
        origin,
        policy,
        stages: p.u32("stages"),
    })
}

impl Description for Silhouette {
    type Config = Config;
    const NAME: &'static str = "silhouette";
    const SUMMARY: &'static str = "silhouette-edge box tester: bundles (all_hit, any_hit, three-valued) or single rays (hit); exact product comparisons, conservative differences";
    const PARAMS: &'static [ParamSpec] = PARAMS;
    fn config(&self, p: &Params) -> Result<Config, ParamError> {
        config(p)
    }
    fn generate(&self, cfg: &Config) -> Module {
        build(cfg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
