//! The wide BVHs of the shipped scenes (`scene::wide`): every decoded child
//! box contains the exact child box (big-integer check, not f64) and is
//! tight, at several N and q, with binary32 and e5m10 frames; the collapse keeps every primitive once and
//! costs no more SAH than a fixed two-level merge; and traversals of the
//! wide trees find the same nearest hit (instance, primitive, t) per pixel
//! as the binary BVH renderer.

use dashu::integer::IBig;
use golden_model::cull::bvh::{Bvh, Node, NodeKind};
use golden_model::float::FloatFormat;
use golden_model::wide::{ChildRef, WideFormat, MAX_CHILDREN};
use scene::bvh::Accel;
use scene::render::{render, render_with, Frame};
use scene::scene::Scene;
use scene::tester::Golden;
use scene::trace::{TraceOpts, Tracer};
use scene::wide::{primary, Boxes, DopSelect, WideAccel, WideBvh, DOP_DIRS, TLAS_BOX_BITS};
use std::cmp::Ordering;
use std::path::Path;

const SCENES: [&str; 4] = ["cornell", "field", "grass", "bunny"];
/// Scenes not used to tune the node format (issue 36): far from the origin, CAD-like thin
/// parts, an instanced field at a tiny scale (`scenes/unseen/`).
const UNSEEN: [&str; 3] = ["unseen/far", "unseen/thin", "unseen/swarm"];

fn load(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../scenes/{name}.toml"));
    let mut s = Scene::load(&path).unwrap();
    s.render.ao_rays = 0;
    s
}

/// A binary64 value as `m · 2^e`, exactly (IEEE definitions).
fn dy(v: f64) -> (IBig, i32) {
    let bits = v.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    let frac = (bits & ((1 << 52) - 1)) as i64;
    let (m, e) = if biased == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, biased - 1075)
    };
    (IBig::from(if v < 0.0 { -m } else { m }), e)
}

/// `a + n·2^s` compared with `b`, exactly.
fn cmp_decoded(a: f64, n: u16, s: i32, b: f64) -> Ordering {
    let (ma, ea) = dy(a);
    let (mb, eb) = dy(b);
    let k = ea.min(eb).min(s);
    let lhs = (ma << (ea - k) as usize) + (IBig::from(n) << (s - k) as usize);
    lhs.cmp(&(mb << (eb - k) as usize))
}

/// Exact containment and one-step tightness of every slot of every node;
/// returns the largest excess per side relative to the node extent.
fn check_tree(w: &WideBvh, what: &str) -> f64 {
    let fmt = w.format.fmt();
    let mut worst = 0f64;
    for (id, node) in w.nodes.iter().enumerate() {
        for a in 0..3 {
            let o = node.frame.origin_f64(fmt, a);
            let e = node.frame.exp[a];
            let valid = (0..w.format.children()).filter(|&i| node.valid >> i & 1 == 1);
            let hi = valid
                .clone()
                .map(|i| w.exact[id][i].1[a])
                .fold(f32::MIN, f32::max);
            let lo = valid
                .clone()
                .map(|i| w.exact[id][i].0[a])
                .fold(f32::MAX, f32::min);
            let extent = (hi as f64 - lo as f64).max(f64::MIN_POSITIVE);
            for i in valid {
                let (bmin, bmax) = (w.exact[id][i].0[a] as f64, w.exact[id][i].1[a] as f64);
                let (ql, qh) = (node.lo[i][a], node.hi[i][a]);
                // o + lo·2^e ≤ min < o + (lo + 1)·2^e, o + (hi − 1)·2^e < max ≤ o + hi·2^e
                let ok = cmp_decoded(o, ql, e, bmin) != Ordering::Greater
                    && cmp_decoded(o, ql + 1, e, bmin) == Ordering::Greater
                    && cmp_decoded(o, qh, e, bmax) != Ordering::Less
                    && (qh == 0 || cmp_decoded(o, qh - 1, e, bmax) == Ordering::Less);
                assert!(
                    ok,
                    "{what}: node {id} slot {i} axis {a}: [{bmin}, {bmax}] vs {node:?}"
                );
                let step = 2f64.powi(e);
                worst = worst.max(
                    ((bmin - (o + ql as f64 * step)) / extent)
                        .max(((o + qh as f64 * step) - bmax) / extent),
                );
            }
        }
    }
    worst
}

