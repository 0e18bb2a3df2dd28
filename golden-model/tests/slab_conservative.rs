//! The conservative slab (`golden_model::slab::eval_conservative`, `slab -p
//! rounding=conservative`) against the exact rational reference
//! (`exact::ray_box`), on the workloads the silhouette tester is checked on:
//! random, grazing, along-face, origin on / inside the box, specials, in five
//! formats, and the realistic binary32 scene distribution.
//!
//! Asserted: 0 false misses everywhere (the design's guarantee, proof in
//! docs/silhouette.md §6), and a ceiling on the false-hit rate of each
//! workload, set from the measured rates with a small margin, so that a
//! looser design fails; the test also shows that a design one ulp looser at
//! the final comparison exceeds the grazing ceiling. Prints the rates beside
//! those of the RNE slab (`slab::eval`). `SILHOUETTE_CASES` scales the counts.

mod silhouette_gen;

use golden_model::exact::ray_box::{ray_hits_box, BoxIn, RayIn};
use golden_model::float::{le, FloatFormat, RoundingMode};
use golden_model::slab::{eval, eval_conservative, SlabIn};
use golden_model::transform::recip as recip_rounded;
use silhouette_gen::*;

const F: FloatFormat = FloatFormat::BINARY32;

fn b(x: f32) -> u64 {
    x.to_bits() as u64
}

/// The conservative slab's input: `inv_d = RTZ(1/d)` (the contract).
fn cons_in(fmt: FloatFormat, bx: &BoxIn, r: &RayIn) -> SlabIn {
    SlabIn {
        p_min: bx.p_min,
        p_max: bx.p_max,
        o: r.o,
        inv_d: r.d.map(|d| recip_rounded(fmt, d, RoundingMode::TowardZero)),
        t_min: r.t_min,
        t_max: r.t_max,
    }
}

/// The RNE slab's input: `inv_d = RNE(1/d)`.
fn rne_in(fmt: FloatFormat, bx: &BoxIn, r: &RayIn) -> SlabIn {
    SlabIn {
        inv_d: r.d.map(|d| recip(fmt, d)),
        ..cons_in(fmt, bx, r)
    }
}

#[derive(Default, Debug, Clone, Copy)]
struct Acc {
    cases: u64,
    hits: u64,
    misses: u64,
    cons_false_hit: u64,
    cons_false_miss: u64,
    /// one ulp looser at the final comparison (`t_enter <= next_up(t_exit)`)
    loose_false_hit: u64,
    rne_false_hit: u64,
    rne_false_miss: u64,
}

impl Acc {
    fn add(&mut self, o: &Acc) {
        self.cases += o.cases;
        self.hits += o.hits;
        self.misses += o.misses;
        self.cons_false_hit += o.cons_false_hit;
        self.cons_false_miss += o.cons_false_miss;
        self.loose_false_hit += o.loose_false_hit;
        self.rne_false_hit += o.rne_false_hit;
        self.rne_false_miss += o.rne_false_miss;
    }
    fn rate(x: u64, of: u64) -> f64 {
        if of == 0 {
            0.0
        } else {
            x as f64 / of as f64
        }
    }
    fn cons_rate(&self) -> f64 {
        Acc::rate(self.cons_false_hit, self.misses)
    }
    fn loose_rate(&self) -> f64 {
        Acc::rate(self.loose_false_hit, self.misses)
    }
}

fn tally(acc: &mut Acc, fmt: FloatFormat, bx: &BoxIn, r: &RayIn) {
    let ex = ray_hits_box(fmt, bx, r);
    if ex.nan || ex.invalid {
        return;
    }
    acc.cases += 1;
    let c = eval_conservative(fmt, &cons_in(fmt, bx, r));
    let n = eval(fmt, &rne_in(fmt, bx, r));
    let loose = c.hit || (!fmt.is_nan(c.t_exit) && le(fmt, c.t_enter, nudge(fmt, c.t_exit, 1)));
    if ex.hit {
        acc.hits += 1;
        if !c.hit {
            panic!("conservative slab false miss, {fmt}: {bx:x?} {r:x?} -> {c:x?}");
        }
        acc.rne_false_miss += !n.hit as u64;
    } else {
        acc.misses += 1;
        acc.cons_false_hit += c.hit as u64;
        acc.loose_false_hit += loose as u64;
        acc.rne_false_hit += n.hit as u64;
    }
}

fn print_row(name: &str, a: &Acc) {
    let r = Acc::rate;
    println!(
        "{name:<24} {:>7} cases {:>7} hits | conservative f.hit {:>9.3e} f.miss {} (1 ulp looser: f.hit {:>9.3e}) | RNE slab f.hit {:>9.3e} f.miss {:>9.3e}",
        a.cases,
        a.hits,
        a.cons_rate(),
        a.cons_false_miss,
        a.loose_rate(),
        r(a.rne_false_hit, a.misses),
        r(a.rne_false_miss, a.hits),
    );
}

