//! The cull-plane units' cost (issue #13): `cull` (per child, beside the
//! box test) and `cull_ray` (per ray and parent, shared by both children),
//! binary32 rays and boxes, against the plane format and K, in one run with
//! one Yosys. Printed by `rtl-gen cull`; the targets are printed
//! with `rtl-gen boxes` (same run as the slab and silhouette figures),
//! never asserted in a timed test.

use crate::synth::{self, SynthOptions, SynthReport};

/// One synthesised cull design.
#[derive(Debug, Clone)]
pub struct CullRow {
    /// `cull` or `cull_ray`
    pub unit: &'static str,
    /// plane format `(Ep, Fp)`
    pub plane: (u32, u32),
    /// planes per node
    pub k: u32,
    /// the synthesis report (default when synthesis failed)
    pub report: SynthReport,
    /// why synthesis failed (first line of the tool's error), if it did
    pub failed: Option<String>,
}

impl CullRow {
    /// Xilinx LUTs (0 when synthesis failed).
    pub fn xilinx_luts(&self) -> u64 {
        self.report.xilinx.as_ref().map_or(0, |x| x.luts)
    }
    /// Xilinx DSP48s.
    pub fn xilinx_dsps(&self) -> u64 {
        self.report.xilinx.as_ref().map_or(0, |x| x.dsps)
    }
    /// iCE40 longest path (LUT4 + carry cells).
    pub fn depth(&self) -> u64 {
        self.report.ice40.as_ref().map_or(0, |i| i.depth)
    }
}

/// The plane formats of the sweep, e4m3 .. e8m23.
pub const PLANE_FORMATS: [(u32, u32); 5] = [(4, 3), (5, 7), (5, 10), (6, 15), (8, 23)];
/// The K values of the sweep (plane format e5m10).
pub const KS: [u32; 4] = [1, 2, 4, 8];

/// Synthesises `cull` and `cull_ray` with binary32 rays for every
/// `(plane format, k)` of `designs`, `stages` pipeline registers, Xilinx /
/// iCE40 / ECP5, no place and route. A design the tools cannot map keeps its
/// row with the reason.
pub fn synthesise(
    designs: &[((u32, u32), u32)],
    stages: u32,
    cached_only: bool,
) -> Result<Vec<CullRow>, String> {
    let o = SynthOptions {
        generic: false,
        pnr: false,
        pnr_ecp5: false,
        cached_only,
        ..SynthOptions::default()
    };
    let mut rows = Vec::new();
    for &(plane, k) in designs {
        for unit in ["cull", "cull_ray"] {
            let p = vec![
                "exp_bits=8".to_string(),
                "frac_bits=23".to_string(),
                format!("plane_exp_bits={}", plane.0),
                format!("plane_frac_bits={}", plane.1),
                format!("k={k}"),
                format!("stages={stages}"),
            ];
            let g = rtl_flow::generate(unit, &p).map_err(|e| format!("{unit}: {e}"))?;
            eprintln!("synthesising {} ...", g.module.name);
            let (report, failed) = match synth::run(&g, &o) {
                Ok(r) => (r, None),
                Err(e) => {
                    let why = e.to_string().lines().next().unwrap_or("").to_string();
                    eprintln!("{}: synthesis failed: {why}", g.module.name);
                    (SynthReport::default(), Some(why))
                }
            };
            rows.push(CullRow {
                unit,
                plane,
                k,
                report,
                failed,
            });
        }
    }
    Ok(rows)
}

/// Every design of the sweep: the plane formats at K = 4, then K at e5m10.
pub fn sweep_designs() -> Vec<((u32, u32), u32)> {
    let mut v: Vec<((u32, u32), u32)> = PLANE_FORMATS.iter().map(|&p| (p, 4)).collect();
    v.extend(KS.iter().filter(|&&k| k != 4).map(|&k| ((5, 10), k)));
    v
}

fn find<'a>(rows: &'a [CullRow], unit: &str, plane: (u32, u32), k: u32) -> Option<&'a CullRow> {
    rows.iter()
        .find(|r| r.unit == unit && r.plane == plane && r.k == k && r.failed.is_none())
}

/// Xilinx LUT of one child test in a binary BVH, `cull + cull_ray / 2` (one
/// `cull_ray` serves both children of a parent), when both synthesised.
fn per_child_luts(rows: &[CullRow], plane: (u32, u32), k: u32) -> Option<f64> {
    let c = find(rows, "cull", plane, k)?;
    let t = find(rows, "cull_ray", plane, k)?;
    Some(c.xilinx_luts() as f64 + t.xilinx_luts() as f64 / 2.0)
}

