//! `fit`: the smallest box-tester format and pipeline depth a scene needs,
//! judged on the scene's own render, with the reasons written down.
//!
//! The workload is the renderer's: camera, shadow and AO rays, bundles and
//! cull planes as `render` uses them, every box test where the hardware does
//! it (instance boxes relative to the scene anchor, everything below in the
//! instance's model space). A candidate format `eXmY` is the silhouette unit
//! with ray and boxes rounded outward ([`scene::tester::Reduced`], proven
//! never to lose a hit); `fit` still checks, on the same render:
//!
//! 1. **ulp rule** (before rendering): in each coordinate space (world
//!    relative to the anchor, each mesh's model space) the format's ulp at
//!    the largest |coordinate| must not exceed the smallest box size (a box's
//!    largest extent; boxes of size 0 excluded), else the boxes collapse onto
//!    the format's grid;
//! 2. **zero false misses**: every single-ray miss of the candidate is
//!    tested exactly (rationals) on the *unrounded* binary32 ray and box;
//! 3. **the same image**: instance, primitive and `t` of every pixel equal
//!    the binary32 render's;
//! 4. **cost**: box tests per ray at most `1 + target` times binary32's (a
//!    false hit costs box tests; the rate has a real denominator).
//!
//! Per exponent width (4..=8) the smallest accepted fraction width is found
//! by bisection (box tests per ray fall as the fraction grows); the pick is
//! the narrowest accepted format. Then stages for the target clock (a
//! calibrated iCE40 estimate, labelled as such) and whether the unit fits
//! the named device.

use crate::synth::{self, SynthOptions};
use golden_model::cull::bvh::Bvh;
use golden_model::float::FloatFormat;
use scene::bvh::Accel;
use scene::render::{render, Frame};
use scene::scene::Scene;
use scene::tester::{Checked, Golden, Reduced};
use scene::trace::TraceOpts;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// Delay per cell of the longest path, ns, calibrated on `slab e8m7 s4`
/// (nextpnr-ice40 on an HX8K: 22.84 MHz for a 224-cell path, mostly
/// SB_CARRY cells) — the carry-dominated paths of these datapaths.
pub const NS_PER_CELL: f64 = 0.195;

/// Exponent widths tried.
pub const EXP_BITS: std::ops::RangeInclusive<u32> = 4..=8;
/// Fraction widths tried.
pub const FRAC_BITS: std::ops::RangeInclusive<u32> = 3..=23;

/// Devices the report checks the unit against: name, LUT4 count.
pub const DEVICES: &[(&str, u64)] = &[
    ("ice40up5k", 5_280),
    ("ice40hx8k", 7_680),
    ("ecp5-25f", 24_288),
    ("ecp5-85f", 83_640),
];

/// Fit options.
#[derive(Debug, Clone)]
pub struct FitOptions {
    /// allowed increase of box tests per ray over binary32 (0.01 = 1 %)
    pub target_rate: f64,
    /// target Fmax, MHz
    pub target_mhz: f64,
    /// render width (default: the scene's)
    pub width: Option<u32>,
    /// run Yosys to pick the stage count (otherwise: the default 4)
    pub synth: bool,
    /// device the unit must fit (one of [`DEVICES`])
    pub device: String,
    /// test every single-ray miss exactly, not only those the binary32 unit calls hits
    pub exact_all: bool,
}

/// One judged candidate.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// the format
    pub format: FloatFormat,
    /// `None`: accepted; else the reason it was rejected
    pub rejected: Option<String>,
    /// box tests per ray (`None` if not rendered)
    pub box_tests_per_ray: Option<f64>,
    /// single-ray misses (before a cut-short render's cut)
    pub misses: u64,
    /// of them, tested with the exact test
    pub misses_checked: u64,
    /// false misses found
    pub false_misses: u64,
    /// same image as binary32
    pub same_image: Option<bool>,
}

