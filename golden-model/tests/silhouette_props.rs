//! Properties of the silhouette tester against the exact reference, on
//! adversarial generated cases in several formats (issue #4, properties 1-4).
//!
//! Default run: 1,200,000 single rays + 240,000 bundles (each bundle checked
//! on all its corner rays plus random interior rays, ~16 exact rays per
//! bundle). `SILHOUETTE_CASES=N` sets the single-ray count, and the bundle
//! count to N/5 unless `SILHOUETTE_BUNDLES=M` sets it. The 10,000,000 runs:
//! `SILHOUETTE_CASES=10000000 SILHOUETTE_BUNDLES=10000000 cargo test --release
//! -p golden-model --test silhouette_props -- --nocapture` (results recorded in
//! `docs/silhouette.md`).

mod silhouette_gen;

use golden_model::exact::ray_box::{ray_hits_box, rays_all_any};
use golden_model::float::FloatFormat;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding, Verdict};
use silhouette_gen::*;

#[derive(Default, Clone, Copy, Debug)]
struct RayStats {
    cases: u64,
    flagged: u64,
    exact_hits: u64,
    exact_misses: u64,
    false_hits: u64,
    uncertain: u64,
    rne_false_miss: u64,
    rne_false_hit: u64,
}

impl RayStats {
    fn add(&mut self, o: &RayStats) {
        self.cases += o.cases;
        self.flagged += o.flagged;
        self.exact_hits += o.exact_hits;
        self.exact_misses += o.exact_misses;
        self.false_hits += o.false_hits;
        self.uncertain += o.uncertain;
        self.rne_false_miss += o.rne_false_miss;
        self.rne_false_hit += o.rne_false_hit;
    }
}

fn single_ray_chunk(fmt: FloatFormat, kind: Kind, seed: u64, n: u64) -> RayStats {
    let cons = Config::new(fmt, OriginMode::Shared, Rounding::Conservative).unwrap();
    let bnd = Config::new(fmt, OriginMode::Bounded, Rounding::Conservative).unwrap();
    let rne = Config::new(fmt, OriginMode::Shared, Rounding::Nearest).unwrap();
    let mut rng = Rng(seed);
    let mut st = RayStats::default();
    for _ in 0..n {
        let (bx, ray) = gen_ray(fmt, &mut rng, kind);
        let ex = ray_hits_box(fmt, &bx, &ray);
        let input = BundleIn::ray(bx.p_min, bx.p_max, ray.o, ray.d, ray.t_min, ray.t_max);
        let out = eval(&cons, &input);
        let ctx = || format!("{fmt} {kind:?} box {bx:x?} ray {ray:x?} exact {ex:?} out {out:?}");
        st.cases += 1;
        assert_eq!(out.nan, ex.nan, "nan flag: {}", ctx());
        assert_eq!(out.invalid, ex.invalid, "invalid flag: {}", ctx());
        assert!(!out.mixed_sign, "single ray mixed: {}", ctx());
        // (1) conservative never misses a true hit; AllHit of a ray is a proof of hit.
        if ex.hit {
            assert!(out.any_hit, "FALSE MISS: {}", ctx());
        }
        if out.all_hit {
            assert!(ex.hit, "all_hit on a miss: {}", ctx());
        }
        assert!(
            !out.all_hit || out.any_hit,
            "all_hit without any_hit: {}",
            ctx()
        );
        // The bounded-origin datapath with coinciding bounds is the same function.
        assert_eq!(
            eval(&bnd, &input),
            out,
            "bounded != shared on a single ray: {}",
            ctx()
        );
        if ex.nan || ex.invalid {
            st.flagged += 1;
            continue;
        }
        if ex.hit {
            st.exact_hits += 1;
        } else {
            st.exact_misses += 1;
            st.false_hits += out.any_hit as u64;
        }
        st.uncertain += (out.any_hit && !out.all_hit) as u64;
        let r = eval(&rne, &input);
        st.rne_false_miss += (ex.hit && !r.any_hit) as u64;
        st.rne_false_hit += (!ex.hit && r.any_hit) as u64;
    }
    st
}

fn par<T: Send + Default + Copy, F: Fn(u64, u64) -> T + Sync>(
    n: u64,
    seed: u64,
    f: F,
    merge: fn(&mut T, &T),
) -> T {
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(2)
        .min(8) as u64;
    let per = n.div_ceil(threads);
    let mut total = T::default();
    std::thread::scope(|s| {
        let hs: Vec<_> = (0..threads)
            .map(|t| {
                let f = &f;
                let cnt = per.min(n.saturating_sub(t * per));
                s.spawn(move || f(seed ^ (t + 1).wrapping_mul(0x2545_F491_4F6C_DD1D), cnt))
            })
            .collect();
        for h in hs {
            merge(&mut total, &h.join().unwrap());
        }
    });
    total
}

