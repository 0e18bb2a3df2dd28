//! `rtl-gen` is the one command (issue #18): every group's subcommands are
//! under it, each with its own `--help`, and one real run per group.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn rtl_gen(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("rtl-gen runs")
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Every subcommand of the flow, the renderer, the cost tools and `fpga`.
const SUBCOMMANDS: [&str; 24] = [
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

#[test]
fn one_run_per_group() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("one_tool");
    let _ = std::fs::remove_dir_all(&tmp);
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
        "scenes/cornell.toml",
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
