//! Bad input to the flow's and the cost tools' commands, as an audit of the
//! command line found it (2026-12-07): each case exits 2 with a message that
//! names the problem, and leaves nothing behind. No Verilator, no synthesis.

mod common;

use common::{rtl_gen, text};
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join("bad_input")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Runs `args`, expects exit 2 and `says` in the output.
fn refused(args: &[&str], says: &str) {
    let o = rtl_gen(args);
    assert_eq!(o.status.code(), Some(2), "rtl-gen {args:?}: {}", text(&o));
    assert!(text(&o).contains(says), "rtl-gen {args:?}: {}", text(&o));
}

/// The files under `dir`, for "nothing was written".
fn files_in(dir: &Path) -> Vec<PathBuf> {
    std::fs::read_dir(dir).map_or_else(|_| Vec::new(), |r| r.map(|e| e.unwrap().path()).collect())
}

#[test]
fn a_parameter_given_twice_is_refused() {
    let dir = scratch("twice");
    let out = dir.join("v");
    for (args, says) in [
        (
            &["emit", "fadd", "-p", "stages=2", "-p", "stages=5"][..],
            "`stages` is given twice",
        ),
        (
            &["emit", "fadd", "--format", "binary16", "-p", "frac_bits=3"],
            "`frac_bits` is given twice",
        ),
        (
            &["emit", "fadd", "--round", "rne", "-p", "round=rtz"],
            "`round` is given twice",
        ),
    ] {
        let mut a = args.to_vec();
        a.extend(["--out", s(&out)]);
        refused(&a, says);
        assert!(!out.exists(), "{args:?} wrote {}", out.display());
    }
    refused(
        &[
            "bringup",
            "mulcmp",
            "-p",
            "stages=1",
            "-p",
            "stages=2",
            "--out",
            s(&out),
        ],
        "given twice",
    );
    assert!(!out.exists());
}

#[test]
fn the_bringup_wrapper_refuses_impossible_options() {
    let dir = scratch("bringup");
    let out = dir.join("b");
    // a UART bit needs 4 clock cycles (it panicked before)
    refused(
        &["bringup", "fadd", "--cycles-per-bit", "3", "--out", s(&out)],
        "4..",
    );
    // the board top must be a Verilog name, and not one of the design's modules
    refused(
        &["bringup", "mulcmp", "--top", "bad name", "--out", s(&out)],
        "Verilog identifier",
    );
    let unit_top = "mulcmp_a16_b16_s2";
    let o = rtl_gen(&["emit", "mulcmp", "--out", s(&dir.join("e"))]);
    assert!(
        text(&o).contains(unit_top),
        "the unit's top is {unit_top}: {}",
        text(&o)
    );
    refused(
        &["bringup", "mulcmp", "--top", unit_top, "--out", s(&out)],
        "other than the design's modules",
    );
    assert!(!out.exists());
}

#[test]
fn emit_is_all_or_nothing() {
    let dir = scratch("emit");
    // one of the names it writes is taken by a directory: nothing else stays
    let out = dir.join("v");
    std::fs::create_dir_all(out.join("fadd_e8m23_rne_s2_top.sdc")).unwrap();
    refused(
        &["emit", "fadd", "--out", s(&out)],
        "fadd_e8m23_rne_s2_top.sdc",
    );
    assert_eq!(files_in(&out), vec![out.join("fadd_e8m23_rne_s2_top.sdc")]);
    // the cocotb files too: the vectors written before the golden results failed are removed
    let out = dir.join("c");
    let golden = out.join("fadd_e8m23_rne_s2_top.golden.txt");
    std::fs::create_dir_all(&golden).unwrap();
    refused(
        &[
            "emit",
            "fadd",
            "--out",
            s(&out),
            "--cocotb",
            "--cocotb-vectors",
            "3",
        ],
        "golden.txt",
    );
    assert_eq!(files_in(&out), vec![golden]);
    // clock periods the SDC cannot state
    for period in ["1e-300", "0.0004", "1e300", "0", "nan"] {
        refused(
            &[
                "emit",
                "fadd",
                "--out",
                s(&dir.join("p")),
                "--clock-period-ns",
                period,
            ],
            "0.001..=1e6",
        );
        assert!(!dir.join("p").exists(), "{period}");
    }
}

