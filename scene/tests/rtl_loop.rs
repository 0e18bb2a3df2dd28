//! RTL in the loop (the second test: over a wide BVH, every node test through
//! the `node` unit; the third: every triangle test through the `outputs=tnum`
//! unit, `--tri tnum`): every box, transform, cull and triangle test of a
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
    let r =
        rtl_loop(&s, &acc, None, TraceOpts::default(), w, h, &work, false).expect("rtl loop runs");
    eprintln!("cornell {w}x{h}, {} rays\n{r}", r.golden.rays());
    assert!(
        r.golden.ids.iter().any(|k| k.0 != u32::MAX),
        "something is hit"
    );
    for u in &r.units {
        let unused = matches!(
            u.stream,
            Stream::Node | Stream::NodeTlas | Stream::TriangleTnum
        );
        assert_eq!(
            u.used, !unused,
            "{}: the default render uses every unit but the node tester and the tnum triangle",
            u.top
        );
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

/// Over the wide BVH (N = 4, q = 8, the TLAS at q = 16): every node test of a
/// cornell 32×32 render (AO 2) through the Verilated `node` unit (its TLAS
/// and BLAS shapes), every transform and triangle test through theirs; the
/// image answered from the RTL is identical, and each node stream is as long
/// as the traversal's node visits of its tree level.
#[test]
fn every_node_test_through_the_rtl_gives_the_identical_image() {
    use golden_model::float::FloatFormat;
    use golden_model::wide::WideFormat;
    use scene::wide::{WideAccel, TLAS_BOX_BITS};
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 2;
    let acc = Accel::build(&s, false);
    let format = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let wide = WideAccel::build(&acc, format, TLAS_BOX_BITS).unwrap();
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rtl_loop_wide");
    let _ = std::fs::remove_dir_all(&work);
    let (w, h) = (32, 32);
    let opts = TraceOpts::single_rays();
    let r = rtl_loop(&s, &acc, Some(&wide), opts, w, h, &work, false).expect("rtl loop runs");
    eprintln!("cornell {w}x{h} wide N=4, {} rays\n{r}", r.golden.rays());
    assert!(r.ok(), "{r}");
    assert_eq!(r.golden.ids, r.rtl.ids);
    assert_eq!(r.golden.t, r.rtl.t);
    let g = r.golden.stats.total();
    let n = |s: Stream| r.unit(s).vectors;
    for u in &r.units {
        let used = matches!(
            u.stream,
            Stream::Node | Stream::NodeTlas | Stream::Transform | Stream::Triangle
        );
        assert_eq!(u.used, used, "{}", u.line());
        assert!(u.ok(), "{}", u.line());
    }
    assert_eq!(n(Stream::Node) + n(Stream::NodeTlas), g.node_visits, "{r}");
    assert!(n(Stream::NodeTlas) >= 1000, "{r}");
    assert!(n(Stream::Node) >= 1000, "{r}");
    assert_eq!(g.tri_tests, n(Stream::Triangle), "{r}");
}

/// `rtl-loop --tri tnum`: every triangle test of a cornell 32×32 render (AO 2,
/// bundles and planes on) through the Verilated `triangle outputs=tnum
/// products=whole` (the build `per-ray` costs; `T` and `det` out, no divider,
/// `t` divided in software once per accepted hit), 0 bits differing from the
/// golden `tnum` model, and the RTL-answered image identical to the render
/// with the `outputs=full` unit's golden model (`--tri golden`): ids, `t`
/// bits, colour bits.
#[test]
fn every_triangle_test_through_the_tnum_unit_gives_the_full_image() {
    use scene::render::render;
    use scene::rtl::differing_pixels;
    use scene::tester::Golden;
    use scene::trace::TriTest;
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 2;
    let acc = Accel::build(&s, true);
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("rtl_loop_tnum");
    let _ = std::fs::remove_dir_all(&work);
    let (w, h) = (32, 32);
    let opts = TraceOpts {
        tri: TriTest::GoldenTnum,
        ..TraceOpts::default()
    };
    let r = rtl_loop(&s, &acc, None, opts, w, h, &work, false).expect("rtl loop runs");
    eprintln!("cornell {w}x{h} --tri tnum, {} rays\n{r}", r.golden.rays());
    assert!(r.ok(), "{r}");
    let (full, tnum) = (r.unit(Stream::Triangle), r.unit(Stream::TriangleTnum));
    assert!(!full.used && full.vectors == 0, "{}", full.line());
    assert!(tnum.used, "{}", tnum.line());
    assert_eq!(tnum.mismatches, 0, "{r}");
    assert_eq!(tnum.missing, 0, "{r}");
    assert_eq!(tnum.answered, tnum.vectors, "{r}");
    assert!(tnum.top.contains("tnum"), "{}", tnum.top);
    let g = r.golden.stats.total();
    assert_eq!(g.tri_tests, tnum.vectors, "{r}");
    assert!(tnum.vectors >= 1000, "{}", tnum.line());
    assert_eq!(r.differing_pixels, 0, "{r}");
    // the image of the `outputs=full` unit's golden model, same options
    let golden_full = render(
        &s,
        &acc,
        &Golden::default(),
        TraceOpts {
            tri: TriTest::Golden,
            ..opts
        },
        w,
        h,
        false,
    );
    assert!(golden_full.ids.iter().any(|k| k.0 != u32::MAX));
    assert_eq!(differing_pixels(&golden_full, &r.rtl), 0, "{r}");
    assert_eq!(golden_full.ids, r.rtl.ids);
    assert_eq!(golden_full.t, r.rtl.t);
}
