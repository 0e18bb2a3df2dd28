//! `rtl-cost fit` on a mesh with a NaN or infinite vertex: exit 2, the error
//! names the file and the vertex, nothing is written (issue #13); an empty
//! mesh likewise (issue #15).

use std::path::Path;
use std::process::{Command, Output};

/// `rtl-cost fit OBJ --out OUT --no-synth`.
fn fit(obj: &Path, out: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rtl-cost"))
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
