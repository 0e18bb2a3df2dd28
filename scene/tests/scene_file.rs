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
    // the bunny lives in ../shared/scenes (beside the clone): a missing
    // folder fails here, naming the path, instead of skipping the mesh
    let bunny = scenes().join("../../shared/scenes/stanford-bunny.obj");
    assert!(
        bunny.exists(),
        "{} is missing (scenes/bunny.toml needs ../shared/scenes beside the clone)",
        bunny.display()
    );
    Scene::load(&scenes().join("bunny.toml")).unwrap_or_else(|e| panic!("{e}"));
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
    for opacity in ["0.0", "1.5", "-0.5", "nan"] {
        let m = bad(&GOOD.replace(
            "mesh = \"quad\"",
            &format!("mesh = \"quad\"\nopacity = {opacity}"),
        ));
        assert!(
            m.contains("field `instances[0].opacity`") && m.contains("(0, 1]"),
            "{m}"
        );
    }
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
    // a camera so far from its target that the f32 set-up overflows (was an empty image)
    let m = bad(&GOOD.replace(
        "position = [0.0, 1.0, 3.0]",
        "position = [0.0, 1.0, 3.0e19]",
    ));
    assert!(
        m.contains("field `camera.look_at`") && m.contains("3.000e19 from camera.position"),
        "{m}"
    );
    let m = bad(&GOOD.replace("position = [0.0, 1.0, 3.0]", "position = [0.0, nan, 3.0]"));
    assert!(
        m.contains("field `camera.position`") && m.contains("finite"),
        "{m}"
    );
    let e = Scene::load(Path::new("scenes/does-not-exist.toml")).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("scenes/does-not-exist.toml: cannot read"),
        "{e}"
    );
}

/// A scene in its own folder under the test temp dir, with `bad.obj` whose
/// third vertex (0-based 2) has the coordinates `c`.
fn bad_vertex_scene(tag: &str, c: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("bad-vertex-{tag}"));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("bad.obj"),
        format!("v 0 0 0\nv 1 0 0\nv {c}\nv 0 0 1\nf 1 2 3\nf 1 3 4\n"),
    )
    .unwrap();
    let toml = GOOD
        .replace("procedural = \"quad\"", "obj = \"bad.obj\"")
        .replace("[meshes.quad]", "[meshes.thing]")
        .replace("mesh = \"quad\"", "mesh = \"thing\"");
    let p = dir.join("scene.toml");
    std::fs::write(&p, toml).unwrap();
    p
}

#[test]
fn non_finite_vertex_names_the_mesh_and_the_vertex() {
    for (tag, c, shown) in [
        ("nan", "0 nan 1", "(0, NaN, 1)"),
        ("inf", "inf 1 0", "(inf, 1, 0)"),
    ] {
        let p = bad_vertex_scene(tag, c);
        let m = Scene::load(&p).unwrap_err().to_string();
        assert!(
            m.contains("field `meshes.thing.obj`")
                && m.contains("bad.obj: vertex 2 (0-based) is ")
                && m.contains(shown)
                && m.contains("must be finite"),
            "{m}"
        );
    }
    // procedural shapes are checked too (a grass blade taller than f32 allows)
    let m = bad(&GOOD.replace(
        "procedural = \"quad\"",
        "procedural = \"grass\"\nblades = 50\nheight = 3.4e38",
    ));
    assert!(
        m.contains("field `meshes.quad`: mesh `quad`: vertex ") && m.contains("inf"),
        "{m}"
    );
}

/// A minimal valid scene with a point light, its instance placed by translate/rotate/scale.
const LIT: &str = include_str!("data/lit.toml");

/// `LIT` with `extra` appended (a later table, or keys of the last one).
fn lit_with(extra: &str) -> String {
    format!("{LIT}{extra}\n")
}

/// `LIT` with an area light appended (`keys` replace the default ones by name).
fn area_light(keys: &str) -> String {
    let mut light = vec![
        ("corner", "[0.0, 3.0, 0.0]"),
        ("edge_u", "[1.0, 0.0, 0.0]"),
        ("edge_v", "[0.0, 0.0, 1.0]"),
        ("color", "[5.0, 5.0, 5.0]"),
    ];
    let mut text = String::from("[[lights]]\nkind = \"area\"\n");
    for line in keys.lines() {
        let key = line.split('=').next().unwrap().trim();
        light.retain(|(k, _)| *k != key);
        text += &format!("{line}\n");
    }
    for (k, v) in light {
        text += &format!("{k} = {v}\n");
    }
    lit_with(&text)
}

