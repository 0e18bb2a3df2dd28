//! The cull tester against the exact reference (issues #6, #13): zero
//! wrongful culls on random and adversarial cases in several ray / plane
//! formats. The tester is the composition the hardware performs: the
//! conservative slab gives the box interval, `ray_terms` (unit `cull_ray`)
//! the parent's per-normal terms, `eval` (unit `cull`) the verdict.
//!
//! Default run: 1,200,000 cases. `CULL_CASES=N` sets the count; the
//! 10,000,000 run (results in `docs/cull.md`):
//! `CULL_CASES=10000000 cargo test --release -p golden-model --test cull_props -- --nocapture`.
//!
//! A wrongful cull is a case where the slab reports a miss while the exact
//! segment meets the closed box, or `keep = 0` while it meets the box
//! intersected with every plane's closed non-empty side.

use golden_model::cull::exact::{region_hit, Dyadic, RegionIn};
use golden_model::cull::tester::{
    box_interval, eval, ray_terms, slab_reciprocal, ChildIn, Config, CullOut, RayIn,
};
use golden_model::float::{add, nudge, ordered, sub, to_f64, FloatFormat, RoundingMode};

const RNE: RoundingMode = RoundingMode::NearestEven;

mod silhouette_gen;
use silhouette_gen::{between, Random, Rng};

use golden_model::float::from_f64;

fn rand_val(fmt: FloatFormat, rng: &mut Rng, scale: i32, spread: i32) -> u64 {
    if rng.chance(1, 30) {
        return fmt.zero(rng.chance(1, 2));
    }
    let k = scale + rng.range(-(spread as i64), spread as i64) as i32;
    let v = (1.0 + rng.unit()) * 2f64.powi(k.clamp(-1070, 1020));
    let r = from_f64(fmt, if rng.chance(1, 2) { -v } else { v });
    if r & !fmt.sign_bit() == fmt.inf(false) {
        fmt.max_finite(r & fmt.sign_bit() != 0)
    } else {
        r
    }
}

