//! Hand-checked cases of the silhouette tester: the seed README's
//! counter-examples, every special-value rule of `docs/silhouette.md`, and
//! the failure of the seed's fixed bounding-component rule.

mod silhouette_gen;

use golden_model::exact::ray_box::{corner_rays, ray_hits_box, rays_all_any, BoxIn, RayIn};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{
    eval, eval_trace, BundleIn, Config, OriginMode, Out, Rounding, Verdict,
};
use silhouette_gen::*;

const F: FloatFormat = FloatFormat::BINARY32;
const INF: f32 = f32::INFINITY;

fn b(x: f32) -> u64 {
    x.to_bits() as u64
}
fn v3(x: [f32; 3]) -> [u64; 3] {
    x.map(b)
}
fn cfg(origin: OriginMode) -> Config {
    Config::new(F, origin, Rounding::Conservative).unwrap()
}

/// Model and exact reference on one binary32 ray; asserts they agree when
/// the model is certain (all_hit or !any_hit), returns (model, exact hit).
fn ray(
    p_min: [f32; 3],
    p_max: [f32; 3],
    o: [f32; 3],
    d: [f32; 3],
    t_min: f32,
    t_max: f32,
) -> (Out, bool) {
    let x = BundleIn::ray(v3(p_min), v3(p_max), v3(o), v3(d), b(t_min), b(t_max));
    let out = eval(&cfg(OriginMode::Shared), &x);
    let bx = BoxIn {
        p_min: x.p_min,
        p_max: x.p_max,
    };
    let r = RayIn {
        o: x.o_lo,
        d: x.d_lo,
        t_min: x.t_min,
        t_max: x.t_max,
    };
    let ex = ray_hits_box(F, &bx, &r);
    assert_eq!((out.nan, out.invalid), (ex.nan, ex.invalid));
    if out.all_hit {
        assert!(ex.hit);
    }
    if !out.any_hit {
        assert!(!ex.hit);
    }
    (out, ex.hit)
}

fn hits(
    p_min: [f32; 3],
    p_max: [f32; 3],
    o: [f32; 3],
    d: [f32; 3],
    t_min: f32,
    t_max: f32,
) -> bool {
    let (out, ex) = ray(p_min, p_max, o, d, t_min, t_max);
    assert_eq!(out.any_hit, ex, "model and exact disagree");
    assert_eq!(
        out.all_hit, ex,
        "exactly representable case should be certain"
    );
    ex
}

#[test]
fn readme_edge2_example_hits_and_the_printed_form_says_outside() {
    let (o, d) = ([2.0, -1.0, 2.0], [-1.5, 1.5, -1.5]);
    assert!(hits([0.0; 3], [1.0; 3], o, d, 0.0, INF));
    // The text's division-free test for edge 2 (max x, max y) as printed:
    // (p_max,x - o_x)·d_y <= (p_max,y - o_y)·d_x, which says "outside".
    let printed = (1.0 - o[0]) * d[1] <= (1.0 - o[1]) * d[0];
    assert!(!printed);
    // The sign-correct form (entry_x <= exit_y): N_x·|d_y| <= X_y·|d_x|.
    let t = eval_trace(
        &cfg(OriginMode::Shared),
        &BundleIn::ray(v3([0.0; 3]), v3([1.0; 3]), v3(o), v3(d), b(0.0), b(INF)),
    );
    assert!(t.any.edge_ok.iter().all(|&k| k));
}

#[test]
fn readme_box_behind_origin_misses_only_thanks_to_the_direction_check() {
    assert!(!hits([-3.0; 3], [-2.0; 3], [0.0; 3], [1.0; 3], 0.0, INF));
    let t = eval_trace(
        &cfg(OriginMode::Shared),
        &BundleIn::ray(
            v3([-3.0; 3]),
            v3([-2.0; 3]),
            v3([0.0; 3]),
            v3([1.0; 3]),
            b(0.0),
            b(INF),
        ),
    );
    // Every silhouette-edge test and distance check passes; the direction checks fail.
    assert!(t.any.edge_ok.iter().all(|&k| k) && t.any.dist_ok.iter().all(|&k| k));
    assert!(t.any.dir_ok.iter().all(|&k| !k));
    // With t_min = -inf (a line), the same ray does hit.
    assert!(hits(
        [-3.0; 3],
        [-2.0; 3],
        [0.0; 3],
        [1.0; 3],
        f32::NEG_INFINITY,
        INF
    ));
    assert!(hits([-3.0; 3], [-2.0; 3], [0.0; 3], [1.0; 3], -2.0, INF));
    assert!(!hits([-3.0; 3], [-2.0; 3], [0.0; 3], [1.0; 3], -1.5, INF));
}

