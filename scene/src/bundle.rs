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

use crate::trace::{BundleOpts, TRay};

#[derive(Clone)]
struct Open {
    rays: Vec<usize>,
    signs: u8,
    o_lo: [f32; 3],
    o_hi: [f32; 3],
    n_lo: [f32; 3],
    n_hi: [f32; 3],
}

fn signs(d: &[f32; 3]) -> u8 {
    (0..3).map(|i| ((d[i] < 0.0) as u8) << i).sum()
}

fn norm(d: &[f32; 3]) -> [f32; 3] {
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    d.map(|x| x / l)
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
        let n = norm(&r.d_w);
        let s = signs(&r.d_w);
        // similarity: minus the growth of (direction range sum + origin extent / scale)
        let mut best: Option<(f32, usize)> = None;
        for (k, b) in open.iter().enumerate() {
            if b.signs != s {
                continue;
            }
            let mut ok = true;
            let mut grow = 0.0f32;
            for a in 0..3 {
                let nl = b.n_lo[a].min(n[a]);
                let nh = b.n_hi[a].max(n[a]);
                let ol = b.o_lo[a].min(r.o_w[a]);
                let oh = b.o_hi[a].max(r.o_w[a]);
                ok &= nh - nl <= opts.max_spread && oh - ol <= max_o;
                grow += (nh - nl) - (b.n_hi[a] - b.n_lo[a])
                    + ((oh - ol) - (b.o_hi[a] - b.o_lo[a])) / scale.max(1e-30);
            }
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
        for a in 0..3 {
            b.n_lo[a] = b.n_lo[a].min(n[a]);
            b.n_hi[a] = b.n_hi[a].max(n[a]);
            b.o_lo[a] = b.o_lo[a].min(r.o_w[a]);
            b.o_hi[a] = b.o_hi[a].max(r.o_w[a]);
        }
        if b.rays.len() >= opts.max_size {
            out.push(open.swap_remove(k).rays);
        }
    }
    out.extend(open.into_iter().map(|b| b.rays));
    out
}
