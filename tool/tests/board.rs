//! `rtl-gen board` end to end without a board: the Verilated bring-up wrapper
//! with its UART pins driven from a pseudo-terminal at the bit level
//! (cost/tests/bringup_pty.cpp, 4 clock cycles a bit), and the same
//! `rtl-gen board` a user runs against /dev/ttyUSB0 talking to it. Two units
//! with 0 mismatches, a corrupted answer reported as a mismatch (exit 1), a
//! silent board reported within its timeout and a port that cannot be opened
//! (exit 2).

use cost::bringup::{record_bytes, Bringup};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::OnceLock;
use std::time::Instant;
mod common;

use common::{rtl_gen, text};

/// Clock cycles a UART bit in the simulated board (the receiver's minimum).
const CPB: u32 = 4;

/// Vectors a unit runs in CI (the figure: docs/fpga.md records the run).
const VECTORS: u64 = 10_000;

/// A unit's simulated board: the executable and its record sizes.
struct Model {
    exe: PathBuf,
    in_bytes: usize,
    out_bytes: usize,
}

fn model(unit: &str, params: &[&str]) -> Model {
    let params: Vec<String> = params.iter().map(|s| s.to_string()).collect();
    let g = rtl_flow::generate(unit, &params).unwrap();
    let b = Bringup::new(&g, CPB);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("board_{}", b.module.name));
    let tb = Path::new(env!("CARGO_MANIFEST_DIR")).join("../cost/tests/bringup_pty.cpp");
    let exe = b
        .build_testbench(&dir, &tb)
        .unwrap_or_else(|e| panic!("{e}"));
    Model {
        exe,
        in_bytes: record_bytes(b.in_widths.iter().copied()),
        out_bytes: record_bytes(b.out_widths.iter().copied()),
    }
}

const MULCMP: [&str; 3] = ["a_width=8", "b_width=8", "stages=2"];
const FADD: [&str; 3] = ["exp_bits=8", "frac_bits=7", "stages=2"];

fn mulcmp() -> &'static Model {
    static M: OnceLock<Model> = OnceLock::new();
    M.get_or_init(|| model("mulcmp", &MULCMP))
}

fn fadd() -> &'static Model {
    static M: OnceLock<Model> = OnceLock::new();
    M.get_or_init(|| model("fadd", &FADD))
}

/// A running simulated board; stops when dropped (its stdin closes).
struct Board {
    child: Child,
    port: String,
}

impl Board {
    fn start(m: &Model, mode: &[&str]) -> Board {
        let mut child = Command::new(&m.exe)
            .args([m.in_bytes, m.out_bytes, CPB as usize].map(|n| n.to_string()))
            .args(mode)
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .spawn()
            .expect("the simulated board runs");
        let mut line = String::new();
        BufReader::new(child.stdout.as_mut().unwrap())
            .read_line(&mut line)
            .unwrap();
        let port = line
            .strip_prefix("pty ")
            .unwrap_or_else(|| panic!("simulated board said `{line}`"))
            .trim()
            .to_string();
        Board { child, port }
    }
}

impl Drop for Board {
    fn drop(&mut self) {
        drop(self.child.stdin.take());
        let _ = self.child.wait();
    }
}

/// `rtl-gen board UNIT -p ... --port PTY EXTRA...`: its exit code and text.
fn board(unit: &str, params: &[&str], port: &str, extra: &[&str]) -> (Option<i32>, String) {
    let mut args = vec!["board", unit];
    for p in params {
        args.extend(["-p", p]);
    }
    args.extend(["--port", port]);
    args.extend(extra);
    let o = rtl_gen(&args);
    (o.status.code(), text(&o))
}

fn all_match(unit: &str, params: &[&str], m: &Model) {
    let b = Board::start(m, &[]);
    let n = VECTORS.to_string();
    let t0 = Instant::now();
    let (code, t) = board(unit, params, &b.port, &["--vectors", &n]);
    eprintln!("{t}{unit}: {:.1} s", t0.elapsed().as_secs_f64());
    assert_eq!(code, Some(0), "{t}");
    assert!(
        t.contains("PASS: board `") && t.contains(&format!("{n} vectors, 0 mismatches")),
        "{t}"
    );
}

#[test]
fn mulcmp_and_fadd_answer_every_vector_right() {
    all_match("mulcmp", &MULCMP, mulcmp());
    all_match("fadd", &FADD, fadd());
}

#[test]
fn vectors_from_a_file() {
    let m = mulcmp();
    let file = Path::new(env!("CARGO_TARGET_TMPDIR")).join("board_vectors.txt");
    let mut args = vec!["vectors", "mulcmp"];
    for p in MULCMP {
        args.extend(["-p", p]);
    }
    args.extend(["--count", "50", "--out", file.to_str().unwrap()]);
    assert!(rtl_gen(&args).status.success());
    let b = Board::start(m, &[]);
    let (code, t) = board(
        "mulcmp",
        &MULCMP,
        &b.port,
        &["--in", file.to_str().unwrap()],
    );
    assert_eq!(code, Some(0), "{t}");
    assert!(t.contains("50 vectors, 0 mismatches"), "{t}");
}

#[test]
fn a_corrupted_answer_is_a_mismatch_with_its_replay_command() {
    let b = Board::start(mulcmp(), &["corrupt", "7"]);
    let (code, t) = board("mulcmp", &MULCMP, &b.port, &["--vectors", "40"]);
    assert_eq!(code, Some(1), "{t}");
    for want in [
        "FAIL: board `",
        "40 vectors, 1 mismatches",
        "first failing vector: index 7",
        "replay:   rtl-gen replay mulcmp",
        "--seed 1 --index 7",
    ] {
        assert!(t.contains(want), "`{want}` missing:\n{t}");
    }
}

#[test]
fn a_silent_board_is_reported_within_its_timeout() {
    let b = Board::start(mulcmp(), &["silent"]);
    let t0 = Instant::now();
    let (code, t) = board("mulcmp", &MULCMP, &b.port, &["--timeout", "0.5"]);
    let secs = t0.elapsed().as_secs_f64();
    assert_eq!(code, Some(2), "{t}");
    assert!(
        t.contains("the board did not answer vector 0") && t.contains("no answer within 0.5 s"),
        "{t}"
    );
    assert!(secs < 5.0, "reported after {secs:.1} s");
}

#[test]
fn a_port_that_cannot_be_opened_is_a_clear_error() {
    let (code, t) = board("mulcmp", &MULCMP, "/dev/no-such-tty", &[]);
    assert_eq!(code, Some(2), "{t}");
    assert!(
        t.contains("cannot open serial port /dev/no-such-tty"),
        "{t}"
    );
}
