//! The synthesis runner: a generated unit through Yosys 0.23 (`synth`,
//! `synth_ice40`, `synth_ecp5`), logic depth by `ltp -noff`, and where the
//! design fits an iCE40, `nextpnr-ice40` for a real Fmax.
//!
//! Method (written down because the numbers depend on it):
//! * every flow reads the emitted Verilog once (`design -save`), then runs
//!   its script **hierarchically** (`-noflatten`): every distinct module is
//!   mapped once, then the mapped netlist is flattened for `stat` and `ltp`.
//!   Flattening before mapping lets constants cross instance boundaries and
//!   was 13 % smaller on `silhouette e5m7` (26,441 against 30,396 LUT4) but
//!   took 9× the CPU time, most of it in `share` (SAT-based resource
//!   sharing) on the flat netlist; `--flat` selects it per run.
//! * `synth`: generic gate cells (`$_AND_`, `$_MUX_`, `$_DFF_P_`, ...) and
//!   the longest path in those cells; `synth_ice40` without `-dsp` (the
//!   HX parts have none): SB_LUT4, SB_CARRY, SB_DFF*, LUT depth; `synth_ecp5`
//!   with its default DSP mapping: LUT4, TRELLIS_FF, MULT18X18D, CCU2C.
//! * place and route runs on the unit inside [`crate::shell`] (three pins)
//!   on the smallest of iCE40UP5K / iCE40HX8K the shell fits, with
//!   `--timing-allow-fail`: the reported Fmax is whatever the router
//!   achieved, pass or fail, together with the target.
//!
//! Results are cached by a hash of the Verilog and of this runner's version
//! under `target/cost-cache/`, so a sweep interrupted half way resumes.

use rtl_gen::flow::Generated;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Bumped whenever a script or a parser changes (invalidates the cache).
pub const RUNNER_VERSION: u32 = 3;

/// Which flows to run.
#[derive(Debug, Clone)]
pub struct SynthOptions {
    /// generic `synth`
    pub generic: bool,
    /// `synth_ice40`
    pub ice40: bool,
    /// `synth_ecp5`
    pub ecp5: bool,
    /// `nextpnr-ice40` when the shell fits a device
    pub pnr: bool,
    /// flatten before mapping (slower, a little smaller)
    pub flat: bool,
    /// target frequency given to nextpnr, MHz
    pub target_mhz: f64,
    /// cache directory (`None`: no cache)
    pub cache: Option<PathBuf>,
    /// report only what the cache holds (no tool runs)
    pub cached_only: bool,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            generic: true,
            ice40: true,
            ecp5: true,
            pnr: true,
            flat: false,
            target_mhz: 12.0,
            cache: Some(default_cache()),
            cached_only: false,
        }
    }
}

/// `$CARGO_TARGET_DIR/cost-cache` or `target/cost-cache` of the workspace.
pub fn default_cache() -> PathBuf {
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../target"));
    target.join("cost-cache")
}

/// Generic gate-level result of `synth`.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Generic {
    /// all cells
    pub cells: u64,
    /// flip-flops among them
    pub ffs: u64,
    /// cells by type
    pub by_type: BTreeMap<String, u64>,
    /// longest topological path, in cells (`ltp -noff`)
    pub depth: u64,
}

/// iCE40 mapping.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Ice40 {
    /// SB_LUT4
    pub luts: u64,
    /// SB_CARRY
    pub carries: u64,
    /// SB_DFF* of every kind
    pub dffs: u64,
    /// longest path in LUT4 + carry cells (`ltp -noff`)
    pub depth: u64,
}

/// ECP5 mapping.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Ecp5 {
    /// LUT4
    pub luts: u64,
    /// TRELLIS_FF
    pub ffs: u64,
    /// MULT18X18D
    pub dsps: u64,
    /// CCU2C (two-bit carry cells)
    pub carries: u64,
}

/// Place and route in the timing shell.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Pnr {
    /// `up5k` or `hx8k`, or empty if it fits neither
    pub device: String,
    /// Fmax of `clk` after routing, MHz (`None`: not run or failed)
    pub fmax_mhz: Option<f64>,
    /// the frequency asked for
    pub target_mhz: f64,
    /// LUT4 used / available (logic cells, shell included)
    pub lcs_used: u64,
    /// logic cells of the device
    pub lcs_total: u64,
    /// why it was not run, or the tool's failure
    pub note: String,
    /// wall time of nextpnr, s
    pub seconds: f64,
}

