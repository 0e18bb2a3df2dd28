//! proptest versions of properties 1-3: values from pools of special and
//! boundary-rich numbers (binary32), and arbitrary bit patterns of a tiny
//! (4, 3) format where every special value is common.

mod silhouette_gen;

use golden_model::exact::ray_box::{corner_rays, ray_hits_box, rays_all_any, BoxIn, RayIn};
use golden_model::float::total_key;
use golden_model::float::FloatFormat;
use golden_model::silhouette::{eval, BundleIn, Config, OriginMode, Rounding, Verdict};
use proptest::prelude::*;

const POOL: &[f32] = &[
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    -0.5,
    2.0,
    -2.0,
    3.0,
    -3.0,
    1.5,
    -1.5,
    0.25,
    1e-3,
    -1e-3,
    7.0,
    -7.0,
    1e30,
    -1e30,
    1e-40,
    -1e-40,
    f32::MIN_POSITIVE,
    f32::MAX,
    f32::MIN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::NAN,
    1.0000001,
    0.99999994,
    -1.0000001,
];

fn pooled() -> impl Strategy<Value = u64> + Clone {
    prop_oneof![
        6 => (0..POOL.len()).prop_map(|i| POOL[i].to_bits() as u64),
        1 => any::<u32>().prop_map(|b| b as u64),
        2 => (-8i32..8, 0u32..4).prop_map(|(m, e)| ((m as f32) / (1 << e) as f32).to_bits() as u64),
    ]
}

fn v3<S: Strategy<Value = u64> + Clone>(s: S) -> impl Strategy<Value = [u64; 3]> {
    [s.clone(), s.clone(), s]
}

fn check_ray(fmt: FloatFormat, bx: BoxIn, r: RayIn) -> Result<(), TestCaseError> {
    let ex = ray_hits_box(fmt, &bx, &r);
    let x = BundleIn::ray(bx.p_min, bx.p_max, r.o, r.d, r.t_min, r.t_max);
    for origin in [OriginMode::Shared, OriginMode::Bounded] {
        let out = eval(
            &Config::new(fmt, origin, Rounding::Conservative).unwrap(),
            &x,
        );
        prop_assert_eq!(
            (out.nan, out.invalid, out.mixed_sign),
            (ex.nan, ex.invalid, false)
        );
        prop_assert!(!ex.hit || out.any_hit, "false miss {:x?} {:x?}", bx, r);
        prop_assert!(
            !out.all_hit || ex.hit,
            "all_hit on a miss {:x?} {:x?}",
            bx,
            r
        );
    }
    Ok(())
}

fn check_bundle(
    fmt: FloatFormat,
    bx: BoxIn,
    x: BundleIn,
    origin: OriginMode,
) -> Result<(), TestCaseError> {
    let out = eval(
        &Config::new(fmt, origin, Rounding::Conservative).unwrap(),
        &x,
    );
    prop_assert!(!out.all_hit || out.any_hit);
    if out.nan || out.invalid {
        prop_assert!(!out.any_hit);
        return Ok(());
    }
    let o_hi = if origin == OriginMode::Bounded {
        x.o_hi
    } else {
        x.o_lo
    };
    let rays = corner_rays(x.o_lo, o_hi, x.d_lo, x.d_hi, x.t_min, x.t_max);
    let (all, any) = rays_all_any(fmt, &bx, &rays);
    match out.verdict() {
        Verdict::AllHit => prop_assert!(all, "AllHit but a corner misses {:x?}", x),
        Verdict::AllMiss => prop_assert!(!any, "AllMiss but a corner hits {:x?}", x),
        Verdict::Mixed => {}
    }
    Ok(())
}

/// Sorts each component pair into (lo, hi) by value (NaNs left in place).
fn sorted(fmt: FloatFormat, a: [u64; 3], b: [u64; 3]) -> ([u64; 3], [u64; 3]) {
    let mut lo = a;
    let mut hi = b;
    for i in 0..3 {
        if !fmt.is_nan(a[i]) && !fmt.is_nan(b[i]) && total_key(fmt, a[i]) > total_key(fmt, b[i]) {
            lo[i] = b[i];
            hi[i] = a[i];
        }
    }
    (lo, hi)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40_000, ..ProptestConfig::default() })]

    #[test]
    fn ray_binary32_pooled(p0 in v3(pooled()), p1 in v3(pooled()), o in v3(pooled()), d in v3(pooled()),
                           t0 in pooled(), t1 in pooled(), sort in any::<bool>()) {
        let f = FloatFormat::BINARY32;
        let (p_min, p_max) = if sort { sorted(f, p0, p1) } else { (p0, p1) };
        check_ray(f, BoxIn { p_min, p_max }, RayIn { o, d, t_min: t0, t_max: t1 })?;
    }

    #[test]
    fn ray_e4m3_any_bits(p0 in v3(0u64..256), p1 in v3(0u64..256), o in v3(0u64..256), d in v3(0u64..256),
                         t0 in 0u64..256, t1 in 0u64..256, sort in any::<bool>()) {
        let f = FloatFormat::new(4, 3).unwrap();
        let (p_min, p_max) = if sort { sorted(f, p0, p1) } else { (p0, p1) };
        check_ray(f, BoxIn { p_min, p_max }, RayIn { o, d, t_min: t0, t_max: t1 })?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 20_000, ..ProptestConfig::default() })]

    #[test]
    fn bundle_e4m3_any_bits(p0 in v3(0u64..256), p1 in v3(0u64..256), o0 in v3(0u64..256), o1 in v3(0u64..256),
                            d0 in v3(0u64..256), d1 in v3(0u64..256), t0 in 0u64..256, t1 in 0u64..256,
                            bounded in any::<bool>()) {
        let f = FloatFormat::new(4, 3).unwrap();
        let (p_min, p_max) = sorted(f, p0, p1);
        let (o_lo, o_hi) = sorted(f, o0, o1);
        let (d_lo, d_hi) = sorted(f, d0, d1);
        let origin = if bounded { OriginMode::Bounded } else { OriginMode::Shared };
        let x = BundleIn { p_min, p_max, o_lo, o_hi, d_lo, d_hi, t_min: t0, t_max: t1 };
        check_bundle(f, BoxIn { p_min, p_max }, x, origin)?;
    }

    #[test]
    fn bundle_binary32_pooled(p0 in v3(pooled()), p1 in v3(pooled()), o0 in v3(pooled()), o1 in v3(pooled()),
                              d0 in v3(pooled()), d1 in v3(pooled()), t0 in pooled(), t1 in pooled(),
                              bounded in any::<bool>()) {
        let f = FloatFormat::BINARY32;
        let (p_min, p_max) = sorted(f, p0, p1);
        let (o_lo, o_hi) = sorted(f, o0, o1);
        let (d_lo, d_hi) = sorted(f, d0, d1);
        let origin = if bounded { OriginMode::Bounded } else { OriginMode::Shared };
        let x = BundleIn { p_min, p_max, o_lo, o_hi, d_lo, d_hi, t_min: t0, t_max: t1 };
        check_bundle(f, BoxIn { p_min, p_max }, x, origin)?;
    }
}
