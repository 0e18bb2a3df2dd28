//! `silhouette`: the silhouette-edge ray / bundle versus box tester (seed
//! 000, issue #4). One transaction per clock: a box, a bundle (direction
//! bounds `d_lo..d_hi`, an origin `o_lo` or origin bounds `o_lo..o_hi`) and a
//! segment `[t_min, t_max]` give AllHit and AnyHit in parallel; a single ray
//! is a bundle whose bounds coincide, and its hit bit is `any_hit`.
//!
//! The specification is `docs/silhouette.md` and the bit-exact twin is
//! `golden_model::silhouette`: this generator performs the same steps with
//! the DSL's float operators.
//!
//! Hierarchy (each block its own Verilog module):
//! - the top classifies the inputs (NaN, invalid, empty segment or box, mixed
//!   direction signs) and combines the verdict;
//! - three `silhouette_axis_*` instances mirror one axis each so that its
//!   directions are `>= 0` and form the four numerators `n_any`, `x_any`,
//!   `n_all`, `x_all` (differences `plane − origin`, the only rounded values);
//! - two `silhouette_corner_*` instances (AnyHit: best corner, AllHit: worst
//!   corner) pick the direction bound per product from the numerator's sign,
//!   form 18 exact products each and evaluate the six silhouette-edge tests,
//!   three distance checks and three direction checks.
//!
//! Rounding rule per operand (conservative policy, §4.3 of the spec):
//! `n_any = near − ô_hi` rounded toward −∞ and `x_any = far − ô_lo` toward
//! +∞ (AnyHit, and the single-ray hit, can only gain hits); `n_all = near −
//! ô_lo` toward +∞ and `x_all = far − ô_hi` toward −∞ (AllHit can only lose
//! them). Shared origin: one exact sum per numerator pair, rounded both ways
//! by `add_down_up`. Nearest policy: every difference rounded to nearest even
//! (charts only). Products are exact (`mul_exact`, format `(E+2, 2F+1)`),
//! the numerators are widened exactly, so every comparison is exact.
//!
//! Pipelining: `stages` registers are spread over 13 logical steps: the
//! difference (6 steps: the adder's 3 and its rounder's 3), the products (5:
//! the multiplier's 2 and the packing rounder's 3), the comparisons and the
//! reduction. One register goes to the outputs first.

use super::Unit;
use crate::arith::float::add::{add_module, ADD_RAW_STEPS};
use crate::arith::float::add_down_up::add_down_up_module;
use crate::arith::float::compare::compare;
use crate::arith::float::convert::convert_module;
use crate::arith::float::mul::MUL_RAW_STEPS;
use crate::arith::float::mul_exact::{exact_product_format, mul_exact_module};
use crate::arith::float::round::ROUND_STEPS;
use crate::arith::float::{spread, Format, Rounding};
use crate::builder::{ModuleBuilder, Sig};
use crate::ir::{Module, Ty};
use crate::params::{ParamError, ParamKind, ParamSpec, Params};
use std::sync::Arc;

/// The `silhouette` unit.
pub struct Silhouette;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: "exp_bits",
        doc: "exponent bits E of the input format (E + 2F <= 60: the exact products need (E+2, 2F+1))",
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
        name: "origin",
        doc: "shared: one origin o_lo; bounded: per-axis origin bounds o_lo..o_hi",
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
        doc: "pipeline stages (latency in cycles), spread over differences, products, comparisons, reduction",
        kind: ParamKind::Int { min: 0, max: 16 },
        default: "4",
    },
];

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
    /// origin mode
    pub origin: Origin,
    /// rounding policy
    pub policy: Policy,
    /// pipeline stages (latency)
    pub stages: u32,
}

