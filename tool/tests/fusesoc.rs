//! The FuseSoC core files `rtl-gen emit` writes, read by FuseSoC itself (the
//! pinned `fusesoc` of scripts/fusesoc-requirements.txt in the venv of
//! `bash scripts/setup.sh`): every unit's core parses, `core show` of one
//! exits 0, and its `lint` target runs Verilator and fails on a lint warning.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
mod common;

use common::{rtl_gen, text};

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `fusesoc --cores-root CORES ARGS` in `work` (its build folder goes there).
fn fusesoc(cores: &Path, work: &Path, args: &[&str]) -> Output {
    let exe = cost::synth::fpga_venv().join("bin/fusesoc");
    assert!(
        exe.is_file(),
        "{} not found: run `bash scripts/setup.sh` (installs scripts/fusesoc-requirements.txt)",
        exe.display()
    );
    Command::new(&exe)
        .arg("--cores-root")
        .arg(cores)
        .args(args)
        .current_dir(work)
        .output()
        .expect("fusesoc runs")
}

/// Emits `unit` with `params` into `dir`; returns the core's name (VLNV).
fn emit(unit: &str, params: &[&str], dir: &Path) -> String {
    let mut args = vec!["emit", unit, "--out", dir.to_str().unwrap()];
    for p in params {
        args.extend(["-p", p]);
    }
    let o = rtl_gen(&args);
    assert!(
        o.status.success(),
        "rtl-gen {}: {}",
        args.join(" "),
        text(&o)
    );
    let core = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "core"))
        .unwrap_or_else(|| panic!("no .core written: {}", text(&o)));
    let body = std::fs::read_to_string(&core).unwrap();
    body.lines()
        .find_map(|l| l.strip_prefix("name: "))
        .expect("the core has a name")
        .to_string()
}

#[test]
fn every_units_core_is_accepted() {
    let root = scratch("fusesoc_all");
    let cores = root.join("cores");
    let units: Vec<String> = text(&rtl_gen(&["list"]))
        .lines()
        .filter(|l| !l.starts_with(' ') && l.contains(": "))
        .map(|l| l.split(':').next().unwrap().to_string())
        .collect();
    assert!(units.len() >= 20, "units of `rtl-gen list`: {units:?}");
    let names: Vec<String> = units.iter().map(|u| emit(u, &[], &cores.join(u))).collect();
    // one FuseSoC call parses (and validates against the CAPI2 schema) every core
    let o = fusesoc(&cores, &root, &["core", "list"]);
    let t = text(&o);
    assert!(o.status.success(), "fusesoc core list: {t}");
    assert!(!t.contains("Parse error"), "a core was rejected: {t}");
    for (u, n) in units.iter().zip(&names) {
        assert!(t.contains(n.as_str()), "{u}: core {n} not listed:\n{t}");
    }
    let o = fusesoc(&cores, &root, &["core", "show", &names[0]]);
    assert!(
        o.status.success(),
        "fusesoc core show {}: {}",
        names[0],
        text(&o)
    );
    for target in ["lint", "sim"] {
        assert!(text(&o).contains(target), "target {target}: {}", text(&o));
    }
    // the filelist beside it names the Verilog files, relative to itself
    let dir = cores.join(&units[0]);
    let f = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "f"))
        .expect("a .f filelist");
    for line in std::fs::read_to_string(&f).unwrap().lines() {
        assert!(dir.join(line).is_file(), "{}: {line} missing", f.display());
    }
}

#[test]
fn lint_target_runs_verilator_and_fails_on_a_warning() {
    let root = scratch("fusesoc_lint");
    let cores = root.join("cores");
    let name = emit("fadd", &["exp_bits=5", "frac_bits=4", "stages=1"], &cores);
    let o = fusesoc(&cores, &root, &["run", "--target", "lint", &name]);
    assert!(
        o.status.success(),
        "fusesoc run --target lint: {}",
        text(&o)
    );
    assert!(text(&o).contains("verilator"), "{}", text(&o));

    // an unused, truncated wire in the top module: the lint target must refuse it
    let top = name.split(':').nth(2).unwrap();
    let path = cores.join(format!("{top}.v"));
    let v = std::fs::read_to_string(&path).unwrap();
    let bad = v.replacen("endmodule", "wire [3:0] stray_w = 8'hff;\nendmodule", 1);
    std::fs::write(&path, bad).unwrap();
    let o = fusesoc(&cores, &root, &["run", "--target", "lint", &name]);
    assert!(!o.status.success(), "lint passed a warning: {}", text(&o));
    assert!(text(&o).contains("stray_w"), "{}", text(&o));
}
