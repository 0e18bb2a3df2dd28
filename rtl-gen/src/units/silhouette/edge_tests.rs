//! The tests block of the silhouette tester: the factors unpacked once, then
//! per test the six silhouette-edge comparisons, the distance and the
//! direction checks as exact comparisons of products.

use super::*;

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
        .param("mode", cfg.mode)
        .param("norm_stages", plan.norm)
        .param("product_stages", plan.product)
        .param("compare_stages", plan.compare);
    let _ty = Ty::UInt(f.width());
    let tests: &[&str] = if cfg.ray() { &[""] } else { &["any", "all"] };
    let prefix = |t: &str, v: &str| {
        if t.is_empty() {
            v.to_string()
        } else {
            format!("{v}_{t}")
        }
    };
    // Inputs, then every factor unpacked once.
    let ins: TestsIn<Sig> = ports::declare_inputs(&mut m, cfg);
    let nx: Vec<([Sig; 3], [Sig; 3])> = if cfg.ray() {
        vec![(ins.n_any, ins.x_any)]
    } else {
        vec![(ins.n_any, ins.x_any), (ins.n_all, ins.x_all)]
    };
    let (a_in, b_in, t_min, t_max) = (ins.a, ins.b, ins.t_min, ins.t_max);

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
    let passes: Vec<Sig> = tests
        .iter()
        .zip(&oks)
        .map(|(t, ok)| all_of(&mut m, ok, &prefix(t, "pass")))
        .collect();
    let outputs = TestsOut {
        pass_any: passes[0],
        pass_all: *passes.last().expect("one test at least"),
    };
    ports::declare_outputs(&mut m, cfg, &outputs);
    Arc::new(
        m.finish()
            .expect("silhouette tests generator is type-correct for every accepted format"),
    )
}
