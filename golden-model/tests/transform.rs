//! The two-step inverse transform model (issue #5): the seed's matrices, the
//! exact invariants, the hardware inversion, and the accuracy study's
//! qualitative result.

use golden_model::float::to_f64;
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::transform::accuracy::{self, forward, Rng, StudyOptions, SEED_MATRICES};
use golden_model::transform::exact::{
    exact_inverse, inverse_entries, scene_builder_inverse, scene_builder_translation,
};
use golden_model::transform::{
    invert_hw, transform, Config, DotStyle, InstanceTransform, InverseSource, WorldRay,
};

const F: FloatFormat = FloatFormat::BINARY32;
const RNE: RoundingMode = RoundingMode::NearestEven;

fn b(x: f32) -> u64 {
    x.to_bits() as u64
}

fn v(x: u64) -> f64 {
    to_f64(F, x)
}

fn configs() -> Vec<Config> {
    let mut v = Vec::new();
    for dot in DotStyle::ALL {
        for source in [InverseSource::PreInverted, InverseSource::Hardware] {
            for mode in RoundingMode::ALL {
                v.push(Config {
                    fmt: F,
                    mode,
                    dot,
                    source,
                });
            }
        }
    }
    v
}

/// The linear input of `cfg` for forward `R`: `R` itself or the scene builder's `R⁻¹`.
fn linear_for(cfg: &Config, r: &[u64; 9]) -> [u64; 9] {
    match cfg.source {
        InverseSource::PreInverted => scene_builder_inverse(F, cfg.mode, r),
        InverseSource::Hardware => *r,
    }
}

fn random_instance(rng: &mut Rng) -> ([u64; 9], [u64; 3]) {
    forward(F, &accuracy::random_placement(rng))
}

fn random_vec(rng: &mut Rng, scale: f64) -> [u64; 3] {
    [(); 3].map(|_| accuracy::from_f64(F, rng.range(-scale, scale)))
}

#[test]
fn seed_m1_m2_inverses_match_the_printed_ones_with_the_two_slips_corrected() {
    // M1 as printed, with (1,0) = -0.019545 (printed -0.195445) and
    // (2,1) = -0.285363 (printed -0.28563); M2 as printed.
    let printed: [([f64; 9], [f64; 3]); 2] = [
        (
            [
                -0.100236, -0.368108, 0.530048, -0.019545, -0.580572, -0.464163, 0.169065,
                -0.285363, 0.260598,
            ],
            [-27011.443359, 22165.703125, -12035.484375],
        ),
        (
            [
                -0.663388, 0.67967, 0.094999, -0.343143, -1.367923, -0.126506, 0.039085, -0.473567,
                0.501764,
            ],
            [5.32914, -2.884673, 22.876669],
        ),
    ];
    for ((name, p), (inv_p, u_p)) in SEED_MATRICES.iter().zip(printed) {
        let (r, t) = forward(F, p);
        let exact = exact_inverse(F, &r).expect("nonsingular");
        let inv = inverse_entries(F, RNE, &exact);
        for k in 0..9 {
            assert!(
                (v(inv[k]) - inv_p[k]).abs() < 2e-6,
                "{name} entry {k}: {} vs printed {}",
                v(inv[k]),
                inv_p[k]
            );
        }
        let u = scene_builder_translation(F, RNE, &exact, t).unwrap();
        for k in 0..3 {
            // the printed column was computed in single precision
            let tol = 1e-6 * u_p[k].abs() + 1e-2;
            assert!(
                (v(u[k]) - u_p[k]).abs() < tol,
                "{name} u[{k}]: {} vs printed {}",
                v(u[k]),
                u_p[k]
            );
        }
    }
}

#[test]
fn origin_at_t_maps_to_zero_in_every_configuration() {
    let mut rng = Rng::new(11);
    for cfg in configs() {
        for _ in 0..200 {
            let (r, t) = random_instance(&mut rng);
            let inst = InstanceTransform {
                linear: linear_for(&cfg, &r),
                translation: t,
                rotation_hint: false,
            };
            let ray = WorldRay {
                origin: t,
                dir: random_vec(&mut rng, 10.0),
                t_min: b(0.0),
                t_max: b(1e30),
                id: 3,
            };
            let m = transform(&cfg, &ray, &inst);
            assert!(!m.singular);
            assert!(
                m.origin.iter().all(|&x| v(x) == 0.0),
                "{cfg:?}: {:x?}",
                m.origin
            );
        }
    }
}

