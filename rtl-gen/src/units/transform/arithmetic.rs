//! The transform's arithmetic: the dot products of an engine in each style
//! (separate, fma, dot3, wide), the 2x2 determinants and the hardware
//! inverse of `R` (adjugate, determinant, reciprocal, scaling).

use super::*;

pub(super) fn close(m: &mut ModuleBuilder, n: u32) {
    for _ in 0..n {
        m.stage();
    }
}

/// Dot products `a · b` for each `(tag, a, b)`, built side by side from the
/// current stage in the configured style; closes `plan[..depth]` stages, so
/// every result belongs to the stage after the last operator.
pub(super) fn dots(
    m: &mut ModuleBuilder,
    cfg: &Config,
    items: &[(String, [Sig; 3], [Sig; 3])],
    plan: &[u32],
) -> Vec<Sig> {
    let (fmt, mode) = (cfg.fmt, cfg.mode);
    match cfg.dot {
        Dot::Separate => {
            let mul = mul_module(fmt, mode, plan[0]);
            let p: Vec<[Sig; 3]> = items
                .iter()
                .map(|(tag, a, b)| {
                    [0, 1, 2].map(|j| {
                        rounded(m, &format!("u_{tag}_mul{j}"), &mul, &Pair::new(a[j], b[j]))
                    })
                })
                .collect();
            close(m, plan[0]);
            let add1 = add_module(fmt, mode, false, plan[1]);
            let s: Vec<Sig> = items
                .iter()
                .zip(&p)
                .map(|((tag, _, _), p)| {
                    rounded(m, &format!("u_{tag}_add_a"), &add1, &Pair::new(p[0], p[1]))
                })
                .collect();
            close(m, plan[1]);
            let add2 = add_module(fmt, mode, false, plan[2]);
            let out = items
                .iter()
                .zip(p.iter().zip(&s))
                .map(|((tag, _, _), (p, s))| {
                    rounded(m, &format!("u_{tag}_add_b"), &add2, &Pair::new(*s, p[2]))
                })
                .collect();
            close(m, plan[2]);
            out
        }
        Dot::Fma => {
            let mul = mul_module(fmt, mode, plan[0]);
            let p: Vec<Sig> = items
                .iter()
                .map(|(tag, a, b)| {
                    rounded(m, &format!("u_{tag}_mul"), &mul, &Pair::new(a[0], b[0]))
                })
                .collect();
            close(m, plan[0]);
            let fma1 = fma_module(fmt, mode, plan[1]);
            let s: Vec<Sig> = items
                .iter()
                .zip(&p)
                .map(|((tag, a, b), p)| {
                    rounded(
                        m,
                        &format!("u_{tag}_fma_a"),
                        &fma1,
                        &Triple::new(a[1], b[1], *p),
                    )
                })
                .collect();
            close(m, plan[1]);
            let fma2 = fma_module(fmt, mode, plan[2]);
            let out = items
                .iter()
                .zip(&s)
                .map(|((tag, a, b), s)| {
                    rounded(
                        m,
                        &format!("u_{tag}_fma_b"),
                        &fma2,
                        &Triple::new(a[2], b[2], *s),
                    )
                })
                .collect();
            close(m, plan[2]);
            out
        }
        Dot::Wide => {
            // operands already in the wide format; one rounding there, one to the format
            let w = wide_format(fmt).expect("checked with the parameters");
            let d = dot3_module(w, mode, plan[0]);
            let sums: Vec<Sig> = items
                .iter()
                .map(|(tag, a, b)| {
                    rounded(m, &format!("u_{tag}_dot_wide"), &d, &DotTerms::new(*a, *b))
                })
                .collect();
            close(m, plan[0]);
            let narrow = convert_module(w, fmt, mode, plan[1]);
            let out = items
                .iter()
                .zip(&sums)
                .map(|((tag, _, _), s)| {
                    rounded(m, &format!("u_{tag}_round"), &narrow, &Source::new(*s))
                })
                .collect();
            close(m, plan[1]);
            out
        }
        Dot::Dot3 => {
            let d = dot3_module(fmt, mode, plan[0]);
            let out = items
                .iter()
                .map(|(tag, a, b)| rounded(m, &format!("u_{tag}_dot"), &d, &DotTerms::new(*a, *b)))
                .collect();
            close(m, plan[0]);
            out
        }
    }
}

