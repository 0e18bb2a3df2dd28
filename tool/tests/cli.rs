//! The `rtl-gen` command line, run as a user would.

use std::path::PathBuf;
mod common;

use common::{rtl_gen, text};

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn help_explains_the_handshake_and_the_subcommands() {
    let o = rtl_gen(&["--help"]);
    assert!(o.status.success());
    let t = text(&o);
    for want in ["list", "emit", "check", "replay", "in_valid", "latency"] {
        assert!(t.contains(want), "--help lacks {want}:\n{t}");
    }
}

#[test]
fn list_shows_units_with_parameter_ranges() {
    let t = text(&rtl_gen(&["list"]));
    assert!(
        t.contains("mulcmp:")
            && t.contains("a_width")
            && t.contains("1..=32")
            && t.contains("stages"),
        "{t}"
    );
}

#[test]
fn emit_writes_verilog_port_list_and_constraints() {
    let dir = scratch("cli_emit");
    let o = rtl_gen(&[
        "emit",
        "mulcmp",
        "-p",
        "stages=1",
        "--param",
        "b_width=8",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    for f in [
        "mulcmp_a16_b8_s1.v",
        "umul_16x8_s0.v",
        "mulcmp_a16_b8_s1.ports.json",
        "mulcmp_a16_b8_s1.sdc",
    ] {
        assert!(dir.join(f).is_file(), "missing {f}: {}", text(&o));
    }
    let ports = sim::PortList::load(dir.join("mulcmp_a16_b8_s1.ports.json")).unwrap();
    assert_eq!(ports.latency, 1);
    let sdc = std::fs::read_to_string(dir.join("mulcmp_a16_b8_s1.sdc")).unwrap();
    assert!(
        sdc.contains("create_clock -name clk -period 10.000 [get_ports clk]"),
        "{sdc}"
    );
}

#[test]
fn bad_parameters_exit_with_a_clear_message() {
    let o = rtl_gen(&["emit", "mulcmp", "-p", "a_width=0", "--out", "/tmp/never"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("a_width=0 is invalid; expected an integer in 1..=32"),
        "{}",
        text(&o)
    );
    let o = rtl_gen(&["check", "raybox"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("unknown unit `raybox`"), "{}", text(&o));
}

#[test]
fn check_reports_zero_mismatches_and_throughput_and_replay_traces() {
    let dir = scratch("cli_check");
    let o = rtl_gen(&[
        "check",
        "mulcmp",
        "-p",
        "stages=2",
        "--vectors",
        "200000",
        "--seed",
        "3",
        "--no-progress",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    assert!(t.contains("verilator --lint-only -Wall: clean"), "{t}");
    assert!(t.contains("vectors/s"), "{t}");
    let vcd = dir.join("one.vcd");
    let o = rtl_gen(&[
        "replay",
        "mulcmp",
        "-p",
        "stages=2",
        "--seed",
        "3",
        "--index",
        "123456",
        "--vcd",
        vcd.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("out lt"), "{}", text(&o));
    let trace = std::fs::read_to_string(&vcd).unwrap();
    assert!(
        trace.contains("$var") && trace.contains("ab_lt_cd"),
        "trace lacks signals"
    );
}

/// A `handshake=ready` unit through the vectors flow: `check` and `sim` drive
/// it with random stalls on both sides (docs/handshake.md) and pass.
#[test]
fn check_and_sim_drive_a_ready_unit_with_stalls() {
    let dir = scratch("cli_ready");
    let unit = [
        "mulcmp",
        "-p",
        "a_width=8",
        "-p",
        "b_width=8",
        "-p",
        "handshake=ready",
    ];
    let out = ["--out", dir.to_str().unwrap()];
    let o = rtl_gen(
        &[
            &["check"][..],
            &unit,
            &["--vectors", "30000", "--no-progress"],
            &out,
        ]
        .concat(),
    );
    let t = text(&o);
    assert!(
        o.status.success() && t.contains("PASS: `mulcmp_a8_b8_s2_rdy`, 30000 vectors"),
        "{t}"
    );
    assert!(!t.contains("(0 bubbles)"), "no input-side stalls: {t}");
    let vecs = dir.join("v.txt");
    let o = rtl_gen(
        &[
            &["vectors"][..],
            &unit,
            &["--count", "500", "--out", vecs.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(o.status.success(), "{}", text(&o));
    let results = dir.join("r.txt");
    let files = [
        "--in",
        vecs.to_str().unwrap(),
        "--out",
        results.to_str().unwrap(),
    ];
    let o = rtl_gen(
        &[
            &["sim"][..],
            &unit,
            &files,
            &["--dir", dir.to_str().unwrap()],
        ]
        .concat(),
    );
    let t = text(&o);
    assert!(
        o.status.success() && t.contains("500 records") && t.contains("PASS"),
        "{t}"
    );
}

/// Every subcommand of the flow, the renderer, the cost tools and `fpga`.
const SUBCOMMANDS: [&str; 25] = [
    "list",
    "emit",
    "check",
    "sim",
    "golden",
    "vectors",
    "convert",
    "merge-reports",
    "replay",
    "transform-accuracy",
    "render",
    "hybrid",
    "rtl-loop",
    "bench",
    "wide",
    "synth",
    "fit",
    "boxes",
    "cull",
    "depth",
    "per-ray",
    "dot-styles",
    "charts",
    "bringup",
    "fpga",
];

/// `rtl-gen` is the one command (issue #18): every group's subcommands are
/// under it, each with its own `--help`.
#[test]
fn every_subcommand_is_listed_and_explains_itself() {
    let top = rtl_gen(&["--help"]);
    assert!(top.status.success(), "{}", text(&top));
    let help = text(&top);
    for s in SUBCOMMANDS {
        assert!(
            help.lines()
                .any(|l| l.trim_start().starts_with(&format!("{s} "))),
            "`rtl-gen --help` lists {s}:\n{help}"
        );
        let o = rtl_gen(&[s, "--help"]);
        assert!(o.status.success(), "rtl-gen {s} --help: {}", text(&o));
        assert!(text(&o).contains("Usage: rtl-gen"), "rtl-gen {s} --help");
    }
}

/// One real run per group of `rtl-gen`, and one bad input each (exit 2).
#[test]
fn one_run_per_group() {
    let tmp = scratch("one_tool");
    std::fs::create_dir_all(&tmp).unwrap();

    // the flow
    let o = rtl_gen(&["list"]);
    assert!(
        o.status.success() && text(&o).contains("silhouette:"),
        "{}",
        text(&o)
    );

    // the renderer
    let png = tmp.join("cornell.png");
    let o = rtl_gen(&[
        "render",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell.toml"),
        "--width",
        "16",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "rtl-gen render: {}", text(&o));
    assert!(std::fs::metadata(&png).unwrap().len() > 0);

    // the cost tools' bring-up wrapper (Verilator lints it)
    let dir = tmp.join("bringup");
    let o = rtl_gen(&[
        "bringup",
        "mulcmp",
        "-p",
        "stages=1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "rtl-gen bringup: {}", text(&o));
    assert!(dir.join("bringup_top.v").is_file());

    // bad input: exit 2 with a message, in each group
    for args in [
        &["emit", "no_such_unit", "--out", "x"][..],
        &["render", "no_such_scene.toml", "--out", "x.png"],
        &["synth", "no_such_unit", "--no-pnr"],
    ] {
        let o = rtl_gen(args);
        assert_eq!(o.status.code(), Some(2), "rtl-gen {args:?}: {}", text(&o));
        assert!(text(&o).contains("error"), "rtl-gen {args:?}: {}", text(&o));
    }
}

/// `rtl-gen hybrid` with a partial-render mode and reversed depth: every
/// order identical; a bad `--mode` or `--compare` exits 2 naming the option.
#[test]
fn hybrid_modes_and_bad_options() {
    let tmp = scratch("hybrid_modes");
    std::fs::create_dir_all(&tmp).unwrap();
    let png = tmp.join("h.png");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell.toml");
    let run = |extra: &[&str]| {
        let mut a = vec![
            "hybrid",
            scene,
            "--width",
            "16",
            "-o",
            png.to_str().unwrap(),
        ];
        a.extend_from_slice(extra);
        rtl_gen(&a)
    };
    let o = run(&["--mode", "partial:4", "--compare", "greater"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("hybrid: every order identical to the synchronous render"),
        "{}",
        text(&o)
    );
    for (opt, bad) in [
        ("--mode", "partial:0"),
        ("--mode", "later"),
        ("--compare", "never"),
    ] {
        let o = run(&[opt, bad]);
        assert_eq!(o.status.code(), Some(2), "{opt} {bad}: {}", text(&o));
        assert!(
            text(&o).contains(opt) && text(&o).contains(bad),
            "{}",
            text(&o)
        );
    }
}
