//! `rtl-gen fit` on every shipped scene, judged on the scene's own render
//! (issue #15): the picked format renders the same image as binary32
//! (instance, primitive and `t` per pixel), no single-ray miss of any
//! rendered candidate is a hit of the exact test on the unrounded ray, and
//! the picked format's box tests per ray are within the target. Small
//! renders (48 pixels wide) to keep CI short; docs/cost.md has full size.

use std::path::Path;

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