#[test]
fn single_ray_conservative_never_misses_and_false_hit_rates() {
    let total = cases(1_200_000);
    let fmts = formats();
    let per_fmt_kind = total / (fmts.len() as u64 * KINDS.len() as u64);
    let mut grand = RayStats::default();
    println!("single rays, {per_fmt_kind} per format and kind (conservative vs exact; RNE policy for comparison)");
    println!(
        "{:<8} {:<13} {:>9} {:>8} {:>9} {:>9} {:>10} {:>10} {:>10} {:>10}",
        "format",
        "kind",
        "cases",
        "flagged",
        "hits",
        "misses",
        "false hit",
        "uncertain",
        "RNE f.miss",
        "RNE f.hit"
    );
    for (fi, &fmt) in fmts.iter().enumerate() {
        for (ki, &kind) in KINDS.iter().enumerate() {
            let seed = 0x51_1E77_0000 + (fi as u64) * 100 + ki as u64;
            let st = par(
                per_fmt_kind,
                seed,
                |s, n| single_ray_chunk(fmt, kind, s, n),
                RayStats::add,
            );
            println!(
                "{:<8} {:<13} {:>9} {:>8} {:>9} {:>9} {:>10} {:>10} {:>10} {:>10}",
                fmt.to_string(),
                format!("{kind:?}"),
                st.cases,
                st.flagged,
                st.exact_hits,
                st.exact_misses,
                st.false_hits,
                st.uncertain,
                st.rne_false_miss,
                st.rne_false_hit
            );
            grand.add(&st);
        }
    }
    println!("total: {grand:?}");
    println!(
        "false-hit rate (false hits / exact misses): {:.3e}",
        grand.false_hits as f64 / grand.exact_misses.max(1) as f64
    );
    assert!(grand.cases >= total - 100);
}

#[derive(Default, Clone, Copy, Debug)]
struct BundleStats {
    cases: u64,
    checked_rays: u64,
    all_hit: u64,
    all_miss: u64,
    mixed: u64,
    mixed_sign: u64,
    flagged: u64,
    mixed_truly_all_hit: u64,
    mixed_truly_all_miss: u64,
}

impl BundleStats {
    fn add(&mut self, o: &BundleStats) {
        self.cases += o.cases;
        self.checked_rays += o.checked_rays;
        self.all_hit += o.all_hit;
        self.all_miss += o.all_miss;
        self.mixed += o.mixed;
        self.mixed_sign += o.mixed_sign;
        self.flagged += o.flagged;
        self.mixed_truly_all_hit += o.mixed_truly_all_hit;
        self.mixed_truly_all_miss += o.mixed_truly_all_miss;
    }
}

fn bundle_chunk(fmt: FloatFormat, bounded: bool, seed: u64, n: u64) -> BundleStats {
    let mode = if bounded {
        OriginMode::Bounded
    } else {
        OriginMode::Shared
    };
    let cfg = Config::new(fmt, mode, Rounding::Conservative).unwrap();
    let mut rng = Rng(seed);
    let mut st = BundleStats::default();
    for c in 0..n {
        let kind = KINDS[(c % KINDS.len() as u64) as usize];
        let allow_mixed = rng.chance(1, 10);
        let (bx, b) = gen_bundle(fmt, &mut rng, kind, bounded, allow_mixed);
        let out = eval(&cfg, &b);
        st.cases += 1;
        let ctx = || format!("{fmt} bounded={bounded} {kind:?} bundle {b:x?} out {out:?}");
        assert!(
            !out.all_hit || out.any_hit,
            "all_hit without any_hit: {}",
            ctx()
        );
        if out.nan || out.invalid {
            st.flagged += 1;
            assert!(!out.all_hit && !out.any_hit, "flagged but hit: {}", ctx());
            continue;
        }
        assert!(
            bundle_well_formed(fmt, &b, bounded),
            "unflagged ill-formed bundle: {}",
            ctx()
        );
        st.mixed_sign += out.mixed_sign as u64;
        let v = out.verdict();
        // Mixed claims nothing: check a sample of those only, for the statistics.
        let n_random = if v == Verdict::Mixed { 2 } else { 8 };
        let rays = bundle_rays(fmt, &mut rng, &b, bounded, n_random);
        st.checked_rays += rays.len() as u64;
        let (all, any) = rays_all_any(fmt, &bx, &rays);
        match v {
            // (2) AllHit ⇒ every ray of the bundle hits exactly.
            Verdict::AllHit => {
                st.all_hit += 1;
                assert!(all, "ALLHIT BUT A RAY MISSES: {}", ctx());
            }
            // (3) AnyHit false ⇒ every ray misses exactly.
            Verdict::AllMiss => {
                st.all_miss += 1;
                assert!(!any, "ALLMISS BUT A RAY HITS: {}", ctx());
            }
            Verdict::Mixed => {
                st.mixed += 1;
                st.mixed_truly_all_hit += all as u64;
                st.mixed_truly_all_miss += !any as u64;
            }
        }
    }
    st
}

#[test]
fn bundles_allhit_and_anyhit_are_sound() {
    let total = std::env::var("SILHOUETTE_BUNDLES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(cases(1_200_000) / 5);
    let fmts = formats();
    let per = total / (fmts.len() as u64 * 2);
    println!("bundles, {per} per format and origin mode; every corner ray + 8 random rays checked exactly (2 for Mixed)");
    let mut grand = BundleStats::default();
    for (fi, &fmt) in fmts.iter().enumerate() {
        for bounded in [false, true] {
            let seed = 0xB0_0D1E_0000 + fi as u64 * 10 + bounded as u64;
            let st = par(
                per,
                seed,
                |s, n| bundle_chunk(fmt, bounded, s, n),
                BundleStats::add,
            );
            println!("{:<8} bounded={:<5} {st:?}", fmt.to_string(), bounded);
            grand.add(&st);
        }
    }
    println!("total: {grand:?}");
}