/// Everything measured for one unit and parameter set.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct SynthReport {
    /// unit name
    pub unit: String,
    /// resolved parameters
    pub params: BTreeMap<String, String>,
    /// top module
    pub top: String,
    /// latency in cycles (from the generator)
    pub latency: u32,
    /// tests (transactions that complete a result) per clock
    pub throughput: f64,
    /// flattened before mapping
    pub flat: bool,
    /// `synth`
    pub generic: Option<Generic>,
    /// `synth_ice40`
    pub ice40: Option<Ice40>,
    /// `synth_ecp5`
    pub ecp5: Option<Ecp5>,
    /// `nextpnr-ice40`
    pub pnr: Option<Pnr>,
    /// wall time of Yosys, s
    pub yosys_seconds: f64,
}

/// Failure of an external tool or of the file system.
#[derive(Debug)]
pub struct SynthError(pub String);

impl std::fmt::Display for SynthError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SynthError {}

fn io<E: std::fmt::Display>(what: &str) -> impl FnOnce(E) -> SynthError + '_ {
    move |e| SynthError(format!("{what}: {e}"))
}

/// Tests per clock of a unit: one per transaction, except the half-throughput
/// transform (two transactions per ray).
pub fn throughput(g: &Generated) -> f64 {
    match g.params.values().get("throughput").map(String::as_str) {
        Some("half") => 0.5,
        _ => 1.0,
    }
}

fn hash_text(parts: &[&str]) -> String {
    // FNV-1a 64, twice with different offsets: a cache key, not security.
    let mut a: u64 = 0xcbf29ce484222325;
    let mut b: u64 = 0x84222325cbf29ce4;
    for p in parts {
        for byte in p.bytes().chain(std::iter::once(0)) {
            a = (a ^ byte as u64).wrapping_mul(0x100000001b3);
            b = (b ^ byte as u64).wrapping_mul(0x100000001b3).rotate_left(5);
        }
    }
    format!("{a:016x}{b:016x}")
}

/// A fresh scratch directory under the system temp dir.
pub fn scratch_dir(tag: &str) -> Result<PathBuf, SynthError> {
    let base = std::env::temp_dir().join(format!(
        "rtl-cost-{}-{}-{}",
        std::process::id(),
        tag,
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0)
    ));
    std::fs::create_dir_all(&base).map_err(io("scratch dir"))?;
    Ok(base)
}

fn coarse_without_share(flow: &str) -> &'static str {
    // The `coarse` label of synth_ice40 / synth_ecp5 in Yosys 0.23 minus `share`.
    match flow {
        "ice40" => {
            "opt_expr\nopt_clean\ncheck\nopt -nodffe -nosdff\nfsm\nopt\nwreduce\npeepopt\nopt_clean\n\
             techmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\nmemory_dff\nwreduce t:$mul\n\
             alumacc\nopt\nmemory -nomap\nopt_clean\n"
        }
        _ => {
            "proc\nflatten\ntribuf -logic\ndeminout\nopt_expr\nopt_clean\ncheck\nopt -nodffe -nosdff\nfsm\nopt\n\
             wreduce\npeepopt\nopt_clean\ntechmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\n\
             techmap -map +/mul2dsp.v -map +/ecp5/dsp_map.v -D DSP_A_MAXWIDTH=18 -D DSP_B_MAXWIDTH=18 \
             -D DSP_A_MINWIDTH=2 -D DSP_B_MINWIDTH=2 -D DSP_NAME=$__MUL18X18\n\
             chtype -set $mul t:$__soft_mul\nalumacc\nopt\nmemory -nomap\nopt_clean\n"
        }
    }
}

