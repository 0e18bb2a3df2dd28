//! `rtl-gen wide`: on a small render of the Cornell box the report is sane
//! (nodes, bytes per node as `golden_model::wide` computes them, non-zero
//! visits and bytes per ray, child tests with compressed boxes at least those
//! with exact binary32 boxes, the same hits), and bad shapes are errors
//! (exit 2) with a message.

use golden_model::float::FloatFormat;
use golden_model::wide::WideFormat;
use std::path::Path;
use std::process::Command;

fn wide(args: &[&str]) -> std::process::Output {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml");
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .arg("wide")
        .arg(scene)
        .args(["--width", "24"])
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn report_is_sane_on_a_small_render() {
    let o = wide(&["--children", "4,8", "--box-bits", "8,12"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{out}\n{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.contains("24x24 camera rays"), "{out}");
    let rows: Vec<Vec<&str>> = out
        .lines()
        .filter(|l| l.starts_with("| cornell |"))
        .map(|l| l.trim_matches('|').split('|').map(str::trim).collect())
        .collect();
    assert_eq!(rows.len(), 4, "{out}");
    for r in &rows {
        let num = |i: usize| -> f64 { r[i].parse().unwrap_or_else(|_| panic!("{r:?}")) };
        let (n, q) = (num(1) as usize, num(2) as u32);
        let f = WideFormat::new(FloatFormat::BINARY32, n, q).unwrap();
        assert!(num(3) > 0.0, "nodes {r:?}");
        assert_eq!(num(4), f.record_bytes() as f64, "bytes per node {r:?}");
        assert_eq!(num(5), num(3) * num(4), "node bytes {r:?}");
        assert!(num(6) > 0.0, "node visits per ray {r:?}");
        // bytes per ray = bytes per node × visits per ray (rounded in print)
        assert!(
            (num(7) - num(4) * num(6)).abs() <= num(4) * 0.01 + 1.0,
            "{r:?}"
        );
        assert!(num(8) >= num(6), "a visit tests at least one child {r:?}");
        assert_eq!(num(9), f.baseline_bytes() as f64);
        assert!(num(10) > num(7), "binary32 boxes fetch more {r:?}");
        assert!(num(12) >= 1.0, "child-test ratio below 1 {r:?}");
        assert_eq!(r[13], "yes");
        assert!(out.contains(&format!(
            "child tests per ray q={q} / binary32 (N={n}): cornell {}",
            r[12]
        )));
    }
}

#[test]
fn bad_shapes_are_errors() {
    for (args, msg) in [
        (["--children", "3"], "children = 3"),
        (["--box-bits", "3"], "box bits = 3"),
        (["--box-bits", "17"], "box bits = 17"),
    ] {
        let o = wide(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(msg), "{args:?}");
        assert!(o.stdout.is_empty());
    }
}
