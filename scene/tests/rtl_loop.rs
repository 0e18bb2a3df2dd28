//! RTL in the loop: every box test of a cornell 32×32 render (single rays,
//! shared-origin and bounded-origin bundles) runs through the Verilated
//! binary32 silhouette units (the configurations of `tests/silhouette_rtl.rs`,
//! so their harness builds are shared through `target/rtl-cache`), and the
//! render answered from the RTL outputs is bit-identical to the golden one.
//! The first run builds the two harnesses (minutes); later runs reuse them.

use scene::bvh::Accel;
use scene::rtl::rtl_loop;
use scene::scene::Scene;
use scene::trace::TraceOpts;
use std::path::{Path, PathBuf};

#[test]
fn every_box_test_through_the_rtl_gives_the_identical_image() {
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 2;
    let acc = Accel::build(&s, true);
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rtl_loop");
    let _ = std::fs::remove_dir_all(&work);
    let (w, h) = (32, 32);
    let r = rtl_loop(&s, &acc, TraceOpts::default(), w, h, &work, false).expect("rtl loop runs");
    eprintln!("cornell {w}x{h}, {} rays\n{r}", r.golden.rays());
    assert!(
        r.golden.ids.iter().any(|k| k.0 != u32::MAX),
        "something is hit"
    );
    // both units were exercised: single rays and bundles of both kinds
    assert!(r.shared.vectors > 1000, "{r}");
    assert!(r.bounded.vectors > 0, "{r}");
    assert!(r.golden.stats.total().bundle_tests > 0);
    assert_eq!(r.shared.mismatches, 0, "{r}");
    assert_eq!(r.bounded.mismatches, 0, "{r}");
    assert_eq!(r.missing, 0, "{r}");
    assert_eq!(r.answered, r.box_tests(), "{r}");
    assert_eq!(r.differing_pixels, 0, "{r}");
    assert_eq!(r.golden.ids, r.rtl.ids);
    assert_eq!(r.golden.t, r.rtl.t);
    // every box test the traversal counted went through the RTL
    let (g, t) = (r.golden.stats.total(), r.rtl.stats.total());
    assert_eq!(g.ray_box_tests + g.bundle_tests, r.box_tests(), "{r}");
    assert_eq!(
        (g.ray_box_tests, g.bundle_tests),
        (t.ray_box_tests, t.bundle_tests)
    );
    assert!(r.ok());
}