/// Every binary leaf's primitives appear once, in leaf slots.
fn check_structure(b: &Bvh, w: &WideBvh, what: &str) {
    let mut seen = vec![0u32; b.tri_order.len()];
    let mut inner_refs = 0;
    for node in &w.nodes {
        for i in 0..w.format.children() {
            match node.child(i) {
                ChildRef::Leaf { first, count } => {
                    for &p in &w.prims[first as usize..(first + count) as usize] {
                        seen[b.tri_order.iter().position(|&x| x == p).unwrap_or(0)] += 1;
                    }
                }
                ChildRef::Inner(c) => {
                    assert!(
                        (c as usize) < w.nodes.len(),
                        "{what}: child {c} out of range"
                    );
                    inner_refs += 1;
                }
                ChildRef::Empty => {}
            }
        }
    }
    assert_eq!(w.prims.len(), b.tri_order.len(), "{what}");
    assert!(
        seen.iter().all(|&k| k == 1),
        "{what}: a primitive not exactly once"
    );
    // every node but the root is referenced once
    assert_eq!(inner_refs + 1, w.nodes.len(), "{what}");
}

/// `Σ area` of the wide nodes (each as the union of its slots): the cost
/// the collapse minimises.
fn sah(w: &WideBvh) -> f64 {
    (0..w.nodes.len())
        .map(|id| {
            let slots = (0..MAX_CHILDREN).filter(|&i| w.nodes[id].valid >> i & 1 == 1);
            let lo = [0, 1, 2].map(|a| {
                slots
                    .clone()
                    .map(|i| w.exact[id][i].0[a])
                    .fold(f32::MAX, f32::min) as f64
            });
            let hi = [0, 1, 2].map(|a| {
                slots
                    .clone()
                    .map(|i| w.exact[id][i].1[a])
                    .fold(f32::MIN, f32::max) as f64
            });
            let e = [0, 1, 2].map(|a| hi[a] - lo[a]);
            2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
        })
        .sum()
}

/// The same measure for the fixed two-level merge (a node's slots are its
/// grandchildren, or its children where those are leaves), N = 4.
fn sah_two_level(b: &Bvh) -> f64 {
    let union_area = |ids: &[usize]| {
        let lo = [0, 1, 2].map(|a| {
            ids.iter()
                .map(|&i| b.nodes[i].min[a])
                .fold(f32::MAX, f32::min) as f64
        });
        let hi = [0, 1, 2].map(|a| {
            ids.iter()
                .map(|&i| b.nodes[i].max[a])
                .fold(f32::MIN, f32::max) as f64
        });
        let e = [0, 1, 2].map(|a| hi[a] - lo[a]);
        2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
    };
    let mut cost = 0.0;
    let mut stack = vec![0usize];
    while let Some(id) = stack.pop() {
        let NodeKind::Inner { left, right } = b.nodes[id].kind else {
            continue;
        };
        let mut slots = Vec::new();
        for c in [left as usize, right as usize] {
            match b.nodes[c].kind {
                NodeKind::Inner { left, right } => slots.extend([left as usize, right as usize]),
                NodeKind::Leaf { .. } => slots.push(c),
            }
        }
        cost += union_area(&slots);
        stack.extend(
            slots
                .iter()
                .filter(|&&s| matches!(b.nodes[s].kind, NodeKind::Inner { .. })),
        );
    }
    cost
}

