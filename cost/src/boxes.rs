//! The box testers side by side (issue #19), all in one run with one Yosys:
//! the silhouette tester in ray and bundle mode, the RNE slab, the
//! conservative slab (the equal-accuracy competitor) and the slab's per-ray
//! reciprocal, counted per box test as `3 · frecip / N` with N the box tests
//! per ray measured on the shipped scenes; RAABB's published figures as
//! references. Printed by `rtl-gen boxes`; the targets of the issue are
//! checked and printed, never asserted in a timed test.

use crate::synth::{self, SynthOptions, SynthReport};
use std::path::Path;

/// RAABB (Xilinx XST estimates, exponent 11, conservative interval slab):
/// (fraction bits, LUT, FF, DSP48) as published.
pub const RAABB: [(u32, u64, u64, u64); 2] = [(7, 9_338, 5_858, 0), (23, 17_561, 10_686, 36)];

/// The designs of the comparison: (label, unit, parameters without the format).
pub const DESIGNS: [(&str, &str, &[&str]); 5] = [
    ("silhouette ray", "silhouette", &["mode=ray"]),
    ("silhouette bundle", "silhouette", &["mode=bundle"]),
    ("slab conservative", "slab", &["rounding=conservative"]),
    ("slab RNE", "slab", &["rounding=nearest"]),
    ("frecip RTZ", "frecip", &["round=rtz"]),
];

/// The node tester beside them (issue #36): (label, N), q = 8, the xc7
/// build's products ([`crate::per_ray::node_products`]); its figures are per
/// node test, divided by N for the per-child table.
pub const NODE_SHAPES: [(&str, u32); 2] = [("node N=4 q=8", 4), ("node N=8 q=8", 8)];

/// Issue #36's per-child targets: (N, at most xc7 LUT, at most DSP48).
const NODE_TARGETS: [(u32, f64, f64); 2] = [(4, 1_500.0, 2.0), (8, 1_000.0, 2.0)];

/// One synthesised design.
#[derive(Debug, Clone)]
pub struct Row {
    /// label of [`DESIGNS`]
    pub label: &'static str,
    /// fraction bits (exponent 8)
    pub frac: u32,
    /// the synthesis report (default when synthesis failed)
    pub report: SynthReport,
    /// why synthesis failed (first line of the tool's error), if it did
    pub failed: Option<String>,
}

impl Row {
    fn xilinx_luts(&self) -> u64 {
        self.report.xilinx.as_ref().map_or(0, |x| x.luts)
    }
    fn ok(&self) -> bool {
        self.failed.is_none()
    }
}

/// Box tests per ray of one shipped scene (single rays, no bundles, no
/// planes: every box test of the traversal).
#[derive(Debug, Clone)]
pub struct SceneLoad {
    /// scene file name
    pub scene: String,
    /// rays traced
    pub rays: u64,
    /// box tests per ray
    pub per_ray: f64,
}