/// Logical steps of the numerators: the adder's exact part and its rounder.
pub const DIFF_STEPS: u32 = ADD_RAW_STEPS + ROUND_STEPS;
/// Logical steps of the exact products: the multiplier and the packing rounder.
pub const PRODUCT_STEPS: u32 = MUL_RAW_STEPS + ROUND_STEPS;
/// All logical steps: differences, products, comparisons, reduction.
pub const STEPS: u32 = DIFF_STEPS + PRODUCT_STEPS + 2;

/// How the `stages` registers are placed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StagePlan {
    /// registers inside the difference operators (axis blocks)
    pub diff: u32,
    /// registers inside the exact multipliers and widenings (corner blocks)
    pub product: u32,
    /// registers after the 24 comparisons (corner blocks)
    pub compare: u32,
    /// registers after the reduction and verdict (top)
    pub reduce: u32,
}

impl StagePlan {
    /// The plan for `stages` registers ([`spread`] over [`STEPS`] steps).
    pub fn new(stages: u32) -> StagePlan {
        let cuts = spread(stages, STEPS);
        let (d, p) = (DIFF_STEPS as usize, PRODUCT_STEPS as usize);
        StagePlan {
            diff: cuts[..d].iter().sum(),
            product: cuts[d..d + p].iter().sum(),
            compare: cuts[d + p],
            reduce: cuts[d + p + 1],
        }
    }
}

impl Config {
    /// The exact-product format `(E + 2, 2F + 1)`.
    pub fn wide(&self) -> Format {
        exact_product_format(self.fmt).expect("checked when the configuration was made")
    }

