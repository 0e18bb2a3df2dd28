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
