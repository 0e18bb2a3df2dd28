//! The slab baseline against the exact reference and the silhouette tester:
//! where the slab test fails (0·∞ → NaN, grazing rays) and where the
//! conservative silhouette test holds; and the binary32 accuracy table on a
//! realistic scene distribution (property 4).

mod silhouette_gen;

use golden_model::exact::ray_box::{ray_hits_box, BoxIn, RayIn};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding};
use golden_model::slab::{self, SlabIn};
use silhouette_gen::*;

const F: FloatFormat = FloatFormat::BINARY32;

fn b(x: f32) -> u64 {
    x.to_bits() as u64
}

fn slab_in(fmt: FloatFormat, bx: &BoxIn, r: &RayIn) -> SlabIn {
    SlabIn {
        p_min: bx.p_min,
        p_max: bx.p_max,
        o: r.o,
        inv_d: r.d.map(|d| recip(fmt, d)),
        t_min: r.t_min,
        t_max: r.t_max,
    }
}

fn sil(fmt: FloatFormat, rounding: Rounding, bx: &BoxIn, r: &RayIn) -> bool {
    let c = Config::new(fmt, OriginMode::Shared, rounding).unwrap();
    eval(
        &c,
        &BundleIn::ray(bx.p_min, bx.p_max, r.o, r.d, r.t_min, r.t_max),
    )
    .any_hit
}

#[test]
fn slab_zero_times_inf_misses_a_ray_along_a_face() {
    // Box [0,1]^3; the ray runs inside the face x = 0 (d_x = 0, o_x = 0).
    let bx = BoxIn {
        p_min: [b(0.0); 3],
        p_max: [b(1.0); 3],
    };
    let r = RayIn {
        o: [b(0.0), b(0.5), b(-1.0)],
        d: [b(0.0), b(0.0), b(1.0)],
        t_min: b(0.0),
        t_max: b(f32::INFINITY),
    };
    assert!(ray_hits_box(F, &bx, &r).hit);
    let s = slab::eval(F, &slab_in(F, &bx, &r));
    assert!(F.is_nan(s.t_enter), "0·inf should give NaN: {s:x?}");
    assert!(!s.hit, "the slab test misses the touching ray");
    assert!(sil(F, Rounding::Conservative, &bx, &r));
    assert!(sil(F, Rounding::Nearest, &bx, &r));
}

#[derive(Default, Debug, Clone, Copy)]
struct Acc {
    cases: u64,
    hits: u64,
    misses: u64,
    cons_false_hit: u64,
    cons_false_miss: u64,
    rne_false_hit: u64,
    rne_false_miss: u64,
    slab_false_hit: u64,
    slab_false_miss: u64,
    slab_nan: u64,
}

fn tally(acc: &mut Acc, fmt: FloatFormat, bx: &BoxIn, r: &RayIn) {
    let ex = ray_hits_box(fmt, bx, r);
    if ex.nan || ex.invalid {
        return;
    }
    acc.cases += 1;
    let c = sil(fmt, Rounding::Conservative, bx, r);
    let n = sil(fmt, Rounding::Nearest, bx, r);
    let s = slab::eval(fmt, &slab_in(fmt, bx, r));
    acc.slab_nan += (fmt.is_nan(s.t_enter) || fmt.is_nan(s.t_exit)) as u64;
    if ex.hit {
        acc.hits += 1;
        acc.cons_false_miss += !c as u64;
        acc.rne_false_miss += !n as u64;
        acc.slab_false_miss += !s.hit as u64;
    } else {
        acc.misses += 1;
        acc.cons_false_hit += c as u64;
        acc.rne_false_hit += n as u64;
        acc.slab_false_hit += s.hit as u64;
    }
}

fn print_row(name: &str, a: &Acc) {
    let r = |x: u64, of: u64| if of == 0 { 0.0 } else { x as f64 / of as f64 };
    println!(
        "{name:<22} {:>8} {:>8} | cons f.hit {:>9.2e} f.miss {:>2} | RNE f.hit {:>9.2e} f.miss {:>9.2e} | slab f.hit {:>9.2e} f.miss {:>9.2e} (NaN {})",
        a.hits, a.misses,
        r(a.cons_false_hit, a.misses), a.cons_false_miss,
        r(a.rne_false_hit, a.misses), r(a.rne_false_miss, a.hits),
        r(a.slab_false_hit, a.misses), r(a.slab_false_miss, a.hits), a.slab_nan
    );
}

/// Grazing / along-face / random cases in binary32 and two reduced formats:
/// the slab test misses true hits, the conservative silhouette test never does.
#[test]
fn slab_fails_where_the_silhouette_test_holds() {
    let n = cases(1_200_000) / 12;
    println!("rates: false hits / exact misses, false misses / exact hits; {n} cases per row");
    for fmt in [F, FloatFormat::BINARY16, FloatFormat::BFLOAT16] {
        for kind in [
            Kind::Random,
            Kind::Grazing,
            Kind::AlongFace,
            Kind::OriginOnBox,
        ] {
            let mut rng = Rng(0x51AB ^ (kind as u64) << 8 ^ fmt.frac_bits() as u64);
            let mut acc = Acc::default();
            for _ in 0..n {
                let (bx, r) = gen_ray(fmt, &mut rng, kind);
                tally(&mut acc, fmt, &bx, &r);
            }
            print_row(&format!("{fmt} {kind:?}"), &acc);
            assert_eq!(acc.cons_false_miss, 0);
            if kind == Kind::Grazing || kind == Kind::AlongFace {
                assert!(
                    acc.slab_false_miss > 0,
                    "expected the slab test to miss true hits on {kind:?}"
                );
            }
        }
    }
}

/// Property 4: binary32 false-hit rate on a realistic distribution: boxes in
/// [-1,1]^3 of random size, origins in [-4,4]^3, unit directions (aimed near
/// the box half the time), t_min = 0, t_max = inf or finite.
#[test]
fn binary32_false_hit_rate_realistic() {
    let n = cases(1_200_000) / 3;
    let mut rng = Rng(0xACC0_0001);
    let mut acc = Acc::default();
    for _ in 0..n {
        let (bx, r) = realistic_scene_case(&mut rng);
        tally(&mut acc, F, &bx, &r);
    }
    println!("binary32 realistic scene, {} rays:", acc.cases);
    print_row("e8m23 realistic", &acc);
    println!("{acc:?}");
    assert_eq!(acc.cons_false_miss, 0);
}