#[test]
fn every_node_of_the_shipped_scenes_decodes_to_a_box_containing_its_child() {
    for name in SCENES {
        let s = load(name);
        let acc = Accel::build(&s, false);
        let trees: Vec<(&Bvh, String)> = std::iter::once((&acc.tlas, format!("{name} TLAS")))
            .chain(
                acc.blas
                    .iter()
                    .enumerate()
                    .map(|(m, b)| (&b.bvh, format!("{name} mesh {m}"))),
            )
            .collect();
        for (n, q) in [(2, 4), (2, 16), (4, 8), (4, 12), (8, 5), (8, 8), (8, 12)] {
            let w = WideFormat::new(FloatFormat::BINARY32, n, q).unwrap();
            let mut worst = 0f64;
            for (b, what) in &trees {
                let wb = WideBvh::build(b, w).unwrap();
                let what = format!("{what} N={n} q={q}");
                check_structure(b, &wb, &what);
                worst = worst.max(check_tree(&wb, &what));
                if n == 2 {
                    // N = 2 keeps the binary tree: one wide node per inner node
                    let inner = b
                        .nodes
                        .iter()
                        .filter(|x| matches!(x.kind, NodeKind::Inner { .. }))
                        .count();
                    assert_eq!(wb.nodes.len(), inner.max(1), "{what}");
                }
            }
            // tightness: one step per side at most, a step below 2·extent/(2^q − 1)
            // (+ the origin's rounding, none in binary32)
            let ceiling = 2.0 / ((1u64 << q) - 1) as f64;
            println!("{name} N={n} q={q}: largest excess per side {worst:.3e} of the node extent (ceiling {ceiling:.3e})");
            assert!(
                worst < ceiling,
                "{name} N={n} q={q}: excess {worst} ≥ {ceiling}"
            );
        }
        // frames in e5m10: the origin rounds down to 11 bits, the children stay inside
        for (n, q) in [(4, 8), (8, 12)] {
            let w = WideFormat::new(FloatFormat::BINARY16, n, q).unwrap();
            for (b, what) in &trees {
                let wb = WideBvh::build(b, w).unwrap();
                check_tree(&wb, &format!("{what} e5m10 N={n} q={q}"));
            }
        }
    }
}

#[test]
fn the_collapse_is_cheaper_than_a_fixed_two_level_merge() {
    let mut strictly = 0;
    for name in SCENES {
        let s = load(name);
        let acc = Accel::build(&s, false);
        let w = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
        for b in acc.blas.iter().map(|b| &b.bvh).chain([&acc.tlas]) {
            if matches!(b.nodes[0].kind, NodeKind::Leaf { .. }) {
                continue; // one leaf: no node to collapse
            }
            let wide = sah(&WideBvh::build(b, w).unwrap());
            let fixed = sah_two_level(b);
            assert!(wide <= fixed * (1.0 + 1e-12), "{name}: {wide} > {fixed}");
            if wide < fixed * (1.0 - 1e-6) {
                strictly += 1;
            }
            println!("{name}: Σ area {wide:.4e} collapsed, {fixed:.4e} two-level merge");
        }
    }
    assert!(strictly > 0, "the collapse never beat the fixed merge");
}

/// The first pixel where two frames differ in hit, `t` or colour, if any.
fn first_difference(a: &Frame, b: &Frame) -> Option<usize> {
    (0..a.ids.len()).find(|&p| {
        a.ids[p] != b.ids[p]
            || (a.ids[p].0 != u32::MAX && a.t[p] != b.t[p])
            || a.color_bits(p) != b.color_bits(p)
    })
}

