//! `rtl-gen render` from the command line. `--box-format eXmY --dump-hits
//! FILE` (issue #15): the reduced-format box tester renders the binary32
//! image (the dumps agree line for line), the dump is one line per pixel
//! with a documented header, and a bad format is an error (exit 2) that
//! writes nothing. A scene with a non-finite vertex: exit 2 with the message,
//! no image. `rtl-loop --tri f64` or `exact`: exit 2.

use std::path::Path;
use std::process::Command;

fn render(args: &[&str], png: &Path) -> std::process::Output {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml");
    Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .arg("render")
        .arg(scene)
        .args(["--width", "32", "-o"])
        .arg(png)
        .args(args)
        .output()
        .unwrap()
}

fn body(text: &str) -> Vec<&str> {
    text.lines().filter(|l| !l.starts_with('#')).collect()
}

#[test]
fn reduced_format_dump_equals_binary32_dump() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-formats");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut dumps = Vec::new();
    for fmt in [None, Some("e6m9"), Some("e5m5")] {
        let dump = dir.join(format!("{}.txt", fmt.unwrap_or("binary32")));
        let mut args = vec!["--dump-hits", dump.to_str().unwrap()];
        if let Some(f) = fmt {
            args.extend(["--box-format", f]);
        }
        let r = render(&args, &dir.join("x.png"));
        assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
        let text = std::fs::read_to_string(&dump).unwrap();
        assert!(text.starts_with("# render --dump-hits:"), "{text}");
        assert!(text.contains("# width 32 height 32"));
        if let Some(f) = fmt {
            assert!(String::from_utf8_lossy(&r.stdout).contains(&format!("reduced {f}")));
        }
        dumps.push(text);
    }
    let base = body(&dumps[0]);
    assert_eq!(base.len(), 32 * 32);
    let hits = base.iter().filter(|l| !l.ends_with(" - - -")).count();
    assert!(hits > 500, "{hits} hit pixels");
    assert_eq!(base[33].split(' ').take(2).collect::<Vec<_>>(), ["1", "1"]);
    for d in &dumps[1..] {
        assert_eq!(body(d), base, "reduced-format render differs from binary32");
    }
}

#[test]
fn a_bad_box_format_is_an_error_and_writes_nothing() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-bad-format");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for (arg, says) in [
        (vec!["--box-format", "e9x3"], "expected binary16"),
        (vec!["--box-format", "e3m70"], "e3m70"),
        (
            vec!["--box-format", "e6m9", "--box", "exact"],
            "--box golden",
        ),
    ] {
        let png = dir.join("x.png");
        let r = render(&arg, &png);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "{arg:?}: {err}");
        assert!(err.contains(says), "{arg:?}: {err}");
        assert!(!png.exists(), "{arg:?} wrote {}", png.display());
    }
}

/// The render CLI exits 2 with the message and writes no image.
#[test]
fn a_non_finite_vertex_is_an_error_and_writes_nothing() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("render-bad-vertex");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("bad.obj"),
        "v 0 0 0\nv 1 0 0\nv nan 0 1\nv 0 0 1\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        r#"
[camera]
position = [0.0, 1.0, 3.0]
look_at = [0.0, 1.0, 0.0]
[meshes.thing]
obj = "bad.obj"
[[instances]]
mesh = "thing"
transform = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]
"#,
    )
    .unwrap();
    let out = dir.join("out.png");
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
        .arg("render")
        .arg(&scene)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(2), "{err}");
    assert!(
        err.contains("error: ")
            && err.contains("field `meshes.thing.obj`")
            && err.contains("vertex 2 (0-based) is (NaN, 0, 1)"),
        "{err}"
    );
    assert!(!out.exists(), "wrote {}", out.display());
}

/// `rtl-loop` runs the triangle unit: `--tri f64` or `exact` asked of it is an
/// error (exit 2) before anything is built or written.
#[test]
fn rtl_loop_refuses_a_software_triangle_test() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("rtl-loop-bad-tri");
    let _ = std::fs::remove_dir_all(&dir);
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml");
    for tri in ["f64", "exact"] {
        let png = dir.join("x.png");
        let r = Command::new(env!("CARGO_BIN_EXE_rtl-gen"))
            .arg("rtl-loop")
            .arg(&scene)
            .args(["--width", "8", "--tri", tri, "-o"])
            .arg(&png)
            .arg("--work")
            .arg(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(2), "--tri {tri}: {err}");
        assert!(err.contains("--tri golden (outputs=full) or tnum"), "{err}");
        assert!(!dir.exists(), "--tri {tri} wrote {}", dir.display());
    }
}
