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
        let (n, q, tlas_q) = (num(1) as usize, num(2) as u32, num(3) as u32);
        assert_eq!(tlas_q, 16, "the TLAS's default q {r:?}");
        let f = WideFormat::new(FloatFormat::BINARY32, n, q).unwrap();
        // every node is a BLAS record (bytes/node) or a TLAS record (finer, larger)
        let (small, large) = (
            f.record_bytes() as f64,
            WideFormat::new(FloatFormat::BINARY32, n, tlas_q)
                .unwrap()
                .record_bytes() as f64,
        );
        assert!(num(4) > 0.0, "nodes {r:?}");
        assert_eq!(num(5), small, "bytes per node {r:?}");
        assert!(
            num(6) > num(4) * small && num(6) < num(4) * large,
            "node bytes {r:?}"
        );
        assert!(num(7) > 0.0, "node visits per ray {r:?}");
        // bytes per ray: visits × the record bytes of the visited nodes (rounded in print)
        assert!(
            num(8) >= num(7) * small - 1.0 && num(8) <= num(7) * large + 1.0,
            "{r:?}"
        );
        assert!(num(9) >= num(7), "a visit tests at least one child {r:?}");
        assert_eq!(num(10), f.baseline_bytes() as f64);
        assert!(num(11) > num(8), "binary32 boxes fetch more {r:?}");
        assert!(num(13) >= 1.0, "child-test ratio below 1 {r:?}");
        assert_eq!(r[14], "yes");
        assert!(out.contains(&format!(
            "child tests per ray q={q} / binary32 (N={n}): cornell {}",
            r[13]
        )));
    }
}

/// `--bundle-tile T` adds one bundle-bound line per shape whose figures add up.
#[test]
fn the_bundle_bound_line_is_printed() {
    let o = wide(&["--children", "4", "--bundle-tile", "4"]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    let line = out
        .lines()
        .find(|l| l.starts_with("bundle bound N=4 q=8 tile 4x4: cornell node tests/ray "))
        .unwrap_or_else(|| panic!("no bundle-bound line: {out}"));
    let nums: Vec<f64> = line
        .split(|c: char| c.is_whitespace() || c == ';' || c == ',')
        .filter_map(|w| w.parse().ok())
        .collect();
    // alone, bundle, single, resolved %, break-even
    let [alone, bundle, single, resolved, even] = nums[nums.len() - 5..] else {
        panic!("{line}")
    };
    assert!(bundle + single < alone, "{line}");
    assert!(resolved > 0.0 && resolved <= 100.0 && even > 1.0, "{line}");
}

#[test]
fn bad_shapes_are_errors() {
    for (args, msg) in [
        (["--children", "3"], "children = 3"),
        (["--box-bits", "3"], "box bits = 3"),
        (["--box-bits", "17"], "box bits = 17"),
        (["--tlas-box-bits", "17"], "TLAS box bits 17"),
        (["--bundle-tile", "0"], "--bundle-tile must be at least 1"),
    ] {
        let o = wide(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains(msg), "{args:?}");
        assert!(o.stdout.is_empty());
    }
}

/// `render --wide` and `per-ray --wide` as a user runs them: the same hits as
/// the binary32 single-ray render, the report's ratio lines, bad shapes refused.
#[test]
fn renders_and_per_ray_over_the_wide_bvh() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let scene = root.join("scenes/field.toml");
    let scene = scene.to_str().unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli-render-wide");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
            .args(args)
            .output()
            .unwrap()
    };
    let path = |n: &str| dir.join(n).to_str().unwrap().to_string();
    let (bin_png, bin_hits, wide_png, wide_hits) = (
        path("bin.png"),
        path("bin.txt"),
        path("wide.png"),
        path("wide.txt"),
    );
    let common = ["--width", "32", "--ao", "1"];
    let mut a = vec!["render", scene];
    a.extend(common);
    a.extend([
        "--bundle",
        "0",
        "--no-planes",
        "-o",
        &bin_png,
        "--dump-hits",
        &bin_hits,
    ]);
    assert!(run(&a).status.success());
    let mut b = vec!["render", scene];
    b.extend(common);
    b.extend(["--wide", "4", "-o", &wide_png, "--dump-hits", &wide_hits]);
    let o = run(&b);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    assert!(out.contains("node unit N=4 q=8"), "{out}");
    assert!(out.contains("| node visits/ray |"), "{out}");
    // the hit dumps agree below their headers (which name the tester)
    let body = |p: &str| {
        std::fs::read_to_string(p)
            .unwrap()
            .lines()
            .skip(2)
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    assert_eq!(body(&bin_hits), body(&wide_hits));
    assert_eq!(
        std::fs::read(&bin_png).unwrap(),
        std::fs::read(&wide_png).unwrap()
    );

    let o = run(&[
        "per-ray",
        scene,
        "--width",
        "24",
        "--wide",
        "4",
        "--no-synth",
    ]);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{out}");
    let line = out
        .lines()
        .find(|l| l.starts_with("child tests per ray q=8 / binary32: field.toml "))
        .unwrap_or_else(|| panic!("{out}"));
    let ratio: f64 = line.rsplit(' ').next().unwrap().parse().unwrap();
    // below 1 when rays that miss a tree's root box skip its N children (docs/wide.md §5)
    assert!((0.85..=1.10).contains(&ratio), "{line}");
    assert!(out.contains("| yes |"), "{out}");

    for (args, says) in [
        (
            vec!["render", scene, "--wide", "3", "-o", &path("x.png")],
            "expected 2, 4 or 8",
        ),
        (
            vec![
                "render",
                scene,
                "--wide",
                "4",
                "--box",
                "exact",
                "-o",
                &path("x.png"),
            ],
            "no --box",
        ),
        (
            vec!["per-ray", scene, "--wide", "4", "--box-bits", "17"],
            "4..=16",
        ),
    ] {
        let o = run(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert!(!dir.join("x.png").exists(), "nothing written on an error");
}