#[test]
fn direction_does_not_depend_on_t_and_t_id_pass_through() {
    let mut rng = Rng::new(12);
    for cfg in configs() {
        for _ in 0..200 {
            let (r, t) = random_instance(&mut rng);
            let t2 = random_vec(&mut rng, 1e6);
            let lin = linear_for(&cfg, &r);
            let ray = WorldRay {
                origin: random_vec(&mut rng, 1e5),
                dir: random_vec(&mut rng, 1.0),
                t_min: rng.next_u64() & 0xffff_ffff,
                t_max: rng.next_u64() & 0xffff_ffff,
                id: rng.next_u64(),
            };
            let a = transform(
                &cfg,
                &ray,
                &InstanceTransform {
                    linear: lin,
                    translation: t,
                    rotation_hint: false,
                },
            );
            let c = transform(
                &cfg,
                &ray,
                &InstanceTransform {
                    linear: lin,
                    translation: t2,
                    rotation_hint: false,
                },
            );
            assert_eq!(a.dir, c.dir);
            assert_eq!((a.t_min, a.t_max, a.id), (ray.t_min, ray.t_max, ray.id));
        }
    }
}

#[test]
fn identity_gives_the_rounded_difference() {
    let one = b(1.0);
    let id = [one, 0, 0, 0, one, 0, 0, 0, one];
    let mut rng = Rng::new(13);
    for cfg in configs() {
        for _ in 0..300 {
            let t = random_vec(&mut rng, 1e6);
            let o = random_vec(&mut rng, 1e6);
            let m = transform(
                &cfg,
                &WorldRay {
                    origin: o,
                    dir: o,
                    t_min: 0,
                    t_max: 0,
                    id: 0,
                },
                &InstanceTransform {
                    linear: id,
                    translation: t,
                    rotation_hint: false,
                },
            );
            for k in 0..3 {
                let want = golden_model::float::sub(F, o[k], t[k], cfg.mode);
                assert_eq!(m.origin[k], want, "{cfg:?}");
                assert_eq!(m.dir[k], o[k], "{cfg:?}");
            }
        }
    }
}

#[test]
fn singular_and_non_finite_transforms_raise_the_flag_and_give_nan() {
    let one = b(1.0);
    let sing = [one, b(2.0), b(3.0), b(2.0), b(4.0), b(6.0), 0, 0, one];
    let ok = [one, 0, 0, 0, one, 0, 0, 0, one];
    let ray = WorldRay {
        origin: [b(1.0); 3],
        dir: [b(1.0); 3],
        t_min: b(0.5),
        t_max: b(2.0),
        id: 9,
    };
    for cfg in configs() {
        let mut cases = vec![
            (ok, [b(0.0), b(f32::INFINITY), b(0.0)]),
            (ok, [b(f32::NAN), b(0.0), b(0.0)]),
        ];
        let mut bad = ok;
        bad[4] = b(f32::NEG_INFINITY);
        cases.push((bad, [0; 3]));
        if cfg.source == InverseSource::Hardware {
            cases.push((sing, [0; 3]));
            // det = 1e-45² · … underflows to zero
            let tiny = b(1e-30);
            cases.push(([tiny, 0, 0, 0, tiny, 0, 0, 0, tiny], [0; 3]));
        } else {
            cases.push((scene_builder_inverse(F, cfg.mode, &sing), [0; 3]));
        }
        for (lin, t) in cases {
            let m = transform(
                &cfg,
                &ray,
                &InstanceTransform {
                    linear: lin,
                    translation: t,
                    rotation_hint: false,
                },
            );
            assert!(m.singular, "{cfg:?} {lin:x?} {t:x?}");
            assert_eq!(m.origin, [F.canonical_nan(); 3]);
            assert_eq!(m.dir, [F.canonical_nan(); 3]);
            assert_eq!((m.t_min, m.t_max, m.id), (b(0.5), b(2.0), 9));
        }
    }
}

/// A determinant that overflows to ∞ while every cofactor is finite: 1/det
/// rounds to 0, so every entry of the inverse is a finite 0 and only the
/// determinant's class says the matrix cannot be inverted.
#[test]
fn an_overflowing_determinant_is_singular_though_the_inverse_is_finite() {
    let big = b(2f32.powi(43));
    let r = [big, 0, 0, 0, big, 0, 0, 0, big];
    for dot in DotStyle::ALL {
        let h = invert_hw(F, RNE, dot, &r, false);
        assert_eq!(h.det, b(f32::INFINITY), "{dot:?}");
        assert!(
            h.inv.iter().all(|&x| F.is_finite(x)),
            "{dot:?} {:x?}",
            h.inv
        );
        assert!(h.singular, "{dot:?}");
    }
}