#[test]
fn touching_counts_as_a_hit() {
    // Through the corner (1,1,1) exactly; along an edge; tangent to a face.
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 2.0, 2.0],
        [-1.0, -1.0, -1.0],
        0.0,
        INF
    ));
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [3.0, 0.0, 2.0],
        [-2.0, 1.0, -1.0],
        0.0,
        INF
    ));
    // Grazing the top face, and one ulp above it.
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 2.0, 1.0],
        [-1.0, -1.0, 0.0],
        0.0,
        INF
    ));
    assert!(!hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 2.0, 1.0000001],
        [-1.0, -1.0, 0.0],
        0.0,
        INF
    ));
    // Through the silhouette edge x = 1, z = 0 (seen from o) at y = 0.5, and just outside it.
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 0.5, 2.0],
        [-1.0, 0.0, -2.0],
        0.0,
        INF
    ));
    assert!(!hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 0.5, 2.0],
        [-1.0, 0.0, -2.0000002],
        0.0,
        INF
    ));
    // Segment ending exactly on the box, or starting exactly on it.
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [-1.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        0.0,
        1.0
    ));
    assert!(!hits(
        [0.0; 3],
        [1.0; 3],
        [-1.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        0.0,
        0.5
    ));
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [2.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        -1.0,
        0.0
    ));
}

#[test]
fn zero_direction_components_are_parallel_slabs() {
    let (lo, hi) = ([0.0; 3], [1.0; 3]);
    // Along the face x = 0, with +0 and -0.
    assert!(hits(lo, hi, [0.0, 0.5, -1.0], [0.0, 0.0, 1.0], 0.0, INF));
    assert!(hits(lo, hi, [0.0, 0.5, -1.0], [-0.0, 0.0, 1.0], 0.0, INF));
    assert!(hits(lo, hi, [1.0, 0.5, -1.0], [-0.0, 0.0, 1.0], 0.0, INF));
    // One ulp outside the face.
    let out = f32::from_bits((-0.0f32).to_bits() + 1);
    assert!(!hits(lo, hi, [out, 0.5, -1.0], [0.0, 0.0, 1.0], 0.0, INF));
    // Along an edge (two zero components).
    assert!(hits(lo, hi, [1.0, 0.0, -5.0], [0.0, -0.0, 3.0], 0.0, INF));
    // Direction all zero: a point test (inside, on the box, outside).
    assert!(hits(lo, hi, [0.5, 0.5, 0.5], [0.0; 3], 0.0, INF));
    assert!(hits(lo, hi, [1.0, 0.0, 0.5], [-0.0, 0.0, 0.0], 0.0, INF));
    assert!(!hits(lo, hi, [1.5, 0.5, 0.5], [0.0; 3], 0.0, INF));
    // ... and still an empty segment misses.
    assert!(!hits(lo, hi, [0.5, 0.5, 0.5], [0.0; 3], 1.0, 0.5));
}

#[test]
fn origin_inside_and_degenerate_and_empty_boxes() {
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [0.5; 3],
        [1.0, -2.0, 3.0],
        0.0,
        0.0
    ));
    assert!(hits(
        [0.0; 3],
        [1.0; 3],
        [0.5; 3],
        [0.0, -2.0, 3.0],
        0.0,
        INF
    ));
    // A flat box (p_min_z == p_max_z) and a point box.
    assert!(hits(
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.0, 1.0],
        0.0,
        INF
    ));
    assert!(hits([1.0; 3], [1.0; 3], [0.0; 3], [2.0; 3], 0.0, INF));
    assert!(!hits(
        [1.0; 3],
        [1.0; 3],
        [0.0; 3],
        [2.0, 2.0, 2.0000002],
        0.0,
        INF
    ));
    // Empty boxes always miss, even around the origin.
    assert!(!hits(
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.5; 3],
        [1.0; 3],
        0.0,
        INF
    ));
    assert!(!hits(
        [0.0, 0.0, INF],
        [1.0, 1.0, INF],
        [0.5; 3],
        [0.0, 0.0, 1.0],
        0.0,
        INF
    ));
    assert!(!hits(
        [0.0, -INF, 0.0],
        [1.0, -INF, 1.0],
        [0.5; 3],
        [0.0, -1.0, 0.0],
        0.0,
        INF
    ));
}