/// The table: one row per design, both units, and the cost per child test
/// in a binary BVH (`cull + cull_ray / 2`: one `cull_ray` serves both
/// children of a parent).
pub fn markdown(rows: &[CullRow], stages: u32) -> String {
    let yosys = rows
        .iter()
        .find(|r| r.failed.is_none())
        .map(|r| r.report.yosys_version.clone())
        .unwrap_or_default();
    let mut s = format!(
        "Cull-plane units, binary32 rays and boxes, stages={stages}; {yosys}; Xilinx = \
         `synth_xilinx -flatten` (synthesis estimates), iCE40 = `synth_ice40` LUT4 (depth: longest \
         path in LUT4 + carry cells), ECP5 = `synth_ecp5` LUT4 / MULT18X18D. Per child test = \
         cull + cull_ray / 2 (binary BVH: one cull_ray per ray and parent serves both children).\n\n\
         | unit | planes | K | Xilinx LUT | FF | DSP48 | iCE40 LUT4 | iCE40 depth | ECP5 LUT4 | ECP5 DSP | per child test, Xilinx LUT |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        let fmt = format!("e{}m{}", r.plane.0, r.plane.1);
        if let Some(why) = &r.failed {
            s += &format!(
                "| {} | {fmt} | {} | synthesis failed: {} | | | | | | | |\n",
                r.unit,
                r.k,
                why.replace('|', "/")
            );
            continue;
        }
        let x = r.report.xilinx.clone().unwrap_or_default();
        let ice = r.report.ice40.clone().unwrap_or_default();
        let (el, ed) = r.report.ecp5.as_ref().map_or((0, 0), |e| (e.luts, e.dsps));
        let per_child = match per_child_luts(rows, r.plane, r.k) {
            Some(l) if r.unit == "cull" => format!("{l:.0}"),
            _ => "-".into(),
        };
        s += &format!(
            "| {} | {fmt} | {} | {} | {} | {} | {} | {} | {el} | {ed} | {per_child} |\n",
            r.unit, r.k, x.luts, x.ffs, x.dsps, ice.luts, ice.depth
        );
    }
    s
}

/// Two charts of the report, Xilinx LUT of `cull`, `cull_ray` and the per
/// child test: against the plane format's bits at K = 4
/// (`<dir>/cull_luts_vs_plane_bits`) and against K at e5m10
/// (`<dir>/cull_luts_vs_k`), PNG and SVG; designs that did not synthesise
/// are left out.
pub fn charts(
    rows: &[CullRow],
    dir: &std::path::Path,
) -> Result<Vec<std::path::PathBuf>, Box<dyn std::error::Error>> {
    use crate::charts::{write_chart, Chart, Point, Series};
    use plotters::prelude::RGBColor;
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(230, 110, 14),
        RGBColor(44, 160, 44),
    ];
    // (x, label) of a design, or None when it is not on this chart
    let chart = |stem: &str,
                 title: &str,
                 x_label: &str,
                 on: &dyn Fn(&CullRow) -> Option<(f64, String)>|
     -> Result<Vec<std::path::PathBuf>, Box<dyn std::error::Error>> {
        let ok = |u: &'static str| {
            rows.iter()
                .filter(move |r| r.unit == u && r.failed.is_none())
        };
        let of_unit = |u: &'static str| -> Vec<Point> {
            ok(u)
                .filter_map(|r| on(r).map(|(x, l)| Point::new(x, r.xilinx_luts() as f64, l)))
                .collect()
        };
        let per_child: Vec<Point> = ok("cull")
            .filter_map(|c| {
                let y = per_child_luts(rows, c.plane, c.k)?;
                let (x, l) = on(c)?;
                Some(Point::new(x, y, l))
            })
            .collect();
        let series = [
            ("cull (per child)", of_unit("cull")),
            ("cull_ray (per ray and parent)", of_unit("cull_ray")),
            ("per child test: cull + cull_ray / 2", per_child),
        ]
        .into_iter()
        .zip(colors)
        .map(|((name, points), color)| Series {
            name: name.into(),
            color,
            points,
            hollow: false,
            line: true,
        })
        .collect();
        write_chart(
            &Chart::plain(
                stem,
                title,
                x_label,
                "Xilinx LUT (synth_xilinx -flatten estimate)",
                series,
            ),
            dir,
        )
    };
    let mut out = chart(
        "cull_luts_vs_plane_bits",
        "Cull-plane units, binary32 rays, K = 4: cost against the plane format",
        "plane format bits (1 + Ep + Fp)",
        &|r| {
            (r.k == 4).then(|| {
                (
                    (1 + r.plane.0 + r.plane.1) as f64,
                    format!("e{}m{}", r.plane.0, r.plane.1),
                )
            })
        },
    )?;
    out.extend(chart(
        "cull_luts_vs_k",
        "Cull-plane units, binary32 rays, e5m10 planes: cost against K",
        "planes per node K",
        &|r| (r.plane == (5, 10)).then(|| (r.k as f64, format!("K={}", r.k))),
    )?);
    Ok(out)
}

