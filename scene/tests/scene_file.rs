//! Scene files: the shipped ones load; bad files name the file and the field.

use scene::scene::Scene;
use std::path::{Path, PathBuf};

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

const GOOD: &str = r#"
[camera]
position = [0.0, 1.0, 3.0]
look_at = [0.0, 1.0, 0.0]
[meshes.quad]
procedural = "quad"
[[instances]]
mesh = "quad"
transform = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]]
"#;

fn bad(text: &str) -> String {
    let e = Scene::parse(text, Path::new("scenes/bad.toml")).unwrap_err();
    e.to_string()
}

#[test]
fn shipped_scenes_load() {
    for name in ["cornell", "field", "grass"] {
        let p = scenes().join(format!("{name}.toml"));
        let s = Scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
        assert!(!s.instances.is_empty());
    }
    // the bunny lives in ../shared/scenes; only when that folder is present
    let p = scenes().join("bunny.toml");
    if scenes()
        .join("../../shared/scenes/stanford-bunny.obj")
        .exists()
    {
        Scene::load(&p).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(Scene::parse(GOOD, Path::new("x.toml")).is_ok());
}

#[test]
fn type_error_names_file_and_field() {
    let m = bad(&GOOD.replace(
        "look_at = [0.0, 1.0, 0.0]",
        "look_at = [0.0, 1.0, 0.0]\nfov_y = \"wide\"",
    ));
    assert!(
        m.starts_with("scenes/bad.toml: field `camera.fov_y`:"),
        "{m}"
    );
}

#[test]
fn missing_and_unknown_fields_are_named() {
    let m = bad(&GOOD.replace("look_at = [0.0, 1.0, 0.0]\n", ""));
    assert!(
        m.contains("scenes/bad.toml") && m.contains("camera") && m.contains("look_at"),
        "{m}"
    );
    let m = bad(&GOOD.replace(
        "procedural = \"quad\"",
        "procedural = \"quad\"\nsubdivision = 3",
    ));
    assert!(
        m.contains("meshes.quad") && m.contains("subdivision"),
        "{m}"
    );
    let m = bad(&GOOD.replace("[[instances]]", "[render]\nwidth = -3\n[[instances]]"));
    assert!(m.contains("field `render.width`"), "{m}");
}

#[test]
fn semantic_errors_are_named() {
    let m = bad(&GOOD.replace("mesh = \"quad\"", "mesh = \"teapot\""));
    assert!(
        m.contains("field `instances[0].mesh`") && m.contains("teapot"),
        "{m}"
    );
    let m = bad(&GOOD.replace("[0, 1, 0, 0], [0, 0, 1, 0]]", "[0, 0, 0, 0], [0, 0, 1, 0]]"));
    assert!(
        m.contains("field `instances[0].transform`") && m.contains("singular"),
        "{m}"
    );
    let m = bad(&GOOD.replace("procedural = \"quad\"", "procedural = \"torus\""));
    assert!(
        m.contains("field `meshes.quad.procedural`") && m.contains("torus"),
        "{m}"
    );
    let m = bad(&GOOD.replace("procedural = \"quad\"", "obj = \"nope/missing.obj\""));
    assert!(
        m.contains("field `meshes.quad.obj`") && m.contains("missing.obj"),
        "{m}"
    );
    let m = bad(&GOOD.replace("[[instances]]", "[camera2]\n[[instances]]"));
    assert!(m.contains("camera2"), "{m}");
    let m = bad(&(GOOD.to_string() + "[[lights]]\nkind = \"spot\"\nposition = [0, 0, 0]\n"));
    assert!(m.contains("lights[0]") && m.contains("spot"), "{m}");
    let e = Scene::load(Path::new("scenes/does-not-exist.toml")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("scenes/does-not-exist.toml: cannot read"),
        "{e}"
    );
}
