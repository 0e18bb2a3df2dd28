//! `rtl-cost fit` on every shipped scene, judged on the scene's own render
//! (issue #15): the picked format renders the same image as binary32
//! (instance, primitive and `t` per pixel), no single-ray miss of any
//! rendered candidate is a hit of the exact test on the unrounded ray, and
//! the picked format's box tests per ray are within the target. Small
//! renders (48 pixels wide) to keep CI short; docs/cost.md has full size.

use std::path::Path;
use std::process::Command;

fn options(width: u32) -> cost::fit::FitOptions {
    cost::fit::FitOptions {
        target_rate: 0.01,
        target_mhz: 20.0,
        width: Some(width),
        synth: false,
        device: "ecp5-85f".into(),
        exact_all: false,
    }
}

#[test]
fn every_shipped_scene_gets_a_format_with_the_binary32_image() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    for name in ["cornell", "bunny", "field", "grass"] {
        let path = dir.join(format!("{name}.toml"));
        let scene = cost::fit::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let f =
            cost::fit::fit(&scene, name, &options(48)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let p = f.picked();
        println!(
            "{name}: {} ({:?} box tests/ray, binary32 {:.3}), {} candidates, {:.1} s",
            f.format,
            p.box_tests_per_ray,
            f.binary32_box_tests_per_ray,
            f.candidates.len(),
            f.seconds
        );
        assert_eq!(p.same_image, Some(true), "{name}: {}", f.report);
        assert_eq!(p.false_misses, 0, "{name}");
        assert!(p.misses > 0, "{name}: no single-ray miss");
        let cost = p.box_tests_per_ray.expect("rendered");
        assert!(
            cost <= 1.01 * f.binary32_box_tests_per_ray,
            "{name}: {cost}"
        );
        for c in &f.candidates {
            assert_eq!(c.false_misses, 0, "{name} {}: false misses", c.format);
            if c.same_image.is_some() {
                assert_eq!(
                    c.same_image,
                    Some(true),
                    "{name} {}: a sound tester changed the image",
                    c.format
                );
            }
        }
        // narrower than binary32, and not so narrow that the render grows (field's old pick,
        // e6m4 from flattened world coordinates, lost every hit pixel)
        assert!(
            f.format.exp_bits() + f.format.frac_bits() < 31,
            "{name}: {}",
            f.format
        );
        assert!(f.format.frac_bits() >= 5, "{name}: {}", f.format);
    }
}

#[test]
fn every_shipped_mesh_gets_a_format_with_the_binary32_image() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/meshes");
    for name in ["spot", "suzanne", "teapot"] {
        let path = dir.join(format!("{name}.obj"));
        let scene = cost::fit::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
        let f =
            cost::fit::fit(&scene, name, &options(40)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let p = f.picked();
        println!(
            "{name}: {} ({:?} box tests/ray, binary32 {:.3})",
            f.format, p.box_tests_per_ray, f.binary32_box_tests_per_ray
        );
        assert_eq!(p.same_image, Some(true), "{name}: {}", f.report);
        assert_eq!(p.false_misses, 0, "{name}");
        assert!(f.candidates.iter().all(|c| c.false_misses == 0), "{name}");
    }
}

#[test]
fn fit_writes_json_and_rejects_a_scene_without_instances() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fit-json");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let json = dir.join("fit.json");
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-cost"))
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
    let r = Command::new(env!("CARGO_BIN_EXE_rtl-cost"))
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