fn rand_scale(fmt: FloatFormat, rng: &mut Rng) -> i32 {
    match rng.below(12) {
        0 => fmt.emax() - rng.range(0, 3) as i32,
        1 => fmt.emin() - fmt.frac_bits() as i32 + rng.range(0, 6) as i32,
        2 => fmt.emin() + rng.range(-2, 4) as i32,
        _ => rng.range(-5, 5) as i32,
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// everything random
    Random,
    /// planes fitted tightly around random points in the box; rays aimed at
    /// a support point of a plane, then nudged
    Fitted,
    /// the ray parallel to a plane (n·d = 0 exactly), origin on / near it
    Parallel,
    /// the origin on a plane or inside the box
    OriginOnPlane,
    /// NaN / inf / negative t_min / inverted boxes and segments
    Specials,
}

const KINDS: [Kind; 5] = [
    Kind::Random,
    Kind::Fitted,
    Kind::Parallel,
    Kind::OriginOnPlane,
    Kind::Specials,
];

/// A normal in the plane format: random, axis-like or diagonal.
fn rand_normal(pf: FloatFormat, rng: &mut Rng) -> [u64; 3] {
    let mut n = [0.0f64; 3];
    match rng.below(4) {
        0 => {
            for c in n.iter_mut() {
                *c = [-1.0, 0.0, 1.0][rng.below(3) as usize];
            }
        }
        _ => {
            for c in n.iter_mut() {
                *c = 2.0 * rng.unit() - 1.0;
                if rng.chance(1, 8) {
                    *c = 0.0;
                }
            }
        }
    }
    if rng.chance(1, 6) {
        let s = 2f64.powi(rng.range(-6, 6) as i32);
        n = n.map(|c| c * s);
    }
    n.map(|c| finite(pf, from_f64(pf, c)))
}

/// `v` with an infinity replaced by the largest finite value of its sign.
fn finite(fmt: FloatFormat, v: u64) -> u64 {
    if v & !fmt.sign_bit() == fmt.inf(false) {
        fmt.max_finite(v & fmt.sign_bit() != 0)
    } else {
        v
    }
}

/// `w` = the exact maximum of `n·(p − c)` over `pts` (`c` the reference
/// point), rounded up to `pf` (what the builder does).
fn fit_w(f: FloatFormat, pf: FloatFormat, n: &[u64; 3], pts: &[[u64; 3]], c: &[Dyadic; 3]) -> u64 {
    let mut best: Option<Dyadic> = None;
    for p in pts {
        let mut s = Dyadic::zero();
        for i in 0..3 {
            let ni = Dyadic::from_bits(pf, n[i]).unwrap();
            let pi = Dyadic::from_bits(f, p[i]).unwrap();
            s = s.add(&ni.mul(&pi.sub(&c[i])));
        }
        if best.as_ref().is_none_or(|b| s.cmp_exact(b).is_gt()) {
            best = Some(s);
        }
    }
    let w = best.unwrap().round_to(pf, RoundingMode::Up);
    if w & !pf.sign_bit() == pf.inf(false) {
        pf.max_finite(false)
    } else {
        w
    }
}

fn gen(f: FloatFormat, pf: FloatFormat, k: usize, rng: &mut Rng, kind: Kind) -> RegionIn {
    let scale = rand_scale(f, rng);
    let mut x = RegionIn::default();
    for i in 0..3 {
        let a = rand_val(f, rng, scale, 2);
        let b = if rng.chance(1, 12) {
            a
        } else {
            rand_val(f, rng, scale, 2)
        };
        let (lo, hi) = ordered(f, a, b);
        x.p_min[i] = lo;
        x.p_max[i] = hi;
    }
    // the reference point (the parent box's lower corner): the box's own
    // corner, or a point below it (a parent box around this child)
    x.r = x.p_min;
    if rng.chance(1, 2) {
        for i in 0..3 {
            let ext = sub(f, x.p_max[i], x.p_min[i], RoundingMode::Up);
            let below = sub(f, x.p_min[i], ext, RoundingMode::Down);
            x.r[i] = finite(f, between(f, rng, below, x.p_min[i]));
        }
    }
    let c: [Dyadic; 3] = x.r.map(|v| Dyadic::from_bits(f, v).unwrap());
    // "geometry": a few points in the box
    let pts: Vec<[u64; 3]> = (0..rng.range(1, 4))
        .map(|_| [0, 1, 2].map(|i| between(f, rng, x.p_min[i], x.p_max[i])))
        .collect();
    for _ in 0..k {
        if rng.chance(1, 10) {
            x.normals.push([0; 3]);
            x.w.push(0);
            continue;
        }
        let n = rand_normal(pf, rng);
        let w = if kind == Kind::Random && rng.chance(1, 2) {
            rand_val(
                pf,
                rng,
                scale.clamp(pf.emin() - pf.frac_bits() as i32, pf.emax() - 1),
                3,
            )
        } else {
            fit_w(f, pf, &n, &pts, &c)
        };
        x.normals.push(n);
        x.w.push(w);
    }
    let far = scale + rng.range(-1, 3) as i32;
    x.o = [0, 1, 2].map(|_| rand_val(f, rng, far, 2));
    x.d = [0, 1, 2].map(|_| {
        let sc = rng.range(-4, 4) as i32;
        rand_val(f, rng, sc, 3)
    });
    x.t_min = f.zero(false);
    x.t_max = f.inf(false);
    if rng.chance(1, 4) {
        x.t_min = from_f64(f, rng.unit() * 2.0);
        if rng.chance(1, 2) {
            x.t_max = from_f64(f, to_f64(f, x.t_min) + rng.unit() * 4.0);
        }
    }
    match kind {
        Kind::Random => {
            if rng.chance(1, 2) {
                let t = [0, 1, 2].map(|i| between(f, rng, x.p_min[i], x.p_max[i]));
                for i in 0..3 {
                    x.d[i] = sub(f, t[i], x.o[i], RNE);
                }
            }
        }
        Kind::Fitted => {
            // aim at a geometry point (on some plane's boundary), nudge
            let target = pts[rng.below(pts.len() as u64) as usize];
            if rng.chance(1, 2) {
                for i in 0..3 {
                    x.d[i] = sub(f, target[i], x.o[i], RNE);
                }
                if rng.chance(1, 2) {
                    x.t_min = f.zero(false);
                    x.t_max = from_f64(f, 1.0);
                }
            } else {
                for i in 0..3 {
                    x.d[i] = rand_val(f, rng, scale - 2, 1);
                    x.o[i] = sub(f, target[i], x.d[i], RNE);
                }
            }
            for i in 0..3 {
                if rng.chance(1, 2) {
                    x.d[i] = nudge(f, x.d[i], rng.range(-2, 2));
                }
                if rng.chance(1, 3) {
                    x.o[i] = nudge(f, x.o[i], rng.range(-2, 2));
                }
            }
        }
        Kind::Parallel => {
            // d ⟂ n for a plane with small-integer normal: choose d so n·d = 0.
            let p = rng.below(k as u64) as usize;
            let n =
                [0, 1, 2].map(|_| from_f64(pf, [-1.0, 0.0, 1.0, 2.0, -0.5][rng.below(5) as usize]));
            let target = pts[0];
            x.normals[p] = n;
            x.w[p] = fit_w(f, pf, &n, &pts, &c);
            let nf = n.map(|b| to_f64(pf, b));
            // d = n × r for a random r with small-integer components: exact
            let r = [0, 1, 2].map(|_| rng.range(-3, 3) as f64);
            let s = 2f64.powi(rng.range(-4, 4) as i32);
            let d = [
                nf[1] * r[2] - nf[2] * r[1],
                nf[2] * r[0] - nf[0] * r[2],
                nf[0] * r[1] - nf[1] * r[0],
            ];
            x.d = d.map(|v| from_f64(f, v * s));
            // origin: the support point moved along d, sometimes nudged off the plane
            let back = rng.range(-4, 1) as f64;
            for i in 0..3 {
                x.o[i] = add(f, target[i], from_f64(f, d[i] * s * back), RNE);
                if rng.chance(1, 3) {
                    x.o[i] = nudge(f, x.o[i], rng.range(-1, 1));
                }
            }
        }
        Kind::OriginOnPlane => {
            let target = pts[rng.below(pts.len() as u64) as usize];
            x.o = target;
            if rng.chance(1, 2) {
                for i in 0..3 {
                    x.o[i] = nudge(f, x.o[i], rng.range(-1, 1));
                }
            }
        }
        Kind::Specials => {
            let v = [
                f.canonical_nan(),
                f.inf(false),
                f.inf(true),
                f.zero(true),
                f.max_finite(false),
                f.min_subnormal(true),
                from_f64(f, -1.0),
            ][rng.below(7) as usize];
            match rng.below(11) {
                0 => x.t_min = v,
                1 => x.t_max = v,
                2 => x.o[rng.below(3) as usize] = v,
                3 => x.d[rng.below(3) as usize] = v,
                4 => x.p_min[rng.below(3) as usize] = v,
                9 => x.r[rng.below(3) as usize] = v,
                10 => {
                    let p = rng.below(k as u64) as usize;
                    x.normals[p][rng.below(3) as usize] =
                        [pf.canonical_nan(), pf.inf(true)][rng.below(2) as usize];
                }
                5 => std::mem::swap(&mut x.p_min, &mut x.p_max),
                6 => {
                    let p = rng.below(k as u64) as usize;
                    x.w[p] = [
                        pf.canonical_nan(),
                        pf.inf(false),
                        pf.max_finite(true),
                        pf.zero(true),
                    ][rng.below(4) as usize];
                }
                _ => std::mem::swap(&mut x.t_min, &mut x.t_max),
            }
        }
    }
    x
}

#[derive(Default, Debug, Clone)]
struct Stats {
    cases: u64,
    invalid: u64,
    exact_box: u64,
    exact_region: u64,
    tester_culls: u64,
    /// plane culls of segments starting behind the origin (`t_min < 0`)
    culls_negative_t_min: u64,
    tester_box_miss: u64,
    checked: u64,
    false_keeps: u64,
    /// wrongful culls (tester box miss or cull where the exact reference hits)
    wrongful: u64,
    /// the first wrongful case, for the failure message
    first_wrongful: Option<String>,
}

impl Stats {
    fn add(&mut self, o: &Stats) {
        self.cases += o.cases;
        self.invalid += o.invalid;
        self.exact_box += o.exact_box;
        self.exact_region += o.exact_region;
        self.tester_culls += o.tester_culls;
        self.culls_negative_t_min += o.culls_negative_t_min;
        self.tester_box_miss += o.tester_box_miss;
        self.checked += o.checked;
        self.false_keeps += o.false_keeps;
        self.wrongful += o.wrongful;
        if self.first_wrongful.is_none() {
            self.first_wrongful.clone_from(&o.first_wrongful);
        }
    }
}

/// The hardware's composition: `None` when the conservative slab misses
/// the box, else the cull unit's verdict.
fn tester(cfg: &Config, x: &RegionIn) -> Option<CullOut> {
    let f = cfg.ray;
    let inv_d = slab_reciprocal(f, &x.d);
    let (t_lo, t_hi) = box_interval(f, &x.p_min, &x.p_max, &x.o, &inv_d, x.t_min, x.t_max)?;
    let terms = ray_terms(
        cfg,
        &RayIn {
            o: x.o,
            d: x.d,
            r: x.r,
            normals: x.normals.clone(),
        },
    );
    Some(eval(
        cfg,
        &ChildIn {
            t_lo,
            t_hi,
            w: x.w.clone(),
            terms: terms.terms,
        },
    ))
}

fn chunk(f: FloatFormat, pf: FloatFormat, k: usize, kind: Kind, seed: u64, n: u64) -> Stats {
    let cfg = Config::new(f, pf, k).unwrap();
    let mut rng = Rng(seed);
    let mut st = Stats::default();
    for i in 0..n {
        let x = gen(f, pf, k, &mut rng, kind);
        let out = tester(&cfg, &x);
        let box_hit = out.is_some();
        let keep = out.is_some_and(|o| o.keep);
        st.cases += 1;
        // The exact reference on every cull and box miss (soundness), and on
        // one case in 8 otherwise (tightness statistics).
        let need = !keep || i % 8 == 0;
        if !need {
            continue;
        }
        let ex = region_hit(f, pf, &x);
        st.checked += 1;
        let ctx = || format!("{f}/{pf} k={k} {kind:?}\n{x:x?}\nout {out:?}\nexact {ex:?}");
        if ex.invalid {
            // no exact answer (NaN or infinity in the inputs)
            st.invalid += 1;
            continue;
        }
        assert!(
            !out.is_some_and(|o| o.invalid),
            "the cull unit calls valid inputs invalid: {}",
            ctx()
        );
        st.exact_box += ex.box_hit as u64;
        st.exact_region += ex.region_hit as u64;
        st.tester_box_miss += !box_hit as u64;
        st.tester_culls += (box_hit && !keep) as u64;
        let behind = x.t_min & f.sign_bit() != 0 && x.t_min & !f.sign_bit() != 0;
        st.culls_negative_t_min += (box_hit && !keep && behind) as u64;
        if (ex.box_hit && !box_hit) || (ex.region_hit && !keep) {
            st.wrongful += 1;
            if st.first_wrongful.is_none() {
                st.first_wrongful = Some(ctx());
            }
            continue;
        }
        if !ex.region_hit && keep && i % 8 == 0 {
            st.false_keeps += 1;
        }
    }
    st
}

fn total_cases() -> u64 {
    std::env::var("CULL_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1_200_000)
}

#[test]
fn no_wrongful_culls_on_random_and_adversarial_cases() {
    let configs: [(FloatFormat, FloatFormat, usize); 5] = [
        (FloatFormat::BINARY32, FloatFormat::BINARY16, 4),
        (FloatFormat::BINARY32, FloatFormat::BFLOAT16, 8),
        (FloatFormat::BINARY16, FloatFormat::new(4, 3).unwrap(), 2),
        (
            FloatFormat::new(4, 6).unwrap(),
            FloatFormat::new(3, 2).unwrap(),
            3,
        ),
        (
            FloatFormat::new(6, 12).unwrap(),
            FloatFormat::new(6, 12).unwrap(),
            1,
        ),
    ];
    let total = total_cases();
    let jobs: Vec<(usize, Kind)> = (0..configs.len())
        .flat_map(|c| KINDS.iter().map(move |&k| (c, k)))
        .collect();
    let per_job = total.div_ceil(jobs.len() as u64);
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let shards = 4u64;
    let mut grand = Stats::default();
    let work: Vec<(usize, Kind, u64)> = jobs
        .iter()
        .flat_map(|&(c, k)| (0..shards).map(move |s| (c, k, s)))
        .collect();
    let results = std::sync::Mutex::new(Vec::new());
    let next = std::sync::atomic::AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let j = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(&(c, kind, shard)) = work.get(j) else {
                    break;
                };
                let (f, pf, k) = configs[c];
                let seed = (0xC011_0000 + (c as u64)) << 20 ^ (kind as u64) << 8 ^ shard;
                let st = chunk(f, pf, k, kind, seed, per_job / shards);
                results.lock().unwrap().push((c, kind, st));
            });
        }
    });
    let mut results = results.into_inner().unwrap();
    results.sort_by_key(|r| (r.0, r.1 as u8));
    for c in 0..configs.len() {
        for kind in KINDS {
            let mut st = Stats::default();
            for r in results.iter().filter(|r| r.0 == c && r.1 == kind) {
                st.add(&r.2);
            }
            let (f, pf, k) = configs[c];
            eprintln!(
                "{f} planes {pf} k={k} {kind:?}: {} cases, exact-checked {}, invalid {}, tester box misses {}, plane culls {}, wrongful {}; exact region hits {} / box hits {} among checked, false keeps (1/8 sample) {}",
                st.cases, st.checked, st.invalid, st.tester_box_miss, st.tester_culls, st.wrongful, st.exact_region, st.exact_box, st.false_keeps
            );
            grand.add(&st);
        }
    }
    eprintln!(
        "TOTAL {} cases, {} exact checks, {} tester plane culls ({} with t_min < 0), {} box misses, wrongful culls {}, false keeps (1/8 sample) {}",
        grand.cases, grand.checked, grand.tester_culls, grand.culls_negative_t_min, grand.tester_box_miss, grand.wrongful, grand.false_keeps
    );
    assert_eq!(
        grand.wrongful,
        0,
        "wrongful culls; the first: {}",
        grand.first_wrongful.as_deref().unwrap_or("")
    );
    assert!(grand.cases >= total.min(1_000_000));
    // Tightness, from the measured rates (1.2 M CI run of the shared-normal tester with the fused
    // dot products: 120,914 plane culls = 10.08 % of the cases, 6,527 false keeps = 0.544 %; with
    // two rounded adders per dot product 9.81 % and 0.577 %): a floor on the culls made and a
    // ceiling on the culls lost to rounding, so a looser tester fails.
    let cases = grand.cases as f64;
    assert!(
        grand.tester_culls as f64 >= 0.097 * cases,
        "the planes cull too little: {} of {} cases (floor 9.7 %, measured 10.1 %)",
        grand.tester_culls,
        grand.cases
    );
    assert!(
        grand.false_keeps as f64 <= 0.0058 * cases + 20.0,
        "too many culls lost to rounding: {} false keeps in the 1/8 sample of {} cases (ceiling 0.58 %, measured 0.54 %)",
        grand.false_keeps,
        grand.cases
    );
}

/// A rejected configuration says what is wrong: the message a caller prints.
#[test]
fn rejected_configurations_say_why() {
    let (b16, b32) = (FloatFormat::BINARY16, FloatFormat::BINARY32);
    let wider_plane = Config::new(b16, b32, 4).unwrap_err().to_string();
    assert_eq!(
        wider_plane,
        "the plane format must not have more exponent or fraction bits than the ray format"
    );
    assert_eq!(
        Config::new(b32, b16, 9).unwrap_err().to_string(),
        "k = 9 outside 1..=8"
    );
}
