//! The triangle unit over its whole float range (issue #42): a ray from
//! `o = c + (3, 2, 2.5)·2^k` toward the centre `c` of a closed cube of
//! half-size `2^k` must hit exactly 2 of its 12 triangles, at `t = 2/3` and
//! `4/3`, for `k` from the bottom to the top of the format's normal range,
//! the cube offset from the origin by up to `2^20` times its size where the
//! format holds it, in every rounding mode, in binary32, e8m7 and e5m10.
//!
//! Reference: the exact rational test ([`exact::intersect`], big integers)
//! on the mesh as rounded to the format and on the ray the unit is given
//! (origin `o`, direction `(s_x, s_y, 1)` on the axes `(kx, ky, kz)`, its
//! parameter scaled by `s_z`): every triangle's hit must agree (0 holes, 0
//! wrong hits), the exact hits must be 2, and `t` within 4 ulps of the
//! exact `t`. `outputs=tnum` ([`eval_tnum`]) gives the same hits, and its
//! `t` finished in software ([`finish_t`]) is `outputs=full`'s bit for bit;
//! `segment=log` gives `outputs=tnum`'s answer.
//!
//! CI sweeps a few scales per format and mode (both ends of the range, 1,
//! and two between); `TRIANGLE_RANGE=full` sweeps every `k` (the release
//! run, `scripts/release.sh`).

use golden_model::float::{from_f64, to_f64, FloatFormat, RoundingMode};
use golden_model::triangle::{
    eval_tnum, eval_tnum_with, eval_with, exact, finish_t, shear, Segment, TriIn,
};

/// The offsets tried, in multiples of the cube's size (`2^j`), capped
/// where the format no longer holds the cube exactly.
const OFFSETS: [i32; 5] = [0, 1, 4, 10, 20];

