//! Routed Fmax against pipeline depth: for one unit, each `stages` and each
//! register placement (`pipeline=plan|balanced`), `synth_ecp5` and
//! `nextpnr-ecp5` of the timing shell on the LFE5U-85F-6, one table, so a
//! user can choose the depth for a target clock.

use crate::synth::{self, SynthOptions, SynthReport};
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
) -> Result<Vec<DepthRow>, Box<dyn std::error::Error>> {
    let o = SynthOptions {
        generic: false,
        ice40: false,
        xilinx: false,
        pnr: false,
        ecp5: true,
        pnr_ecp5: true,
        ecp5_target_mhz: target_mhz,
        ..Default::default()
    };
    let mut rows = Vec::new();
    for &s in stages {
        for pipeline in pipelines {
            let mut p = params.to_vec();
            p.push(format!("stages={s}"));
            p.push(format!("pipeline={pipeline}"));
            let g = rtl_gen::flow::generate(unit, &p).map_err(|e| format!("{unit}: {e}"))?;
            let model_period = rtl_gen::retime::modelled_period(&g.module)?;
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
pub fn table(unit: &str, params: &[String], rows: &[DepthRow]) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "`{unit}` {}: ECP5 LFE5U-85F-6 (synth_ecp5, nextpnr-ecp5 in the timing shell)\n",
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
