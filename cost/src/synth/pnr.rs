//! Place and route in the timing shell: the devices, nextpnr-ice40 and
//! nextpnr-ecp5 runs and what is read from their logs.

use super::*;
use std::process::Command;

/// An iCE40 device nextpnr can target.
#[derive(Debug, Clone, Copy)]
pub struct Device {
    /// nextpnr flag without dashes
    pub name: &'static str,
    /// package
    pub package: &'static str,
    /// logic cells (LUT4 + FF pairs)
    pub lcs: u64,
}

/// UP5K (iCEBreaker) and HX8K (iCE40-HX8K breakout), smallest first.
pub const DEVICES: [Device; 2] = [
    Device {
        name: "up5k",
        package: "sg48",
        lcs: 5280,
    },
    Device {
        name: "hx8k",
        package: "ct256",
        lcs: 7680,
    },
];

/// The ECP5 device of the ECP5 place and route: LFE5U-85F-6BG381C (ULX3S),
/// `nextpnr-ecp5 --85k --package CABGA381 --speed 6`.
pub const ECP5_DEVICE: &str = "LFE5U-85F-6";

/// LUT4 (TRELLIS_COMB) of the LFE5U-85F.
pub const ECP5_LUTS: u64 = 83_640;

/// MULT18X18D of the LFE5U-85F.
pub const ECP5_DSPS: u64 = 156;

/// Fills below this fraction of the logic cells are attempted (routing
/// congestion makes fuller designs fail or take very long).
pub const MAX_FILL: f64 = 0.9;

/// Parses nextpnr's log: the last `Max frequency for clock` line.
pub fn parse_fmax(log: &str) -> Option<f64> {
    log.lines()
        .rev()
        .find(|l| l.contains("Max frequency for clock"))
        .and_then(|l| {
            let i = l.find("': ")?;
            let rest = &l[i + 3..];
            rest.split_whitespace().next()?.parse().ok()
        })
}

/// Parses the last `<cell>: used/ total` utilisation line of a nextpnr log.
pub fn parse_utilisation(log: &str, cell: &str) -> Option<(u64, u64)> {
    let tag = format!("{cell}:");
    let l = log.lines().rev().find(|l| l.contains(&tag))?;
    let rest = l.split(&tag).nth(1)?;
    let mut it = rest.split('/');
    let used = it.next()?.trim().parse().ok()?;
    let total = it.next()?.split_whitespace().next()?.parse().ok()?;
    Some((used, total))
}

/// Parses the `ICESTORM_LC: used/ total` utilisation line.
pub fn parse_lcs(log: &str) -> Option<(u64, u64)> {
    parse_utilisation(log, "ICESTORM_LC")
}

/// Which iCE40 the shell fits, or why none (`Err`: the note).
fn ice40_device(g: &Generated, est: Option<&Ice40>) -> Result<&'static Device, String> {
    let in_bits: u64 = g.module.inputs.iter().map(|p| p.ty.width() as u64).sum();
    // LUTs of the unit, plus FFs of the chain that cannot pack with a LUT.
    let estimate = est.map(|e| e.luts.max(e.dffs + in_bits)).unwrap_or(0);
    DEVICES
        .iter()
        .find(|d| (estimate as f64) < MAX_FILL * d.lcs as f64)
        .ok_or_else(|| {
            format!(
                "does not fit an iCE40: ~{estimate} LUT4 (+{in_bits} scan FFs) > {:.0} % of HX8K's {} LCs",
                MAX_FILL * 100.0,
                DEVICES[1].lcs
            )
        })
}

/// Whether the shell fits the LFE5U-85F (`Err`: the note).
fn ecp5_fits(est: Option<&Ecp5>) -> Result<(), String> {
    let Some(e) = est else { return Ok(()) };
    if (e.luts as f64) >= MAX_FILL * ECP5_LUTS as f64 {
        return Err(format!(
            "does not fit the {ECP5_DEVICE}: ~{} LUT4 > {:.0} % of its {ECP5_LUTS}",
            e.luts,
            MAX_FILL * 100.0
        ));
    }
    if e.dsps > ECP5_DSPS {
        return Err(format!(
            "does not fit the {ECP5_DEVICE}: {} MULT18X18D > its {ECP5_DSPS}",
            e.dsps
        ));
    }
    Ok(())
}