/// The result.
#[derive(Debug, Clone)]
pub struct Fit {
    /// the picked format
    pub format: FloatFormat,
    /// pipeline stages
    pub stages: u32,
    /// iCE40 LUT4 of the unit at `stages` (when synthesised)
    pub ice40_luts: Option<u64>,
    /// the device checked and whether the unit fits it (`None`: not synthesised)
    pub device_fit: Option<bool>,
    /// binary32 box tests per ray
    pub binary32_box_tests_per_ray: f64,
    /// every candidate judged, in the order tried
    pub candidates: Vec<Candidate>,
    /// `key=value` parameters of the silhouette unit
    pub params: Vec<String>,
    /// render size
    pub size: (u32, u32),
    /// wall time of the format search, s
    pub seconds: f64,
    /// the report, markdown
    pub report: String,
}

impl Fit {
    /// The picked candidate's figures.
    pub fn picked(&self) -> &Candidate {
        self.candidates
            .iter()
            .find(|c| c.format == self.format && c.rejected.is_none())
            .expect("the picked format was accepted")
    }
    /// The result as JSON (`rtl-gen fit --json`).
    pub fn json(&self, scene: &str) -> serde_json::Value {
        let p = self.picked();
        serde_json::json!({
            "scene": scene,
            "format": self.format.to_string(),
            "exp_bits": self.format.exp_bits(),
            "frac_bits": self.format.frac_bits(),
            "stages": self.stages,
            "params": self.params,
            "width": self.size.0,
            "height": self.size.1,
            "box_tests_per_ray": p.box_tests_per_ray,
            "binary32_box_tests_per_ray": self.binary32_box_tests_per_ray,
            "false_misses": p.false_misses,
            "misses": p.misses,
            "misses_tested_exactly": p.misses_checked,
            "same_image_as_binary32": p.same_image,
            "ice40_luts": self.ice40_luts,
            "device_fit": self.device_fit,
            "search_seconds": self.seconds,
            "candidates": self.candidates.iter().map(|c| serde_json::json!({
                "format": c.format.to_string(),
                "rejected": c.rejected,
                "box_tests_per_ray": c.box_tests_per_ray,
                "false_misses": c.false_misses,
                "same_image_as_binary32": c.same_image,
            })).collect::<Vec<_>>(),
        })
    }
}