/// The Yosys script for the unit `top` whose files are `files`.
pub fn yosys_script(top: &str, files: &[String], o: &SynthOptions) -> String {
    let mut s = String::new();
    s += &format!("read_verilog {}\n", files.join(" "));
    s += &format!("hierarchy -check -top {top}\ndesign -save orig\n");
    let nf = if o.flat { "" } else { " -noflatten" };
    if o.generic {
        let flat = if o.flat { " -flatten -noshare" } else { "" };
        s += &format!(
            "design -load orig\nsynth -top {top}{flat}\nflatten\nopt_clean -purge\n\
             tee -q -o generic.stat.json stat -json\ntee -q -o generic.ltp ltp -noff\n"
        );
    }
    if o.ice40 {
        s += "design -load orig\n";
        if o.flat {
            s += &format!("synth_ice40 -top {top} -run begin:coarse\n");
            s += coarse_without_share("ice40");
            s += &format!("synth_ice40 -top {top} -run map_ram:\n");
        } else {
            s += &format!("synth_ice40{nf} -top {top}\n");
        }
        s += "flatten\nopt_clean -purge\ntee -q -o ice40.stat.json stat -json\ntee -q -o ice40.ltp ltp -noff\n";
    }
    if o.ecp5 {
        s += "design -load orig\n";
        if o.flat {
            s += &format!("synth_ecp5 -top {top} -run begin:coarse\n");
            s += coarse_without_share("ecp5");
            s += &format!("synth_ecp5 -top {top} -run map_ram:\n");
        } else {
            s += &format!("synth_ecp5{nf} -top {top}\n");
        }
        s += "flatten\nopt_clean -purge\ntee -q -o ecp5.stat.json stat -json\n";
    }
    s
}

fn cells_by_type(json_path: &Path) -> Result<BTreeMap<String, u64>, SynthError> {
    let text = std::fs::read_to_string(json_path).map_err(io("stat json"))?;
    // `tee -o` may prepend the command echo; the JSON starts at the first brace.
    let start = text
        .find('{')
        .ok_or_else(|| SynthError("stat: no JSON".into()))?;
    let v: serde_json::Value =
        serde_json::from_str(&text[start..]).map_err(io("stat json parse"))?;
    let mut out = BTreeMap::new();
    if let Some(types) = v["design"]["num_cells_by_type"].as_object() {
        for (k, n) in types {
            out.insert(k.clone(), n.as_u64().unwrap_or(0));
        }
    }
    Ok(out)
}

/// Parses `length=N` from the output of `ltp`.
pub fn parse_ltp(text: &str) -> Option<u64> {
    let i = text.find("(length=")?;
    let rest = &text[i + 8..];
    let end = rest.find(')')?;
    rest[..end].trim().parse().ok()
}

fn sum_prefix(m: &BTreeMap<String, u64>, prefix: &str) -> u64 {
    m.iter()
        .filter(|(k, _)| k.starts_with(prefix))
        .map(|(_, v)| *v)
        .sum()
}

/// Runs the flows of `o` on `g`.
pub fn run(g: &Generated, o: &SynthOptions) -> Result<SynthReport, SynthError> {
    let texts: Vec<&str> = g.files.iter().map(|f| f.text.as_str()).collect();
    let key = hash_text(
        &[
            texts.clone(),
            vec![&format!(
                "v{RUNNER_VERSION} g{} i{} e{} p{} f{} t{}",
                o.generic, o.ice40, o.ecp5, o.pnr, o.flat, o.target_mhz
            )],
        ]
        .concat(),
    );
    let cache_file = o
        .cache
        .as_ref()
        .map(|c| c.join(format!("{}-{key}.json", g.module.name)));
    if let Some(cf) = &cache_file {
        if let Ok(text) = std::fs::read_to_string(cf) {
            if let Ok(r) = serde_json::from_str::<SynthReport>(&text) {
                return Ok(r);
            }
        }
    }
    if o.cached_only {
        return Err(SynthError(format!("{}: not in the cache", g.module.name)));
    }
    let dir = scratch_dir(&g.module.name)?;
    let result = run_in(g, o, &dir);
    let _ = std::fs::remove_dir_all(&dir);
    let report = result?;
    if let Some(cf) = &cache_file {
        if let Some(parent) = cf.parent() {
            let _ = std::fs::create_dir_all(parent);
        }
        let tmp = cf.with_extension("tmp");
        let text = serde_json::to_string_pretty(&report).expect("report serialises");
        if std::fs::write(&tmp, text).is_ok() {
            let _ = std::fs::rename(&tmp, cf);
        }
    }
    Ok(report)
}

