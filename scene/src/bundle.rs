//! The bundle builder of seed 000 (FIG. 10): a set of open bundles; for each
//! incoming ray, the similarity with every open bundle is how little the
//! bundle's bounds would grow if the ray joined it; the best match takes the
//! ray if the grown bundle stays under the thresholds (direction range per
//! normalised component, origin box extent), otherwise a new bundle is
//! opened (emitting the fullest open bundle when no slot is free). Full
//! bundles (`max_size` rays) are emitted at once; the rest when the stream ends.
//!
//! Rays whose direction signs differ are never grouped (the unit's AllHit needs
//! one sign per axis, `docs/silhouette.md` §4.2).

use crate::render::unit_by_division;
use crate::trace::{BundleOpts, TRay};
use glam::Vec3;

#[derive(Clone)]
struct Open {
    rays: Vec<usize>,
    signs: u32,
    o_lo: Vec3,
    o_hi: Vec3,
    n_lo: Vec3,
    n_hi: Vec3,
}

/// Groups the rays `idxs` of `rays` into bundles (each a list of indices, in
/// arrival order inside a bundle). `scale` is the scene size for the origin
/// threshold. With bundles disabled every ray is its own bundle.
pub fn build_bundles(
    rays: &[TRay],
    idxs: &[usize],
    opts: &BundleOpts,
    scale: f32,
) -> Vec<Vec<usize>> {
    if !opts.enabled || opts.max_size < 2 {
        return idxs.iter().map(|&i| vec![i]).collect();
    }
    let max_o = opts.max_origin_extent * scale;
    let mut open: Vec<Open> = Vec::new();
    let mut out = Vec::new();
    for &i in idxs {
        let r = &rays[i];
        let n = unit_by_division!(r.d_w);
        // `< 0`, not the sign bit: -0 joins the positive side
        let s = r.d_w.cmplt(Vec3::ZERO).bitmask();
        // similarity: minus the growth of (direction range sum + origin extent / scale)
        let mut best: Option<(f32, usize)> = None;
        for (k, b) in open.iter().enumerate() {
            if b.signs != s {
                continue;
            }
            // the bundle's bound is min/max's second operand: glam keeps it
            // on ties (±0) and when the new value is NaN
            let n_ext = n.max(b.n_hi) - n.min(b.n_lo);
            let o_ext = r.o_w.max(b.o_hi) - r.o_w.min(b.o_lo);
            let ok = n_ext.cmple(Vec3::splat(opts.max_spread)).all()
                && o_ext.cmple(Vec3::splat(max_o)).all();
            let growth =
                (n_ext - (b.n_hi - b.n_lo)) + (o_ext - (b.o_hi - b.o_lo)) / scale.max(1e-30);
            let grow = growth.element_sum();
            if ok && best.is_none_or(|(g, _)| grow < g) {
                best = Some((grow, k));
            }
        }
        let k = match best {
            Some((_, k)) => k,
            None => {
                if open.len() >= opts.open.max(1) {
                    let (f, _) = open
                        .iter()
                        .enumerate()
                        .max_by_key(|(_, b)| b.rays.len())
                        .unwrap();
                    out.push(open.swap_remove(f).rays);
                }
                open.push(Open {
                    rays: Vec::new(),
                    signs: s,
                    o_lo: r.o_w,
                    o_hi: r.o_w,
                    n_lo: n,
                    n_hi: n,
                });
                open.len() - 1
            }
        };
        let b = &mut open[k];
        b.rays.push(i);
        (b.n_lo, b.n_hi) = (n.min(b.n_lo), n.max(b.n_hi));
        (b.o_lo, b.o_hi) = (r.o_w.min(b.o_lo), r.o_w.max(b.o_hi));
        if b.rays.len() >= opts.max_size {
            out.push(open.swap_remove(k).rays);
        }
    }
    out.extend(open.into_iter().map(|b| b.rays));
    out
}
