//! Exhaustive checks on small formats against the exact oracle (and, as a
//! check of the oracle itself, against rustc_apfloat):
//! * (4,3): all 65,536 pairs × 4 modes for add, sub, mul, add_down_up;
//!   all pairs for lt/le/eq/min/max and mul_exact (into (6,7));
//! * (3,2): all 262,144 triples × 4 modes for fma; smaller formats: all
//!   pairs (add, sub, mul), all fma triples, all dot3 product triples;
//! * conversions of every value of (4,3), (5,10) and (8,7) into several
//!   formats, 4 modes.

mod common;

use common::exact::{self, V};
use common::{apfloat as ap, mode_name, Tally};
use golden_model::float::{self as fp, ExactProductFormat, FloatFormat, RoundingMode};
use std::cmp::Ordering;

fn fmt(e: u32, f: u32) -> FloatFormat {
    FloatFormat::new(e, f).unwrap()
}

fn all(f: FloatFormat) -> impl Iterator<Item = u64> + Clone {
    0..=f.mask()
}

/// Our result must equal the exact oracle's; the exact oracle must agree
/// with apfloat (NaN: any NaN there, canonical here).
fn agree(f: FloatFormat, ours: u64, exact: u64, apfloat: Option<u64>) -> bool {
    let oracles_agree = match apfloat {
        Some(o) if f.is_nan(o) => exact == f.canonical_nan(),
        Some(o) => exact == o,
        None => true,
    };
    ours == exact && oracles_agree
}

#[test]
fn e4m3_add_sub_mul_all_pairs_all_modes() {
    let f = fmt(4, 3);
    for mode in RoundingMode::ALL {
        let m = mode_name(mode);
        let mut t_add = Tally::new(format!("{f} add {m}, all pairs"));
        let mut t_sub = Tally::new(format!("{f} sub {m}, all pairs"));
        let mut t_mul = Tally::new(format!("{f} mul {m}, all pairs"));
        for a in all(f) {
            let va = exact::decode(f, a);
            for b in all(f) {
                let vb = exact::decode(f, b);
                let neg_b = exact::decode(f, b ^ f.sign_bit());
                let want = exact::round(f, &exact::sum(&[va.clone(), vb.clone()], mode), mode);
                let ours = fp::add(f, a, b, mode);
                t_add.check(agree(f, ours, want, Some(ap::add(f, a, b, mode))), || {
                    format!("add({a:#x}, {b:#x}) = {ours:#x}, exact {want:#x}")
                });
                let want = exact::round(f, &exact::sum(&[va.clone(), neg_b], mode), mode);
                let ours = fp::sub(f, a, b, mode);
                t_sub.check(agree(f, ours, want, Some(ap::sub(f, a, b, mode))), || {
                    format!("sub({a:#x}, {b:#x}) = {ours:#x}, exact {want:#x}")
                });
                let want = exact::round(f, &exact::mul(&va, &vb), mode);
                let ours = fp::mul(f, a, b, mode);
                t_mul.check(agree(f, ours, want, Some(ap::mul(f, a, b, mode))), || {
                    format!("mul({a:#x}, {b:#x}) = {ours:#x}, exact {want:#x}")
                });
            }
        }
        t_add.finish();
        t_sub.finish();
        t_mul.finish();
    }
}

#[test]
fn e4m3_add_down_up_all_pairs() {
    let f = fmt(4, 3);
    let mut t = Tally::new(format!("{f} add_down_up, all pairs"));
    for a in all(f) {
        for b in all(f) {
            let terms = [exact::decode(f, a), exact::decode(f, b)];
            let dn = exact::round(
                f,
                &exact::sum(&terms, RoundingMode::Down),
                RoundingMode::Down,
            );
            let up = exact::round(f, &exact::sum(&terms, RoundingMode::Up), RoundingMode::Up);
            let r = fp::add_down_up(f, a, b);
            t.check((r.down, r.up) == (dn, up), || {
                format!("add_down_up({a:#x}, {b:#x}) = {r:x?}, exact ({dn:#x}, {up:#x})")
            });
        }
    }
    t.finish();
}

