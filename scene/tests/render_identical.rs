//! Conservativeness end to end: the image rendered with the silhouette unit's
//! reduced-precision conservative box tests is identical (hit/miss, instance
//! and primitive id, t, colour bits) to the one rendered with exact box tests;
//! bundles and cull planes do not change a bit either.

use scene::bvh::Accel;
use scene::render::{render, Frame};
use scene::scene::Scene;
use scene::tester::{Exact, Golden};
use scene::trace::{BundleOpts, TraceOpts};
use std::path::Path;

fn cornell() -> Scene {
    let mut s =
        Scene::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell.toml")).unwrap();
    s.render.ao_rays = 2;
    s
}

fn same(a: &Frame, b: &Frame, what: &str) {
    let hits = a.ids.iter().filter(|k| k.0 != u32::MAX).count();
    assert!(hits > 0, "{what}: nothing hit");
    for p in 0..a.ids.len() {
        assert_eq!(a.ids[p], b.ids[p], "{what}: pixel {p} primitive");
        assert_eq!(a.t[p], b.t[p], "{what}: pixel {p} t");
        assert_eq!(a.color_bits(p), b.color_bits(p), "{what}: pixel {p} colour");
    }
}

#[test]
fn conservative_equals_exact_and_bundles_and_planes_change_nothing() {
    let s = cornell();
    let acc = Accel::build(&s, true);
    let singles = TraceOpts {
        bundles: BundleOpts {
            enabled: false,
            ..BundleOpts::default()
        },
        ..TraceOpts::default()
    };
    let (w, h) = (32, 32);
    let golden = render(&s, &acc, &Golden::default(), singles, w, h, false);
    let exact = render(&s, &acc, &Exact, singles, w, h, false);
    same(&golden, &exact, "golden vs exact box tests");
    for max_size in [4, 16, 64] {
        let b = TraceOpts {
            bundles: BundleOpts {
                max_size,
                ..BundleOpts::default()
            },
            ..TraceOpts::default()
        };
        let f = render(&s, &acc, &Golden::default(), b, w, h, false);
        assert!(f.stats.total().bundle_tests > 0);
        same(
            &golden,
            &f,
            &format!("bundles of {max_size} vs single rays"),
        );
    }
    let no_planes = TraceOpts {
        planes: false,
        ..singles
    };
    let f = render(&s, &acc, &Golden::default(), no_planes, w, h, false);
    same(&golden, &f, "cull planes vs none");
    assert!(
        golden.stats.total().culled_nodes > 0,
        "the planes culled something"
    );
    assert!(golden.stats.total().leaf_visits < f.stats.total().leaf_visits);
}

/// Bundles are tested with the largest `t_max` of their rays (sound: the
/// bundle's segment covers every ray's). The gross counter "box tests saved by
/// bundles" is reported beside the net figure, box tests without bundles minus
/// with them (`render --bundle-savings`); on cornell the net saving is real
/// for primary rays and the image is unchanged.
#[test]
fn bundle_savings_are_reported_net() {
    let s = cornell();
    let acc = Accel::build(&s, true);
    let (w, h) = (32, 32);
    let with = render(
        &s,
        &acc,
        &Golden::default(),
        TraceOpts::default(),
        w,
        h,
        false,
    );
    let single = TraceOpts {
        bundles: BundleOpts {
            enabled: false,
            ..BundleOpts::default()
        },
        ..TraceOpts::default()
    };
    let without = render(&s, &acc, &Golden::default(), single, w, h, false);
    same(&with, &without, "bundles vs single rays");
    let tests = |f: &Frame| {
        let k = &f.stats.kinds[scene::stats::RayKind::Primary as usize];
        k.ray_box_tests + k.bundle_tests
    };
    assert!(
        tests(&with) < tests(&without),
        "{} vs {}",
        tests(&with),
        tests(&without)
    );
    let t = scene::stats::bundle_savings(&with.stats, &without.stats);
    let all = t
        .lines()
        .find(|l| l.starts_with("| all |"))
        .expect("total row");
    let net = tests(&without) as i64 - tests(&with) as i64;
    let primary = t
        .lines()
        .find(|l| l.starts_with("| primary |"))
        .expect("primary row");
    assert!(primary.contains(&format!("| {net} (")), "{primary}");
    println!("{t}\n{all}");
}