/// Synthesises every design at every fraction width of `fracs` (exponent 8,
/// `stages` pipeline registers; the reciprocal, which runs once per ray,
/// `recip_stages`), Xilinx / iCE40 / ECP5, no place and route.
pub fn synthesise(
    fracs: &[u32],
    stages: u32,
    recip_stages: u32,
    cached_only: bool,
) -> Result<Vec<Row>, String> {
    let o = SynthOptions {
        generic: false,
        pnr: false,
        pnr_ecp5: false,
        cached_only,
        ..SynthOptions::default()
    };
    let mut rows = Vec::new();
    for &frac in fracs {
        let nodes: Vec<(&'static str, &str, Vec<String>)> = NODE_SHAPES
            .iter()
            .map(|&(label, n)| {
                let p = vec![
                    format!("children={n}"),
                    "box_bits=8".to_string(),
                    format!("products={}", crate::per_ray::node_products(8)),
                ];
                (label, "node", p)
            })
            .collect();
        let designs = DESIGNS
            .iter()
            .map(|&(label, unit, extra)| {
                (label, unit, extra.iter().map(|s| s.to_string()).collect())
            })
            .chain(nodes);
        for (label, unit, mut p) in designs {
            let depth = if unit == "frecip" {
                recip_stages
            } else {
                stages
            };
            p.extend([
                "exp_bits=8".into(),
                format!("frac_bits={frac}"),
                format!("stages={depth}"),
            ]);
            let g = rtl_flow::generate(unit, &p).map_err(|e| format!("{unit}: {e}"))?;
            eprintln!("synthesising {} ...", g.module.name);
            // one design the tools cannot map must not lose the others' figures
            let (report, failed) = match synth::run(&g, &o) {
                Ok(r) => (r, None),
                Err(e) => {
                    let why = e.to_string();
                    let assertion = why.lines().find(|l| l.contains("yosys.wasm!abc::"));
                    let first = why.lines().next().unwrap_or("").to_string();
                    let reason = match assertion {
                        Some(_) => format!("{first} (an ABC9 assertion inside Yosys)"),
                        None => first,
                    };
                    eprintln!("{}: synthesis failed: {reason}", g.module.name);
                    (SynthReport::default(), Some(reason))
                }
            };
            rows.push(Row {
                label,
                frac,
                report,
                failed,
            });
        }
    }
    Ok(rows)
}

/// Box tests per ray of each scene in `scenes`, rendered at `width` pixels
/// across with single rays and no planes.
pub fn scene_loads(scenes: &[&Path], width: u32) -> Result<Vec<SceneLoad>, String> {
    use scene::bvh::Accel;
    use scene::render::render;
    use scene::trace::{BundleOpts, TraceOpts};
    let mut out = Vec::new();
    for path in scenes {
        let s = scene::scene::Scene::load(path).map_err(|e| e.to_string())?;
        let (_, h) = s.render.image_size(Some(width), None)?;
        let opts = TraceOpts {
            planes: false,
            bundles: BundleOpts {
                enabled: false,
                ..BundleOpts::default()
            },
            f32_transform: true,
            ..TraceOpts::default()
        };
        let acc = Accel::build(&s, false);
        let f = render(&s, &acc, &scene::tester::Slab, opts, width, h, false);
        let mut total = scene::stats::KindStats::default();
        for k in &f.stats.kinds {
            total.add(k);
        }
        out.push(SceneLoad {
            scene: path
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default(),
            rays: total.rays,
            per_ray: total.box_tests_per_ray(),
        });
    }
    Ok(out)
}

fn find<'a>(rows: &'a [Row], label: &str, frac: u32) -> Option<&'a Row> {
    rows.iter()
        .find(|r| r.label == label && r.frac == frac && r.ok())
}