#[test]
fn the_lit_scene_and_its_area_light_load() {
    assert!(Scene::parse(LIT, Path::new("x.toml")).is_ok());
    assert!(Scene::parse(&area_light(""), Path::new("x.toml")).is_ok());
    let grid =
        lit_with("[[grids]]\nmesh = \"q\"\ncount = [3, 2]\nspacing = 1.0\ncolors = [[1, 0, 0]]");
    let s = Scene::parse(&grid, Path::new("x.toml")).unwrap();
    assert_eq!(s.instances.len(), 7);
}

#[test]
fn image_size_and_ao_rays_are_bounded() {
    use scene::scene::{ao_rays_in_range, RenderSettings, MAX_AO_RAYS, MAX_IMAGE_SIDE};
    let r = RenderSettings {
        width: 8,
        height: 16,
        ..RenderSettings::default()
    };
    assert_eq!(r.image_size(None, None), Ok((8, 16)));
    assert_eq!(r.image_size(Some(4), None), Ok((4, 8)));
    assert_eq!(
        r.image_size(Some(MAX_IMAGE_SIDE), Some(MAX_IMAGE_SIDE)),
        Ok((MAX_IMAGE_SIDE, MAX_IMAGE_SIDE))
    );
    for (w, h, named) in [
        (Some(100_000), None, "--width 100000"),
        (Some(0), None, "--width 0"),
        (None, Some(0), "--height 0"),
        (None, Some(MAX_IMAGE_SIDE + 1), "--height 16385"),
        // the height scaled with the width: 2 × 16384
        (
            Some(MAX_IMAGE_SIDE),
            None,
            "the height scaled to --width 16384",
        ),
    ] {
        let e = r.image_size(w, h).unwrap_err();
        assert!(e.contains(named) && e.contains("1..=16384"), "{e}");
    }
    assert_eq!(ao_rays_in_range(MAX_AO_RAYS), Ok(MAX_AO_RAYS));
    assert!(ao_rays_in_range(4_000_000_000).is_err());
    let m = bad(&lit_with("").replace("height = 8", "height = 8\nao_rays = 4000000000"));
    assert!(
        m.contains("field `render.ao_rays`") && m.contains("0..=256"),
        "{m}"
    );
}

#[test]
fn grid_count_product_does_not_wrap() {
    // 65536 × 65536 is 2^32: 0 in u32 arithmetic, which passed the 1e6 check
    let m = bad(&lit_with(
        "[[grids]]\nmesh = \"q\"\ncount = [65536, 65536]\nspacing = 1.0",
    ));
    assert!(
        m.contains("field `grids[0].count`") && m.contains("1..=1e6"),
        "{m}"
    );
}

#[test]
fn grass_parameters_are_bounded() {
    let grass = |keys: &str| {
        lit_with(&format!(
            "[meshes.g]\nprocedural = \"grass\"\nblades = 10\n{keys}"
        ))
    };
    for (keys, field, says) in [
        ("segments = 4000000000", "meshes.g.segments", "1..=1024"),
        ("segments = 0", "meshes.g.segments", "1..=1024"),
        (
            "segments = 1024\nblades = 2000000",
            "meshes.g.segments",
            "blades × segments",
        ),
        ("height = nan", "meshes.g.height", "positive and finite"),
        ("width = 0.0", "meshes.g.width", "positive and finite"),
        ("width = inf", "meshes.g.width", "positive and finite"),
        ("size = -1.0", "meshes.g.size", "not negative"),
    ] {
        // `blades = 2000000` replaces the default 10 (a duplicate key is a TOML error)
        let text = if keys.contains("blades") {
            grass(keys).replace("blades = 10\n", "")
        } else {
            grass(keys)
        };
        let m = bad(&text);
        assert!(
            m.contains(&format!("field `{field}")) && m.contains(says),
            "{keys}: {m}"
        );
    }
    let m = bad(&lit_with("[meshes.g]\nprocedural = \"quad\"\nsegments = 4"));
    assert!(
        m.contains("field `meshes.g.segments`") && m.contains("grass"),
        "{m}"
    );
    let m = bad(&lit_with(
        "[meshes.g]\nprocedural = \"grass\"\nsubdivisions = 2",
    ));
    assert!(
        m.contains("field `meshes.g.subdivisions`") && m.contains("sphere"),
        "{m}"
    );
    assert!(Scene::parse(&grass("segments = 1024"), Path::new("x.toml")).is_ok());
}