/// Ceilings on the conservative false-hit rate per workload (all five
/// formats together), just above the rates measured at the default counts
/// (seeded, so CI sees exactly these) and below those of the design one ulp
/// looser at the final comparison, which the test checks it rejects.
/// Measured (conservative, one ulp looser): random 8.40e-3, 1.11e-2;
/// grazing 3.51e-1, 3.89e-1; along-face 8.64e-3, 1.10e-2; origin on box
/// 2.25e-4, 4.50e-4; origin inside 6.29e-4, 7.08e-4; specials 5.94e-3,
/// 7.42e-3; realistic binary32 scene 1.42e-4, 1.55e-4.
fn ceiling(kind: Kind) -> f64 {
    if measuring() {
        return 1.0;
    }
    match kind {
        Kind::Random => 1.0e-2,
        Kind::Grazing => 3.7e-1,
        Kind::AlongFace => 1.0e-2,
        Kind::OriginOnBox => 3.0e-4,
        Kind::OriginInside => 6.9e-4,
        Kind::Specials => 7.0e-3,
    }
}

/// Ceiling on the realistic binary32 scene (see [`ceiling`]).
const REALISTIC_CEILING: f64 = 1.5e-4;

/// `SLAB_MEASURE` set: print the rates, assert only soundness.
fn measuring() -> bool {
    std::env::var("SLAB_MEASURE").is_ok()
}

/// The default counts (the ceilings are tuned to them).
fn default_counts() -> bool {
    std::env::var("SILHOUETTE_CASES").is_err() && !measuring()
}

/// The ceiling holds, and (at the default counts) rejects the looser design;
/// at other counts the ceiling is 1.5 times wider (sampling noise: some
/// workloads have only ~13,000 exact misses per 100,000 cases).
fn check_ceiling(what: &str, a: &Acc, ceiling: f64) {
    let ceiling = if default_counts() {
        ceiling
    } else {
        ceiling * 1.5
    };
    assert!(
        a.cons_rate() <= ceiling,
        "{what}: false-hit rate {:.3e} above the ceiling {ceiling:.2e}",
        a.cons_rate()
    );
    if default_counts() {
        assert!(
            a.loose_rate() > ceiling,
            "{what}: the ceiling {ceiling:.2e} should reject a design one ulp looser ({:.3e})",
            a.loose_rate()
        );
    }
}

/// 0 false misses and the false-hit ceilings on the six adversarial
/// workloads in five formats (binary32, binary16, bfloat16, (4,3), (6,9)).
#[test]
fn conservative_slab_never_misses_adversarial_workloads() {
    let n = cases(600_000) / (KINDS.len() as u64 * formats().len() as u64);
    println!("rates: false hits / exact misses, false misses / exact hits; {n} cases per row");
    for kind in KINDS {
        let mut all = Acc::default();
        for fmt in formats() {
            let mut rng = Rng(0xC0A5_5AB0 ^ (kind as u64) << 8 ^ fmt.frac_bits() as u64);
            let mut acc = Acc::default();
            for _ in 0..n {
                let (bx, r) = gen_ray(fmt, &mut rng, kind);
                tally(&mut acc, fmt, &bx, &r);
            }
            print_row(&format!("{fmt} {kind:?}"), &acc);
            all.add(&acc);
        }
        print_row(&format!("all {kind:?}"), &all);
        assert_eq!(all.cons_false_miss, 0);
        check_ceiling(&format!("{kind:?}"), &all, ceiling(kind));
        if kind == Kind::AlongFace {
            assert!(
                all.rne_false_miss > 0,
                "the RNE slab misses along-face rays"
            );
        }
    }
}

/// The realistic binary32 scene distribution of `silhouette_slab.rs`
/// (property 4): boxes in [-1,1]^3, origins in [-4,4]^3, unit directions
/// aimed near the box half the time; 0 false misses and a false-hit ceiling.
#[test]
fn conservative_slab_binary32_realistic_scene() {
    let n = cases(200_000);
    let mut rng = Rng(0xACC0_0001);
    let mut acc = Acc::default();
    for _ in 0..n {
        let (bx, r) = realistic_scene_case(&mut rng);
        tally(&mut acc, F, &bx, &r);
    }
    print_row("e8m23 realistic", &acc);
    assert_eq!(acc.cons_false_miss, 0);
    if !measuring() {
        check_ceiling("realistic", &acc, REALISTIC_CEILING);
    }
}