/// One ray against the 12 triangles of one cube; returns (unit hits, the
/// largest `t` error in ulps of the format).
fn cube(fmt: FloatFormat, mode: RoundingMode, k: i32, j: Option<i32>) -> Option<(usize, f64)> {
    let h = 2f64.powi(k);
    // the centre, offset along a fixed direction (all of its coordinates
    // and the vertices' exact in the format, or the case is skipped)
    let c = j.map_or([0.0; 3], |j| {
        [0.75, -0.5, 0.25].map(|x| x * h * 2f64.powi(j))
    });
    let exact_in = |v: f64| {
        let b = from_f64(fmt, v);
        (fmt.is_finite(b) && to_f64(fmt, b) == v).then_some(b)
    };
    let mut verts = Vec::new();
    for i in 0..8 {
        let v: Option<Vec<u64>> = (0..3)
            .map(|a| exact_in(c[a] + h * if i >> a & 1 == 1 { 1.0 } else { -1.0 }))
            .collect();
        verts.push(<[u64; 3]>::try_from(v?).unwrap());
    }
    let o_f = [0, 1, 2].map(|a| c[a] + [3.0, 2.0, 2.5][a] * h);
    let o: Vec<u64> = o_f.iter().map(|&v| exact_in(v)).collect::<Option<_>>()?;
    let o: [u64; 3] = o.try_into().unwrap();
    let d: Vec<u64> = (0..3)
        .map(|a| exact_in(c[a] - o_f[a]))
        .collect::<Option<_>>()?;
    let (kz, s) = shear(fmt, d.try_into().unwrap());
    if !s.iter().all(|&x| fmt.is_finite(x)) {
        return None;
    }
    // the ray the unit tests: direction ±(s_x, s_y, 1) on (kx, ky, kz), so
    // that its parameter grows along the ray; t = that parameter · |s_z|
    let sz = to_f64(fmt, s[2]);
    let flip = |x: u64| if sz < 0.0 { fmt.negate(x) } else { x };
    let (kx, ky) = golden_model::triangle::other_axes(kz);
    let mut dir = [0u64; 3];
    dir[kx] = flip(s[0]);
    dir[ky] = flip(s[1]);
    dir[kz as usize] = flip(from_f64(fmt, 1.0));
    let quads = [
        [0, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ];
    let (mut hits, mut exact_hits, mut worst) = (0, 0, 0f64);
    for q in quads {
        for tri in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            let [a, b, cc] = tri.map(|i| verts[i]);
            let x = TriIn {
                o,
                kz,
                s,
                a,
                b,
                c: cc,
                t_min: fmt.zero(false),
                t_max: fmt.inf(false),
            };
            let got = eval_with(fmt, mode, &x);
            let want = exact::intersect(fmt, o, dir, [a, b, cc], fmt.zero(false), fmt.inf(false));
            let what = format!(
                "{fmt:?} {mode:?} k={k} offset={j:?}: o={o:#x?} s={s:#x?} kz={kz} tri={:#x?}",
                [a, b, cc]
            );
            assert!(!got.invalid, "flagged invalid: {what}");
            // outputs=tnum: the same hit, and t finished in software as full rounds it
            let num = eval_tnum(fmt, mode, &x);
            assert_eq!((num.hit, num.invalid), (got.hit, false), "tnum: {what}");
            // segment=log decides [0, inf) as the exact test does (t = 2/3, 4/3 is
            // far from the format's end), at every scale
            let log = eval_tnum_with(fmt, mode, Segment::Log, &x);
            assert_eq!(log, num, "tnum segment=log: {what}");
            if num.hit {
                assert_eq!(
                    finish_t(fmt, mode, num.t_num, num.t_den),
                    got.t,
                    "tnum t: {what}"
                );
            }
            assert_eq!(
                got.hit,
                want.is_some(),
                "unit hit {} exact hit {}: {what}",
                got.hit,
                want.is_some()
            );
            if let Some(w) = want {
                exact_hits += 1;
                hits += 1;
                let te = w.t_f64() * sz.abs();
                let tg = to_f64(fmt, got.t);
                assert!(tg.is_finite(), "t = {tg}: {what}");
                let ulp = 2f64.powi(te.log2().floor() as i32 - fmt.frac_bits() as i32);
                worst = worst.max((tg - te).abs() / ulp);
            }
        }
    }
    assert_eq!(
        exact_hits, 2,
        "{fmt:?} {mode:?} k={k} offset={j:?}: exact hits"
    );
    Some((hits, worst))
}

fn sweep(fmt: FloatFormat, full: bool) {
    let (lo, hi) = (fmt.emin() + 2, fmt.emax() - 3);
    let ks: Vec<i32> = if full {
        (lo..=hi).collect()
    } else {
        vec![lo, lo + (hi - lo) / 4, 0, hi - (hi - lo) / 4, hi]
    };
    for mode in RoundingMode::ALL {
        let (mut cases, mut worst) = (0u32, 0f64);
        for &k in &ks {
            for j in std::iter::once(None).chain(OFFSETS.map(Some)) {
                if let Some((hits, err)) = cube(fmt, mode, k, j) {
                    assert_eq!(hits, 2);
                    cases += 1;
                    worst = worst.max(err);
                }
            }
        }
        eprintln!(
            "{fmt:?} {mode:?}: k {lo}..={hi} ({} scales), {cases} cubes, 2 hits each, \
             worst t error {worst:.2} ulp",
            ks.len()
        );
        // every scale at least without an offset and centred at the origin
        assert!(cases as usize >= 2 * ks.len(), "{cases} cubes");
        assert!(worst <= 4.0, "{fmt:?} {mode:?}: t error {worst} ulp");
    }
}

fn full() -> bool {
    std::env::var("TRIANGLE_RANGE").is_ok_and(|v| v == "full")
}

#[test]
fn closed_cube_binary32_whole_range() {
    sweep(FloatFormat::BINARY32, full());
}

#[test]
fn closed_cube_e8m7_whole_range() {
    sweep(FloatFormat::BFLOAT16, full());
}

