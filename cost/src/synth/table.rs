//! The synthesis table: one markdown row per report.

use super::*;

pub(super) fn fmax_cell(p: Option<&Pnr>, with_device: bool) -> String {
    match p {
        Some(p) if p.fmax_mhz.is_some() => {
            if with_device {
                format!("{:.1} ({})", p.fmax_mhz.unwrap(), p.device)
            } else {
                format!("{:.1}", p.fmax_mhz.unwrap())
            }
        }
        Some(p) if p.device.is_empty() => "no fit".into(),
        Some(p) => format!("– ({})", p.note),
        None => "–".into(),
    }
}

/// One markdown table row per report (header from [`table_header`]).
pub fn table_row(r: &SynthReport) -> String {
    let p: Vec<String> = r.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let opt = |v: Option<u64>| v.map(|x| x.to_string()).unwrap_or_else(|| "–".into());
    let g = r.generic.as_ref();
    let i = r.ice40.as_ref();
    let e = r.ecp5.as_ref();
    let x = r.xilinx.as_ref();
    let cells = [
        r.unit.clone(),
        p.join(" "),
        r.latency.to_string(),
        r.throughput.to_string(),
        opt(g.map(|g| g.cells)),
        opt(g.map(|g| g.depth)),
        opt(i.map(|i| i.luts)),
        opt(i.map(|i| i.carries)),
        opt(i.map(|i| i.dffs)),
        opt(i.map(|i| i.depth)),
        opt(e.map(|e| e.luts)),
        opt(e.map(|e| e.ffs)),
        opt(e.map(|e| e.dsps)),
        opt(x.map(|x| x.luts)),
        opt(x.map(|x| x.ffs)),
        opt(x.map(|x| x.dsps)),
        opt(x.map(|x| x.carries)),
        opt(x.map(|x| x.srls)),
        fmax_cell(r.pnr.as_ref(), true),
        fmax_cell(r.pnr_ecp5.as_ref(), false),
        format!("{:.0}", r.yosys_seconds),
    ];
    format!("| {} |", cells.join(" | "))
}

/// Header of the markdown table. The xc7 columns are `synth_xilinx -flatten`
/// synthesis estimates (no vendor place and route).
pub fn table_header() -> String {
    "| unit | parameters | latency | tests/clk | cells | depth | iCE40 LUT4 | carry | DFF | LUT depth | ECP5 LUT4 | FF | DSP | xc7 LUT (synth. est.) | xc7 FF | DSP48E1 | CARRY4 | SRL | iCE40 Fmax MHz (device) | ECP5-85F-6 Fmax MHz | yosys s |\n\
     |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        .to_string()
}