/// The 2×2 determinants `p·q − r·s` for each `(tag, [p, q, r, s])`, in the
/// configured style (as `golden_model::transform::det2`); closes `plan[..det2_depth]`.
fn det2s(
    m: &mut ModuleBuilder,
    cfg: &Config,
    items: &[(String, [Sig; 4])],
    plan: &[u32],
) -> Vec<Sig> {
    let (fmt, mode) = (cfg.fmt, cfg.mode);
    match cfg.dot {
        Dot::Separate => {
            let mul = mul_module(fmt, mode, plan[0]);
            let p: Vec<(Sig, Sig)> = items
                .iter()
                .map(|(tag, [p, q, r, s])| {
                    let pq = rounded(m, &format!("u_{tag}_mul_pq"), &mul, &Pair::new(*p, *q));
                    let rs = rounded(m, &format!("u_{tag}_mul_rs"), &mul, &Pair::new(*r, *s));
                    (pq, rs)
                })
                .collect();
            close(m, plan[0]);
            let sub = add_module(fmt, mode, true, plan[1]);
            let out = items
                .iter()
                .zip(&p)
                .map(|((tag, _), (pq, rs))| {
                    rounded(m, &format!("u_{tag}_sub"), &sub, &Pair::new(*pq, *rs))
                })
                .collect();
            close(m, plan[1]);
            out
        }
        Dot::Fma => {
            let mul = mul_module(fmt, mode, plan[0]);
            let rs: Vec<Sig> = items
                .iter()
                .map(|(tag, [_, _, r, s])| {
                    let rs = rounded(m, &format!("u_{tag}_mul_rs"), &mul, &Pair::new(*r, *s));
                    negate(m, fmt, rs)
                })
                .collect();
            close(m, plan[0]);
            let fma = fma_module(fmt, mode, plan[1]);
            let out = items
                .iter()
                .zip(&rs)
                .map(|((tag, [p, q, _, _]), rs)| {
                    rounded(m, &format!("u_{tag}_fma"), &fma, &Triple::new(*p, *q, *rs))
                })
                .collect();
            close(m, plan[1]);
            out
        }
        Dot::Wide => unreachable!("the inversion runs in the dot3 style (Dot::inversion)"),
        Dot::Dot3 => {
            let zero = m.uint(fmt.width(), 0);
            let list: Vec<(String, [Sig; 3], [Sig; 3])> = items
                .iter()
                .map(|(tag, [p, q, r, s])| {
                    let ns = negate(m, fmt, *s);
                    (tag.clone(), [*p, *r, zero], [*q, ns, zero])
                })
                .collect();
            dots(m, cfg, &list, plan)
        }
    }
}

/// `R⁻¹` from `R` (row-major) and the "inversion failed" bit, as
/// `golden_model::transform::invert_hw`; starts in the current stage and
/// closes `plan[..det2_depth + depth + 2]`.
pub(super) fn invert(
    m: &mut ModuleBuilder,
    cfg: &Config,
    r: &[Sig; 9],
    hint: Sig,
    plan: &[u32],
) -> ([Sig; 9], Sig) {
    let cfg = &Config {
        dot: cfg.dot.inversion(),
        ..*cfg
    };
    let (fmt, mode) = (cfg.fmt, cfg.mode);
    let at = |i: usize, j: usize| r[3 * (i % 3) + (j % 3)];
    let items: Vec<(String, [Sig; 4])> = (0..9)
        .map(|k| {
            let (i, j) = (k / 3, k % 3);
            (
                format!("adj{i}{j}"),
                [
                    at(j + 1, i + 1),
                    at(j + 2, i + 2),
                    at(j + 1, i + 2),
                    at(j + 2, i + 1),
                ],
            )
        })
        .collect();
    let n2 = cfg.dot.det2_depth() as usize;
    let adj = det2s(m, cfg, &items, &plan[..n2]);
    let nd = cfg.dot.depth() as usize;
    let det = dots(
        m,
        cfg,
        &[(
            "det".to_string(),
            [r[0], r[1], r[2]],
            [adj[0], adj[3], adj[6]],
        )],
        &plan[n2..n2 + nd],
    )[0];
    let det = m.name(det, "det");
    // the checks are formed where each value is, so that one bit, not the value, is carried
    // to the end: det must be finite and nonzero, and no value of the sequence at ±max
    // finite (a directed mode's overflow, which does not reach ±∞)
    let det_nf = is_special(m, fmt, det);
    let det_zero = is_zero(m, fmt, det);
    let mut failed = m.or(det_nf, det_zero);
    for x in adj.iter().chain([&det]) {
        let saturated = is_max_finite(m, fmt, *x);
        failed = m.or(failed, saturated);
    }
    let failed_early = m.name(failed, "inversion_failed_early");
    let k = n2 + nd;
    let recip = recip_module(fmt, mode, plan[k]);
    let rc = rounded(m, "u_recip", &recip, &Operand { x: det });
    close(m, plan[k]);
    let rc_saturated = is_max_finite(m, fmt, rc);
    let mul = mul_module(fmt, mode, plan[k + 1]);
    let inv: Vec<Sig> = (0..9)
        .map(|j| {
            rounded(
                m,
                &format!("u_scale{}{}", j / 3, j % 3),
                &mul,
                &Pair::new(adj[j], rc),
            )
        })
        .collect();
    close(m, plan[k + 1]);
    // every entry of the inverse finite and below ±max finite
    let mut failed = m.or(failed_early, rc_saturated);
    for x in &inv {
        let nf = is_special(m, fmt, *x);
        failed = m.or(failed, nf);
        let saturated = is_max_finite(m, fmt, *x);
        failed = m.or(failed, saturated);
    }
    let use_inv = m.not(hint);
    let failed = m.and(failed, use_inv);
    let out = std::array::from_fn(|j| m.mux(hint, at(j % 3, j / 3), inv[j]));
    (out, failed)
}