/// The targets of issue #13, checked against the figures: `cull` K = 4,
/// e5m10 planes at most 7,700 Xilinx LUT and 12 DSP48, its longest path no
/// longer than the silhouette tester's (`silhouette_depth`, same stages).
pub fn targets(rows: &[CullRow], silhouette_depth: Option<u64>) -> String {
    let mut s =
        String::from("\nTargets of issue #13 (cull K = 4, binary32 rays, e5m10 planes):\n\n");
    let mut check = |what: String, ok: bool| {
        s += &format!("- {}: {what}\n", if ok { "met" } else { "NOT MET" });
    };
    let Some(c) = find(rows, "cull", (5, 10), 4) else {
        s += "- NOT MET: cull K = 4 e5m10 was not synthesised\n";
        return s;
    };
    check(
        format!(
            "cull: {} LUT (at most 7700), {} DSP48 (at most 12)",
            c.xilinx_luts(),
            c.xilinx_dsps()
        ),
        c.xilinx_luts() <= 7_700 && c.xilinx_dsps() <= 12,
    );
    if let Some(sd) = silhouette_depth {
        check(
            format!(
                "cull longest path {} iCE40 cells, the silhouette tester's {sd}",
                c.depth()
            ),
            c.depth() <= sd,
        );
    }
    // the cost of culling one child must follow the plane format; `cull`
    // alone is listed beside it (planes in the ray format skip the widening
    // of the distances, so its top step may fall)
    let list = |cost: &dyn Fn((u32, u32)) -> Option<f64>| -> Vec<(String, f64)> {
        PLANE_FORMATS
            .iter()
            .filter_map(|&p| cost(p).map(|l| (format!("e{}m{}", p.0, p.1), l)))
            .collect()
    };
    let show = |v: &[(String, f64)]| -> String {
        let v: Vec<String> = v.iter().map(|(f, l)| format!("{f} {l:.0}")).collect();
        v.join(", ")
    };
    let per_child = list(&|p| per_child_luts(rows, p, 4));
    if per_child.len() > 1 {
        check(
            format!(
                "per child test (cull + cull_ray / 2) LUT grows with the plane format: {}",
                show(&per_child)
            ),
            per_child.windows(2).all(|w| w[0].1 <= w[1].1),
        );
    }
    let alone = list(&|p| find(rows, "cull", p, 4).map(|r| r.xilinx_luts() as f64));
    if alone.len() > 1 {
        s += &format!("- (cull alone: {})\n", show(&alone));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::{Ice40, Xilinx};

    fn row(unit: &'static str, plane: (u32, u32), luts: u64, dsps: u64, depth: u64) -> CullRow {
        CullRow {
            unit,
            plane,
            k: 4,
            report: SynthReport {
                xilinx: Some(Xilinx {
                    luts,
                    dsps,
                    ..Xilinx::default()
                }),
                ice40: Some(Ice40 {
                    depth,
                    ..Ice40::default()
                }),
                ..SynthReport::default()
            },
            failed: None,
        }
    }

    #[test]
    fn targets_follow_the_figures_and_the_per_child_cost_halves_cull_ray() {
        let rows = vec![
            row("cull", (4, 3), 3_000, 4, 50),
            row("cull", (5, 10), 5_000, 8, 60),
            row("cull_ray", (4, 3), 8_000, 12, 70),
            row("cull_ray", (5, 10), 9_000, 12, 70),
            row("cull", (8, 23), 7_000, 8, 65),
            row("cull_ray", (8, 23), 12_000, 24, 70),
        ];
        let t = targets(&rows, Some(60));
        assert!(
            t.contains("- met: cull: 5000 LUT (at most 7700), 8 DSP48 (at most 12)"),
            "{t}"
        );
        assert!(
            t.contains("- met: cull longest path 60 iCE40 cells, the silhouette tester's 60"),
            "{t}"
        );
        assert!(
            t.contains(
                "- met: per child test (cull + cull_ray / 2) LUT grows with the plane format: \
                 e4m3 7000, e5m10 9500, e8m23 13000"
            ),
            "{t}"
        );
        assert!(
            t.contains("- (cull alone: e4m3 3000, e5m10 5000, e8m23 7000)"),
            "{t}"
        );
        let m = markdown(&rows, 4);
        assert!(
            m.contains("| cull | e5m10 | 4 | 5000 | 0 | 8 | 0 | 60 | 0 | 0 | 9500 |"),
            "{m}"
        );
        let worse = vec![
            row("cull", (5, 10), 7_800, 8, 61),
            row("cull_ray", (5, 10), 9_000, 12, 70),
            row("cull", (8, 23), 7_000, 8, 61),
            row("cull_ray", (8, 23), 9_000, 12, 70),
        ];
        let t = targets(&worse, Some(60));
        assert!(t.contains("- NOT MET: cull: 7800 LUT"), "{t}");
        assert!(t.contains("- NOT MET: cull longest path 61"), "{t}");
        assert!(
            t.contains("- NOT MET: per child test (cull + cull_ray / 2) LUT grows"),
            "{t}"
        );
        assert!(targets(&[], None).contains("NOT MET: cull K = 4 e5m10 was not synthesised"));
    }
}
