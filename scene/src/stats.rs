//! The traversal's counters per ray type ([`Stats`], filled by
//! `trace::Tracer`) and their report: one table per scene, one row per ray
//! type.

/// Ray types, for statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RayKind {
    /// camera rays
    Primary = 0,
    /// shadow rays to point and area lights
    Shadow = 1,
    /// ambient-occlusion rays
    Ao = 2,
}

impl RayKind {
    /// All kinds, in report order.
    pub const ALL: [RayKind; 3] = [RayKind::Primary, RayKind::Shadow, RayKind::Ao];
    /// Report name.
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Ao => "ao",
        }
    }
}

/// Counters for one ray type.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct KindStats {
    /// rays traced
    pub rays: u64,
    /// rays that hit something
    pub hits: u64,
    /// single-ray box tests
    pub ray_box_tests: u64,
    /// bundle box tests
    pub bundle_tests: u64,
    /// bundle tests that ended AllHit
    pub all_hit: u64,
    /// ... AllMiss
    pub all_miss: u64,
    /// ... Mixed (the bundle is split and its rays tested one by one)
    pub mixed: u64,
    /// rays in all bundle tests
    pub bundle_rays: u64,
    /// box tests saved by bundles: Σ(n − 1) over decided tests − 1 per Mixed test
    pub saved_box_tests: i64,
    /// bundles split by the splitting metric before a test (too few rays,
    /// mixed direction signs, too much spread)
    pub split_by_metric: u64,
    /// leaves entered (per ray)
    pub leaf_visits: u64,
    /// triangle tests
    pub tri_tests: u64,
    /// ... of which the unit flagged `invalid` (three zero edge functions:
    /// the ray in the triangle's plane as the rounded products tell), decided
    /// by the exact test as a shader would
    pub tri_flagged: u64,
    /// cull-plane tests
    pub cull_tests: u64,
    /// per-ray terms of a node's shared normals computed (unit `cull_ray`,
    /// once per ray and inner node whose children are cull-tested)
    pub cull_ray_terms: u64,
    /// nodes culled by their planes (per ray)
    pub culled_nodes: u64,
    /// of which leaves
    pub culled_leaves: u64,
    /// triangle tests skipped in culled leaves
    pub culled_leaf_tris: u64,
    /// instance transforms (per ray)
    pub transforms: u64,
    /// wide traversal (`render --wide`): wide nodes tested (TLAS and BLAS)
    pub node_visits: u64,
    /// ... node record bytes fetched
    pub node_bytes: u64,
    /// ... child boxes tested (valid slots of the visited nodes; with the
    /// `node` unit also the root box tests)
    pub child_tests: u64,
    /// ... of the node visits, those of TLAS nodes
    pub tlas_node_visits: u64,
    /// ... box tests of a tree's root before its first node test (`node`
    /// unit: one per tree entered, a conservative slab on the root's box)
    pub root_box_tests: u64,
    /// culling oracle (`crate::oracle`, wide traversal): BLAS node tests a perfect, free
    /// culler inside the node tests of the same tree would still make (the path to the hit's
    /// leaf slot)
    pub oracle_blas_node_tests: u64,
    /// ... TLAS node tests (the path to the hit instance's leaf slot; the root's test for a
    /// ray that hits nothing, if the traversal made it)
    pub oracle_tlas_node_tests: u64,
    /// ... instance transforms (one per hit)
    pub oracle_transforms: u64,
    /// ... triangle tests (every triangle of the hit's leaf slot; one for an any-hit ray)
    pub oracle_tri_tests: u64,
}

impl KindStats {
    /// Adds another set of counters.
    pub fn add(&mut self, o: &KindStats) {
        self.rays += o.rays;
        self.hits += o.hits;
        self.ray_box_tests += o.ray_box_tests;
        self.bundle_tests += o.bundle_tests;
        self.all_hit += o.all_hit;
        self.all_miss += o.all_miss;
        self.mixed += o.mixed;
        self.bundle_rays += o.bundle_rays;
        self.saved_box_tests += o.saved_box_tests;
        self.split_by_metric += o.split_by_metric;
        self.leaf_visits += o.leaf_visits;
        self.tri_tests += o.tri_tests;
        self.tri_flagged += o.tri_flagged;
        self.cull_tests += o.cull_tests;
        self.cull_ray_terms += o.cull_ray_terms;
        self.culled_nodes += o.culled_nodes;
        self.culled_leaves += o.culled_leaves;
        self.culled_leaf_tris += o.culled_leaf_tris;
        self.transforms += o.transforms;
        self.node_visits += o.node_visits;
        self.node_bytes += o.node_bytes;
        self.child_tests += o.child_tests;
        self.tlas_node_visits += o.tlas_node_visits;
        self.root_box_tests += o.root_box_tests;
        self.oracle_blas_node_tests += o.oracle_blas_node_tests;
        self.oracle_tlas_node_tests += o.oracle_tlas_node_tests;
        self.oracle_transforms += o.oracle_transforms;
        self.oracle_tri_tests += o.oracle_tri_tests;
    }
    /// `x` per ray.
    pub fn per_ray(&self, x: u64) -> f64 {
        x as f64 / self.rays.max(1) as f64
    }
    /// Box tests (single and bundle) per ray.
    pub fn box_tests_per_ray(&self) -> f64 {
        (self.ray_box_tests + self.bundle_tests) as f64 / self.rays.max(1) as f64
    }
}

/// Counters per ray type.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// indexed by `RayKind as usize`
    pub kinds: [KindStats; 3],
}

impl Stats {
    /// Adds another set.
    pub fn add(&mut self, o: &Stats) {
        for k in 0..3 {
            self.kinds[k].add(&o.kinds[k]);
        }
    }
    /// Sum over the ray types.
    pub fn total(&self) -> KindStats {
        let mut t = KindStats::default();
        for k in &self.kinds {
            t.add(k);
        }
        t
    }
}

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

/// Markdown table of a wide traversal's counters (`render --wide`) per ray type and in total.
pub fn wide_table(s: &Stats) -> String {
    let row = |name: &str, k: &KindStats| {
        format!(
            "| {name} | {} | {} | {:.2} | {:.0} | {:.2} | {:.2} | {:.2} | {} |\n",
            k.rays,
            k.hits,
            k.per_ray(k.node_visits),
            k.per_ray(k.node_bytes),
            k.per_ray(k.child_tests),
            k.per_ray(k.leaf_visits),
            k.per_ray(k.tri_tests),
            k.transforms,
        )
    };
    let mut out = String::from(
        "| rays | count | hits | node visits/ray | node bytes/ray | child tests/ray | leaf visits/ray | tri tests/ray | transforms |\n|---|---|---|---|---|---|---|---|---|\n",
    );
    for k in RayKind::ALL {
        let ks = &s.kinds[k as usize];
        if ks.rays > 0 {
            out += &row(k.name(), ks);
        }
    }
    out += &row("all", &s.total());
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