fn run_in(g: &Generated, o: &SynthOptions, dir: &Path) -> Result<SynthReport, SynthError> {
    g.write(dir, 1000.0 / o.target_mhz)
        .map_err(|e| SynthError(e.to_string()))?;
    let files: Vec<String> = g.files.iter().map(|f| f.file_name.clone()).collect();
    let script = yosys_script(&g.module.name, &files, o);
    std::fs::write(dir.join("run.ys"), &script).map_err(io("script"))?;
    let t0 = Instant::now();
    yosys(dir, "run.ys", "yosys.log")?;
    let yosys_seconds = t0.elapsed().as_secs_f64();
    let mut r = SynthReport {
        unit: g.unit.clone(),
        params: g.params.values().clone().into_iter().collect(),
        top: g.module.name.clone(),
        latency: g.module.latency,
        throughput: throughput(g),
        flat: o.flat,
        yosys_seconds,
        ..Default::default()
    };
    if o.generic {
        let by_type = cells_by_type(&dir.join("generic.stat.json"))?;
        let ltp = std::fs::read_to_string(dir.join("generic.ltp")).unwrap_or_default();
        r.generic = Some(Generic {
            cells: by_type.values().sum(),
            ffs: by_type
                .iter()
                .filter(|(k, _)| k.contains("DFF"))
                .map(|(_, v)| *v)
                .sum(),
            by_type,
            depth: parse_ltp(&ltp).unwrap_or(0),
        });
    }
    if o.ice40 {
        let t = cells_by_type(&dir.join("ice40.stat.json"))?;
        let ltp = std::fs::read_to_string(dir.join("ice40.ltp")).unwrap_or_default();
        r.ice40 = Some(Ice40 {
            luts: sum_prefix(&t, "SB_LUT4"),
            carries: sum_prefix(&t, "SB_CARRY"),
            dffs: sum_prefix(&t, "SB_DFF"),
            depth: parse_ltp(&ltp).unwrap_or(0),
        });
    }
    if o.ecp5 {
        let t = cells_by_type(&dir.join("ecp5.stat.json"))?;
        r.ecp5 = Some(Ecp5 {
            luts: sum_prefix(&t, "LUT4"),
            ffs: sum_prefix(&t, "TRELLIS_FF"),
            dsps: sum_prefix(&t, "MULT18X18D"),
            carries: sum_prefix(&t, "CCU2C"),
        });
    }
    if o.pnr {
        r.pnr = Some(place_and_route(g, o, dir, r.ice40.as_ref())?);
    }
    Ok(r)
}

fn yosys(dir: &Path, script: &str, log: &str) -> Result<(), SynthError> {
    let out = Command::new("yosys")
        .current_dir(dir)
        .args(["-q", "-l", log, "-s", script])
        .output()
        .map_err(io("running yosys (installed? scripts/setup.sh)"))?;
    if !out.status.success() {
        let log_text = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
        let tail: Vec<&str> = log_text.lines().rev().take(15).collect();
        return Err(SynthError(format!(
            "yosys failed in {}: {}\n{}",
            dir.display(),
            String::from_utf8_lossy(&out.stderr),
            tail.into_iter().rev().collect::<Vec<_>>().join("\n")
        )));
    }
    Ok(())
}

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

/// Parses the `ICESTORM_LC: used/ total` utilisation line.
pub fn parse_lcs(log: &str) -> Option<(u64, u64)> {
    let l = log.lines().rev().find(|l| l.contains("ICESTORM_LC:"))?;
    let rest = l.split("ICESTORM_LC:").nth(1)?;
    let mut it = rest.split('/');
    let used = it.next()?.trim().parse().ok()?;
    let total = it.next()?.split_whitespace().next()?.parse().ok()?;
    Some((used, total))
}