#[test]
fn e4m3_compare_min_max_mul_exact_all_pairs() {
    let f = fmt(4, 3);
    let p = ExactProductFormat::new(f).unwrap();
    let w = p.wide();
    assert_eq!((w.exp_bits(), w.frac_bits()), (6, 7));
    let mut t_cmp = Tally::new(format!("{f} lt/le/eq/min/max, all pairs"));
    let mut t_mx = Tally::new(format!("{f} mul_exact into {w}, all pairs"));
    let mut products = Vec::new();
    for a in all(f) {
        for b in all(f) {
            let (va, vb) = (exact::decode(f, a), exact::decode(f, b));
            let ord = exact::cmp(&va, &vb);
            let want = (
                ord == Some(Ordering::Less),
                matches!(ord, Some(Ordering::Less | Ordering::Equal)),
                ord == Some(Ordering::Equal),
            );
            let got = (fp::lt(f, a, b), fp::le(f, a, b), fp::eq(f, a, b));
            let smaller_first = match ord {
                None => None,
                Some(Ordering::Equal) => Some(a & f.sign_bit() != 0),
                Some(o) => Some(o == Ordering::Less),
            };
            let want_mm = match smaller_first {
                None => (f.canonical_nan(), f.canonical_nan()),
                Some(true) => (a, b),
                Some(false) => (b, a),
            };
            let got_mm = (fp::min(f, a, b), fp::max(f, a, b));
            t_cmp.check(got == want && got_mm == want_mm, || {
                format!("({a:#x}, {b:#x}): {got:?} {got_mm:x?}, want {want:?} {want_mm:x?}")
            });

            let prod = fp::mul_exact(p, a, b);
            let exact_prod = exact::mul(&va, &vb);
            // Exact: rounding the exact product into the wide format in any
            // mode gives the same bits, and those bits decode to the product.
            let ok = RoundingMode::ALL
                .iter()
                .all(|&m| exact::round(w, &exact_prod, m) == prod)
                && match (&exact_prod, exact::decode(w, prod)) {
                    (V::NaN, _) => prod == w.canonical_nan(),
                    (
                        V::Fin { mag, exp, neg },
                        V::Fin {
                            mag: m2,
                            exp: e2,
                            neg: n2,
                        },
                    ) => *neg == n2 && exact::cmp_mag(mag, *exp, &m2, e2) == Ordering::Equal,
                    (x, y) => *x == y,
                };
            t_mx.check(ok, || {
                format!("mul_exact({a:#x}, {b:#x}) = {prod:#x}, exact {exact_prod:?}")
            });
            if a % 7 == 0 && b % 5 == 0 {
                products.push(prod);
            }
        }
    }
    // Comparing exact products = comparing in the wide format.
    for (i, &x) in products.iter().enumerate() {
        for &y in products.iter().skip(i % 3).step_by(17) {
            let ord = exact::cmp(&exact::decode(w, x), &exact::decode(w, y));
            t_cmp.check(fp::lt(w, x, y) == (ord == Some(Ordering::Less)), || {
                format!("wide lt({x:#x}, {y:#x})")
            });
        }
    }
    t_cmp.finish();
    t_mx.finish();
}

#[test]
fn e3m2_fma_all_triples_all_modes() {
    let f = fmt(3, 2);
    for mode in RoundingMode::ALL {
        let mut t = Tally::new(format!("{f} fma {}, all triples", mode_name(mode)));
        for a in all(f) {
            for b in all(f) {
                let prod = exact::mul(&exact::decode(f, a), &exact::decode(f, b));
                for c in all(f) {
                    let want = exact::round(
                        f,
                        &exact::sum(&[prod.clone(), exact::decode(f, c)], mode),
                        mode,
                    );
                    let ours = fp::fma(f, a, b, c, mode);
                    t.check(
                        agree(f, ours, want, Some(ap::fma(f, a, b, c, mode))),
                        || format!("fma({a:#x}, {b:#x}, {c:#x}) = {ours:#x}, exact {want:#x}"),
                    );
                }
            }
        }
        t.finish();
    }
}

#[test]
fn conversions_of_every_value() {
    let cases = [
        (
            fmt(4, 3),
            vec![fmt(3, 2), fmt(5, 10), fmt(8, 7), fmt(11, 52), fmt(6, 9)],
        ),
        (
            fmt(5, 10),
            vec![fmt(4, 3), fmt(8, 7), fmt(3, 2), fmt(6, 9), fmt(8, 23)],
        ),
        (
            fmt(8, 7),
            vec![fmt(5, 10), fmt(4, 3), fmt(6, 9), fmt(8, 23)],
        ),
    ];
    for (from, tos) in cases {
        for to in tos {
            for mode in RoundingMode::ALL {
                let mut t = Tally::new(format!(
                    "convert {from} -> {to} {}, every value",
                    mode_name(mode)
                ));
                for x in all(from) {
                    let want = exact::round(to, &exact::decode(from, x), mode);
                    let ours = fp::convert(from, to, x, mode);
                    t.check(
                        agree(to, ours, want, Some(ap::convert(from, to, x, mode))),
                        || format!("convert({x:#x}) = {ours:#x}, exact {want:#x}"),
                    );
                }
                t.finish();
            }
        }
    }
}