    /// The parameter tags of module names, e.g. `e8m23_shared_cons_s4`.
    pub fn tag(&self) -> String {
        let o = match self.origin {
            Origin::Shared => "shared",
            Origin::Bounded => "bounded",
        };
        let r = match self.policy {
            Policy::Conservative => "cons",
            Policy::Nearest => "near",
        };
        format!("{}_{o}_{r}_s{}", self.fmt.tag(), self.stages)
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

/// `v` is ±0.
#[track_caller]
fn is_zero(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let mag = m.slice(v, fmt.width() - 2, 0);
    let any = m.any_set(mag);
    m.not(any)
}

/// OR of `flags` (Bool), one reduction, named `name`.
#[track_caller]
fn any_of(m: &mut ModuleBuilder, flags: &[Sig], name: &str) -> Sig {
    let bits: Vec<Sig> = flags.iter().map(|&f| m.as_uint(f)).collect();
    let v = m.cat(&bits);
    let v = m.name(v, &format!("{name}_flags"));
    let r = m.any_set(v);
    m.name(r, name)
}

/// AND of `flags` (Bool), one reduction, named `name`.
#[track_caller]
fn all_of(m: &mut ModuleBuilder, flags: &[Sig], name: &str) -> Sig {
    let bits: Vec<Sig> = flags.iter().map(|&f| m.as_uint(f)).collect();
    let v = m.cat(&bits);
    let v = m.name(v, &format!("{name}_flags"));
    let r = m.all_ones(v);
    m.name(r, name)
}

/// `v` is a NaN.
#[track_caller]
fn is_nan(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let mag = m.slice(v, fmt.width() - 2, 0);
    let inf = m.uint(fmt.width() - 1, fmt.inf_bits());
    m.gt(mag, inf)
}

/// `v` is +∞ (`negative = false`) or −∞.
#[track_caller]
fn is_inf(m: &mut ModuleBuilder, fmt: Format, v: Sig, negative: bool) -> Sig {
    let bits = fmt.inf_bits()
        | if negative {
            1u128 << (fmt.width() - 1)
        } else {
            0
        };
    let k = m.uint(fmt.width(), bits);
    m.eq(v, k)
}

/// `v` is ±∞.
#[track_caller]
fn is_any_inf(m: &mut ModuleBuilder, fmt: Format, v: Sig) -> Sig {
    let mag = m.slice(v, fmt.width() - 2, 0);
    let inf = m.uint(fmt.width() - 1, fmt.inf_bits());
    m.eq(mag, inf)
}

/// IEEE quiet `a <= b` (false if either is NaN).
#[track_caller]
fn le(m: &mut ModuleBuilder, fmt: Format, a: Sig, b: Sig) -> Sig {
    compare(m, fmt, a, b).1
}

/// Module name of the axis block.
pub fn axis_name(cfg: &Config, stages: u32) -> String {
    let c = Config { stages, ..*cfg };
    format!("silhouette_axis_{}", c.tag())
}

/// The axis block: mirrors one axis so that its directions are `>= 0`
/// (sign flips only) and forms the four numerators; `stages` registers
/// inside the difference operators.
///
/// Inputs `p_min p_max o_lo [o_hi] d_lo d_hi`; outputs (all `stages` cycles
/// later) `neg` (`d_lo < 0`: the axis is mirrored), `pos` (`d_hi > 0`),
/// `a`/`b` (smallest / largest `|d|`), `n_any x_any n_all x_all`.
pub fn axis_module(cfg: &Config, stages: u32) -> Arc<Module> {
    let f = cfg.fmt;
    let mut m = ModuleBuilder::new(axis_name(cfg, stages));
    m.describe(
        "One axis of the silhouette tester: mirror so that directions are >= 0, then the entry \
         numerators n = near - o and exit numerators x = far - o for AnyHit (n down, x up) and \
         AllHit (n up, x down).",
    );
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("origin", format!("{:?}", cfg.origin).to_lowercase())
        .param("rounding", format!("{:?}", cfg.policy).to_lowercase())
        .param("stages", stages);
    let ty = Ty::UInt(f.width());
    let p_min = m.input("p_min", ty);
    let p_max = m.input("p_max", ty);
    let o_lo = m.input("o_lo", ty);
    let o_hi = match cfg.origin {
        Origin::Shared => o_lo,
        Origin::Bounded => m.input("o_hi", ty),
    };
    let d_lo = m.input("d_lo", ty);
    let d_hi = m.input("d_hi", ty);

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
    let pos = strictly(&mut m, d_hi, false);
    let pos = m.name(pos, "pos");

    // Mirror: sign flips and swaps only, exact.
    let sb = sign_bit(&mut m, f);
    let abs_mask = m.uint(f.width(), (1u128 << (f.width() - 1)) - 1);
    let p_max_n = m.xor(p_max, sb);
    let p_min_n = m.xor(p_min, sb);
    let near = m.mux(neg, p_max_n, p_min);
    let near = m.name(near, "near");
    let far = m.mux(neg, p_min_n, p_max);
    let far = m.name(far, "far");
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
    let b = m.mux(neg, d_lo_abs, d_hi_abs);

    // The numerators (the only rounded values).
    let get = |io: crate::builder::InstanceOutputs, port: &str| {
        io.get(port).expect("operator output exists")
    };
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
            let n_any = get(m.instance("u_n_any", &dn, &[("a", near), ("b", m_hi)]), "z");
            let x_any = get(m.instance("u_x_any", &up, &[("a", far), ("b", m_lo)]), "z");
            let n_all = get(m.instance("u_n_all", &up, &[("a", near), ("b", m_lo)]), "z");
            let x_all = get(m.instance("u_x_all", &dn, &[("a", far), ("b", m_hi)]), "z");
            (n_any, x_any, n_all, x_all)
        }
        (Origin::Shared, Policy::Nearest) => {
            let rne = add_module(f, Rounding::Rne, false, stages);
            let n = get(
                m.instance("u_entry", &rne, &[("a", near), ("b", m_lo)]),
                "z",
            );
            let x = get(m.instance("u_exit", &rne, &[("a", far), ("b", m_lo)]), "z");
            (n, x, n, x)
        }
        (Origin::Bounded, Policy::Nearest) => {
            let rne = add_module(f, Rounding::Rne, false, stages);
            let n_any = get(
                m.instance("u_n_any", &rne, &[("a", near), ("b", m_hi)]),
                "z",
            );
            let x_any = get(m.instance("u_x_any", &rne, &[("a", far), ("b", m_lo)]), "z");
            let n_all = get(
                m.instance("u_n_all", &rne, &[("a", near), ("b", m_lo)]),
                "z",
            );
            let x_all = get(m.instance("u_x_all", &rne, &[("a", far), ("b", m_hi)]), "z");
            (n_any, x_any, n_all, x_all)
        }
    };
    for _ in 0..stages {
        m.stage();
    }
    m.output("neg", neg);
    m.output("pos", pos);
    m.output("a", a);
    m.output("b", b);
    m.output("n_any", n_any);
    m.output("x_any", x_any);
    m.output("n_all", n_all);
    m.output("x_all", x_all);
    Arc::new(
        m.finish()
            .expect("silhouette axis generator is type-correct for every accepted format"),
    )
}