/// `render --wide`: every ray type (camera, shadow, AO) through the wide BVH,
/// each node tested by the `node` unit's model, gives the binary32
/// single-ray render pixel for pixel (hit, `t`, colour), and costs at most
/// 1.10x the child tests of exact binary32 child boxes at q = 8 (issue 36's
/// target: a looser node test fails here even with an identical image); at
/// N = 4, q = 8 the window-and-anchors model too.
#[test]
fn wide_renders_are_the_binary32_single_ray_render() {
    for name in SCENES.into_iter().chain(UNSEEN) {
        let (s, acc, bin) = binary32_render(name);
        let (w, h, opts, golden) = (40, 28, TraceOpts::single_rays(), Golden::default());
        let hits = bin.ids.iter().filter(|k| k.0 != u32::MAX).count();
        assert!(hits > 0, "{name}: nothing hit");
        for (n, q) in [(2, 4), (4, 8), (8, 8), (8, 12)] {
            let wide = WideAccel::build(
                &acc,
                WideFormat::new(FloatFormat::BINARY32, n, q).unwrap(),
                TLAS_BOX_BITS,
            )
            .unwrap();
            let mut child_tests = Vec::new();
            // N = 4, q = 8 also through the window-and-anchors model (docs/node.md §1-9)
            let kinds: &[Boxes] = if (n, q) == (4, 8) {
                &[Boxes::Node, Boxes::Exact, Boxes::Anchored]
            } else {
                &[Boxes::Node, Boxes::Exact]
            };
            for &boxes in kinds {
                let tracer = Tracer::new(&s, &acc, &golden, opts).with_wide(&wide, boxes);
                let f = render_with(&s, &acc, &tracer, w, h, false);
                if let Some(p) = first_difference(&f, &bin) {
                    panic!(
                        "{name} N={n} q={q} {boxes:?}: pixel {p}: wide {:?} t {:#x} colour {:?}, binary {:?} t {:#x} colour {:?}",
                        f.ids[p], f.t[p], f.color[p], bin.ids[p], bin.t[p], bin.color[p]
                    );
                }
                let st = f.stats.total();
                assert!(st.node_visits > 0 && st.child_tests >= st.node_visits);
                child_tests.push(st.child_tests);
                // the report's camera rays are the frame's
                let (got, _) = primary(&s, &acc, &wide, boxes, w, h);
                let ids: Vec<(u32, u32)> = got.iter().map(|g| (g.inst, g.prim)).collect();
                assert_eq!(ids, bin.ids, "{name} N={n} q={q} {boxes:?}: primary()");
            }
            let ratio = child_tests[0] as f64 / child_tests[1] as f64;
            println!("{name} N={n} q={q}: child tests node unit / exact binary32 boxes {ratio:.4}");
            if q == 8 {
                assert!(
                    ratio <= 1.10,
                    "{name} N={n} q=8: child tests {ratio:.4}x exact boxes"
                );
            }
            if let Some(&anchored) = child_tests.get(2) {
                let ratio = anchored as f64 / child_tests[1] as f64;
                println!("{name} N={n} q={q}: window-and-anchors model / exact boxes {ratio:.4}");
                assert!(
                    ratio <= 1.10,
                    "{name}: window-and-anchors model {ratio:.4}x exact boxes"
                );
            }
        }
    }
}

/// A random binary tree of `leaves` one-primitive leaves with random boxes,
/// parents the exact union of their children (parent before children).
fn random_tree(seed: &mut u64, leaves: usize) -> Bvh {
    fn next(seed: &mut u64) -> f32 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 40) as f32 / (1u64 << 24) as f32
    }
    fn make(b: &mut Bvh, seed: &mut u64, leaves: usize, first: &mut u32) -> usize {
        let me = b.nodes.len();
        b.nodes.push(Node {
            min: [0.0; 3],
            max: [0.0; 3],
            kind: NodeKind::Leaf { first: 0, count: 0 },
        });
        if leaves == 1 {
            let lo = [0, 1, 2].map(|_| next(seed) * 10.0);
            let hi = lo.map(|x| x + next(seed) * next(seed) * 4.0);
            b.nodes[me] = Node {
                min: lo,
                max: hi,
                kind: NodeKind::Leaf {
                    first: *first,
                    count: 1,
                },
            };
            *first += 1;
            return me;
        }
        let k = 1 + (next(seed) * (leaves - 1) as f32) as usize;
        let l = make(b, seed, k.min(leaves - 1), first);
        let r = make(b, seed, leaves - k.min(leaves - 1), first);
        let (a, c) = (b.nodes[l], b.nodes[r]);
        b.nodes[me] = Node {
            min: [0, 1, 2].map(|i| a.min[i].min(c.min[i])),
            max: [0, 1, 2].map(|i| a.max[i].max(c.max[i])),
            kind: NodeKind::Inner {
                left: l as u32,
                right: r as u32,
            },
        };
        me
    }
    let mut b = Bvh {
        nodes: Vec::new(),
        tri_order: (0..leaves as u32).collect(),
    };
    make(&mut b, seed, leaves, &mut 0);
    b
}