#[test]
fn hardware_inverse_is_within_a_few_ulps_of_the_exact_one_when_well_conditioned() {
    // TRANSFORM_CASES: cases over all dot styles (scripts/release.sh: 10^7)
    let total: usize = std::env::var("TRANSFORM_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000 * DotStyle::ALL.len());
    let per_style = total.div_ceil(DotStyle::ALL.len());
    let mut rng = Rng::new(14);
    for dot in DotStyle::ALL {
        let mut worst = 0.0f64;
        for _ in 0..per_style {
            let mut p = accuracy::random_placement(&mut rng);
            p.scale = p.scale.map(|s| s.signum() * s.abs().clamp(0.5, 2.0));
            let (r, _) = forward(F, &p);
            let h = invert_hw(F, RNE, dot, &r, false);
            assert!(!h.singular);
            let exact = scene_builder_inverse(F, RNE, &r);
            let norm = exact.iter().map(|&x| v(x).abs()).fold(0.0, f64::max);
            for (&got, &want) in h.inv.iter().zip(&exact) {
                let err = (v(got) - v(want)).abs() / (norm * f32::EPSILON as f64);
                worst = worst.max(err);
            }
        }
        // a handful of roundings on well-conditioned matrices
        println!("{dot:?}: {per_style} matrices against the exact inverse, worst {worst:.2} ulps of the largest entry");
        assert!(worst < 16.0, "{dot:?}: {worst} ulps of the largest entry");
    }
}

/// Diagonal matrices whose inversion overflows in the directed modes, where
/// the overflow rounds to ±max finite and no ±∞ appears: flagged in every mode
/// and style. binary32 ±2^43·I (`det` 2^129), 2^-45·I (`det` 2^-135 is exact,
/// `1/det` overflows), binary16 48·I (`det` 110,592 > 65,504).
#[test]
fn an_overflow_is_flagged_in_every_rounding_mode() {
    let h16 = FloatFormat::BINARY16;
    let diag = |x: u64| [x, 0, 0, 0, x, 0, 0, 0, x];
    let cases = [
        (F, diag(b(2f32.powi(43)))),
        (F, diag(b(-(2f32.powi(43))))),
        (F, diag(b(2f32.powi(-45)))),
        (h16, diag(0x5200)), // 48
    ];
    for (fmt, r) in cases {
        for mode in RoundingMode::ALL {
            for dot in DotStyle::ALL {
                let h = invert_hw(fmt, mode, dot, &r, false);
                assert!(
                    h.singular,
                    "{fmt:?} {mode:?} {dot:?} {:#x}: det {:#x} recip {:#x} inv {:#x}",
                    r[0], h.det, h.recip, h.inv[0]
                );
            }
        }
    }
}

/// The hardware inverse over binary32's whole range, in every mode and style:
/// well-conditioned matrices (rotations, row scales 0.5 to 2) scaled by 2^k,
/// k from -60 to 60 (`det` overflows above about 2^42 and underflows below
/// about 2^-42): each inverse is flagged `singular` or within 16 ulps (of the
/// largest entry) of the exact inverse; and flagged from |k| = 45 on, where
/// `det` is beyond the format. The directed modes round an overflow to ±max finite, not ±∞: before
/// the flag read ±max finite, 2^43·I in `rtz` gave 2^-42 for 2^-43, unflagged.
#[test]
fn the_hardware_inverse_is_accurate_or_flagged_across_the_range_in_every_mode() {
    let mut rng = Rng::new(16);
    let placements: Vec<_> = (0..12)
        .map(|_| {
            let mut p = accuracy::random_placement(&mut rng);
            p.scale = p.scale.map(|s| s.signum() * s.abs().clamp(0.5, 2.0));
            forward(F, &p).0
        })
        .collect();
    let (mut flagged, mut accurate) = (0, 0);
    for mode in RoundingMode::ALL {
        for dot in DotStyle::ALL {
            for k in (-60..=60).step_by(3) {
                for r0 in &placements {
                    let r = r0.map(|x| b((v(x) * 2f64.powi(k)) as f32));
                    let h = invert_hw(F, mode, dot, &r, false);
                    let exact = scene_builder_inverse(F, RNE, &r);
                    if h.singular {
                        flagged += 1;
                        continue;
                    }
                    // |det| = 2^(3k) times 1/8 to 8: beyond binary32 from |k| = 45 on
                    assert!(
                        (-44..=44).contains(&k),
                        "{mode:?} {dot:?} 2^{k}: det {:#x} leaves the range unflagged",
                        h.det
                    );
                    let norm = exact.iter().map(|&x| v(x).abs()).fold(0.0, f64::max);
                    let ulp = norm * f32::EPSILON as f64;
                    for (&got, &want) in h.inv.iter().zip(&exact) {
                        let err = (v(got) - v(want)).abs() / ulp;
                        assert!(
                            err < 16.0,
                            "{mode:?} {dot:?} 2^{k}: {err:.1} ulps, got {got:#x} for {want:#x}, det {:#x}, recip {:#x}",
                            h.det,
                            h.recip
                        );
                    }
                    accurate += 1;
                }
            }
        }
    }
    println!("{accurate} accurate, {flagged} flagged");
    // the matrices inside the range are inverted: a flag everywhere is no answer
    assert!(accurate >= 4 * 4 * 12 * 26, "{accurate} accurate");
}

#[test]
fn rotation_hint_uses_the_transpose() {
    let mut rng = Rng::new(15);
    for _ in 0..100 {
        let mut p = accuracy::random_placement(&mut rng);
        p.scale = [1.0; 3];
        let (r, _) = forward(F, &p);
        let h = invert_hw(F, RNE, DotStyle::Fma, &r, true);
        assert!(!h.singular);
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(h.inv[3 * i + j], r[3 * j + i]);
            }
        }
        let full = invert_hw(F, RNE, DotStyle::Dot3, &r, false);
        for k in 0..9 {
            assert!((v(full.inv[k]) - v(h.inv[k])).abs() < 1e-6);
        }
    }
}