/// Module name of the corner block (`all`: AllHit, else AnyHit).
pub fn corner_name(cfg: &Config, all: bool, product: u32, compare: u32) -> String {
    format!(
        "silhouette_corner_{}_{}_p{product}_c{compare}",
        if all { "all" } else { "any" },
        cfg.fmt.tag()
    )
}

/// The corner block of one test: AllHit (`all`, every left side at its
/// largest and every right side at its smallest over the bundle: the worst
/// corner) or AnyHit (the best corner). For each product `v·|d_k|` the bound
/// of `|d_k|` (`a_k` smallest, `b_k` largest) is picked by the sign bit of
/// `v`; a zero factor gives `+0` (so `±∞·0 = 0`). Products are exact; the
/// numerators are widened exactly; the twelve comparisons are exact.
///
/// Inputs `n_x n_y n_z x_x x_y x_z a_x .. b_z t_min t_max`; output `pass`
/// (all twelve tests hold), `product + compare` cycles later.
pub fn corner_module(cfg: &Config, all: bool, product: u32, compare_stages: u32) -> Arc<Module> {
    let f = cfg.fmt;
    let w = cfg.wide();
    let mut m = ModuleBuilder::new(corner_name(cfg, all, product, compare_stages));
    m.describe(if all {
        "AllHit corner test: six silhouette-edge tests N_i*|d_j| <= X_j*|d_i|, three distance checks \
         N_i <= t_max*|d_i| and three direction checks t_min*|d_i| <= X_i, each side taken at its \
         worst corner of the bundle; exact products and comparisons."
    } else {
        "AnyHit corner test: six silhouette-edge tests N_i*|d_j| <= X_j*|d_i|, three distance checks \
         N_i <= t_max*|d_i| and three direction checks t_min*|d_i| <= X_i, each side taken at its \
         best corner of the bundle; exact products and comparisons."
    });
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("test", if all { "all" } else { "any" })
        .param("product_stages", product)
        .param("compare_stages", compare_stages);
    let ty = Ty::UInt(f.width());
    let n: Vec<Sig> = AXES
        .iter()
        .map(|a| m.input(&format!("n_{a}"), ty))
        .collect();
    let x: Vec<Sig> = AXES
        .iter()
        .map(|a| m.input(&format!("x_{a}"), ty))
        .collect();
    let a: Vec<Sig> = AXES
        .iter()
        .map(|ax| m.input(&format!("a_{ax}"), ty))
        .collect();
    let b: Vec<Sig> = AXES
        .iter()
        .map(|ax| m.input(&format!("b_{ax}"), ty))
        .collect();
    let t_min = m.input("t_min", ty);
    let t_max = m.input("t_max", ty);

    let mulx = mul_exact_module(f, product);
    let widen = convert_module(f, w, Rounding::Rne, product);
    let a_zero: Vec<Sig> = a.iter().map(|&v| is_zero(&mut m, f, v)).collect();
    let b_zero: Vec<Sig> = b.iter().map(|&v| is_zero(&mut m, f, v)).collect();
    let zero = m.uint(f.width(), 0);

    // `v · |d_k|`, with |d_k| the bound that makes the product largest
    // (`want_max`) or smallest, exactly; `+0` if either factor is zero.
    let product_of = |m: &mut ModuleBuilder, v: Sig, k: usize, want_max: bool, inst: &str| {
        let s = m.msb(v);
        // sgn(v) != want_max picks b (the largest |d_k|)
        let pick_b = if want_max { m.not(s) } else { s };
        let d = m.mux(pick_b, b[k], a[k]);
        let d_zero = m.mux(pick_b, b_zero[k], a_zero[k]);
        let v_zero = is_zero(m, f, v);
        let z = m.or(v_zero, d_zero);
        let v = m.mux(z, zero, v);
        m.instance(inst, &mulx, &[("a", v), ("b", d)])
            .get("z")
            .expect("exact multiplier has output z")
    };
    let mut lhs = Vec::new();
    let mut rhs = Vec::new();
    let mut labels = Vec::new();
    for &(i, j) in EDGES.iter() {
        let tag = format!("{}{}", AXES[i], AXES[j]);
        lhs.push(product_of(&mut m, n[i], j, all, &format!("u_edge_{tag}_l")));
        rhs.push(product_of(
            &mut m,
            x[j],
            i,
            !all,
            &format!("u_edge_{tag}_r"),
        ));
        labels.push(format!("edge_{tag}_ok"));
    }
    for i in 0..3 {
        let nw = m.instance(&format!("u_widen_n_{}", AXES[i]), &widen, &[("a", n[i])]);
        lhs.push(nw.get("z").expect("converter has output z"));
        rhs.push(product_of(
            &mut m,
            t_max,
            i,
            !all,
            &format!("u_dist_{}_r", AXES[i]),
        ));
        labels.push(format!("dist_{}_ok", AXES[i]));
    }
    for i in 0..3 {
        lhs.push(product_of(
            &mut m,
            t_min,
            i,
            all,
            &format!("u_dir_{}_l", AXES[i]),
        ));
        let xw = m.instance(&format!("u_widen_x_{}", AXES[i]), &widen, &[("a", x[i])]);
        rhs.push(xw.get("z").expect("converter has output z"));
        labels.push(format!("dir_{}_ok", AXES[i]));
    }
    for _ in 0..product {
        m.stage();
    }
    let mut oks = Vec::new();
    for k in 0..12 {
        let ok = le(&mut m, w, lhs[k], rhs[k]);
        oks.push(m.name(ok, &labels[k]));
    }
    for _ in 0..compare_stages {
        m.stage();
    }
    let pass = all_of(&mut m, &oks, "pass");
    m.output("pass", pass);
    Arc::new(
        m.finish()
            .expect("silhouette corner generator is type-correct for every accepted format"),
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
    m.describe(
        "Silhouette-edge ray/bundle versus box tester (docs/silhouette.md): all_hit = every ray of \
         the bundle hits the box, any_hit = 0 only if every ray misses (a single ray's conservative \
         hit bit); nan = a NaN input, invalid = infinite or unordered origin/direction bounds, \
         mixed_sign = direction bounds straddle 0 on an axis (all_hit = 0, any_hit = nonempty).",
    );
    m.param("exp_bits", f.exp_bits)
        .param("frac_bits", f.frac_bits)
        .param("origin", format!("{:?}", cfg.origin).to_lowercase())
        .param("rounding", format!("{:?}", cfg.policy).to_lowercase())
        .param("stages", cfg.stages);
    let ty = Ty::UInt(f.width());
    let bounded = cfg.origin == Origin::Bounded;
    let vec3 = |m: &mut ModuleBuilder, name: &str| -> Vec<Sig> {
        AXES.iter()
            .map(|a| m.input(&format!("{name}_{a}"), ty))
            .collect()
    };
    let p_min = vec3(&mut m, "p_min");
    let p_max = vec3(&mut m, "p_max");
    let o_lo = vec3(&mut m, "o_lo");
    let o_hi = if bounded {
        vec3(&mut m, "o_hi")
    } else {
        o_lo.clone()
    };
    let d_lo = vec3(&mut m, "d_lo");
    let d_hi = vec3(&mut m, "d_hi");
    let t_min = m.input("t_min", ty);
    let t_max = m.input("t_max", ty);

    // Step 1: classify the inputs (no arithmetic).
    let mut read: Vec<Sig> = Vec::new();
    read.extend(
        p_min
            .iter()
            .chain(&p_max)
            .chain(&o_lo)
            .chain(&d_lo)
            .chain(&d_hi),
    );
    if bounded {
        read.extend(&o_hi);
    }
    read.extend([t_min, t_max]);
    let nans: Vec<Sig> = read.iter().map(|&v| is_nan(&mut m, f, v)).collect();
    let nan = any_of(&mut m, &nans, "nan_in");
    let mut bad = Vec::new();
    for i in 0..3 {
        let mut vals = vec![o_lo[i], d_lo[i], d_hi[i]];
        if bounded {
            vals.push(o_hi[i]);
        }
        for v in vals {
            bad.push(is_any_inf(&mut m, f, v));
        }
        let d_ok = le(&mut m, f, d_lo[i], d_hi[i]);
        bad.push(m.not(d_ok));
        if bounded {
            // shared mode: o_lo <= o_lo holds for every non-NaN value
            let o_ok = le(&mut m, f, o_lo[i], o_hi[i]);
            bad.push(m.not(o_ok));
        }
    }
    let bad = any_of(&mut m, &bad, "bad_bounds");
    let not_nan = m.not(nan);
    let invalid = m.and(bad, not_nan);
    let invalid = m.name(invalid, "invalid_in");
    let t_ok = le(&mut m, f, t_min, t_max);
    let mut empty = vec![m.not(t_ok)];
    empty.push(is_inf(&mut m, f, t_min, false));
    empty.push(is_inf(&mut m, f, t_max, true));
    for i in 0..3 {
        let p_ok = le(&mut m, f, p_min[i], p_max[i]);
        empty.push(m.not(p_ok));
        empty.push(is_inf(&mut m, f, p_min[i], false));
        empty.push(is_inf(&mut m, f, p_max[i], true));
    }
    let empty = any_of(&mut m, &empty, "empty");

    // Steps 2 and 3: per axis, mirror and form the numerators.
    let axis = axis_module(cfg, plan.diff);
    let mut neg = Vec::new();
    let mut pos = Vec::new();
    let mut av = Vec::new();
    let mut bv = Vec::new();
    let mut n_any = Vec::new();
    let mut x_any = Vec::new();
    let mut n_all = Vec::new();
    let mut x_all = Vec::new();
    for i in 0..3 {
        let mut ins = vec![
            ("p_min", p_min[i]),
            ("p_max", p_max[i]),
            ("o_lo", o_lo[i]),
            ("d_lo", d_lo[i]),
            ("d_hi", d_hi[i]),
        ];
        if bounded {
            ins.push(("o_hi", o_hi[i]));
        }
        let out = m.instance(&format!("u_axis_{}", AXES[i]), &axis, &ins);
        let g = |p: &str| out.get(p).expect("axis block output");
        neg.push(g("neg"));
        pos.push(g("pos"));
        av.push(g("a"));
        bv.push(g("b"));
        n_any.push(g("n_any"));
        x_any.push(g("x_any"));
        n_all.push(g("n_all"));
        x_all.push(g("x_all"));
    }
    for _ in 0..plan.diff {
        m.stage();
    }
    let straddles: Vec<Sig> = (0..3).map(|i| m.and(neg[i], pos[i])).collect();
    let mixed = any_of(&mut m, &straddles, "mixed");

    // Step 4: the two corner tests, in parallel.
    let mut pass = Vec::new();
    for all in [false, true] {
        let corner = corner_module(cfg, all, plan.product, plan.compare);
        let (nn, xx) = if all {
            (&n_all, &x_all)
        } else {
            (&n_any, &x_any)
        };
        let names: Vec<[String; 4]> = AXES
            .iter()
            .map(|a| {
                [
                    format!("n_{a}"),
                    format!("x_{a}"),
                    format!("a_{a}"),
                    format!("b_{a}"),
                ]
            })
            .collect();
        let mut ins: Vec<(&str, Sig)> = Vec::new();
        for i in 0..3 {
            ins.push((names[i][0].as_str(), nn[i]));
            ins.push((names[i][1].as_str(), xx[i]));
            ins.push((names[i][2].as_str(), av[i]));
            ins.push((names[i][3].as_str(), bv[i]));
        }
        ins.push(("t_min", t_min));
        ins.push(("t_max", t_max));
        let inst = if all { "u_corner_all" } else { "u_corner_any" };
        let p = m
            .instance(inst, &corner, &ins)
            .get("pass")
            .expect("corner block has output pass");
        pass.push(p);
    }
    for _ in 0..plan.product + plan.compare {
        m.stage();
    }
    let (pass_any, pass_all) = (m.name(pass[0], "pass_any"), m.name(pass[1], "pass_all"));

    // Step 5: the verdict.
    let not_invalid = m.not(invalid);
    let valid = m.and(not_nan, not_invalid);
    let not_empty = m.not(empty);
    let ok = m.and(valid, not_empty);
    let not_mixed = m.not(mixed);
    let all_hit = m.and(ok, not_mixed);
    let all_hit = m.and(all_hit, pass_all);
    let any_pass = m.or(mixed, pass_any);
    let any_hit = m.and(ok, any_pass);
    let mixed_sign = m.and(valid, mixed);
    for _ in 0..plan.reduce {
        m.stage();
    }
    m.output("all_hit", all_hit);
    m.output("any_hit", any_hit);
    m.output("nan", nan);
    m.output("invalid", invalid);
    m.output("mixed_sign", mixed_sign);
    m.finish()
        .expect("silhouette generator is type-correct for every accepted configuration")
}

/// The configuration of resolved parameters, or why it cannot be built.
pub fn config(p: &Params) -> Result<Config, ParamError> {
    let fmt =
        Format::new(p.u32("exp_bits"), p.u32("frac_bits")).map_err(ParamError::Combination)?;
    exact_product_format(fmt).map_err(ParamError::Combination)?;
    let origin = match p.word("origin") {
        "bounded" => Origin::Bounded,
        _ => Origin::Shared,
    };
    let policy = match p.word("rounding") {
        "nearest" => Policy::Nearest,
        _ => Policy::Conservative,
    };
    Ok(Config {
        fmt,
        origin,
        policy,
        stages: p.u32("stages"),
    })
}

impl Unit for Silhouette {
    fn name(&self) -> &'static str {
        "silhouette"
    }
    fn summary(&self) -> &'static str {
        "silhouette-edge ray/bundle vs box tester: all_hit, any_hit (three-valued), exact products, conservative differences"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn build(&self, p: &Params) -> Result<Module, ParamError> {
        Ok(build(&config(p)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stage_plan_covers_every_register_and_registers_outputs_first() {
        for s in 0..=16 {
            let p = StagePlan::new(s);
            assert_eq!(p.diff + p.product + p.compare + p.reduce, s);
        }
        assert_eq!(StagePlan::new(1).reduce, 1);
        let p4 = StagePlan::new(4);
        assert!(p4.diff >= 1 && p4.product >= 1 && p4.reduce == 1, "{p4:?}");
    }
}