#[test]
fn fixed_length_arrays_refuse_other_lengths() {
    for (from, to, field) in [
        (
            "position = [0.0, 1.0, 3.0]",
            "position = [0, 1, 3, 99]",
            "camera.position",
        ),
        (
            "look_at = [0.0, 0.0, 0.0]",
            "look_at = [0.0, 0.0]",
            "camera.look_at",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\nrotate = [0, 1, 0, 30, 45]",
            "instances[0].rotate",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\nscale = [1, 1]",
            "instances[0].scale",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\ntransform = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]",
            "instances[0].transform",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\ntransform = [[1, 0, 0, 0, 5], [0, 1, 0, 0], [0, 0, 1, 0]]",
            "instances[0].transform",
        ),
        (
            "height = 8",
            "height = 8\nbackground = [0, 0, 0, 1]",
            "render.background",
        ),
        (
            "color = [5.0, 5.0, 5.0]",
            "color = [5.0, 5.0, 5.0, 5.0]",
            "lights[0].color",
        ),
    ] {
        let m = bad(&LIT.replace(from, to));
        assert!(
            m.contains(&format!("field `{field}`")) && m.contains("elements"),
            "{to}: {m}"
        );
    }
    let m = bad(&lit_with(
        "[[grids]]\nmesh = \"q\"\ncount = [2, 2, 2]\nspacing = 1.0",
    ));
    assert!(
        m.contains("field `grids[0].count`") && m.contains("elements"),
        "{m}"
    );
    let m = bad(&lit_with(
        "[[grids]]\nmesh = \"q\"\ncount = [2, 2]\nspacing = 1.0\ncolors = [[1, 1, 1, 1]]",
    ));
    assert!(
        m.contains("field `grids[0].colors`") && m.contains("elements"),
        "{m}"
    );
}

#[test]
fn a_degenerate_camera_up_is_refused() {
    for up in ["[0.0, 0.0, 0.0]", "[0.0, -1.0, -3.0]", "[0.0, 2.0, 6.0]"] {
        let m = bad(&LIT.replace(
            "look_at = [0.0, 0.0, 0.0]",
            &format!("look_at = [0.0, 0.0, 0.0]\nup = {up}"),
        ));
        assert!(
            m.contains("field `camera.up`") && m.contains("parallel"),
            "{up}: {m}"
        );
    }
}

#[test]
fn colours_ambient_and_lights_must_be_finite() {
    for (from, to, field) in [
        ("height = 8", "height = 8\nambient = nan", "render.ambient"),
        ("height = 8", "height = 8\nambient = inf", "render.ambient"),
        ("height = 8", "height = 8\nambient = -5.0", "render.ambient"),
        (
            "height = 8",
            "height = 8\nbackground = [nan, -1, inf]",
            "render.background",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\ncolor = [nan, -3, inf]",
            "instances[0].color",
        ),
        (
            "mesh = \"q\"",
            "mesh = \"q\"\ncolor = [1, -3, 1]",
            "instances[0].color",
        ),
        (
            "position = [0.0, 3.0, 0.0]",
            "position = [nan, inf, 0]",
            "lights[0].position",
        ),
        (
            "color = [5.0, 5.0, 5.0]",
            "color = [nan, -5, inf]",
            "lights[0].color",
        ),
    ] {
        let m = bad(&LIT.replace(from, to));
        assert!(
            m.contains(&format!("field `{field}`")) && m.contains("finite"),
            "{to}: {m}"
        );
    }
    for (keys, field) in [
        ("edge_u = [0.0, 0.0, 0.0]", "lights[1].edge_v"),
        ("edge_v = [2.0, 0.0, 0.0]", "lights[1].edge_v"),
        ("corner = [nan, 0.0, 0.0]", "lights[1].corner"),
        ("color = [1.0, inf, 1.0]", "lights[1].color"),
    ] {
        let m = bad(&area_light(keys));
        assert!(
            m.contains(&format!("field `{field}`")) && m.contains("finite"),
            "{keys}: {m}"
        );
    }
    let m = bad(&area_light("samples = 0"));
    assert!(
        m.contains("field `lights[1].samples`") && m.contains("1..=256"),
        "{m}"
    );
    let m = bad(&lit_with(
        "[[grids]]\nmesh = \"q\"\ncount = [2, 2]\nspacing = 1.0\ncolors = [[1, 1, 1], [nan, 1, 1]]",
    ));
    assert!(
        m.contains("field `grids[0].colors[1]`") && m.contains("finite"),
        "{m}"
    );
}