#[test]
fn infinite_planes_and_segment_ends() {
    // Half-spaces and the whole space.
    assert!(hits(
        [-INF; 3],
        [INF; 3],
        [1e30, -1e30, 0.0],
        [1.0, 0.0, -3.0],
        0.0,
        INF
    ));
    assert!(hits(
        [-INF, 0.0, 0.0],
        [0.0, 1.0, 1.0],
        [5.0, 0.5, 0.5],
        [-1.0, 0.0, 0.0],
        0.0,
        INF
    ));
    assert!(!hits(
        [-INF, 0.0, 0.0],
        [0.0, 1.0, 1.0],
        [5.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        0.0,
        INF
    ));
    // Distance check with a finite t_max.
    assert!(!hits(
        [10.0, 0.0, 0.0],
        [11.0, 1.0, 1.0],
        [0.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        0.0,
        9.5
    ));
    assert!(hits(
        [10.0, 0.0, 0.0],
        [11.0, 1.0, 1.0],
        [0.0, 0.5, 0.5],
        [1.0, 0.0, 0.0],
        0.0,
        10.0
    ));
    // Empty segments: t_min > t_max, t_min = +inf, t_max = -inf.
    assert!(!hits([0.0; 3], [1.0; 3], [0.5; 3], [1.0; 3], 1.0, 0.0));
    assert!(!hits([0.0; 3], [1.0; 3], [0.5; 3], [1.0; 3], INF, INF));
    assert!(!hits([-INF; 3], [INF; 3], [0.5; 3], [1.0; 3], -INF, -INF));
}

#[test]
fn nan_and_infinite_rays_are_flagged_misses() {
    let (out, ex) = ray([0.0; 3], [1.0; 3], [0.5; 3], [f32::NAN, 1.0, 1.0], 0.0, INF);
    assert!(out.nan && !out.any_hit && !out.all_hit && !ex);
    let (out, _) = ray([0.0, f32::NAN, 0.0], [1.0; 3], [0.5; 3], [1.0; 3], 0.0, INF);
    assert!(out.nan && !out.any_hit);
    let (out, _) = ray([0.0; 3], [1.0; 3], [0.5; 3], [1.0; 3], 0.0, f32::NAN);
    assert!(out.nan && !out.any_hit);
    let (out, _) = ray([0.0; 3], [1.0; 3], [-INF, 0.5, 0.5], [1.0; 3], 0.0, INF);
    assert!(out.invalid && !out.nan && !out.any_hit);
    let (out, _) = ray([0.0; 3], [1.0; 3], [0.5; 3], [INF, 0.0, 0.0], 0.0, INF);
    assert!(out.invalid && !out.any_hit);
    // o_hi is not read in shared mode, so a NaN there is ignored.
    let mut x = BundleIn::ray(
        v3([0.0; 3]),
        v3([1.0; 3]),
        v3([0.5; 3]),
        v3([1.0; 3]),
        b(0.0),
        b(INF),
    );
    x.o_hi[1] = b(f32::NAN);
    assert!(eval(&cfg(OriginMode::Shared), &x).all_hit);
    let out = eval(&cfg(OriginMode::Bounded), &x);
    assert!(out.nan && !out.any_hit);
}

#[test]
fn bundles_three_valued() {
    let shared = cfg(OriginMode::Shared);
    let bundle = |d_lo: [f32; 3], d_hi: [f32; 3]| BundleIn {
        p_min: v3([-1.0; 3]),
        p_max: v3([1.0; 3]),
        o_lo: v3([0.0, 0.0, -10.0]),
        o_hi: v3([0.0, 0.0, -10.0]),
        d_lo: v3(d_lo),
        d_hi: v3(d_hi),
        t_min: b(0.0),
        t_max: b(INF),
    };
    // A narrow cone down the z axis: all hit.
    assert_eq!(
        eval(&shared, &bundle([0.01, 0.01, 1.0], [0.05, 0.05, 1.0])).verdict(),
        Verdict::AllHit
    );
    // Pointing away from the box: all miss.
    assert_eq!(
        eval(&shared, &bundle([0.5, 0.5, 1.0], [0.6, 0.6, 1.0])).verdict(),
        Verdict::AllMiss
    );
    // Straddling the silhouette: mixed.
    assert_eq!(
        eval(&shared, &bundle([0.05, 0.0, 1.0], [0.2, 0.0, 1.0])).verdict(),
        Verdict::Mixed
    );
    // Direction bounds straddling 0 on an axis: mixed, flagged.
    let out = eval(&shared, &bundle([-0.01, 0.01, 1.0], [0.01, 0.02, 1.0]));
    assert!(out.mixed_sign && out.verdict() == Verdict::Mixed);
    // A one-sided interval touching zero is not mixed: [-0.01, +0] and [-0, 0.01].
    let out = eval(&shared, &bundle([-0.01, -0.0, 1.0], [0.0, 0.01, 1.0]));
    assert!(!out.mixed_sign && out.verdict() == Verdict::AllHit);
    // Inverted bounds are invalid.
    let out = eval(&shared, &bundle([0.05, 0.0, 1.0], [0.01, 0.0, 1.0]));
    assert!(out.invalid && !out.any_hit);
}

#[test]
fn bounded_origins_widen_anyhit_and_shrink_allhit() {
    let bounded = cfg(OriginMode::Bounded);
    let mk = |o_lo: [f32; 3], o_hi: [f32; 3]| BundleIn {
        p_min: v3([-1.0; 3]),
        p_max: v3([1.0; 3]),
        o_lo: v3(o_lo),
        o_hi: v3(o_hi),
        d_lo: v3([0.0, 0.0, 1.0]),
        d_hi: v3([0.0, 0.0, 1.0]),
        t_min: b(0.0),
        t_max: b(INF),
    };
    assert_eq!(
        eval(&bounded, &mk([-0.5, -0.5, -5.0], [0.5, 0.5, -4.0])).verdict(),
        Verdict::AllHit
    );
    assert_eq!(
        eval(&bounded, &mk([0.5, -0.5, -5.0], [1.5, 0.5, -4.0])).verdict(),
        Verdict::Mixed
    );
    assert_eq!(
        eval(&bounded, &mk([1.5, -0.5, -5.0], [2.5, 0.5, -4.0])).verdict(),
        Verdict::AllMiss
    );
    // Touching: origins from x = 1 (on the face plane) to 2.
    assert_eq!(
        eval(&bounded, &mk([1.0, -0.5, -5.0], [2.0, 0.5, -4.0])).verdict(),
        Verdict::Mixed
    );
}

/// The seed README's candidate rule (AllHit: an edge's entry-plane side takes
/// the largest |d|, its exit-plane side the smallest, whatever the signs of
/// the numerators) is only right while `t_min >= 0`: with a negative `t_min`
/// it claims AllHit for bundles with a missing ray. Binary32 products are
/// exact in f64, so the rule is evaluated exactly here on the model's own
/// (directed-rounded) numerators.
#[test]
fn fixed_bounding_rule_fails_for_negative_t_min_sign_rule_holds() {
    let c = cfg(OriginMode::Shared);
    let mut rng = Rng(0xF1CED);
    let val = |v: u64| f32::from_bits(v as u32) as f64;
    let mut found = None;
    for _ in 0..200_000 {
        let (bx, mut x) = gen_bundle(F, &mut rng, Kind::Random, false, false);
        x.t_min = b(-((1u32 << rng.below(8)) as f32));
        let t = eval_trace(&c, &x);
        if t.out.nan || t.out.invalid || t.empty || t.out.mixed_sign {
            continue;
        }
        let ax = t.axis;
        let edges_fixed = golden_model::silhouette::EDGES
            .iter()
            .all(|&(i, j)| val(ax[i].n_all) * val(ax[j].b) <= val(ax[j].x_all) * val(ax[i].a));
        // Same distance/direction checks as the model (their selection is by t's sign).
        let fixed_all_hit = edges_fixed && t.all.dist_ok.iter().chain(&t.all.dir_ok).all(|&k| k);
        let rays = corner_rays(x.o_lo, x.o_lo, x.d_lo, x.d_hi, x.t_min, x.t_max);
        let (all, _) = rays_all_any(F, &bx, &rays);
        if t.out.all_hit {
            assert!(all, "sign rule unsound: {x:x?}");
        }
        if fixed_all_hit && !all {
            found = Some(x);
            break;
        }
    }
    let x = found.expect("no counter-example to the fixed rule found");
    println!("fixed rule claims AllHit, a corner ray misses: {x:x?}");
}