#[test]
fn outputs_are_checked_before_the_work() {
    let dir = scratch("outputs");
    let vectors = dir.join("v.txt");
    let o = rtl_gen(&[
        "vectors",
        "fadd",
        "--format",
        "binary16",
        "--count",
        "3",
        "--out",
        s(&vectors),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    // indices past 2^64 - 1 (it wrote a header and no vector)
    refused(
        &[
            "vectors",
            "fadd",
            "--count",
            "3",
            "--first",
            "18446744073709551614",
            "--out",
            s(&dir.join("w.txt")),
        ],
        "2^64 - 1",
    );
    assert!(!dir.join("w.txt").exists());
    let golden = dir.join("g.txt");
    let run = |extra: &[&str]| {
        let mut a = vec![
            "golden",
            "fadd",
            "--format",
            "binary16",
            "--in",
            s(&vectors),
            "--out",
            s(&golden),
        ];
        a.extend(extra);
        a.iter().map(|x| x.to_string()).collect::<Vec<_>>()
    };
    let missing = dir.join("nodir").join("r.json");
    for (extra, says) in [
        (vec!["--report", s(&missing)], "no such directory"),
        (vec!["--junit", s(&dir)], "is a directory"),
        (vec!["--report", s(&golden)], "two outputs"),
    ] {
        let a = run(&extra);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        refused(&a, says);
        assert!(!golden.exists(), "{a:?} left {}", golden.display());
    }
    // outputs are renamed into place: a special file would be replaced (as
    // root, `--out /dev/full` replaced the device); a FIFO stands for one here
    let fifo = dir.join("fifo");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo {}", fifo.display());
    let a = run(&[]);
    let mut a: Vec<&str> = a.iter().map(String::as_str).collect();
    let out_at = a.iter().position(|x| *x == s(&golden)).unwrap();
    a[out_at] = s(&fifo);
    refused(&a, "not a regular file");
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(!kind.is_file(), "the FIFO was replaced by a file");
    // the renderer's outputs too
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell.toml");
    let png = dir.join("x.png");
    refused(
        &[
            "render",
            scene,
            "--width",
            "8",
            "--out",
            s(&png),
            "--dump-hits",
            s(&fifo),
        ],
        "not a regular file",
    );
    assert!(!png.exists());
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(!kind.is_file(), "the FIFO was replaced by a file");
    // an output that is a symbolic link is written through it: the link stays, the file it
    // names gets the output (a rename onto the link replaced the link and left the file
    // stale); one file named twice through a link is two outputs on one file
    let real = dir.join("real.txt");
    std::fs::write(&real, "stale").unwrap();
    let link = dir.join("link.txt");
    std::os::unix::fs::symlink("real.txt", &link).unwrap();
    let a = run(&[]);
    let mut a: Vec<&str> = a.iter().map(String::as_str).collect();
    a[out_at] = s(&link);
    let o = rtl_gen(&a);
    assert!(o.status.success(), "{a:?}: {}", text(&o));
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    let written = std::fs::read_to_string(&real).unwrap();
    assert!(written.len() > 5 && written != "stale", "{written}");
    a.extend(["--report", s(&real)]);
    refused(&a, "two outputs");
    let png_link = dir.join("img.png");
    std::os::unix::fs::symlink("real.png", &png_link).unwrap();
    let o = rtl_gen(&["render", scene, "--width", "8", "--out", s(&png_link)]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(std::fs::symlink_metadata(&png_link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::metadata(dir.join("real.png")).unwrap().len() > 0);
    // a report, then merge-reports: a bad junit path leaves no merged report
    let report = dir.join("r.json");
    let a = run(&["--report", s(&report)]);
    let o = rtl_gen(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", text(&o));
    let merged = dir.join("m.json");
    refused(
        &[
            "merge-reports",
            s(&report),
            "--out",
            s(&merged),
            "--junit",
            s(&missing),
        ],
        "no such directory",
    );
    assert!(!merged.exists());
    // a report whose verdict disagrees with its counts is not merged
    let edited = dir.join("edited.json");
    let json = std::fs::read_to_string(&report).unwrap();
    assert!(json.contains("\"passed\": true"), "{json}");
    std::fs::write(
        &edited,
        json.replace("\"passed\": true", "\"passed\": false"),
    )
    .unwrap();
    refused(
        &["merge-reports", s(&edited), "--out", s(&merged)],
        "says passed = false",
    );
    assert!(!merged.exists());
}

/// `fit` checks its JSON path before the fit (it wrote the design and its
/// report, then failed on the JSON), and the cost tools' render widths are
/// the scene file's image sides.
#[test]
fn cost_commands_check_outputs_and_widths_first() {
    let dir = scratch("cost");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell.toml");
    let out = dir.join("fit");
    let json = dir.join("nodir").join("f.json");
    refused(
        &[
            "fit",
            scene,
            "--no-synth",
            "--out",
            s(&out),
            "--json",
            s(&json),
        ],
        "no such directory",
    );
    assert!(!out.exists(), "fit left {}", out.display());
    for command in ["per-ray", "boxes"] {
        for width in ["0", "100000"] {
            refused(&[command, "--width", width], "1..=16384");
        }
    }
}

/// Options that would do nothing, or pass on nothing, are refused: a check
/// of 0 vectors (it printed PASS), a cocotb test of none, `--plane-savings`
/// without planes, `hybrid --work` without `--rtl`.
#[test]
fn options_that_would_do_nothing_are_refused() {
    let dir = scratch("nothing");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/cornell.toml");
    let png = dir.join("x.png");
    for (args, says) in [
        (&["check", "fadd", "--vectors", "0"][..], "--vectors"),
        (
            &[
                "emit",
                "fadd",
                "--out",
                s(&dir.join("e")),
                "--cocotb",
                "--cocotb-vectors",
                "0",
            ],
            "--cocotb-vectors",
        ),
        (
            &[
                "render",
                scene,
                "--out",
                s(&png),
                "--no-planes",
                "--plane-savings",
            ],
            "cannot be used with",
        ),
        (
            &[
                "hybrid",
                scene,
                "--out",
                s(&png),
                "--work",
                s(&dir.join("w")),
            ],
            "--rtl",
        ),
    ] {
        refused(args, says);
    }
    assert!(files_in(&dir).is_empty(), "{:?}", files_in(&dir));
}