/// Loads a TOML scene, or an OBJ mesh placed in a default scene: one
/// instance, identity transform, the camera on the +z side of its box
/// looking at the centre, one point light at the camera.
pub fn load(path: &Path) -> Result<Scene, String> {
    if path.extension().is_some_and(|x| x == "toml") {
        return Scene::load(path).map_err(|e| e.to_string());
    }
    let mesh = crate::accuracy::load_mesh(path)?;
    if mesh.triangles.is_empty() {
        return Err(format!(
            "{}: the mesh has no triangles (nothing to fit)",
            path.display()
        ));
    }
    let (lo, hi) = mesh.bounds();
    let c = [0, 1, 2].map(|i| (lo[i] as f64 + hi[i] as f64) / 2.0);
    let diag = (0..3)
        .map(|i| (hi[i] as f64 - lo[i] as f64).powi(2))
        .sum::<f64>()
        .sqrt()
        .max(1e-6);
    let eye = [c[0] + 0.35 * diag, c[1] + 0.45 * diag, c[2] + 1.6 * diag];
    let abs = std::fs::canonicalize(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let text = format!(
        "[render]\nwidth = 128\nheight = 128\n[camera]\nposition = [{:?}, {:?}, {:?}]\nlook_at = [{:?}, {:?}, {:?}]\nfov_y = 40.0\n\
         [meshes.m]\nobj = {:?}\n[[instances]]\nmesh = \"m\"\n[[lights]]\nkind = \"point\"\nposition = [{:?}, {:?}, {:?}]\ncolor = [{:?}, {:?}, {:?}]\n",
        eye[0], eye[1], eye[2], c[0], c[1], c[2],
        abs.display().to_string(),
        eye[0], eye[1], eye[2],
        3.0 * diag * diag, 3.0 * diag * diag, 3.0 * diag * diag,
    );
    Scene::parse(&text, path).map_err(|e| e.to_string())
}

/// The largest |coordinate|, the smallest nonzero box size and the smallest
/// nonzero |coordinate| of `bvh`, coordinates relative to `anchor`.
fn extents(bvh: &Bvh, anchor: [f64; 3]) -> (f64, f64, f64) {
    let mut big = 0f64;
    let mut small = f64::INFINITY;
    let mut least = f64::INFINITY;
    for n in &bvh.nodes {
        let mut size = 0f64;
        for i in 0..3 {
            for x in [n.min[i] as f64 - anchor[i], n.max[i] as f64 - anchor[i]] {
                big = big.max(x.abs());
                if x != 0.0 {
                    least = least.min(x.abs());
                }
            }
            size = size.max(n.max[i] as f64 - n.min[i] as f64);
        }
        if size > 0.0 {
            small = small.min(size);
        }
    }
    (big, small, least)
}

/// The ulp of `fmt` at magnitude `x` (normal range).
fn ulp(fmt: FloatFormat, x: f64) -> f64 {
    let e = x.log2().floor().max(fmt.emin() as f64);
    (e - fmt.frac_bits() as f64).exp2()
}

/// The largest finite value of `fmt`.
fn max_value(fmt: FloatFormat) -> f64 {
    (2.0 - (-(fmt.frac_bits() as f64)).exp2()) * (fmt.emax() as f64).exp2()
}

/// Renders `scene` with `tester`.
fn frame(
    scene: &Scene,
    accel: &Accel,
    tester: &dyn scene::tester::BoxTester,
    w: u32,
    h: u32,
) -> Frame {
    render(scene, accel, tester, TraceOpts::default(), w, h, false)
}

/// Runs the fit on `scene`.
pub fn fit(scene: &Scene, name: &str, o: &FitOptions) -> Result<Fit, Box<dyn std::error::Error>> {
    let device = DEVICES.iter().find(|d| d.0 == o.device).ok_or_else(|| {
        format!(
            "--device {}: expected one of {}",
            o.device,
            DEVICES.iter().map(|d| d.0).collect::<Vec<_>>().join(", ")
        )
    })?;
    if !(o.target_rate >= 0.0 && o.target_rate.is_finite()) {
        return Err(format!(
            "--target-rate {}: must be a finite number ≥ 0",
            o.target_rate
        )
        .into());
    }
    let (w, h) = scene.render.image_size(o.width, None)?;
    let start = Instant::now();
    let accel = Accel::build(scene, true);
    let anchor = Reduced::scene_anchor(&accel);
    let base = frame(scene, &accel, &Golden::default(), w, h);
    let base_cost = base.stats.total().box_tests_per_ray();
    let base_tests = {
        let t = base.stats.total();
        t.ray_box_tests + t.bundle_tests
    };
    // the same image means the same rays, so more tests than this is a rejection
    let budget = ((1.0 + o.target_rate) * base_tests as f64).floor() as u64;
    let mut r = String::new();
    writeln!(r, "# Fit of the box tester to `{name}`\n")?;
    writeln!(
        r,
        "Workload: the renderer's own rays at {w}x{h} (camera, shadow and AO rays; bundles ≤ 16; cull planes on): {} rays, {base_cost:.3} box tests per ray with the binary32 unit.\n",
        base.rays()
    )?;
    writeln!(
        r,
        "Box tests where the hardware does them: the instance boxes relative to the scene anchor {anchor:?} (centre of the top-level root box), everything below in the instance's model space. A candidate `eXmY` is the silhouette unit with ray and box rounded outward (`rtl-gen render --box-format eXmY`; bounded origin, direction intervals, conservative).\n"
    )?;
    writeln!(
        r,
        "Accepted when: ulp at the largest |coordinate| ≤ the smallest box size in every space; 0 false misses (every single-ray miss tested exactly on the unrounded binary32 ray); the image (instance, primitive, `t` per pixel) equals binary32's; box tests per ray ≤ {:.2} × binary32's ({:.3}).\n",
        1.0 + o.target_rate,
        (1.0 + o.target_rate) * base_cost
    )?;
    // coordinate spaces: world (relative to the anchor) and each mesh's model space
    let a64 = anchor.map(|x| x as f64);
    let mut spaces = vec![("world (top level)".to_string(), extents(&accel.tlas, a64))];
    for (m, blas) in accel.blas.iter().enumerate() {
        spaces.push((
            format!("mesh `{}`", scene.meshes[m].0),
            extents(&blas.bvh, [0.0; 3]),
        ));
    }
    writeln!(r, "| space | largest coordinate magnitude | smallest box size | smallest nonzero coordinate magnitude |\n|---|---|---|---|")?;
    for (s, (big, small, least)) in &spaces {
        writeln!(r, "| {s} | {big:.4e} | {small:.4e} | {least:.4e} |")?;
    }
    let ulp_reason = |fmt: FloatFormat| -> Option<String> {
        spaces.iter().find_map(|(s, (big, small, _))| {
            if *big >= max_value(fmt) / 16.0 {
                return Some(format!(
                    "{s}: coordinate magnitude {big:.3e} beyond the range / 16"
                ));
            }
            let u = ulp(fmt, *big);
            (u > *small)
                .then(|| format!("{s}: ulp {u:.3e} at {big:.3e} > smallest box {small:.3e}"))
        })
    };
    let mut candidates: Vec<Candidate> = Vec::new();
    let judge = |fmt: FloatFormat, candidates: &mut Vec<Candidate>| -> bool {
        if let Some(c) = candidates.iter().find(|c| c.format == fmt) {
            return c.rejected.is_none();
        }
        let mut c = Candidate {
            format: fmt,
            rejected: None,
            box_tests_per_ray: None,
            misses: 0,
            misses_checked: 0,
            false_misses: 0,
            same_image: None,
        };
        if let Some(why) = ulp_reason(fmt) {
            c.rejected = Some(why);
        } else {
            match Reduced::new(fmt) {
                Err(e) => c.rejected = Some(e),
                Ok(t) => {
                    let mut t = Checked::with_budget(t.with_world_anchor(anchor), budget);
                    t.exact_all = o.exact_all;
                    let f = frame(scene, &accel, &t, w, h);
                    let cost = f.stats.total().box_tests_per_ray();
                    c.misses = t.misses.load(Ordering::Relaxed);
                    c.misses_checked = t.exact_checks.load(Ordering::Relaxed);
                    c.false_misses = t.false_misses.load(Ordering::Relaxed);
                    let same = f.same_hits(&base);
                    if !t.over_budget() {
                        c.box_tests_per_ray = Some(cost);
                        c.same_image = Some(same);
                    }
                    c.rejected = if c.false_misses != 0 {
                        Some(format!("{} false misses", c.false_misses))
                    } else if t.over_budget() {
                        Some(format!(
                            "over {budget} box tests (the budget: {:.2} × binary32's, with the same rays); render cut short",
                            1.0 + o.target_rate
                        ))
                    } else if !same {
                        Some("image differs from binary32".into())
                    } else if cost > (1.0 + o.target_rate) * base_cost {
                        Some(format!(
                            "{:.2} % more box tests per ray",
                            100.0 * (cost / base_cost - 1.0)
                        ))
                    } else {
                        None
                    };
                }
            }
        }
        let ok = c.rejected.is_none();
        candidates.push(c);
        ok
    };
    let mut best: Option<FloatFormat> = None;
    let mut skipped = String::new();
    let width = |f: FloatFormat| f.exp_bits() + f.frac_bits();
    // the smallest nonzero magnitude that matters: coordinates and box sizes
    let tiny = spaces
        .iter()
        .map(|(_, x)| x.1.min(x.2))
        .fold(f64::INFINITY, f64::min);
    for e in EXP_BITS {
        if let Some(b) = best {
            let emin = (b.emin() as f64).exp2();
            if tiny >= emin {
                // every value is normal in b's exponent: a wider exponent with fewer
                // fraction bits is coarser at every value that matters
                skipped = format!(
                    "Exponents e{e}..e{} not tried: every nonzero coordinate and box size (smallest {tiny:.3e}) is a normal number of {b} (≥ 2^{}), so a wider exponent with fewer fraction bits is coarser at every one of them.\n",
                    EXP_BITS.end(),
                    b.emin()
                );
                break;
            }
        }
        // the narrowest accepted fraction for this exponent, by bisection (box
        // tests per ray fall as the fraction grows)
        let (mut lo, mut hi) = (*FRAC_BITS.start(), *FRAC_BITS.end());
        if let Some(b) = best {
            // only narrower than the best so far is of interest
            if width(b) <= e + lo {
                continue;
            }
            hi = hi.min(width(b) - e - 1);
        }
        let fmt = |f: u32| FloatFormat::new(e, f).expect("exponent 4..=8, fraction 3..=23");
        // with a bound from a narrower exponent, its widest fraction first: if that
        // fails, every narrower one does
        if best.is_some() && !judge(fmt(hi), &mut candidates) {
            continue;
        }
        let mut found = None;
        while lo <= hi {
            let mid = (lo + hi) / 2;
            if judge(fmt(mid), &mut candidates) {
                found = Some(mid);
                hi = mid - 1;
            } else {
                lo = mid + 1;
            }
        }
        if let Some(f) = found {
            if best.is_none_or(|b| width(fmt(f)) < width(b)) {
                best = Some(fmt(f));
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    writeln!(r, "\n## Candidates ({seconds:.1} s)\n")?;
    if !skipped.is_empty() {
        writeln!(r, "{skipped}")?;
    }
    writeln!(r, "Single-ray misses: a miss the binary32 unit also reports is an exact miss (that unit is proven conservative and checked against the exact test by its own tests); every other miss, and one in {}, is tested with the exact rational test{}.\n", Checked::<Golden>::SAMPLE, if o.exact_all { " — here every miss was (`--exact-all`)" } else { " (`--exact-all`: every miss)" })?;
    writeln!(r, "| format | box tests/ray | vs binary32 | single-ray misses | tested exactly | false misses | same image | verdict |\n|---|---|---|---|---|---|---|---|")?;
    for c in &candidates {
        let (cost, rel) = match c.box_tests_per_ray {
            Some(x) => (
                format!("{x:.3}"),
                format!("{:+.2} %", 100.0 * (x / base_cost - 1.0)),
            ),
            None => ("–".into(), "–".into()),
        };
        writeln!(
            r,
            "| {} | {cost} | {rel} | {} | {} | {} | {} | {} |",
            c.format,
            c.misses,
            c.misses_checked,
            c.false_misses,
            c.same_image.map_or("–".into(), |s| if s {
                "yes".to_string()
            } else {
                "no".to_string()
            }),
            c.rejected.as_deref().unwrap_or("accepted"),
        )?;
    }
    let format = best.ok_or("no format e4..e8 × m3..m23 meets the target")?;
    writeln!(
        r,
        "\nFormat {format} ({} bits): the narrowest accepted.\n",
        1 + width(format)
    )?;
    // stages and device
    writeln!(r, "## Pipeline stages and device\n")?;
    let ecp5 = device.0.starts_with("ecp5");
    // on ECP5 the unit is routed, with its registers placed by the delay model
    let balanced = o.synth && ecp5;
    let params = |s: u32| {
        let mut p = vec![
            format!("exp_bits={}", format.exp_bits()),
            format!("frac_bits={}", format.frac_bits()),
            "mode=bundle".to_string(),
            "origin=bounded".to_string(),
            "rounding=conservative".to_string(),
            format!("stages={s}"),
        ];
        if balanced {
            p.push("pipeline=balanced".to_string());
        }
        p
    };
    let mut stages = 4u32;
    let mut ice40_luts = None;
    let mut device_luts = None;
    if balanced {
        let (s, luts) = routed_ecp5_stages(&mut r, &params, o.target_mhz)?;
        stages = s;
        device_luts = luts;
    } else if o.synth {
        let budget_cells = (1000.0 / o.target_mhz / NS_PER_CELL).floor() as u64;
        writeln!(
            r,
            "Estimate, not a routed figure: {:.1} ns per stage at {} MHz ≈ {budget_cells} cells of {NS_PER_CELL} ns (calibration: slab e8m7 s4 routed on an HX8K).\n",
            1000.0 / o.target_mhz,
            o.target_mhz
        )?;
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
            let g = rtl_flow::generate("silhouette", &params(s))?;
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
                ice40_luts = Some(ice.luts);
                device_luts = Some(ice.luts);
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
            "Not synthesised (`--no-synth`): stages = {stages}, the default; device fit unknown.\n"
        )?;
    }
    let device_fit = device_luts.map(|l| l <= device.1);
    if let Some(l) = device_luts {
        writeln!(
            r,
            "Device {}: {l} LUT4 needed ({} mapping) of {} → {} ({}).\n",
            device.0,
            if ecp5 { "synth_ecp5" } else { "synth_ice40" },
            device.1,
            if l <= device.1 {
                "fits"
            } else {
                "does NOT fit"
            },
            if balanced {
                "the unit alone placed and routed on the LFE5U-85F-6 above"
            } else {
                "LUT4 count only, not placed: routing may need more room"
            }
        )?;
    }
    let p = params(stages);
    writeln!(
        r,
        "## Result\n\n`rtl-gen emit silhouette -p {}`\n",
        p.join(" -p ")
    )?;
    Ok(Fit {
        format,
        stages,
        ice40_luts,
        device_fit,
        binary32_box_tests_per_ray: base_cost,
        candidates,
        params: p,
        size: (w, h),
        seconds,
        report: r,
    })
}

/// Stages of the balanced unit that meet `target_mhz` routed on the
/// LFE5U-85F-6, by the search `rtl-gen fpga` uses ([`crate::fpga::search_stages`]:
/// the delay model's guess, up two stages while timing fails, down to the fewest
/// a met route's Fmax suggests, at most four routes, at most 32 stages). Writes
/// the table into `r`; returns the stages and their ECP5 LUT4.
fn routed_ecp5_stages(
    r: &mut String,
    params: &dyn Fn(u32) -> Vec<String>,
    target_mhz: f64,
) -> Result<(u32, Option<u64>), Box<dyn std::error::Error>> {
    use crate::fpga::{first_guess, search_stages, NS_PER_LEVEL_ECP5};
    let first = first_guess("silhouette", params, target_mhz, NS_PER_LEVEL_ECP5, 32)?;
    writeln!(
        r,
        "Routed, not estimated: the unit with `pipeline=balanced` in the timing shell, `synth_ecp5` and `nextpnr-ecp5` on the LFE5U-85F-6 (speed grade 6, the slower of the two ECP5 boards) at {target_mhz} MHz; first guess from the delay model at {NS_PER_LEVEL_ECP5} ns a level.\n"
    )?;
    writeln!(r, "| stages | modelled period (LUT levels) | ECP5 LUT4 | FF | MULT18X18D | routed Fmax MHz | verdict |\n|---|---|---|---|---|---|---|")?;
    let so = SynthOptions::ecp5_routed(target_mhz);
    let mut luts_at: Vec<(u32, u64)> = Vec::new();
    let mut route = |s: u32| -> Result<Option<f64>, Box<dyn std::error::Error>> {
        let g = rtl_flow::generate("silhouette", &params(s))?;
        let rep = synth::run(&g, &so)?;
        let e = rep.ecp5.clone().unwrap_or_default();
        let fmax = rep.pnr_ecp5.as_ref().and_then(|p| p.fmax_mhz);
        let ok = fmax.is_some_and(|f| f >= target_mhz);
        writeln!(
            r,
            "| {s} | {:.1} | {} | {} | {} | {} | {} |",
            g.modelled_period()?,
            e.luts,
            e.ffs,
            e.dsps,
            fmax.map_or("not routed".to_string(), |f| format!("{f:.1}")),
            if ok { "meets the target" } else { "too slow" }
        )?;
        luts_at.push((s, e.luts));
        Ok(fmax)
    };
    let (s, ok) = search_stages(first, 32, target_mhz, &mut route)?;
    writeln!(
        r,
        "\nstages = {s}{}.\n",
        if ok { "" } else { " (the clock is NOT met)" }
    )?;
    let luts = luts_at.iter().find(|(k, _)| *k == s).map(|(_, l)| *l);
    Ok((s, luts))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ulp_of_binary32_at_one_is_two_to_minus_23() {
        assert_eq!(ulp(FloatFormat::BINARY32, 1.0), (-23f64).exp2());
        assert_eq!(ulp(FloatFormat::BINARY32, 1.5e4), (13.0 - 23f64).exp2());
    }
}
