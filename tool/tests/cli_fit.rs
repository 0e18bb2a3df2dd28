//! `rtl-gen fit` from the command line: the JSON result of a scene; a scene
//! without instances, a mesh with a NaN or infinite vertex (issue #13) or an
//! empty mesh (issue #15): exit 2, the error names the file and the field or
//! vertex, nothing is written.

use std::path::Path;
use std::process::{Command, Output};

/// `rtl-gen fit OBJ --out OUT --no-synth`.
fn fit(obj: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .arg("fit")
        .arg(obj)
        .arg("--out")
        .arg(out)
        .arg("--no-synth")
        .output()
        .unwrap()
}

#[test]
fn fit_rejects_a_non_finite_vertex() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit-bad-vertex");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (c, shown) in [("0 nan 1", "(0, NaN, 1)"), ("0 0 -inf", "(0, 0, -inf)")] {
        let obj = dir.join("bad.obj");
        std::fs::write(&obj, format!("v 0 0 0\nv 1 0 0\nv {c}\nf 1 2 3\n")).unwrap();
        let out = dir.join("out");
        let r = fit(&obj, &out);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{err}");
        assert!(
            err.contains("bad.obj: line 3: vertex 2 (0-based) is ")
                && err.contains(shown)
                && err.contains("must be finite"),
            "{err}"
        );
        assert!(!out.exists(), "wrote {}", out.display());
    }
}

/// An OBJ without triangles (or without anything) is an error, not a fit of
/// "0 box tests" (issue #15).
#[test]
fn fit_rejects_an_empty_mesh() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit-empty-mesh");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in [("empty.obj", ""), ("points.obj", "v 0 0 0\nv 1 0 0\n")] {
        let obj = dir.join(name);
        std::fs::write(&obj, text).unwrap();
        let out = dir.join("out");
        let r = fit(&obj, &out);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(name) && err.contains("no triangles"), "{err}");
        assert!(!out.exists(), "wrote {}", out.display());
    }
}

#[test]
fn fit_writes_json_and_rejects_a_scene_without_instances() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit-json");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let json = dir.join("fit.json");
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(["fit", "--no-synth", "--width", "32", "--out"])
        .arg(dir.join("out"))
        .arg("--json")
        .arg(&json)
        .arg(scenes.join("cornell.toml"))
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let fmt = v["format"].as_str().expect("format");
    let (e, m) = fmt
        .strip_prefix('e')
        .and_then(|s| s.split_once('m'))
        .expect("eXmY");
    assert_eq!(v["exp_bits"].as_u64(), e.parse::<u64>().ok(), "{v}");
    assert_eq!(v["frac_bits"].as_u64(), m.parse::<u64>().ok(), "{v}");
    assert_eq!(v["same_image_as_binary32"], true);
    assert_eq!(v["false_misses"], 0);
    assert!(v["stages"].is_u64() && v["box_tests_per_ray"].is_f64());

    // a scene that places no instance: exit 2, the file and the field named, nothing written
    let empty = dir.join("empty.toml");
    std::fs::write(&empty, "[camera]\nposition = [0.0, 0.0, 3.0]\nlook_at = [0.0, 0.0, 0.0]\n[meshes.q]\nprocedural = \"quad\"\n").unwrap();
    let out = dir.join("out-empty");
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .args(["fit", "--no-synth", "--out"])
        .arg(&out)
        .arg(&empty)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("empty.toml") && err.contains("instances") && err.contains("no instance"),
        "{err}"
    );
    assert!(!out.exists());
    let err = cost::fit::load(&scenes.join("no_such_scene.toml")).unwrap_err();
    assert!(err.contains("no_such_scene.toml"), "{err}");
}

/// `fit --wide`: the bunny's node shape at width 48 under the 10 % rule: the
/// chosen q is within the rule and every smaller q of its N was refused (at
/// width 64 it is N = 4, q = 6), the chosen `node` unit's RTL is written; a
/// rule of 0 to 1 only.
#[test]
fn fit_wide_chooses_the_smallest_q_within_the_rule() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit-wide");
    let _ = std::fs::remove_dir_all(&out);
    let run = |rate: &str| {
        Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
            .args([
                "fit",
                "--wide",
                "--no-synth",
                "--width",
                "48",
                "--target-rate",
                rate,
            ])
            .arg(root.join("scenes/bunny.toml"))
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    let r = run("0.10");
    let text = String::from_utf8_lossy(&r.stdout);
    assert!(
        r.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let line = text
        .lines()
        .find(|l| l.starts_with("fit --wide: N="))
        .unwrap_or_else(|| panic!("{text}"));
    let (n, q): (u32, u32) = {
        let f: Vec<u32> = line
            .split(|c: char| !c.is_ascii_digit())
            .filter(|s| !s.is_empty())
            .map(|s| s.parse().unwrap())
            .collect();
        (f[0], f[1])
    };
    // every smaller q of that N was refused for its child tests, and q itself is within the rule
    let row = text
        .lines()
        .find(|l| l.starts_with(&format!("| {n} | {q} |")))
        .unwrap_or_else(|| panic!("{text}"));
    let ratio: f64 = row.split('|').nth(4).unwrap().trim().parse().unwrap();
    assert!(ratio <= 1.10, "{row}");
    for smaller in 4..q {
        assert!(row.contains(&format!("q={smaller}: ")), "{row}");
    }
    assert!(q < 12, "the bunny needs no more than q = {q}: {text}");
    assert!(out.join(format!("node_n{n}_q{q}_m9_e8m23_s4.v")).exists());
    assert!(out.join("fit-report.md").exists());
    let bad = run("2");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--target-rate 2"));
}