#[test]
fn grids_get_the_instance_checks() {
    let grid = |keys: &str| {
        lit_with(&format!(
            "[[grids]]\nmesh = \"q\"\ncount = [2, 2]\nspacing = 1.0\n{keys}"
        ))
    };
    for (keys, field, says) in [
        ("spacing = nan", "grids[0].spacing", "finite"),
        ("spacing = inf", "grids[0].spacing", "finite"),
        (
            "origin = [1e300, 0, 0]",
            "grids[0] (instance x 0, z 0)",
            "finite f32",
        ),
        ("origin = [nan, 0, 0]", "grids[0].origin", "finite"),
        ("scale = inf", "grids[0].scale", "finite"),
        (
            "scale = 1e-45",
            "grids[0] (instance x 0, z 0)",
            "overflows binary32",
        ),
        (
            "scale = 1e-39",
            "grids[0] (instance x 0, z 0)",
            "overflows binary32",
        ),
    ] {
        let text = if keys.starts_with("spacing") {
            grid(keys).replace("spacing = 1.0\n", "")
        } else {
            grid(keys)
        };
        let m = bad(&text);
        assert!(
            m.contains(&format!("field `{field}`")) && m.contains(says),
            "{keys}: {m}"
        );
    }
}

#[test]
fn a_transform_whose_inverse_overflows_binary32_is_refused() {
    // determinant nonzero, but 1/1e-39 is past binary32's range: the instance vanished
    let m = bad(&LIT.replace("mesh = \"q\"", "mesh = \"q\"\nscale = [0.5, 0.5, 1e-39]"));
    assert!(
        m.contains("field `instances[0].transform`")
            && m.contains("inverse")
            && m.contains("overflows binary32"),
        "{m}"
    );
    let ok = LIT.replace("mesh = \"q\"", "mesh = \"q\"\nscale = [0.5, 0.5, 1e-38]");
    assert!(Scene::parse(&ok, Path::new("x.toml")).is_ok());
}

#[test]
fn errors_in_lights_and_grids_name_their_table() {
    // a value's error names its key; a key missing from or foreign to the light's kind
    // names the light and the key
    let m = bad(&LIT.replace("color = [5.0, 5.0, 5.0]", "color = \"white\""));
    assert!(m.contains("field `lights[0].color`"), "{m}");
    let m = bad(&LIT.replace("position = [0.0, 3.0, 0.0]\n", ""));
    assert!(
        m.contains("field `lights[0]`") && m.contains("missing field `position`"),
        "{m}"
    );
    let m = bad(&LIT.replace(
        "position = [0.0, 3.0",
        "edge_u = [1.0, 0.0, 0.0]\nposition = [0.0, 3.0",
    ));
    assert!(
        m.contains("field `lights[0]`") && m.contains("`edge_u` is not a point light's"),
        "{m}"
    );
    let m = bad(&area_light("samples = \"many\""));
    assert!(m.contains("field `lights[1].samples`"), "{m}");
    let m = bad(&lit_with(
        "[[grids]]\nmesh = \"q\"\ncount = [2, 2]\nspacing = \"wide\"",
    ));
    assert!(m.contains("field `grids[0].spacing`"), "{m}");
    let m = bad(&lit_with("[[grids]]\nmesh = \"q\"\ncount = [2, 2]"));
    assert!(
        m.contains("field `grids[0]") && m.contains("spacing"),
        "{m}"
    );
}
