//! RTL in the loop: every box, transform, cull and triangle test of a
//! cornell 32×32 render (AO 2, bundles and cull planes on) runs through the
//! Verilated binary32 units (the configurations of `tests/silhouette_rtl.rs`,
//! `transform_rtl.rs`, `cull_rtl.rs` and `triangle_rtl.rs`, so the harness
//! builds are shared through `target/rtl-cache`), and the render answered
//! from the RTL outputs is bit-identical to the golden one. Every unit's
//! stream must be non-empty and exactly as long as the traversal's count of
//! that test. The first run builds the harnesses (minutes); later runs reuse
//! them.

use scene::bvh::Accel;
use scene::rtl::{rtl_loop, Stream};
use scene::scene::Scene;
use scene::trace::TraceOpts;
use std::path::{Path, PathBuf};

#[test]
fn every_unit_through_the_rtl_gives_the_identical_image() {
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
    for u in &r.units {
        assert!(u.used, "{}: the default render uses every unit", u.top);
        assert_eq!(u.mismatches, 0, "{r}");
        assert_eq!(u.missing, 0, "{r}");
        assert_eq!(u.answered, u.vectors, "{r}");
        assert!(u.ok(), "{}", u.line());
    }
    assert_eq!(r.differing_pixels, 0, "{r}");
    assert_eq!(r.golden.ids, r.rtl.ids);
    assert_eq!(r.golden.t, r.rtl.t);
    assert!(r.ok());
    // every test the traversal counted went through the RTL, and each unit
    // was exercised well beyond a token count (floors well under cornell
    // 32×32's figures, docs/scene.md §9)
    let (g, t) = (r.golden.stats.total(), r.rtl.stats.total());
    let n = |s: Stream| r.unit(s).vectors;
    assert_eq!(g.ray_box_tests + g.bundle_tests, r.box_tests(), "{r}");
    assert_eq!(g.transforms, n(Stream::Transform), "{r}");
    assert_eq!(g.cull_ray_terms, n(Stream::CullRay), "{r}");
    assert_eq!(g.cull_tests, n(Stream::Cull), "{r}");
    assert_eq!(g.tri_tests, n(Stream::Triangle), "{r}");
    assert_eq!(
        (g.ray_box_tests, g.bundle_tests, g.tri_tests, g.cull_tests),
        (t.ray_box_tests, t.bundle_tests, t.tri_tests, t.cull_tests)
    );
    assert!(g.bundle_tests > 0);
    for (s, floor) in [
        (Stream::BoxShared, 1000),
        (Stream::BoxBounded, 1),
        (Stream::Transform, 1000),
        (Stream::CullRay, 100),
        (Stream::Cull, 100),
        (Stream::Triangle, 1000),
    ] {
        assert!(n(s) >= floor, "{}: {} tests\n{r}", s.label(), n(s));
    }
}
