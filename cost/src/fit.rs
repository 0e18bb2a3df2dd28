//! `fit`: the smallest silhouette-tester format and pipeline depth a scene
//! needs, with the reasons written down.
//!
//! 1. **Exponent bits** from the scene's coordinate range: the largest
//!    magnitude a difference `p − o` can take (rays start on a sphere of
//!    1.5 × the half diagonal around the mesh, so |p − o| ≤ 4 × the largest
//!    |coordinate| + the diagonal) must stay below the largest finite value
//!    with a factor 2^8 of headroom, and the smallest nonzero |coordinate|
//!    and the smallest nonzero box extent must be normal numbers.
//! 2. **Fraction bits**: the smallest F (4..=23) whose false-hit rate on
//!    the scene's rays (every box an exact BVH traversal visits) is below
//!    the target, with **zero false misses** and zero wrong bundle verdicts
//!    as hard rules (checked on the same rays, not assumed from the proof).
//! 3. **Stages** for a target Fmax: Yosys maps the unit for the iCE40 at a
//!    candidate stage count, `ltp -noff` gives the longest register-to-
//!    register path in cells, and the delay per cell calibrated by nextpnr
//!    on the slab unit (see `NS_PER_CELL`) turns it into an Fmax estimate;
//!    the stage count grows until the estimate meets the target. This is an
//!    estimate: only designs that fit an iCE40 get a routed Fmax (`synth`).

use crate::accuracy::{self, Case};
use crate::synth::{self, SynthOptions};
use golden_model::cull::bvh::{Bvh, Mesh};
use golden_model::float::FloatFormat;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Exact misses a format's false-hit rate must be measured over before the
/// format can be accepted.
pub const MIN_EXACT_MISSES: u64 = 100;

/// Delay per cell of the longest path, ns, calibrated on `slab e8m7 s4`
/// (nextpnr-ice40 on an HX8K: 22.84 MHz for a 224-cell path, mostly
/// SB_CARRY cells) — the carry-dominated paths of these datapaths.
pub const NS_PER_CELL: f64 = 0.195;

/// Fit options.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// false-hit rate target (exclusive)
    pub target_rate: f64,
    /// target Fmax, MHz
    pub target_mhz: f64,
    /// rays traced through the scene
    pub rays: usize,
    /// run Yosys to pick the stage count (otherwise: stages from the rule of thumb)
    pub synth: bool,
    /// seed
    pub seed: u64,
}

/// The result.
#[derive(Debug, Clone)]
pub struct Fit {
    /// exponent bits
    pub exp_bits: u32,
    /// fraction bits
    pub frac_bits: u32,
    /// pipeline stages
    pub stages: u32,
    /// `key=value` parameters of the silhouette unit
    pub params: Vec<String>,
    /// the report, markdown
    pub report: String,
}

fn bits_for_exponent(e: i32) -> u32 {
    // smallest E with emax = 2^(E-1) - 1 >= e
    (2..=11)
        .find(|&eb| (1i32 << (eb - 1)) - 1 >= e)
        .unwrap_or(11)
}

/// Loads a mesh from an OBJ file, or a whole TOML scene (the scene crate's
/// format) flattened into one world-space mesh: every instance's triangles
/// through its forward transform, so the fit sees the scene's real
/// coordinate range (e.g. instances translated far from the origin).
pub fn load(path: &Path) -> Result<(Mesh, PathBuf), String> {
    if path.extension().is_some_and(|x| x == "toml") {
        let scene = scene::scene::Scene::load(path).map_err(|e| e.to_string())?;
        let mut world = Mesh {
            vertices: Vec::new(),
            triangles: Vec::new(),
        };
        for inst in &scene.instances {
            let mesh = &scene.meshes[inst.mesh].1;
            let base = world.vertices.len() as u32;
            let t = &inst.transform;
            world.vertices.extend(mesh.vertices.iter().map(|v| {
                let row = |r: &[f32; 4]| r[0] * v[0] + r[1] * v[1] + r[2] * v[2] + r[3];
                [row(&t[0]), row(&t[1]), row(&t[2])]
            }));
            world
                .triangles
                .extend(mesh.triangles.iter().map(|tri| tri.map(|i| i + base)));
        }
        if world.triangles.is_empty() {
            return Err(format!(
                "{}: the scene has no instanced triangles",
                path.display()
            ));
        }
        return Ok((world, path.to_path_buf()));
    }
    let mesh = accuracy::load_mesh(path)?;
    if mesh.triangles.is_empty() {
        return Err(format!(
            "{}: the mesh has no triangles (nothing to fit)",
            path.display()
        ));
    }
    Ok((mesh, path.to_path_buf()))
}