/// The report: the table, the reciprocal per box test, the targets.
pub fn markdown(rows: &[Row], loads: &[SceneLoad], stages: u32, recip_stages: u32) -> String {
    let yosys = rows
        .iter()
        .find(|r| r.ok())
        .map(|r| r.report.yosys_version.clone())
        .unwrap_or_default();
    let mut s = format!(
        "Box testers, exponent 8, stages={stages} (the per-ray reciprocal `frecip`: \
         stages={recip_stages}); {yosys}; Xilinx = `synth_xilinx -flatten` \
         (LUT = LUT1..LUT6 summed; synthesis estimates, no vendor place and route), iCE40 = \
         `synth_ice40` LUT4, ECP5 = `synth_ecp5` LUT4 / MULT18X18D.\n\n\
         | design | format | Xilinx LUT | FF | DSP48 | CARRY4 | iCE40 LUT4 | ECP5 LUT4 | ECP5 DSP | LUT / conservative slab | LUT / RNE slab |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    let mut fracs: Vec<u32> = rows.iter().map(|r| r.frac).collect();
    fracs.dedup();
    for &frac in &fracs {
        let cons = find(rows, "slab conservative", frac).map(Row::xilinx_luts);
        let rne = find(rows, "slab RNE", frac).map(Row::xilinx_luts);
        for r in rows.iter().filter(|r| r.frac == frac) {
            if let Some(why) = &r.failed {
                s += &format!(
                    "| {} | e8m{frac} | synthesis failed: {} | | | | | | | | |\n",
                    r.label,
                    why.replace('|', "/")
                );
                continue;
            }
            let x = r.report.xilinx.clone().unwrap_or_default();
            let ice = r.report.ice40.as_ref().map_or(0, |i| i.luts);
            let (el, ed) = r.report.ecp5.as_ref().map_or((0, 0), |e| (e.luts, e.dsps));
            let ratio = |base: Option<u64>| match base {
                Some(b) if b > 0 && r.label.starts_with("silhouette") => {
                    format!("{:.2}", x.luts as f64 / b as f64)
                }
                _ => "-".into(),
            };
            s += &format!(
                "| {} | e8m{frac} | {} | {} | {} | {} | {ice} | {el} | {ed} | {} | {} |\n",
                r.label,
                x.luts,
                x.ffs,
                x.dsps,
                x.carries,
                ratio(cons),
                ratio(rne)
            );
        }
    }
    for (frac, lut, ff, dsp) in RAABB {
        s += &format!(
            "| RAABB (published, Xilinx XST, exponent 11) | m={frac} | {lut} | {ff} | {dsp} | - | - | - | - | - | - |\n"
        );
    }

    s += &node_section(rows, &fracs);
    s += "\nThe slab needs 1/d per ray (three reciprocals): per box test it costs slab + 3 · frecip / N, \
          N = box tests per ray (single rays, no planes, measured on the shipped scenes):\n\n\
          | scene | rays | N | format | conservative slab LUT | + 3 frecip / N | silhouette ray LUT |\n|---|---|---|---|---|---|---|\n";
    for l in loads {
        for &frac in &fracs {
            let (Some(slab), Some(rc), Some(ray)) = (
                find(rows, "slab conservative", frac),
                find(rows, "frecip RTZ", frac),
                find(rows, "silhouette ray", frac),
            ) else {
                continue;
            };
            let per =
                slab.xilinx_luts() as f64 + 3.0 * rc.xilinx_luts() as f64 / l.per_ray.max(1e-9);
            s += &format!(
                "| {} | {} | {:.2} | e8m{frac} | {} | {:.0} | {} |\n",
                l.scene,
                l.rays,
                l.per_ray,
                slab.xilinx_luts(),
                per,
                ray.xilinx_luts()
            );
        }
    }

    s += "\nTargets of issue #19 (Xilinx LUT / DSP48):\n\n";
    let mut check = |what: String, ok: bool| {
        s += &format!("- {}: {what}\n", if ok { "met" } else { "NOT MET" });
    };
    let lut = |label: &str, frac: u32| find(rows, label, frac).map(Row::xilinx_luts);
    let dsp = |label: &str, frac: u32| {
        find(rows, label, frac).and_then(|r| r.report.xilinx.as_ref().map(|x| x.dsps))
    };
    for (label, frac, max_lut, max_dsp) in [
        ("silhouette ray", 23, 8_800, Some(36)),
        ("silhouette ray", 7, 4_700, None),
        ("silhouette bundle", 23, 14_000, None),
        ("silhouette bundle", 7, 7_500, None),
    ] {
        if let Some(l) = lut(label, frac) {
            let d = dsp(label, frac).unwrap_or(0);
            let ok = l <= max_lut && max_dsp.is_none_or(|m| d <= m);
            let dsp_part = max_dsp.map_or(String::new(), |m| format!(", {d} DSP48 (at most {m})"));
            check(
                format!("{label} e8m{frac}: {l} LUT (at most {max_lut}){dsp_part}"),
                ok,
            );
        }
    }
    for &frac in &fracs {
        if let (Some(r), Some(c)) = (lut("silhouette ray", frac), lut("slab conservative", frac)) {
            check(
                format!(
                    "silhouette ray e8m{frac} at most 1.0x the conservative slab: {r} / {c} = {:.2}",
                    r as f64 / c.max(1) as f64
                ),
                r <= c,
            );
        }
    }
    s
}

/// The node tester per child test: its figures divided by N, and issue
/// #36's targets checked at binary32.
fn node_section(rows: &[Row], fracs: &[u32]) -> String {
    let mut s = "\nThe node tester per child test (one node test of N q-bit child boxes divided by N, \
                 the per-node part shared; binary32 silhouette ray for comparison):\n\n\
                 | design | format | Xilinx LUT / child | DSP48 / child | iCE40 LUT4 / child | ECP5 LUT4 / child | ECP5 DSP / child | silhouette ray LUT / box test |\n\
                 |---|---|---|---|---|---|---|---|\n"
        .to_string();
    let mut checks = String::new();
    for &frac in fracs {
        let ray = find(rows, "silhouette ray", frac)
            .map_or("-".to_string(), |r| r.xilinx_luts().to_string());
        for (label, n) in NODE_SHAPES {
            let Some(r) = find(rows, label, frac) else {
                continue;
            };
            let per = |v: u64| v as f64 / n as f64;
            let x = r.report.xilinx.clone().unwrap_or_default();
            let ice = r.report.ice40.as_ref().map_or(0, |i| i.luts);
            let (el, ed) = r.report.ecp5.as_ref().map_or((0, 0), |e| (e.luts, e.dsps));
            s += &format!(
                "| {label} | e8m{frac} | {:.0} | {:.2} | {:.0} | {:.0} | {:.2} | {ray} |\n",
                per(x.luts),
                per(x.dsps),
                per(ice),
                per(el),
                per(ed)
            );
            if let Some(&(_, lut, dsp)) = NODE_TARGETS.iter().find(|t| t.0 == n && frac == 23) {
                let ok = per(x.luts) <= lut && per(x.dsps) <= dsp;
                checks += &format!(
                    "- {}: {label} binary32: {:.0} LUT and {:.2} DSP48 per child test (at most {lut:.0} and {dsp:.0})\n",
                    if ok { "met" } else { "NOT MET" },
                    per(x.luts),
                    per(x.dsps)
                );
            }
        }
    }
    if !checks.is_empty() {
        s += &format!("\nTargets of issue #36 (Xilinx, per child test):\n\n{checks}");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::Xilinx;

    fn row(label: &'static str, frac: u32, luts: u64, dsps: u64) -> Row {
        Row {
            label,
            frac,
            report: SynthReport {
                xilinx: Some(Xilinx {
                    luts,
                    dsps,
                    ..Xilinx::default()
                }),
                ..SynthReport::default()
            },
            failed: None,
        }
    }

    #[test]
    fn targets_are_checked_against_the_figures_and_the_reciprocal_is_amortised() {
        let rows = vec![
            row("silhouette ray", 23, 8_000, 36),
            row("silhouette bundle", 23, 15_000, 72),
            row("slab conservative", 23, 9_000, 12),
            row("slab RNE", 23, 7_000, 12),
            row("frecip RTZ", 23, 1_000, 0),
            row("node N=4 q=8", 23, 8_000, 8),
            row("node N=8 q=8", 23, 12_000, 56),
        ];
        let loads = [SceneLoad {
            scene: "s.toml".into(),
            rays: 10,
            per_ray: 4.0,
        }];
        let t = markdown(&rows, &loads, 4, 8);
        assert!(
            t.contains("- met: silhouette ray e8m23: 8000 LUT (at most 8800), 36 DSP48"),
            "{t}"
        );
        assert!(
            t.contains("- NOT MET: silhouette bundle e8m23: 15000 LUT"),
            "{t}"
        );
        assert!(t.contains("- met: silhouette ray e8m23 at most 1.0x the conservative slab: 8000 / 9000 = 0.89"), "{t}");
        // 9,000 + 3 · 1,000 / 4
        assert!(
            t.contains("| s.toml | 10 | 4.00 | e8m23 | 9000 | 9750 | 8000 |"),
            "{t}"
        );
        assert!(
            t.contains("RAABB (published, Xilinx XST, exponent 11) | m=23 | 17561"),
            "{t}"
        );
        // the node per child test: both over the LUT figure, N = 8 over the DSP one too
        assert!(
            t.contains("| node N=4 q=8 | e8m23 | 2000 | 2.00 | 0 | 0 | 0.00 | 8000 |"),
            "{t}"
        );
        assert!(
            t.contains("- NOT MET: node N=4 q=8 binary32: 2000 LUT and 2.00 DSP48 per child test (at most 1500 and 2)"),
            "{t}"
        );
        assert!(
            t.contains("- NOT MET: node N=8 q=8 binary32: 1500 LUT and 7.00 DSP48 per child test (at most 1000 and 2)"),
            "{t}"
        );
        // a failed synthesis is a row that says so, not a figure
        let mut rows = rows;
        rows[0].failed = Some("yosys failed".into());
        let t = markdown(&rows, &loads, 4, 8);
        assert!(
            t.contains("| silhouette ray | e8m23 | synthesis failed: yosys failed |"),
            "{t}"
        );
        assert!(!t.contains("met: silhouette ray e8m23: "), "{t}");
    }
}