fn place_and_route(
    g: &Generated,
    o: &SynthOptions,
    dir: &Path,
    est: Option<&Ice40>,
) -> Result<Pnr, SynthError> {
    let shell = crate::shell::timing_shell(&g.module).map_err(|e| SynthError(e.to_string()))?;
    let in_bits: u64 = g.module.inputs.iter().map(|p| p.ty.width() as u64).sum();
    // LUTs of the unit, plus FFs of the chain that cannot pack with a LUT.
    let estimate = est.map(|e| e.luts.max(e.dffs + in_bits)).unwrap_or(0);
    let device = DEVICES
        .iter()
        .find(|d| (estimate as f64) < MAX_FILL * d.lcs as f64);
    let mut pnr = Pnr {
        target_mhz: o.target_mhz,
        ..Default::default()
    };
    let Some(device) = device else {
        pnr.note = format!(
            "does not fit an iCE40: ~{estimate} LUT4 (+{in_bits} scan FFs) > {:.0} % of HX8K's {} LCs",
            MAX_FILL * 100.0,
            DEVICES[1].lcs
        );
        return Ok(pnr);
    };
    pnr.device = device.name.to_string();
    let files = rtl_gen::emit::emit(&shell, rtl_gen::GENERATOR);
    let mut names = Vec::new();
    for f in &files {
        std::fs::write(dir.join(&f.file_name), &f.text).map_err(io("shell"))?;
        names.push(f.file_name.clone());
    }
    let script = format!(
        "read_verilog {}\nsynth_ice40{} -top {}\nflatten\nwrite_json shell.json\n",
        names.join(" "),
        if o.flat { "" } else { " -noflatten" },
        shell.name
    );
    std::fs::write(dir.join("shell.ys"), script).map_err(io("shell script"))?;
    yosys(dir, "shell.ys", "shell.log")?;
    let t0 = Instant::now();
    let out = Command::new("nextpnr-ice40")
        .current_dir(dir)
        .args([
            &format!("--{}", device.name),
            "--package",
            device.package,
            "--json",
            "shell.json",
            "--pcf-allow-unconstrained",
            "--timing-allow-fail",
            "--freq",
            &format!("{}", o.target_mhz),
            "--seed",
            "1",
            "--asc",
            "shell.asc",
            "-l",
            "nextpnr.log",
        ])
        .output()
        .map_err(io("running nextpnr-ice40 (installed? scripts/setup.sh)"))?;
    pnr.seconds = t0.elapsed().as_secs_f64();
    let log = std::fs::read_to_string(dir.join("nextpnr.log")).unwrap_or_default();
    if let Some((used, total)) = parse_lcs(&log) {
        pnr.lcs_used = used;
        pnr.lcs_total = total;
    }
    pnr.fmax_mhz = parse_fmax(&log);
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        let last: Vec<&str> = err.lines().filter(|l| l.contains("ERROR")).collect();
        pnr.note = format!("nextpnr failed: {}", last.join("; "));
    } else if let Some(f) = pnr.fmax_mhz {
        pnr.note = if f >= o.target_mhz {
            format!("PASS at {} MHz", o.target_mhz)
        } else {
            format!("FAIL at {} MHz (reported, not hidden)", o.target_mhz)
        };
    }
    Ok(pnr)
}

/// One markdown table row per report (header from [`table_header`]).
pub fn table_row(r: &SynthReport) -> String {
    let p: Vec<String> = r.params.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let opt = |v: Option<u64>| v.map(|x| x.to_string()).unwrap_or_else(|| "–".into());
    let g = r.generic.as_ref();
    let i = r.ice40.as_ref();
    let e = r.ecp5.as_ref();
    let fmax = match &r.pnr {
        Some(p) if p.fmax_mhz.is_some() => {
            format!("{:.1} ({})", p.fmax_mhz.unwrap(), p.device)
        }
        Some(p) if p.device.is_empty() => "no fit".into(),
        Some(p) => format!("– ({})", p.note),
        None => "–".into(),
    };
    format!(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
        r.unit,
        p.join(" "),
        r.latency,
        r.throughput,
        opt(g.map(|g| g.cells)),
        opt(g.map(|g| g.depth)),
        opt(i.map(|i| i.luts)),
        opt(i.map(|i| i.carries)),
        opt(i.map(|i| i.dffs)),
        opt(i.map(|i| i.depth)),
        opt(e.map(|e| e.luts)),
        opt(e.map(|e| e.ffs)),
        opt(e.map(|e| e.dsps)),
        fmax,
        format_args!("{:.0}", r.yosys_seconds),
    )
}

/// Header of the markdown table.
pub fn table_header() -> String {
    "| unit | parameters | latency | tests/clk | cells | depth | iCE40 LUT4 | carry | DFF | LUT depth | ECP5 LUT4 | FF | DSP | Fmax MHz (device) | yosys s |\n\
     |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        .to_string()
}
