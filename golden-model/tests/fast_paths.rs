//! The fast paths (issue #20) against the generic models they replace:
//! every output bit equal on random and corner vectors, per unit and
//! format class. `FAST_CASES` sets the number of vectors per unit and class
//! (default 1,000,000; the release run uses 10^8). A disagreement is a bug in
//! the fast path: the first disagreeing input and both outputs are printed
//! in hex.

mod common;
mod silhouette_gen;

use common::{operand, operand_near, specials};
use golden_model::cull::{self, tester::Crossing, tester::NormalTerm, ChildIn, RayIn as CullRay};
use golden_model::float::{
    add, add_down_up, add_down_up_generic, add_generic, dot3_floor, dot3_floor_generic, fma,
    fma_generic, mul, mul_generic, FloatFormat, RoundingMode,
};
use golden_model::silhouette::{
    any_hit, eval, eval_generic, BundleIn, Config, OriginMode, Rounding,
};
use golden_model::slab::{self, SlabIn};
use golden_model::transform::{recip, recip_generic};
use silhouette_gen::{gen_bundle, realistic_scene_case, Random, Rng, KINDS};

/// Vectors per unit and format class.
fn cases() -> u64 {
    std::env::var("FAST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_000_000)
}

/// Counts vectors; panics with the first disagreement.
struct Equal {
    what: String,
    checked: u64,
}

impl Equal {
    fn new(what: impl Into<String>) -> Equal {
        Equal {
            what: what.into(),
            checked: 0,
        }
    }
    fn check<T: PartialEq + std::fmt::Debug>(
        &mut self,
        fast: T,
        generic: T,
        input: impl FnOnce() -> String,
    ) {
        self.checked += 1;
        if fast != generic {
            panic!(
                "{}: fast path disagrees at vector {}\ninput: {}\nfast:    {:x?}\ngeneric: {:x?}",
                self.what,
                self.checked,
                input(),
                fast,
                generic
            );
        }
    }
    fn finish(self) {
        println!("{}: {} vectors, fast == generic", self.what, self.checked);
    }
}

#[test]
fn add_down_up_binary32() {
    let f = FloatFormat::BINARY32;
    let mut eq = Equal::new("add_down_up binary32");
    // garbage above the format's width, on one operand in 16, is ignored by both paths
    let mut junk = common::Rng::new(21);
    pairs(
        |a, b| {
            let a = a | if junk.below(16) == 0 {
                junk.next() << 32
            } else {
                0
            };
            eq.check(add_down_up(f, a, b), add_down_up_generic(f, a, b), || {
                format!("a = {a:#010x}, b = {b:#010x}")
            })
        },
        20,
    );
    eq.finish();
}

/// A bundle of raw operands: random patterns, specials, structured values.
fn raw_bundle(rng: &mut common::Rng, f: FloatFormat, sp: &[u64]) -> BundleIn {
    let mut v = || operand(rng, f, sp);
    BundleIn {
        p_min: [v(), v(), v()],
        p_max: [v(), v(), v()],
        o_lo: [v(), v(), v()],
        o_hi: [v(), v(), v()],
        d_lo: [v(), v(), v()],
        d_hi: [v(), v(), v()],
        t_min: v(),
        t_max: v(),
    }
}

/// `n` silhouette vectors per configuration class of `fmts` (`eval` and
/// `any_hit` against `eval_generic`): adversarial
/// bundles and rays of `silhouette_gen` (grazing, along a face, origin on
/// the box, specials, ...), realistic binary32 scene rays, and raw operands.
fn silhouette_class(what: &str, fmts: &[FloatFormat], seed: u64) {
    let n = cases();
    let mut eq = Equal::new(format!("silhouette {what}"));
    let mut rng = Rng(seed);
    let mut raw_rng = common::Rng::new(seed);
    let mut k = 0u64;
    while eq.checked < n {
        let f = fmts[(k % fmts.len() as u64) as usize];
        let origin = if (k / fmts.len() as u64).is_multiple_of(2) {
            OriginMode::Shared
        } else {
            OriginMode::Bounded
        };
        let rounding = if k / (2 * fmts.len() as u64) % 4 == 3 {
            Rounding::Nearest
        } else {
            Rounding::Conservative
        };
        k += 1;
        let cfg = Config::new(f, origin, rounding).unwrap();
        let bounded = origin == OriginMode::Bounded;
        let x = match rng.below(16) {
            0 => raw_bundle(&mut raw_rng, f, &specials(f)),
            1 | 2 if f == FloatFormat::BINARY32 => {
                let (bx, r) = realistic_scene_case(&mut rng);
                BundleIn::ray(bx.p_min, bx.p_max, r.o, r.d, r.t_min, r.t_max)
            }
            _ => {
                let kind = KINDS[rng.below(KINDS.len() as u64) as usize];
                let mixed = rng.chance(1, 4);
                gen_bundle(f, &mut rng, kind, bounded, mixed).1
            }
        };
        let generic = eval_generic(&cfg, &x);
        eq.check(
            (eval(&cfg, &x), any_hit(&cfg, &x)),
            (generic, generic.any_hit),
            || format!("{cfg:?}\n{x:x?}"),
        );
    }
    eq.finish();
}

#[test]
fn silhouette_binary32() {
    silhouette_class("binary32", &[FloatFormat::BINARY32], 1);
}

#[test]
fn silhouette_small_formats() {
    let fmts = [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(4, 3).unwrap(),
        FloatFormat::new(6, 9).unwrap(),
        FloatFormat::new(8, 22).unwrap(),
        FloatFormat::new(2, 1).unwrap(),
    ];
    silhouette_class("E <= 8, F <= 23 (not binary32)", &fmts, 2);
}

/// Operand pairs for a binary32 two-operand operator: specials against
/// specials and their one-ulp neighbours, then random pairs (cancellation,
/// near cancellation, exponents far apart and close).
fn pairs(mut one: impl FnMut(u64, u64), seed: u64) {
    let f = FloatFormat::BINARY32;
    let sp = specials(f);
    for &a in &sp {
        for &b in &sp {
            one(a, b);
            for d in [1u64, 2] {
                one(a, (b + d) & f.mask());
                one(a, b.wrapping_sub(d) & f.mask());
            }
        }
    }
    let mut rng = common::Rng::new(seed);
    for _ in 0..cases() {
        let a = operand(&mut rng, f, &sp);
        let b = match rng.below(6) {
            0 => operand(&mut rng, f, &sp),
            1 => a ^ f.sign_bit(),
            2 => (a ^ f.sign_bit()).wrapping_add(rng.below(5).wrapping_sub(2)) & f.mask(),
            3 => operand_near(&mut rng, f, a, 30),
            _ => operand_near(&mut rng, f, a, 3),
        };
        one(a, b);
    }
}

#[test]
fn add_binary32_every_mode() {
    let f = FloatFormat::BINARY32;
    for (m, mode) in RoundingMode::ALL.into_iter().enumerate() {
        let mut eq = Equal::new(format!("add binary32 {mode:?}"));
        pairs(
            |a, b| {
                eq.check(add(f, a, b, mode), add_generic(f, a, b, mode), || {
                    format!("a = {a:#010x}, b = {b:#010x}")
                })
            },
            30 + m as u64,
        );
        eq.finish();
    }
}

#[test]
fn mul_binary32_every_mode() {
    let f = FloatFormat::BINARY32;
    for (m, mode) in RoundingMode::ALL.into_iter().enumerate() {
        let mut eq = Equal::new(format!("mul binary32 {mode:?}"));
        let mut rng = common::Rng::new(40 + m as u64);
        pairs(
            |a, b| {
                // products near the overflow and underflow thresholds too:
                // b's exponent chosen so that the exponents sum to about
                // 128 or to -126 .. -150
                let b = if rng.below(4) == 0 {
                    let ea = ((a >> 23) & 0xff) as i64 - 127;
                    let target = [128, 127, -126, -140, -150][rng.below(5) as usize];
                    let eb = (target - ea + rng.range(-1, 1)).clamp(-126, 127) + 127;
                    (b & !(0xff << 23)) | ((eb as u64) << 23)
                } else {
                    b
                };
                eq.check(mul(f, a, b, mode), mul_generic(f, a, b, mode), || {
                    format!("a = {a:#010x}, b = {b:#010x}")
                })
            },
            40 + m as u64,
        );
        eq.finish();
    }
}

#[test]
fn fma_binary32_nearest() {
    let f = FloatFormat::BINARY32;
    let mode = RoundingMode::NearestEven;
    let sp = specials(f);
    let mut rng = common::Rng::new(50);
    let mut eq = Equal::new("fma binary32 NearestEven");
    let mut one = |a: u64, b: u64, c: u64| {
        eq.check(fma(f, a, b, c, mode), fma_generic(f, a, b, c, mode), || {
            format!("a = {a:#010x}, b = {b:#010x}, c = {c:#010x}")
        })
    };
    for &a in &sp {
        for &b in &sp {
            for &c in &sp {
                one(a, b, c);
            }
        }
    }
    for _ in 0..cases() {
        let a = operand(&mut rng, f, &sp);
        let b = operand(&mut rng, f, &sp);
        let p = mul(f, a, b, RoundingMode::NearestEven);
        let c = match rng.below(4) {
            0 => operand(&mut rng, f, &sp),
            1 => p ^ f.sign_bit(), // cancellation of the rounded product
            2 => (p ^ f.sign_bit()).wrapping_add(rng.below(5).wrapping_sub(2)) & f.mask(),
            _ => operand_near(&mut rng, f, p, 30),
        };
        one(a, b, c);
    }
    eq.finish();
}

#[test]
fn slab_conservative_binary32() {
    let f = FloatFormat::BINARY32;
    let sp = specials(f);
    let mut rng = common::Rng::new(70);
    let mut eq = Equal::new("conservative slab, binary32");
    let (mut hits, mut parallel) = (0u64, 0u64);
    for _ in 0..cases() {
        let v = |rng: &mut common::Rng| operand(rng, f, &sp);
        let mut x = SlabIn {
            p_min: [v(&mut rng), v(&mut rng), v(&mut rng)],
            p_max: [v(&mut rng), v(&mut rng), v(&mut rng)],
            o: [v(&mut rng), v(&mut rng), v(&mut rng)],
            inv_d: [v(&mut rng), v(&mut rng), v(&mut rng)],
            t_min: v(&mut rng),
            t_max: v(&mut rng),
        };
        for i in 0..3 {
            match rng.below(6) {
                // the origin on or near a slab plane: cancellation in p − o
                0 => x.o[i] = x.p_min[i],
                1 => x.o[i] = operand_near(&mut rng, f, x.p_max[i], 2),
                // a zero direction component: the parallel slab
                2 => x.inv_d[i] = f.inf(rng.bool()),
                // an ordered box around the origin
                3 => {
                    x.p_min[i] = operand_near(&mut rng, f, x.o[i], 3) | f.sign_bit();
                    x.p_max[i] = operand_near(&mut rng, f, x.o[i], 3) & !f.sign_bit();
                }
                _ => {}
            }
            parallel += (x.inv_d[i] & !f.sign_bit() == f.inf(false)) as u64;
        }
        if rng.below(2) == 0 {
            // a usual segment [0, t_max]
            x.t_min = 0;
            x.t_max = operand(&mut rng, f, &sp) & !f.sign_bit();
        }
        let generic = slab::eval_conservative_generic(f, &x);
        hits += generic.hit as u64;
        eq.check(slab::eval_conservative(f, &x), generic, || {
            format!("{x:#x?}")
        });
    }
    println!("conservative slab: {hits} hits, {parallel} parallel slabs");
    eq.finish();
}

/// One random cull child: terms from `ray_terms` of a random ray (or raw
/// operands), distances and segment from structured operands.
fn cull_child(rng: &mut common::Rng, cfg: &cull::Config) -> ChildIn {
    let (f, pf, cf) = (cfg.ray, cfg.plane, cfg.crossing());
    let (sf, sp, sc) = (specials(f), specials(pf), specials(cf));
    let k = if rng.below(8) == 0 {
        rng.below(cfg.k as u64 + 1) as usize
    } else {
        cfg.k
    };
    let terms: Vec<NormalTerm> = if rng.below(2) == 0 {
        let mut v = |fmt, s: &[u64]| operand(rng, fmt, s);
        let x = CullRay {
            o: [v(f, &sf), v(f, &sf), v(f, &sf)],
            d: [v(f, &sf), v(f, &sf), v(f, &sf)],
            r: [v(f, &sf), v(f, &sf), v(f, &sf)],
            normals: (0..k)
                .map(|_| [v(pf, &sp), v(pf, &sp), v(pf, &sp)])
                .collect(),
        };
        cull::ray_terms(cfg, &x).terms
    } else {
        (0..k)
            .map(|_| NormalTerm {
                no_lo: operand(rng, f, &sf),
                rcp_lo: operand(rng, cf, &sc),
                rcp_hi: operand(rng, cf, &sc),
                dir: Crossing::from_code(rng.below(4)),
            })
            .collect()
    };
    let t_lo = operand(rng, f, &sf);
    let t_hi = if rng.below(2) == 0 {
        operand_near(rng, f, t_lo, 4) & !f.sign_bit()
    } else {
        operand(rng, f, &sf)
    };
    ChildIn {
        t_lo,
        t_hi,
        w: (0..k).map(|_| operand(rng, pf, &sp)).collect(),
        terms,
    }
}

#[test]
fn cull_eval_binary32_rays() {
    let f = FloatFormat::BINARY32;
    let planes = [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(5, 5).unwrap(),
        FloatFormat::BINARY32,
    ];
    let mut rng = common::Rng::new(60);
    let mut eq = Equal::new("cull eval, binary32 rays (planes e5m10, e8m7, e5m5, e8m23; K 1..8)");
    let (mut valid, mut culled) = (0u64, 0u64);
    for i in 0..cases() {
        let pf = planes[(i % planes.len() as u64) as usize];
        let k = 1 + (i / planes.len() as u64 % 8) as usize;
        let cfg = cull::Config::new(f, pf, k).unwrap();
        let x = cull_child(&mut rng, &cfg);
        let out = cull::eval_generic(&cfg, &x);
        valid += !out.invalid as u64;
        culled += !out.keep as u64;
        eq.check(cull::eval(&cfg, &x), out, || format!("{cfg:?}\n{x:x?}"));
    }
    println!("cull eval: {valid} valid inputs, {culled} culled");
    eq.finish();
}

#[test]
fn cull_ray_terms_binary32_rays() {
    let f = FloatFormat::BINARY32;
    let planes = [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(5, 5).unwrap(),
        FloatFormat::new(8, 15).unwrap(),
        FloatFormat::BINARY32,
    ];
    let sf = specials(f);
    let mut rng = common::Rng::new(65);
    let mut eq = Equal::new(
        "cull ray terms, binary32 rays (planes e5m10, e8m7, e5m5, e8m15, e8m23; K 1..8)",
    );
    let mut valid = 0u64;
    for i in 0..cases() {
        let pf = planes[(i % planes.len() as u64) as usize];
        let k = 1 + (i / planes.len() as u64 % 8) as usize;
        let cfg = cull::Config::new(f, pf, k).unwrap();
        let sp = specials(pf);
        let mut v = |fmt, s: &[u64]| operand(&mut rng, fmt, s);
        let o = [v(f, &sf), v(f, &sf), v(f, &sf)];
        let mut r = [v(f, &sf), v(f, &sf), v(f, &sf)];
        let d = [v(f, &sf), v(f, &sf), v(f, &sf)];
        let normals: Vec<[u64; 3]> = (0..k)
            .map(|_| [v(pf, &sp), v(pf, &sp), v(pf, &sp)])
            .collect();
        match rng.below(4) {
            // the corner near the origin: cancellation in o − r
            0 => r = o.map(|x| operand_near(&mut rng, f, x, 2)),
            1 => r = o,
            _ => {}
        }
        // fewer normals than k: the missing ones read as 0
        let n = if rng.below(8) == 0 {
            rng.below(k as u64 + 1) as usize
        } else {
            k
        };
        let fast = cull::normal_terms(&cfg, &o, &d, &r, &normals[..n]);
        valid += !fast.2 as u64;
        eq.check(
            fast,
            cull::normal_terms_generic(&cfg, &o, &d, &r, &normals[..n]),
            || format!("{cfg:?}\no = {o:#x?}, d = {d:#x?}, r = {r:#x?}\nnormals = {normals:#x?}"),
        );
    }
    println!("cull ray terms: {valid} valid inputs");
    eq.finish();
}

#[test]
fn dot3_floor_narrow_formats() {
    // (a format, b format, result format): the cull_ray products n·u and n·d
    let f32f = FloatFormat::BINARY32;
    let e8m18 = FloatFormat::new(8, 18).unwrap();
    let combos = [
        (FloatFormat::BINARY16, f32f, f32f),
        (FloatFormat::BINARY16, f32f, e8m18),
        (FloatFormat::BFLOAT16, f32f, f32f),
        (
            FloatFormat::new(5, 5).unwrap(),
            f32f,
            FloatFormat::new(8, 13).unwrap(),
        ),
        (f32f, f32f, f32f),
        (
            FloatFormat::new(11, 35).unwrap(),
            f32f,
            FloatFormat::BINARY64,
        ),
    ];
    let mut rng = common::Rng::new(70);
    let mut eq = Equal::new("dot3_floor (e5m10|e8m7|e5m5|e8m23|e11m35 x e8m23)");
    for i in 0..cases() {
        let (fa, fb, to) = combos[(i % combos.len() as u64) as usize];
        let (sa, sb) = (specials(fa), specials(fb));
        let a = [0; 3].map(|_| operand(&mut rng, fa, &sa));
        let mut b = [0; 3].map(|_| operand(&mut rng, fb, &sb));
        if rng.below(3) == 0 {
            // products of one magnitude: cancellation between the terms
            b[1] = operand_near(&mut rng, fb, b[0], 2);
            b[2] = operand_near(&mut rng, fb, b[0], 40);
        }
        eq.check(
            dot3_floor(fa, fb, to, a, b),
            dot3_floor_generic(fa, fb, to, a, b),
            || format!("{fa} {fb} -> {to}: a = {a:#x?}, b = {b:#x?}"),
        );
    }
    eq.finish();
}

#[test]
fn recip_every_mode() {
    let fmts = [
        FloatFormat::BINARY32,
        FloatFormat::new(8, 18).unwrap(),
        FloatFormat::BINARY16,
        FloatFormat::new(8, 26).unwrap(),
        FloatFormat::new(11, 29).unwrap(),
    ];
    let mut rng = common::Rng::new(80);
    let mut eq = Equal::new("recip (e8m23, e8m18, e5m10, e8m26, e11m29; 4 modes)");
    for i in 0..cases() {
        let f = fmts[(i % fmts.len() as u64) as usize];
        let mode = RoundingMode::ALL[(i / fmts.len() as u64 % 4) as usize];
        let x = operand(&mut rng, f, &specials(f));
        eq.check(recip(f, x, mode), recip_generic(f, x, mode), || {
            format!("{f} {mode:?}: x = {x:#x}")
        });
    }
    eq.finish();
}

/// `native::round_exact_f64_down_up` (the cull tester's `1/|b|` bounds)
/// against the generic conversion from binary64 rounded down and up, on
/// values of both signs (its caller passes only non-negative ones): random
/// `f64` across binary32's exponent range and beyond it (subnormal,
/// overflowing), values on the target grid (exact: down = up), and specials.
#[test]
fn round_exact_f64_down_up_both_signs() {
    use golden_model::float::{convert, native::round_exact_f64_down_up, native::to_f32};
    let f64f = FloatFormat::BINARY64;
    let fmts = [
        FloatFormat::BINARY32,
        FloatFormat::new(8, 18).unwrap(),
        FloatFormat::new(8, 7).unwrap(),
    ];
    let mut rng = common::Rng::new(95);
    let mut eq = Equal::new("round_exact_f64_down_up (e8m23, e8m18, e8m7; both signs)");
    let f64_specials = specials(f64f);
    for i in 0..cases() {
        let to = fmts[(i % fmts.len() as u64) as usize];
        let bits = match rng.below(8) {
            // on the grid of `to` (exactly representable)
            0 => {
                let x = to_f32(to, operand(&mut rng, to, &specials(to))) as f64;
                x.to_bits()
            }
            1 => f64_specials[rng.below(f64_specials.len() as u64) as usize],
            // binary32's exponents -149 ..= 127 and a margin on each side
            _ => {
                let e = rng.range(-170, 140);
                (rng.next() & (1 << 63)) | ((1023 + e) as u64) << 52 | (rng.next() >> 12)
            }
        };
        let want = (
            convert(f64f, to, bits, RoundingMode::Down),
            convert(f64f, to, bits, RoundingMode::Up),
        );
        eq.check(
            round_exact_f64_down_up(to, f64::from_bits(bits)),
            want,
            || format!("{to}: v = {:e} ({bits:#018x})", f64::from_bits(bits)),
        );
    }
    eq.finish();
}

#[test]
fn to_f32_every_pattern_of_small_formats() {
    use golden_model::float::{convert, native::to_f32};
    let f32f = FloatFormat::BINARY32;
    let mut eq = Equal::new(
        "native::to_f32 (every pattern of e5m10, e8m7, e4m3, e2m1, e6m9; e8m18 sampled)",
    );
    let mut one = |f: FloatFormat, x: u64| {
        // the generic widening conversion is exact; NaN compared as NaN
        let want = convert(f, f32f, x, RoundingMode::NearestEven);
        let got = to_f32(f, x);
        let got = if got.is_nan() {
            f32f.canonical_nan()
        } else {
            got.to_bits() as u64
        };
        eq.check(got, want, || format!("{f}: {x:#x}"));
    };
    for f in [
        FloatFormat::BINARY16,
        FloatFormat::BFLOAT16,
        FloatFormat::new(4, 3).unwrap(),
        FloatFormat::new(2, 1).unwrap(),
        FloatFormat::new(6, 9).unwrap(),
    ] {
        for x in 0..=f.mask() {
            one(f, x);
        }
    }
    let e8m18 = FloatFormat::new(8, 18).unwrap();
    let mut rng = common::Rng::new(90);
    for _ in 0..cases() {
        one(e8m18, rng.next() & e8m18.mask());
    }
    eq.finish();
}
