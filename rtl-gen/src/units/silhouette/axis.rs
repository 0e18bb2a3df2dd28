//! The axis block of the silhouette tester: one axis mirrored so that its
//! directions are `>= 0`, and its numerators (the only rounded values).

use super::*;
use crate::arith::ports::{call, rounded, DownUp, Pair};

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
    let AxisIn {
        p_min,
        p_max,
        o_lo,
        o_hi,
        d_lo,
        d_hi,
    } = ports::declare_inputs(&mut m, cfg);

    // Classify the direction interval (by value: -0 is not negative).
    let neg = is_negative(&mut m, f, d_lo);
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
    let outputs = if cfg.ray() {
        let (entry, exit) = match cfg.policy {
            Policy::Conservative => (Rounding::Rdn, Rounding::Rup),
            Policy::Nearest => (Rounding::Rne, Rounding::Rne),
        };
        let entry = add_module(f, entry, false, stages);
        let exit = add_module(f, exit, false, stages);
        let n = rounded(&mut m, "u_entry", &entry, &Pair::new(near, m_lo));
        let x = rounded(&mut m, "u_exit", &exit, &Pair::new(far, m_lo));
        AxisOut::ray(a, n, x)
    } else {
        let pos = is_positive(&mut m, f, d_hi);
        let pos = m.name(pos, "pos");
        let b = m.mux(neg, d_lo_abs, d_hi_abs);
        let (n_any, x_any, n_all, x_all) = match (cfg.origin, cfg.policy) {
            (Origin::Shared, Policy::Conservative) => {
                // one exact sum per plane, rounded both ways
                let adu = add_down_up_module(f, stages);
                let ty = f.ty();
                let n: DownUp<Sig> = call(&mut m, "u_entry", &adu, &Pair::new(near, m_lo), &ty);
                let x: DownUp<Sig> = call(&mut m, "u_exit", &adu, &Pair::new(far, m_lo), &ty);
                (n.down, x.up, n.up, x.down)
            }
            (Origin::Bounded, Policy::Conservative) => {
                let dn = add_module(f, Rounding::Rdn, false, stages);
                let up = add_module(f, Rounding::Rup, false, stages);
                let n_any = rounded(&mut m, "u_n_any", &dn, &Pair::new(near, m_hi));
                let x_any = rounded(&mut m, "u_x_any", &up, &Pair::new(far, m_lo));
                let n_all = rounded(&mut m, "u_n_all", &up, &Pair::new(near, m_lo));
                let x_all = rounded(&mut m, "u_x_all", &dn, &Pair::new(far, m_hi));
                (n_any, x_any, n_all, x_all)
            }
            (Origin::Shared, Policy::Nearest) => {
                let rne = add_module(f, Rounding::Rne, false, stages);
                let n = rounded(&mut m, "u_entry", &rne, &Pair::new(near, m_lo));
                let x = rounded(&mut m, "u_exit", &rne, &Pair::new(far, m_lo));
                (n, x, n, x)
            }
            (Origin::Bounded, Policy::Nearest) => {
                let rne = add_module(f, Rounding::Rne, false, stages);
                let n_any = rounded(&mut m, "u_n_any", &rne, &Pair::new(near, m_hi));
                let x_any = rounded(&mut m, "u_x_any", &rne, &Pair::new(far, m_lo));
                let n_all = rounded(&mut m, "u_n_all", &rne, &Pair::new(near, m_lo));
                let x_all = rounded(&mut m, "u_x_all", &rne, &Pair::new(far, m_hi));
                (n_any, x_any, n_all, x_all)
            }
        };
        AxisOut {
            neg: Some(neg),
            pos: Some(pos),
            a,
            b,
            n_any,
            x_any,
            n_all,
            x_all,
        }
    };
    for _ in 0..stages {
        m.stage();
    }
    ports::declare_outputs(&mut m, cfg, &outputs);
    Arc::new(
        m.finish()
            .expect("silhouette axis generator is type-correct for every accepted format"),
    )
}
