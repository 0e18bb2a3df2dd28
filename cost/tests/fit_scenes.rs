//! `rtl-cost fit` reads every shipped TOML scene through the scene crate,
//! flattened into world space (instances included).

use std::path::Path;

#[test]
fn every_shipped_scene_loads_for_the_fit_in_world_space() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for name in ["cornell", "field", "grass"] {
        let path = dir.join(format!("{name}.toml"));
        let (mesh, _) = cost::fit::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!mesh.triangles.is_empty(), "{name}");
        let max = mesh
            .vertices
            .iter()
            .flat_map(|v| v.iter())
            .fold(0f32, |m, x| m.max(x.abs()));
        if name == "field" {
            // the field's instances sit around x = z = 1e4: the flattening applied the transforms
            assert!(max > 5_000.0, "field spans {max}");
        }
    }
    let err = cost::fit::load(&dir.join("no_such_scene.toml")).unwrap_err();
    assert!(err.contains("no_such_scene.toml"), "{err}");
}