/// The least `Σ area` over every wide tree of `b` by brute force: a wide
/// node at `n` takes any frontier of at most `n_max` subtree roots below it.
fn brute_force(b: &Bvh, n_max: usize) -> f64 {
    fn area(b: &Bvh, id: usize) -> f64 {
        let n = &b.nodes[id];
        let e = [0, 1, 2].map(|a| n.max[a] as f64 - n.min[a] as f64);
        2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
    }
    /// Every frontier of the subtree of `id` (sets of roots covering its leaves).
    fn fronts(b: &Bvh, id: usize, cap: usize) -> Vec<Vec<usize>> {
        let mut out = vec![vec![id]];
        if let NodeKind::Inner { left, right } = b.nodes[id].kind {
            for x in fronts(b, left as usize, cap) {
                for y in fronts(b, right as usize, cap) {
                    if x.len() + y.len() <= cap {
                        out.push([x.clone(), y].concat());
                    }
                }
            }
        }
        out
    }
    fn best(b: &Bvh, id: usize, n_max: usize) -> f64 {
        let NodeKind::Inner { left, right } = b.nodes[id].kind else {
            return 0.0;
        };
        let mut m = f64::INFINITY;
        for x in fronts(b, left as usize, n_max) {
            for y in fronts(b, right as usize, n_max) {
                if x.len() + y.len() <= n_max {
                    let c: f64 = x.iter().chain(&y).map(|&f| best(b, f, n_max)).sum();
                    m = m.min(c);
                }
            }
        }
        area(b, id) + m
    }
    match b.nodes[0].kind {
        NodeKind::Inner { .. } => best(b, 0, n_max),
        NodeKind::Leaf { .. } => area(b, 0),
    }
}

#[test]
fn the_collapse_is_the_least_sah_cost_by_brute_force() {
    let mut seed = 36;
    for trial in 0..300 {
        let leaves = 2 + trial % 11;
        let b = random_tree(&mut seed, leaves);
        for n in [2, 4, 8] {
            let w =
                WideBvh::build(&b, WideFormat::new(FloatFormat::BINARY32, n, 8).unwrap()).unwrap();
            check_structure(&b, &w, "random tree");
            let (got, want) = (sah(&w), brute_force(&b, n));
            assert!(
                (got - want).abs() <= want * 1e-9,
                "trial {trial}, {leaves} leaves, N={n}: collapse {got}, least {want}"
            );
        }
    }
}

/// Scene `name` with two AO rays, its binary BVH and its binary32 single-ray
/// render at 40×28 (the reference of the wide renders).
fn binary32_render(name: &str) -> (Scene, Accel, Frame) {
    let mut s = load(name);
    s.render.ao_rays = 2;
    let acc = Accel::build(&s, false);
    let bin = render(
        &s,
        &acc,
        &Golden::default(),
        TraceOpts::single_rays(),
        40,
        28,
        false,
    );
    (s, acc, bin)
}

/// The cull-plane study (docs/node.md §11): BLAS slots also bounded along
/// diagonals and tested in the re-origin study's cells give the binary32 image
/// and cut the triangle tests per ray, with the four body diagonals at every
/// node (floors: grass 40 %, bunny 15 %) and with one direction per node
/// chosen by the builder of ten (grass 28 %, bunny 15 %; measured 32.7 % and
/// 19.2 %).
#[test]
fn diagonal_extents_cut_triangle_tests() {
    for (name, floors) in [("grass", [0.40, 0.28, 0.30]), ("bunny", [0.15, 0.15, 0.28])] {
        let (s, acc, bin) = binary32_render(name);
        let (opts, golden) = (TraceOpts::single_rays(), Golden::default());
        let format = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
        let meshes: Vec<_> = s.meshes.iter().map(|(_, m)| m).collect();
        let plain = WideAccel::build(&acc, format, TLAS_BOX_BITS).unwrap();
        let all = plain.clone().with_dop(&meshes, DopSelect::All);
        let one = plain.clone().with_dop(&meshes, DopSelect::One);
        let normal = plain.clone().with_dop(&meshes, DopSelect::Normal);
        for (what, w) in [("one", &one), ("normal", &normal)] {
            assert!(
                w.dop.iter().flatten().all(|n| n.axes.len() == 1),
                "{name}: {what}: one direction per node"
            );
        }
        // the per-node normals are directions of their own, not only the palette's
        let own = normal
            .dop
            .iter()
            .flatten()
            .filter(|n| !DOP_DIRS.contains(&n.axes[0].dir));
        assert!(own.count() > 0, "{name}: no node chose its own normal");
        let mut tri_tests = Vec::new();
        for wide in [&plain, &all, &one, &normal] {
            let tracer = Tracer::new(&s, &acc, &golden, opts).with_wide(wide, Boxes::Node);
            let f = render_with(&s, &acc, &tracer, 40, 28, false);
            if let Some(p) = first_difference(&f, &bin) {
                panic!("{name}: pixel {p} differs from the binary32 render");
            }
            tri_tests.push(f.stats.total().tri_tests as f64);
        }
        for (k, (what, floor)) in ["four diagonals", "one direction", "one per-node normal"]
            .iter()
            .zip(floors)
            .enumerate()
        {
            let cut = 1.0 - tri_tests[k + 1] / tri_tests[0];
            println!(
                "{name}, {what}: triangle tests {} -> {} ({cut:.3} fewer)",
                tri_tests[0],
                tri_tests[k + 1]
            );
            assert!(
                cut >= floor,
                "{name}, {what}: {cut:.3} fewer triangle tests, floor {floor}"
            );
        }
    }
}