#[test]
fn accuracy_study_reproduces_the_seed_qualitatively() {
    let opts = StudyOptions {
        styles: DotStyle::ALL.to_vec(),
        points: 300,
        random_matrices: 60,
        random_points: 20,
        ..Default::default()
    };
    let rows = accuracy::run(&opts);
    assert_eq!(rows.len(), 4 * opts.offsets.len());
    for r in &rows {
        let c = &r.conventional;
        for t in &r.two_step {
            if r.offset == 0.0 {
                // exact zero for the two-step method, a nonzero error for the conventional one
                assert_eq!((t.max_abs, t.inexact), (0.0, 0), "{r:?}");
                assert!(c.med_abs > 0.0, "{r:?}");
            } else if r.offset <= 1e-1 {
                assert!(t.med_rel * 100.0 < c.med_rel, "{r:?}");
                assert!(t.max_rel < 4.0 * f32::EPSILON as f64, "{r:?}");
            } else if r.offset >= 1e5 {
                assert!(
                    t.max_rel < 8.0 * c.max_rel && c.max_rel < 8.0 * t.max_rel,
                    "{r:?}"
                );
            }
        }
    }
}

/// `dot=wide` (issue #16 §4): within half an ulp plus the widened format's
/// own rounding of the real `R⁻¹·(O − T)` for the stored `R⁻¹`, at every
/// offset from 1e-3 to 1e5 (at most 6e-8 relative at binary32); the fma
/// style is far from it (so a wide path that is not wide fails).
#[test]
fn wide_style_is_within_one_rounding_of_the_stored_inverse_product() {
    let opts = StudyOptions {
        styles: vec![DotStyle::Wide, DotStyle::Fma],
        points: 1_000,
        random_matrices: 200,
        random_points: 20,
        ..Default::default()
    };
    let rows = accuracy::run(&opts);
    let (mut wide_max, mut fma_max) = (0.0f64, 0.0f64);
    for r in rows.iter().filter(|r| r.offset >= 1e-3) {
        wide_max = wide_max.max(r.two_step[0].max_rel_stored);
        fma_max = fma_max.max(r.two_step[1].max_rel_stored);
        assert!(r.two_step[0].med_rel_stored < 3e-8, "{r:?}");
    }
    eprintln!(
        "relative error against the stored inverse: wide max {wide_max:.3e}, fma max {fma_max:.3e}"
    );
    assert!(wide_max <= 6e-8, "wide: {wide_max:.3e}");
    assert!(fma_max > 1e-7, "fma: {fma_max:.3e}");
}

/// The dot styles' parameter words (the `transform` unit's `dot=` values) and their
/// parse: each word names its style, and no other word (an empty one) names any.
#[test]
fn every_dot_style_has_its_word_and_parses_back() {
    let words: Vec<&str> = DotStyle::ALL.iter().map(|s| s.word()).collect();
    assert_eq!(words, ["separate", "fma", "dot3", "wide"]);
    for s in DotStyle::ALL {
        assert_eq!(DotStyle::parse(s.word()), Some(s), "{}", s.word());
    }
    assert_eq!(DotStyle::parse(""), None);
    assert_eq!(DotStyle::parse("FMA"), None);
}