/// dot3 depends on its operands only through the three products, so taking
/// one operand pair per distinct product (value, zero sign, inf sign, NaN)
/// and every ordered triple of those covers every case of a tiny format.
#[test]
fn tiny_formats_dot3_all_product_triples_all_modes() {
    for f in [fmt(2, 1), fmt(2, 2), fmt(3, 1)] {
        let mut reps: Vec<(u64, u64, V)> = Vec::new();
        for a in all(f) {
            for b in all(f) {
                let p = exact::mul(&exact::decode(f, a), &exact::decode(f, b));
                let seen = reps.iter().any(|(_, _, q)| match (q, &p) {
                    (
                        V::Fin {
                            neg: n1,
                            mag: m1,
                            exp: e1,
                        },
                        V::Fin {
                            neg: n2,
                            mag: m2,
                            exp: e2,
                        },
                    ) => n1 == n2 && exact::cmp_mag(m1, *e1, m2, *e2) == Ordering::Equal,
                    (q, p) => q == p,
                });
                if !seen {
                    reps.push((a, b, p));
                }
            }
        }
        for mode in RoundingMode::ALL {
            let mut t = Tally::new(format!(
                "{f} dot3 {}, all triples of the {} distinct products",
                mode_name(mode),
                reps.len()
            ));
            for r0 in &reps {
                for r1 in &reps {
                    for r2 in &reps {
                        let terms = [r0.2.clone(), r1.2.clone(), r2.2.clone()];
                        let want = exact::round(f, &exact::sum(&terms, mode), mode);
                        let (a, b) = ([r0.0, r1.0, r2.0], [r0.1, r1.1, r2.1]);
                        let ours = fp::dot3(f, a, b, mode);
                        t.check(ours == want, || {
                            format!("dot3({a:x?}, {b:x?}) = {ours:#x}, exact {want:#x}")
                        });
                    }
                }
            }
            t.finish();
        }
    }
}

/// All pairs of a few more tiny formats (E = 2 and 3, F = 1..5) for add,
/// sub, mul, and all triples for fma, every mode.
#[test]
fn tiny_formats_all_pairs_all_modes() {
    for f in [fmt(2, 1), fmt(2, 3), fmt(3, 1), fmt(2, 5), fmt(3, 4)] {
        for mode in RoundingMode::ALL {
            let mut t = Tally::new(format!("{f} add/sub/mul {}, all pairs", mode_name(mode)));
            for a in all(f) {
                for b in all(f) {
                    let (va, vb) = (exact::decode(f, a), exact::decode(f, b));
                    let nb = exact::decode(f, b ^ f.sign_bit());
                    let want = [
                        exact::round(f, &exact::sum(&[va.clone(), vb.clone()], mode), mode),
                        exact::round(f, &exact::sum(&[va.clone(), nb], mode), mode),
                        exact::round(f, &exact::mul(&va, &vb), mode),
                    ];
                    let ours = [
                        fp::add(f, a, b, mode),
                        fp::sub(f, a, b, mode),
                        fp::mul(f, a, b, mode),
                    ];
                    t.check(ours == want, || {
                        format!("({a:#x}, {b:#x}): ours {ours:x?}, exact {want:x?}")
                    });
                }
            }
            t.finish();
            if f.width() <= 5 {
                let mut t = Tally::new(format!("{f} fma {}, all triples", mode_name(mode)));
                for a in all(f) {
                    for b in all(f) {
                        let p = exact::mul(&exact::decode(f, a), &exact::decode(f, b));
                        for c in all(f) {
                            let want = exact::round(
                                f,
                                &exact::sum(&[p.clone(), exact::decode(f, c)], mode),
                                mode,
                            );
                            let ours = fp::fma(f, a, b, c, mode);
                            t.check(ours == want, || {
                                format!("fma({a:#x}, {b:#x}, {c:#x}) = {ours:#x}, exact {want:#x}")
                            });
                        }
                    }
                }
                t.finish();
            }
        }
    }
}