/// The bundle bound (issue 36, step 3) counts every node test of the camera
/// rays once, and resolves more where the geometry is boxes: cornell's
/// bundles of 4×4 rays answer most of their node tests with one oracle test,
/// the bunny's fewer; a bundle node test on the bunny must cost less than a
/// few single node tests to pay even with an oracle (measured at 64 px: 3.26).
#[test]
fn the_bundle_bound_counts_every_node_test_and_resolves_boxes_best() {
    use scene::wide_bundle::bundle_bound;
    let format = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
    let mut resolved = Vec::new();
    for name in ["cornell", "bunny"] {
        let s = load(name);
        let acc = Accel::build(&s, false);
        let wide = WideAccel::build(&acc, format, TLAS_BOX_BITS).unwrap();
        let (w, h) = (32, 24);
        let b = bundle_bound(&s, &acc, &wide, w, h, 4);
        let (_, st) = primary(&s, &acc, &wide, Boxes::Node, w, h);
        assert_eq!(b.rays, u64::from(w * h), "{name}");
        assert_eq!(
            b.single_tests, st.node_visits,
            "{name}: every node test once"
        );
        assert!(
            b.resolved <= b.bundle_tests && b.single_after < b.single_tests,
            "{b:?}"
        );
        resolved.push(b.resolved_share());
        let be = b.break_even();
        assert!(be > 1.0 && be < 30.0, "{name}: break-even {be}");
    }
    assert!(
        resolved[0] > 0.6 && resolved[1] < resolved[0],
        "share of bundle tests that answer every ray: cornell {}, bunny {}",
        resolved[0],
        resolved[1]
    );
}

/// The carried-position study (docs/node.md §12): each node's ray position from its
/// parent's, kept to F fraction bits below the grid, gives the binary32 render pixel for
/// pixel at any F (it is outward at every step), and at F = 8 the child and triangle tests
/// of the node unit's window sums (measured at 64 px: equal to two decimals on the seven
/// scenes); at F = 0 the bunny's positions, carried over up to 12 binades of scale, are
/// looser (measured: 2.7 % more child tests, 20 % more triangle tests).
#[test]
fn carried_positions_keep_the_image_and_at_eight_bits_the_tests() {
    for name in ["cornell", "bunny"] {
        let (s, acc, bin) = binary32_render(name);
        let (opts, golden) = (TraceOpts::single_rays(), Golden::default());
        let format = WideFormat::new(FloatFormat::BINARY32, 4, 8).unwrap();
        let wide = WideAccel::build(&acc, format, TLAS_BOX_BITS).unwrap();
        let mut tests = Vec::new();
        for boxes in [Boxes::Node, Boxes::Carried(8), Boxes::Carried(0)] {
            let tracer = Tracer::new(&s, &acc, &golden, opts).with_wide(&wide, boxes);
            let f = render_with(&s, &acc, &tracer, 40, 28, false);
            if let Some(p) = first_difference(&f, &bin) {
                panic!("{name} {boxes:?}: pixel {p} differs from the binary32 render");
            }
            let st = f.stats.total();
            println!(
                "{name} {boxes:?}: {} child tests, {} triangle tests",
                st.child_tests, st.tri_tests
            );
            tests.push((st.child_tests as f64, st.tri_tests as f64));
        }
        let (node, eight, zero) = (tests[0], tests[1], tests[2]);
        assert!(
            eight.0 <= node.0 * 1.002 && eight.1 <= node.1 * 1.005,
            "{name}: carried at F = 8 {eight:?} against the window sums' {node:?}"
        );
        if name == "bunny" {
            assert!(
                zero.1 >= eight.1 * 1.05,
                "{name}: carried at F = 0 {zero:?} should be looser than at F = 8 {eight:?}"
            );
        }
    }
}
