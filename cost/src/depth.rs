//! Routed Fmax against pipeline depth: for one unit, each `stages` and each
//! register placement (`pipeline=plan|balanced`), `synth_ecp5` and
//! `nextpnr-ecp5` of the timing shell on the LFE5U-85F-6, one table, so a
//! user can choose the depth for a target clock.

use crate::synth::{self, PlacerWeights, SynthOptions, SynthReport};
use std::fmt::Write as _;

/// One row: what was built and what it measured.
#[derive(Debug, Clone)]
pub struct DepthRow {
    /// `plan` or `balanced`
    pub pipeline: String,
    /// pipeline registers (= latency)
    pub stages: u32,
    /// longest in-stage chain of the delay model, LUT levels
    pub model_period: f64,
    /// the synthesis and place-and-route report
    pub report: SynthReport,
}

/// Synthesises and routes `unit` with `params` at every `stages` and `pipeline`.
pub fn sweep(
    unit: &str,
    params: &[String],
    stages: &[u32],
    pipelines: &[String],
    target_mhz: f64,
    placer: Option<PlacerWeights>,
    seed: u64,
) -> Result<Vec<DepthRow>, Box<dyn std::error::Error>> {
    let o = SynthOptions {
        ecp5_placer: placer,
        ecp5_seed: seed,
        ..SynthOptions::ecp5_routed(target_mhz)
    };
    let mut rows = Vec::new();
    for &s in stages {
        for pipeline in pipelines {
            let mut p = params.to_vec();
            p.push(format!("stages={s}"));
            p.push(format!("pipeline={pipeline}"));
            let g = rtl_flow::generate(unit, &p).map_err(|e| format!("{unit}: {e}"))?;
            let model_period = g.modelled_period()?;
            eprintln!("{unit} stages={s} pipeline={pipeline} ...");
            let report = synth::run(&g, &o)?;
            rows.push(DepthRow {
                pipeline: pipeline.clone(),
                stages: s,
                model_period,
                report,
            });
        }
    }
    Ok(rows)
}

/// The markdown table of a sweep.
pub fn table(
    unit: &str,
    params: &[String],
    rows: &[DepthRow],
    placer: Option<PlacerWeights>,
    seed: u64,
) -> String {
    let mut t = String::new();
    let mut weights = placer
        .map(|w| {
            format!(
                ", placer timing weight {} and criticality exponent {}",
                w.timing_weight, w.crit_exp
            )
        })
        .unwrap_or_default();
    if seed != 1 {
        weights += &format!(", seed {seed}");
    }
    let _ = writeln!(
        t,
        "`{unit}` {}: ECP5 LFE5U-85F-6 (synth_ecp5, nextpnr-ecp5 in the timing shell{weights})\n",
        params.join(" ")
    );
    t.push_str("| pipeline | stages | model period (LUT levels) | ECP5 LUT4 | FF | MULT18X18D | routed Fmax MHz |\n");
    t.push_str("|---|---|---|---|---|---|---|\n");
    for r in rows {
        let (luts, ffs, dsps) = r
            .report
            .ecp5
            .as_ref()
            .map(|e| (e.luts.to_string(), e.ffs.to_string(), e.dsps.to_string()))
            .unwrap_or(("–".into(), "–".into(), "–".into()));
        let fmax = match &r.report.pnr_ecp5 {
            Some(p) => match p.fmax_mhz {
                Some(f) => format!("{f:.1}"),
                None => format!("– ({})", p.note),
            },
            None => "–".into(),
        };
        let _ = writeln!(
            t,
            "| {} | {} | {:.1} | {luts} | {ffs} | {dsps} | {fmax} |",
            r.pipeline, r.stages, r.model_period
        );
    }
    t
}

/// Routed Fmax against stages, one line per register placement, each point
/// labelled with its ECP5 LUT4 and FF: `<stem>.png` and `.svg` in `dir`.
pub fn chart(
    unit: &str,
    params: &[String],
    rows: &[DepthRow],
    stem: &str,
    dir: &std::path::Path,
) -> Result<Vec<std::path::PathBuf>, Box<dyn std::error::Error>> {
    use crate::charts::{write_chart, Chart, Point, Series};
    use plotters::prelude::RGBColor;
    let colors = [RGBColor(230, 110, 14), RGBColor(31, 119, 180)];
    let mut placements: Vec<&str> = Vec::new();
    for r in rows {
        if !placements.contains(&r.pipeline.as_str()) {
            placements.push(&r.pipeline);
        }
    }
    let series = placements
        .iter()
        .enumerate()
        .map(|(i, p)| Series {
            name: format!("pipeline={p}"),
            color: colors[i % colors.len()],
            points: rows
                .iter()
                .filter(|r| r.pipeline == *p)
                .filter_map(|r| {
                    let f = r.report.pnr_ecp5.as_ref()?.fmax_mhz?;
                    let e = r.report.ecp5.as_ref()?;
                    Some(Point::new(
                        r.stages as f64,
                        f,
                        format!(
                            "{:.1}k LUT {:.1}k FF",
                            e.luts as f64 / 1e3,
                            e.ffs as f64 / 1e3
                        ),
                    ))
                })
                .collect(),
            hollow: false,
            line: true,
        })
        .collect();
    let c = Chart::plain(
        stem,
        &format!("{unit} {}: routed Fmax, ECP5-85F-6", params.join(" ")),
        "pipeline stages (latency, cycles)",
        "routed Fmax, MHz",
        series,
    );
    write_chart(&c, dir)
}