/// The cases the RNE slab gets wrong on a zero direction component: a ray in
/// a face plane hits (no `0·∞`), a parallel ray beside the slab misses, and
/// a parallel ray inside the slab is not restricted by it.
#[test]
fn conservative_slab_parallel_rays() {
    let bx = BoxIn {
        p_min: [b(0.0); 3],
        p_max: [b(1.0); 3],
    };
    let ray = |o: [f32; 3], d: [f32; 3]| RayIn {
        o: o.map(b),
        d: d.map(b),
        t_min: b(0.0),
        t_max: b(f32::INFINITY),
    };
    for (o, d, hit) in [
        ([0.0, 0.5, -1.0], [0.0, 0.0, 1.0], true),
        ([1.0, 0.5, -1.0], [-0.0, 0.0, 1.0], true),
        ([0.5, 1.0, 2.0], [0.0, -0.0, -1.0], true),
        ([-1e-30, 0.5, -1.0], [0.0, 0.0, 1.0], false),
        ([1.0000001, 0.5, -1.0], [-0.0, 0.0, 1.0], false),
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], true),
        ([2.0, 0.0, 0.0], [0.0, 0.0, 0.0], false),
    ] {
        let r = ray(o, d);
        assert_eq!(ray_hits_box(F, &bx, &r).hit, hit, "{o:?} {d:?}");
        let c = eval_conservative(F, &cons_in(F, &bx, &r));
        assert_eq!(c.hit, hit, "{o:?} {d:?}: {c:x?}");
        assert!(!F.is_nan(c.t_enter) && !F.is_nan(c.t_exit), "{c:x?}");
    }
    // the ray in the face x = 0 is the RNE slab's 0·inf failure
    let r = ray([0.0, 0.5, -1.0], [0.0, 0.0, 1.0]);
    assert!(!eval(F, &rne_in(F, &bx, &r)).hit);
    // inside on every axis: the parallel axes do not restrict the interval
    let r = ray([0.5, 0.5, 0.5], [0.0, 0.0, 2.0]);
    let c = eval_conservative(F, &cons_in(F, &bx, &r));
    assert!(c.hit);
    assert_eq!(c.t_enter, b(0.0));
    // 1/2 is exact, but the unit cannot know: the exit uses next_up(0.5)
    assert_eq!(c.t_exit, nudge(F, b(0.25), 1));
}

/// Why the contract is RTZ: for a tiny direction `1/d` overflows, to ∞ in
/// RNE (read as a parallel slab: a false miss) but to max_finite in RTZ
/// (widened to max_finite..∞: the hit is kept).
#[test]
fn rtz_reciprocal_keeps_tiny_directions_apart_from_zero() {
    let h = FloatFormat::BINARY16;
    let f = |x: f64| from_f64(h, x);
    let tiny = h.min_subnormal(false); // 2^-24, 1/d = 2^24 > 65504
    let bx = BoxIn {
        p_min: [tiny, f(-1.0), f(-1.0)],
        p_max: [f(1.0); 3],
    };
    let r = RayIn {
        o: [f(0.0); 3],
        d: [tiny, f(0.0), f(0.0)],
        t_min: f(0.0),
        t_max: f(2.0),
    };
    assert!(ray_hits_box(h, &bx, &r).hit, "reaches x = 2^-24 at t = 1");
    let rtz = cons_in(h, &bx, &r);
    assert_eq!(rtz.inv_d[0], h.max_finite(false));
    assert!(eval_conservative(h, &rtz).hit);
    let rne = rne_in(h, &bx, &r);
    assert_eq!(rne.inv_d[0], h.inf(false));
    assert!(
        !eval_conservative(h, &rne).hit,
        "outside the contract: RNE's ∞ reads as d = 0"
    );
}

/// Outside the contract, as measured (docs/silhouette.md §6.2): an infinite
/// origin is a miss or a hit at an infinite `t_enter`, never a hit at a
/// finite one (the slab has no `invalid` output). The audit's reproducer
/// hits at `+∞`; its mirror at `−∞`.
#[test]
fn conservative_slab_infinite_origin_is_a_miss_or_a_hit_at_infinity() {
    let (inf, ninf) = (b(f32::INFINITY), b(f32::NEG_INFINITY));
    let unit = SlabIn {
        p_min: [b(0.0); 3],
        p_max: [b(1.0); 3],
        o: [ninf, b(0.5), b(0.5)],
        inv_d: [b(1.0), inf, inf],
        t_min: b(0.0),
        t_max: inf,
    };
    let c = eval_conservative(F, &unit);
    assert!(c.hit && c.t_enter == inf && c.t_exit == inf, "{c:x?}");
    let mirror = SlabIn {
        o: [inf, b(0.5), b(0.5)],
        t_min: ninf,
        ..unit
    };
    let c = eval_conservative(F, &mirror);
    assert!(c.hit && c.t_enter == ninf, "{c:x?}");
    // every infinite origin component against boxes, directions and segments
    let values = [
        -2.0f32,
        -0.0,
        0.0,
        0.5,
        1.0,
        3.0,
        f32::INFINITY,
        f32::NEG_INFINITY,
    ];
    let mut hits = 0;
    for axis in 0..3 {
        for o_inf in [inf, ninf] {
            for &d in &values {
                for &t_min in &values {
                    for &t_max in &values {
                        let mut x = SlabIn {
                            inv_d: [inf; 3],
                            t_min: b(t_min),
                            t_max: b(t_max),
                            ..unit
                        };
                        x.o = [b(0.5); 3];
                        x.o[axis] = o_inf;
                        x.inv_d[axis] = b(d);
                        let c = eval_conservative(F, &x);
                        let t = f32::from_bits(c.t_enter as u32);
                        assert!(!c.hit || t.is_infinite(), "{x:x?}: {c:x?}");
                        hits += usize::from(c.hit);
                    }
                }
            }
        }
    }
    assert!(hits > 0, "the case the docs describe is reached");
}
