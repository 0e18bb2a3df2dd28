//! `fit --wide`: the node shape a scene needs (issue 36 step 4). For each
//! N = 2, 4, 8 the smallest q whose render over the wide BVH (every node
//! through the `node` unit's model, single rays, no planes, the TLAS at
//! [`TLAS_BOX_BITS`]) is the binary32 single-ray render pixel for pixel and
//! tests at most `1 + target_rate` times the child boxes of exact binary32
//! child boxes in the same tree; among those the cheapest in LUT-cycles per
//! ray (synthesis estimates of the units the render uses), or without
//! synthesis in node bytes fetched per ray. The model is conservative
//! (never a false miss: docs/node.md §12), so the render's hits are the
//! binary32 ones whenever the image is.

use crate::per_ray::{wide_areas, wide_cost_per_ray, wide_workload_of, WideWorkload};
use golden_model::float::FloatFormat;
use golden_model::wide::WideFormat;
use scene::scene::Scene;
use scene::wide::TLAS_BOX_BITS;
use std::fmt::Write as _;

/// Node widths tried.
pub const WIDTHS: [usize; 3] = [2, 4, 8];

/// One node width's outcome.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// N
    pub children: usize,
    /// the smallest q accepted, with its render; `None` when no q in 4..=16 is
    pub accepted: Option<WideWorkload>,
    /// q tried and why each was refused
    pub refused: Vec<(u32, String)>,
    /// LUT-cycles and DSP-cycles per ray (with synthesis)
    pub cost: Option<(f64, f64)>,
}

/// The fit: every width's candidate and the one chosen.
#[derive(Debug, Clone)]
pub struct WideFit {
    /// per width
    pub candidates: Vec<Candidate>,
    /// index into `candidates` of the choice
    pub chosen: usize,
}

impl WideFit {
    /// The chosen shape.
    pub fn format(&self) -> WideFormat {
        let w = self.candidates[self.chosen]
            .accepted
            .as_ref()
            .expect("a chosen candidate is accepted");
        w.format
    }

    /// The report (markdown), ending with `fit --wide: N=<n> q=<q>`.
    pub fn report(&self, name: &str, target_rate: f64) -> String {
        let mut s = format!(
            "# fit --wide: {name}\n\nRule: the render over the wide BVH equals the binary32 single-ray render and tests at most {:.2}x the child boxes of exact binary32 boxes in the same tree; TLAS q = {TLAS_BOX_BITS}.\n\n| N | q | child tests / ray | / exact boxes | node bytes / ray | LUT-cycles / ray | DSP-cycles / ray | refused |\n|---|---|---|---|---|---|---|---|\n",
            1.0 + target_rate
        );
        for c in &self.candidates {
            let refused = c
                .refused
                .iter()
                .map(|(q, why)| format!("q={q}: {why}"))
                .collect::<Vec<_>>()
                .join("; ");
            match &c.accepted {
                Some(w) => {
                    let k = &w.node;
                    let (l, d) = c.cost.map_or(("-".into(), "-".into()), |(l, d)| {
                        (format!("{l:.0}"), format!("{d:.1}"))
                    });
                    let _ = writeln!(
                        s,
                        "| {} | {} | {:.2} | {:.4} | {:.0} | {l} | {d} | {refused} |",
                        c.children,
                        w.format.box_bits(),
                        k.per_ray(k.child_tests),
                        w.child_test_ratio(),
                        k.per_ray(k.node_bytes),
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "| {} | none | - | - | - | - | - | {refused} |",
                        c.children
                    );
                }
            }
        }
        let f = self.format();
        let _ = writeln!(
            s,
            "\nfit --wide: N={} q={} (the cheapest {})",
            f.children(),
            f.box_bits(),
            if self.candidates[self.chosen].cost.is_some() {
                "in LUT-cycles per ray"
            } else {
                "in node bytes per ray (no synthesis)"
            }
        );
        s
    }
}

/// Fits the node shape of `scene` (see the module doc). `synth`: cost the
/// accepted shapes by synthesis (cached), else by node bytes per ray.
pub fn fit_wide(
    scene: &Scene,
    name: &str,
    width: u32,
    target_rate: f64,
    synth: bool,
) -> Result<WideFit, String> {
    if !(0.0..=1.0).contains(&target_rate) {
        return Err(format!("--target-rate {target_rate}: expected 0 to 1"));
    }
    // the renders' height is the scene's scaled with `width`: both checked before any work
    scene.render.image_size(Some(width), None)?;
    let mut candidates = Vec::new();
    for n in WIDTHS {
        let mut c = Candidate {
            children: n,
            accepted: None,
            refused: Vec::new(),
            cost: None,
        };
        for q in 4..=16 {
            let format = WideFormat::new(FloatFormat::BINARY32, n, q).map_err(|e| e.to_string())?;
            let w = wide_workload_of(scene, name, width, format, TLAS_BOX_BITS)?;
            let ratio = w.child_test_ratio();
            if !w.same_image {
                c.refused.push((q, "image differs".into()));
            } else if ratio > 1.0 + target_rate {
                c.refused.push((q, format!("{ratio:.4}x child tests")));
            } else {
                if synth {
                    let areas = wide_areas(format, TLAS_BOX_BITS, false)?;
                    c.cost = Some(wide_cost_per_ray(&w.node, &areas));
                }
                c.accepted = Some(w);
                break;
            }
        }
        candidates.push(c);
    }
    let key = |c: &Candidate| -> Option<f64> {
        let w = c.accepted.as_ref()?;
        Some(match c.cost {
            Some((l, _)) => l,
            None => w.node.per_ray(w.node.node_bytes),
        })
    };
    let chosen = (0..candidates.len())
        .filter_map(|i| key(&candidates[i]).map(|k| (k, i)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, i)| i)
        .ok_or_else(|| {
            format!(
                "{name}: no node shape (N = 2, 4, 8; q = 4..16) meets the rule at --target-rate {target_rate}"
            )
        })?;
    Ok(WideFit { candidates, chosen })
}