#[test]
fn closed_cube_e5m10_whole_range() {
    sweep(FloatFormat::BINARY16, full());
}

/// The issue's reproducer at 2^-76 (binary32 bits): 2 hits in every mode,
/// `t` finite.
#[test]
fn issue_42_reproducer() {
    let f = FloatFormat::BINARY32;
    for mode in RoundingMode::ALL {
        let (hits, err) = cube(f, mode, -76, None).expect("the cube fits binary32");
        assert_eq!(hits, 2);
        assert!(err <= 4.0);
    }
    // the issue's bits: o and s as stated there
    let (kz, s) = shear(f, [0x9a40_0000, 0x9a00_0000, 0x9a20_0000]);
    assert_eq!((kz, s), (0, [0x3f2a_aaab, 0x3f55_5555, 0xe4aa_aaab]));
}

/// Scale invariance, the whole range on random triangles: the ray and the
/// triangle scaled by `2^k` (every coordinate exactly, the shear constants
/// recomputed) give the same hit and the same `t`, `u`, `v` bit for bit as
/// at scale 1, since nothing overflows or underflows in the internal
/// format: the differences, edge functions, `det` and `T` scale by powers
/// of two and `t` does not. Binary32, every mode, `k` near both ends.
#[test]
fn random_triangles_scale_exactly_across_the_range() {
    use golden_model::float::FloatFormat as F;
    let fmt = F::BINARY32;
    let mut state = 0x42u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    for mode in RoundingMode::ALL {
        let (mut compared, mut hits) = (0u32, 0u32);
        for _ in 0..5_000 {
            let tri: [[f64; 3]; 3] =
                [0; 3].map(|_| [0; 3].map(|_| (2.0 * next() - 1.0) as f32 as f64));
            let o: [f64; 3] = [0; 3].map(|_| ((2.0 * next() - 1.0) * 6.0) as f32 as f64);
            let (b1, b2) = (next() * 1.4 - 0.2, next() * 1.4 - 0.2);
            let d: [f64; 3] = [0, 1, 2].map(|i| {
                let aim = tri[0][i] + b1 * (tri[1][i] - tri[0][i]) + b2 * (tri[2][i] - tri[0][i]);
                (aim - o[i]) as f32 as f64
            });
            let at = |k: i32| -> Option<TriIn> {
                let s = 2f64.powi(k);
                let q = |v: f64| {
                    let b = from_f64(fmt, v * s);
                    // the scaled value must be exact (normal, or zero)
                    (to_f64(fmt, b) == v * s && (v == 0.0 || (v * s).abs() >= 2f64.powi(-126)))
                        .then_some(b)
                };
                let v3 = |p: [f64; 3]| -> Option<[u64; 3]> { Some([q(p[0])?, q(p[1])?, q(p[2])?]) };
                let (kz, sh) = shear(fmt, v3(d)?);
                Some(TriIn {
                    o: v3(o)?,
                    kz,
                    s: sh,
                    a: v3(tri[0])?,
                    b: v3(tri[1])?,
                    c: v3(tri[2])?,
                    t_min: fmt.zero(false),
                    t_max: fmt.inf(false),
                })
            };
            let Some(base) = at(0) else { continue };
            let want = eval_with(fmt, mode, &base);
            for k in [-110, -60, 60, 110] {
                let Some(x) = at(k) else { continue };
                // s_z = 1/d_kz must stay normal for t to scale exactly
                if to_f64(fmt, x.s[2]).abs() < 2f64.powi(-126) {
                    continue;
                }
                let got = eval_with(fmt, mode, &x);
                assert_eq!(got, want, "{mode:?} k={k}: {x:?} against {base:?}");
                compared += 1;
                hits += got.hit as u32;
            }
        }
        eprintln!("{mode:?}: {compared} scaled rays, {hits} hits, all bit-identical to scale 1");
        assert!(
            compared > 10_000 && hits > 2_000,
            "{compared} compared, {hits} hits"
        );
    }
}
