//! The statistics report: one table per scene, one row per ray type.

use crate::trace::{KindStats, RayKind, Stats};

fn row(name: &str, k: &KindStats) -> String {
    let per = |x: u64| x as f64 / k.rays.max(1) as f64;
    format!(
        "| {name} | {} | {} | {:.2} | {} | {} / {} / {} | {} | {:.2} | {:.2} | {} | {} ({} leaves, {} tri tests) | {} |",
        k.rays,
        k.hits,
        k.box_tests_per_ray(),
        k.bundle_tests,
        k.all_hit,
        k.all_miss,
        k.mixed,
        k.saved_box_tests,
        per(k.leaf_visits),
        per(k.tri_tests),
        k.cull_tests,
        k.culled_nodes,
        k.culled_leaves,
        k.culled_leaf_tris,
        k.transforms,
    )
}

/// Markdown table of the counters per ray type and in total.
pub fn table(s: &Stats) -> String {
    let mut out = String::from(
        "| rays | count | hits | box tests/ray | bundle tests | AllHit / AllMiss / Mixed | box tests saved by bundles | leaf visits/ray | tri tests/ray | cull tests | culled nodes | transforms |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for k in RayKind::ALL {
        let ks = &s.kinds[k as usize];
        if ks.rays > 0 {
            out += &row(k.name(), ks);
            out.push('\n');
        }
    }
    out += &row("all", &s.total());
    out.push('\n');
    out
}

/// A table of one row per ray type and a total: `header`, then `row(name,
/// with, without)` for the render with the feature and the one without.
fn per_kind(
    header: &str,
    with: &Stats,
    without: &Stats,
    row: impl Fn(&str, &KindStats, &KindStats) -> String,
) -> String {
    let mut out = header.to_string();
    for k in RayKind::ALL {
        let (a, b) = (&with.kinds[k as usize], &without.kinds[k as usize]);
        if a.rays > 0 {
            out += &row(k.name(), a, b);
        }
    }
    out += &row("all", &with.total(), &without.total());
    out
}

/// What the cull planes saved: the same render with and without planes.
pub fn plane_savings(with: &Stats, without: &Stats) -> String {
    let pct = |x: u64, y: u64| 100.0 * (1.0 - x as f64 / y.max(1) as f64);
    per_kind(
        "| rays | leaf visits (no planes → planes) | saved | tri tests (no planes → planes) | saved |\n|---|---|---|---|---|\n",
        with,
        without,
        |name, a, b| {
            format!(
                "| {name} | {} → {} | {:.1} % | {} → {} | {:.1} % |\n",
                b.leaf_visits,
                a.leaf_visits,
                pct(a.leaf_visits, b.leaf_visits),
                b.tri_tests,
                a.tri_tests,
                pct(a.tri_tests, b.tri_tests)
            )
        },
    )
}

/// What the bundles saved, net: the same render with and without bundles.
/// The counter "box tests saved by bundles" is gross (a decided bundle saves
/// `n − 1` single-ray tests, a Mixed one costs one more test); a bundle is
/// tested with the largest `t_max` of its rays, which is sound (the bundle's
/// segment covers every ray's) but lets an AllHit send a ray whose own
/// segment ends before the box into the node, so the net figure, box tests
/// without bundles minus with them, is the one to quote.
pub fn bundle_savings(with: &Stats, without: &Stats) -> String {
    let tests = |k: &KindStats| k.ray_box_tests + k.bundle_tests;
    per_kind(
        "| rays | box tests (no bundles → bundles) | net saved | gross counter | leaf visits (no bundles → bundles) |\n|---|---|---|---|---|\n",
        with,
        without,
        |name, a, b| {
            let net = tests(b) as i64 - tests(a) as i64;
            format!(
                "| {name} | {} → {} | {net} ({:.1} %) | {} | {} → {} |\n",
                tests(b),
                tests(a),
                100.0 * net as f64 / tests(b).max(1) as f64,
                a.saved_box_tests,
                b.leaf_visits,
                a.leaf_visits,
            )
        },
    )
}