pub(super) fn place_and_route(
    g: &Generated,
    o: &SynthOptions,
    dir: &Path,
    est_ice40: Option<&Ice40>,
    est_ecp5: Option<&Ecp5>,
) -> Result<(Option<Pnr>, Option<Pnr>), SynthError> {
    let shell = crate::shell::timing_shell(&g.module).map_err(|e| SynthError(e.to_string()))?;
    let mut ice = o.pnr.then(|| Pnr {
        target_mhz: o.target_mhz,
        ..Default::default()
    });
    let mut ecp = o.pnr_ecp5.then(|| Pnr {
        target_mhz: o.ecp5_target_mhz,
        ..Default::default()
    });
    let mut ice_device = None;
    if let Some(p) = ice.as_mut() {
        match ice40_device(g, est_ice40) {
            Ok(d) => {
                p.device = d.name.to_string();
                ice_device = Some(d);
            }
            Err(note) => p.note = note,
        }
    }
    let mut run_ecp5 = false;
    if let Some(p) = ecp.as_mut() {
        match ecp5_fits(est_ecp5) {
            Ok(()) => {
                p.device = ECP5_DEVICE.to_string();
                run_ecp5 = true;
            }
            Err(note) => p.note = note,
        }
    }
    if ice_device.is_none() && !run_ecp5 {
        return Ok((ice, ecp));
    }
    let files = rtl_gen::emit::emit(&shell, rtl_gen::GENERATOR);
    let mut names = Vec::new();
    for f in &files {
        std::fs::write(dir.join(&f.file_name), &f.text).map_err(io("shell"))?;
        names.push(f.file_name.clone());
    }
    let nf = if o.flat { "" } else { " -noflatten" };
    let mut script = if has_ecp5_cells(g) {
        ECP5_CELLS.to_string()
    } else {
        String::new()
    };
    script += &format!(
        "read_verilog {}\nhierarchy -check -top {}\ndesign -save shell\n",
        names.join(" "),
        shell.name
    );
    if ice_device.is_some() {
        script += &format!(
            "design -load shell\nsynth_ice40{nf} -top {}\nflatten\nwrite_json shell_ice40.json\n",
            shell.name
        );
    }
    if run_ecp5 {
        script += &format!(
            "design -load shell\nsynth_ecp5{nf} -top {}\nflatten\nwrite_json shell_ecp5.json\n",
            shell.name
        );
    }
    std::fs::write(dir.join("shell.ys"), script).map_err(io("shell script"))?;
    yosys(dir, "shell.ys", "shell.log")?;
    if let (Some(p), Some(d)) = (ice.as_mut(), ice_device) {
        let args = [
            format!("--{}", d.name),
            "--package".into(),
            d.package.into(),
            "--json".into(),
            "shell_ice40.json".into(),
            "--pcf-allow-unconstrained".into(),
            "--asc".into(),
            "shell.asc".into(),
        ];
        nextpnr(
            Tool::NextpnrIce40,
            dir,
            &args,
            "nextpnr-ice40.log",
            "ICESTORM_LC",
            1,
            p,
        )?;
    }
    if let (Some(p), true) = (ecp.as_mut(), run_ecp5) {
        let mut args = vec![
            "--85k".to_string(),
            "--package".into(),
            "CABGA381".into(),
            "--speed".into(),
            "6".into(),
            "--json".into(),
            "shell_ecp5.json".into(),
            "--lpf-allow-unconstrained".into(),
        ];
        if let Some(w) = o.ecp5_placer {
            args.extend([
                "--placer-heap-timingweight".into(),
                w.timing_weight.to_string(),
                "--placer-heap-critexp".into(),
                w.crit_exp.to_string(),
            ]);
        }
        nextpnr(
            Tool::NextpnrEcp5,
            dir,
            &args,
            "nextpnr-ecp5.log",
            "TRELLIS_COMB",
            o.ecp5_seed,
            p,
        )?;
    }
    Ok((ice, ecp))
}

/// Runs one nextpnr (`--timing-allow-fail --seed <seed> --freq <target>`
/// added) and fills `p` from its log.
#[allow(clippy::too_many_arguments)]
pub(super) fn nextpnr(
    t: Tool,
    dir: &Path,
    args: &[String],
    log_name: &str,
    lut_cell: &str,
    seed: u64,
    p: &mut Pnr,
) -> Result<(), SynthError> {
    let prog = tool(t)?;
    let t0 = Instant::now();
    let out = Command::new(&prog)
        .current_dir(dir)
        .args(args)
        .args([
            "--timing-allow-fail",
            "--freq",
            &format!("{}", p.target_mhz),
            "--seed",
            &seed.to_string(),
            "-l",
            log_name,
        ])
        .output()
        .map_err(|e| {
            SynthError(format!(
                "running {} (installed? bash scripts/setup.sh): {e}",
                prog.display()
            ))
        })?;
    p.seconds = t0.elapsed().as_secs_f64();
    let log = std::fs::read_to_string(dir.join(log_name)).unwrap_or_default();
    if let Some((used, total)) = parse_utilisation(&log, lut_cell) {
        p.lcs_used = used;
        p.lcs_total = total;
    }
    if out.status.code().is_none() {
        // killed (a signal): no verdict, and nothing that could be cached as one
        return Err(SynthError(format!(
            "{} was stopped by a signal ({})",
            t.program(),
            out.status
        )));
    }
    // a failed run's log may hold the placer's estimate: only a finished
    // route has a routed Fmax
    p.fmax_mhz = out.status.success().then(|| parse_fmax(&log)).flatten();
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last: Vec<&str> = err.lines().filter(|l| l.contains("ERROR")).collect();
        p.note = format!("{} failed: {}", t.program(), last.join("; "));
    } else if let Some(f) = p.fmax_mhz {
        p.note = if f >= p.target_mhz {
            format!("PASS at {} MHz", p.target_mhz)
        } else {
            format!("FAIL at {} MHz (reported, not hidden)", p.target_mhz)
        };
    }
    Ok(())
}