/// Whether a format is accepted: a false-hit rate below `target` measured
/// over at least [`MIN_EXACT_MISSES`] exact misses (0 of 0 is no evidence:
/// a format so coarse that every box snaps onto the rays may have none),
/// and no error at all (false misses, wrong bundle verdicts).
pub fn accepts(exact_misses: u64, false_hit_rate: f64, errors: u64, target: f64) -> bool {
    exact_misses >= MIN_EXACT_MISSES && false_hit_rate < target && errors == 0
}

/// Runs the fit on `mesh`.
pub fn fit(mesh: &Mesh, name: &str, o: &FitOptions) -> Result<Fit, Box<dyn std::error::Error>> {
    let mut r = String::new();
    writeln!(r, "# Fit of the silhouette tester to `{name}`\n")?;
    writeln!(
        r,
        "Target: false-hit rate < {:.2} % on the scene's rays, zero false misses, Fmax ≥ {} MHz (iCE40 estimate).\n",
        100.0 * o.target_rate,
        o.target_mhz
    )?;
    // 1. exponent
    let (lo, hi) = mesh.bounds();
    let max_abs = (0..3)
        .map(|i| (lo[i].abs()).max(hi[i].abs()) as f64)
        .fold(0.0, f64::max);
    let diag = (0..3)
        .map(|i| ((hi[i] - lo[i]) as f64).powi(2))
        .sum::<f64>()
        .sqrt();
    let min_abs = mesh
        .vertices
        .iter()
        .flat_map(|v| v.iter())
        .map(|x| x.abs() as f64)
        .filter(|x| *x > max_abs * f64::powi(2.0, -24))
        .fold(f64::MAX, f64::min);
    let bvh = Bvh::build(mesh, 4);
    let min_extent = bvh
        .nodes
        .iter()
        .flat_map(|n| (0..3).map(move |i| (n.max[i] - n.min[i]) as f64))
        .filter(|x| *x > 0.0)
        .fold(f64::MAX, f64::min);
    let big = 4.0 * max_abs + diag;
    let e_hi = big.log2().ceil() as i32 + 8;
    let small = min_abs.min(min_extent);
    let e_lo = small.log2().floor() as i32;
    let eb_hi = bits_for_exponent(e_hi);
    let eb_lo = bits_for_exponent(1 - e_lo); // emin = 1 - emax <= e_lo
    let exp_bits = eb_hi.max(eb_lo).max(2);
    writeln!(r, "## Exponent: E = {exp_bits}\n")?;
    writeln!(
        r,
        "* bounds {lo:?} … {hi:?}; largest |coordinate| {max_abs:.4e}, diagonal {diag:.4e}"
    )?;
    writeln!(
        r,
        "* largest difference |p − o| ≤ 4·max + diagonal = {big:.4e} = 2^{:.2}; with 2^8 headroom the format needs emax ≥ {e_hi} → E ≥ {eb_hi}",
        big.log2()
    )?;
    writeln!(
        r,
        "* smallest |coordinate| above max·2^-24 (smaller ones are below the mesh's own binary32 resolution and may become subnormal) {min_abs:.4e}, smallest nonzero BVH box extent {min_extent:.4e} → 2^{e_lo}; normal numbers need emin ≤ {e_lo} → E ≥ {eb_lo}"
    )?;
    writeln!(
        r,
        "* E = max of the two = {exp_bits} (the exact products use E + 2)\n"
    )?;
    // 2. fraction
    let cases: Vec<Case> = accuracy::scene_cases(mesh, o.rays, o.seed);
    writeln!(r, "## Fraction bits\n")?;
    writeln!(
        r,
        "{} random rays of the mesh traversed through its BVH (leaves ≤ 4 triangles) by the exact test: {} box tests.\n",
        o.rays,
        cases.len()
    )?;
    writeln!(r, "| F | false-hit rate | false misses | slab f.hit / f.miss | bundles resolved | wrong bundle verdicts | verdict |")?;
    writeln!(r, "|---|---|---|---|---|---|---|")?;
    let mut chosen = None;
    for f in 4..=23u32 {
        if exp_bits + 2 * f > 60 {
            break;
        }
        let fmt = FloatFormat::new(exp_bits, f)?;
        let accuracy::RayStatsAll {
            silhouette: sil,
            slab: slb,
            ..
        } = accuracy::ray_stats(fmt, &cases);
        let nb = cases.len().min(5000);
        let b = accuracy::bundle_stats(fmt, &cases[..nb], 1e-3, o.seed);
        let misses = sil.n - sil.hits;
        let judged = misses >= MIN_EXACT_MISSES;
        let ok = accepts(
            misses,
            sil.false_hit_rate(),
            sil.false_misses + b.wrong,
            o.target_rate,
        );
        writeln!(
            r,
            "| {f} | {:.3e} | {} | {:.2e} / {} | {:.3} | {} | {} |",
            sil.false_hit_rate(),
            sil.false_misses,
            slb.false_hit_rate(),
            slb.false_misses,
            b.resolved(),
            b.wrong,
            if ok {
                "meets the target".to_string()
            } else if !judged {
                format!("not judged: {misses} exact misses (at least {MIN_EXACT_MISSES} needed)")
            } else {
                "too coarse".to_string()
            }
        )?;
        if sil.false_misses != 0 || b.wrong != 0 {
            return Err(format!(
                "F={f}: {} false misses, {} wrong bundle verdicts: the conservative guarantee is broken",
                sil.false_misses, b.wrong
            )
            .into());
        }
        if ok {
            chosen = Some(f);
            break;
        }
    }
    let frac_bits = chosen.ok_or("no format up to F = 23 meets the target")?;
    writeln!(r, "\nF = {frac_bits}: the first fraction width that meets the target (format e{exp_bits}m{frac_bits}, {} bits).\n", 1 + exp_bits + frac_bits)?;
    // 3. stages
    writeln!(r, "## Pipeline stages\n")?;
    let budget_cells = (1000.0 / o.target_mhz / NS_PER_CELL).floor() as u64;
    writeln!(
        r,
        "Budget: {:.1} ns per stage at {} MHz ≈ {budget_cells} cells of {NS_PER_CELL} ns (calibration: slab e8m7 s4 on an HX8K).\n",
        1000.0 / o.target_mhz,
        o.target_mhz
    )?;
    let base = |s: u32| {
        vec![
            format!("exp_bits={exp_bits}"),
            format!("frac_bits={frac_bits}"),
            "origin=shared".to_string(),
            "rounding=conservative".to_string(),
            format!("stages={s}"),
        ]
    };
    let mut stages = 4u32;
    if o.synth {
        let so = SynthOptions {
            generic: false,
            ecp5: false,
            xilinx: false,
            pnr: false,
            pnr_ecp5: false,
            target_mhz: o.target_mhz,
            ..Default::default()
        };
        writeln!(r, "| stages | iCE40 LUT4 | longest path (cells) | estimated Fmax MHz | verdict |\n|---|---|---|---|---|")?;
        let mut s = 0u32;
        let mut tries = 0;
        loop {
            let g = rtl_gen::flow::generate("silhouette", &base(s))?;
            let rep = synth::run(&g, &so)?;
            let ice = rep.ice40.clone().unwrap_or_default();
            let est = 1000.0 / (ice.depth.max(1) as f64 * NS_PER_CELL);
            let ok = est >= o.target_mhz;
            writeln!(
                r,
                "| {s} | {} | {} | {est:.1} | {} |",
                ice.luts,
                ice.depth,
                if ok { "meets the target" } else { "too slow" }
            )?;
            if ok || s >= 16 || tries >= 4 {
                stages = s;
                break;
            }
            // the path shrinks roughly as 1/(stages + 1): jump there, then step
            s = if s == 0 {
                ((ice.depth as f64 / budget_cells.max(1) as f64).ceil() as u32)
                    .saturating_sub(1)
                    .max(1)
            } else {
                s + 1
            }
            .min(16);
            tries += 1;
        }
        writeln!(r, "\nstages = {stages}.\n")?;
    } else {
        writeln!(
            r,
            "Not synthesised (`--no-synth`): stages = {stages}, the unit's default.\n"
        )?;
    }
    let params = base(stages);
    writeln!(
        r,
        "## Result\n\n`rtl-gen emit silhouette -p {}`\n",
        params.join(" -p ")
    )?;
    Ok(Fit {
        exp_bits,
        frac_bits,
        stages,
        params,
        report: r,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rate_over_too_few_exact_misses_is_not_accepted() {
        assert!(accepts(MIN_EXACT_MISSES, 0.0, 0, 0.01));
        assert!(!accepts(0, 0.0, 0, 0.01), "0 false hits of 0 misses");
        assert!(!accepts(MIN_EXACT_MISSES - 1, 0.0, 0, 0.01));
        assert!(!accepts(10_000, 0.02, 0, 0.01));
        assert!(!accepts(10_000, 0.0, 1, 0.01));
    }
}
