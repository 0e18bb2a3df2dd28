//! Stimulus and golden-model adapter for `cull`.
//!
//! Ports (`units::cull::CullIn`, `CullOut`): `t_lo`, `t_hi` (ray
//! format), `w<j>` (plane format), then per plane `no_lo<j>`, `rcp_lo<j>`,
//! `rcp_hi<j>`, `dir<j>`; outputs `keep`, `invalid`.
//!
//! Vectors (each computed from `(seed, index)` alone) start from the
//! realistic composition: a parent box, a child inside it, a ray and K
//! quantised normals (the scene of [`super::cull_ray`]); the ray terms from
//! the golden `ray_terms`, `[t_lo, t_hi]` from the conservative slab
//! (`box_interval` with `slab_reciprocal`; a random interval when it
//! misses) and each distance fitted around a few points of the child box
//! (`max n·(p − r)` rounded up, in binary64; sometimes through a single
//! point so that the plane cuts the box, sometimes nudged by ulps). By `index % 16`: 0-6 that
//! alone (the segment sometimes `[0, +∞)`, sometimes from a random `t_min`);
//! 7 an exactly perpendicular ray (parallel planes, `b_lo = 0`); 8 `D = 0`
//! exactly (`no_lo` the widened `w`, signed zeros); 9 reciprocals at the
//! ends of the range (0, subnormal, largest, ∞, either sign); 10 `no_lo =
//! −∞` and huge `no_lo`; 11 a NaN, an infinity, a zero or a subnormal in
//! some inputs; 12 raw bit patterns; 13 `t_lo < 0`, `−0`, `t_lo > t_hi`,
//! infinite bounds; 14 random `dir` codes (3 included) and parallel planes
//! with `no_lo` near `w`; 15 extreme scales and subnormal distances.

use super::cull_ray::{from_f64, golden_config, parallel, scale, scene, tiny, Gen};
use super::stimulus::{specials, VectorRng};
use super::Testbench;
use golden_model::cull::tester::{
    box_interval, eval, ray_terms, slab_reciprocal, ChildIn, Config, Crossing, NormalTerm, RayIn,
};
use golden_model::float::{convert, nudge, to_f64, FloatFormat, RoundingMode};
use rtl_gen::units::cull::{Config as UnitConfig, CullIn, CullOut, Terms};
use rtl_gen::units::ports;

/// Testbench of one `cull` configuration.
pub struct CullBench {
    cfg: Config,
    unit: UnitConfig,
}

/// `n·(p − r)` in binary64 (the stimulus needs distances near the points,
/// not exact ones).
fn height(f: FloatFormat, pf: FloatFormat, n: &[u64; 3], p: &[u64; 3], r: &[u64; 3]) -> f64 {
    (0..3)
        .map(|i| to_f64(pf, n[i]) * (to_f64(f, p[i]) - to_f64(f, r[i])))
        .sum()
}

/// A point of the box `[lo, hi]`: per axis a face or a random interior
/// value (kept inside: a rounded interior value can fall just outside).
fn point(g: &mut Gen, f: FloatFormat, lo: &[u64; 3], hi: &[u64; 3]) -> [u64; 3] {
    [0, 1, 2].map(|i| {
        let (a, b) = (to_f64(f, lo[i]), to_f64(f, hi[i]));
        match g.r.below(3) {
            0 => lo[i],
            1 => hi[i],
            _ => {
                let v = from_f64(f, a + g.unit() * (b - a));
                let x = to_f64(f, v);
                if x < a {
                    lo[i]
                } else if x > b {
                    hi[i]
                } else {
                    v
                }
            }
        }
    })
}

impl CullBench {
    /// The testbench of a `cull` configuration.
    pub fn new(unit: &UnitConfig) -> Self {
        CullBench {
            cfg: golden_config(unit),
            unit: *unit,
        }
    }

    /// The golden model's input from port values.
    pub fn unpack(&self, v: &[u64]) -> ChildIn {
        let x: CullIn<u64> = ports::unpack(&self.unit, v);
        ChildIn {
            t_lo: x.t_lo,
            t_hi: x.t_hi,
            w: x.w,
            terms: x
                .terms
                .iter()
                .map(|t| NormalTerm {
                    no_lo: t.no_lo,
                    rcp_lo: t.rcp_lo,
                    rcp_hi: t.rcp_hi,
                    dir: Crossing::from_code(t.dir),
                })
                .collect(),
        }
    }

    /// The input ports of one child test (the renderer's call of
    /// `eval_parts`), each value masked to its port; distances and terms
    /// beyond the slices' lengths read as 0, as in the golden model.
    pub fn to_ports(&self, t_lo: u64, t_hi: u64, w: &[u64], terms: &[NormalTerm], v: &mut [u64]) {
        ports::pack(&self.unit, &self.record(t_lo, t_hi, w, terms), v)
    }

    /// The record of [`CullBench::to_ports`].
    fn record(&self, t_lo: u64, t_hi: u64, w: &[u64], terms: &[NormalTerm]) -> CullIn<u64> {
        let fm = self.cfg.ray.mask();
        let pm = self.cfg.plane.mask();
        let cm = self.cfg.crossing().mask();
        CullIn {
            t_lo: t_lo & fm,
            t_hi: t_hi & fm,
            w: (0..self.cfg.k)
                .map(|j| w.get(j).copied().unwrap_or(0) & pm)
                .collect(),
            terms: (0..self.cfg.k)
                .map(|j| {
                    let t = terms.get(j).copied().unwrap_or_default();
                    Terms {
                        no_lo: t.no_lo & fm,
                        rcp_lo: t.rcp_lo & cm,
                        rcp_hi: t.rcp_hi & cm,
                        dir: t.dir.code(),
                    }
                })
                .collect(),
        }
    }

    /// `keep` of the output ports.
    pub fn keep_from_ports(&self, out: &[u64]) -> bool {
        ports::unpack::<CullOut<u64>>(&self.unit, out).keep & 1 != 0
    }

    /// The golden configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }

    /// [`CullBench::to_ports`] with the direction codes given (code 3 is
    /// no [`Crossing`]: the stimulus drives it too).
    fn pack(&self, x: &ChildIn, dir_codes: &[u64], v: &mut [u64]) {
        let mut record = self.record(x.t_lo, x.t_hi, &x.w, &x.terms);
        for (t, code) in record.terms.iter_mut().zip(dir_codes) {
            t.dir = code & 3;
        }
        ports::pack(&self.unit, &record, v)
    }

    /// The realistic composition at scale `s` (kind 7: a perpendicular ray).
    fn compose(&self, g: &mut Gen, s: f64, perpendicular: bool) -> ChildIn {
        let (f, pf, k) = (self.cfg.ray, self.cfg.plane, self.cfg.k);
        let mut sc = scene(g, f, pf, k, s);
        let child = if g.chance(7, 8) { sc.aim } else { 1 - sc.aim };
        let (c_min, c_max) = sc.children[child];
        // the child's "geometry": every plane keeps these points
        let pts: Vec<[u64; 3]> = (0..g.range(1, 4))
            .map(|_| point(g, f, &c_min, &c_max))
            .collect();
        if perpendicular {
            let (d, normals) = parallel(g, f, pf, k);
            sc.d = d;
            sc.normals = normals;
        } else if g.chance(1, 3) {
            // aimed at a kept point (kept by every fitted plane), sometimes off by ulps
            let p = g.pick(&pts);
            let len = 2f64.powi(g.range(-3, 3) as i32);
            for i in 0..3 {
                let dd = (to_f64(f, p[i]) - to_f64(f, sc.o[i])) * len;
                sc.d[i] = from_f64(f, dd);
                if g.chance(1, 3) {
                    sc.d[i] = nudge(f, sc.d[i], g.range(-2, 2));
                }
            }
        }
        let r = sc.p_min;
        let terms = ray_terms(
            &self.cfg,
            &RayIn {
                o: sc.o,
                d: sc.d,
                r,
                normals: sc.normals.clone(),
            },
        );
        let (t_min, t_max) = if g.chance(1, 2) {
            (f.zero(false), f.inf(false))
        } else {
            (
                from_f64(f, g.signed() * 2.0),
                if g.chance(1, 2) {
                    f.inf(false)
                } else {
                    from_f64(f, g.unit() * 40.0)
                },
            )
        };
        let (t_lo, t_hi) = box_interval(
            f,
            &c_min,
            &c_max,
            &sc.o,
            &slab_reciprocal(f, &sc.d),
            t_min,
            t_max,
        )
        .unwrap_or_else(|| {
            let a = from_f64(f, g.signed() * 30.0);
            let b = from_f64(f, g.signed() * 30.0);
            (a, b)
        });
        let w = sc
            .normals
            .iter()
            .map(|n| {
                // through a single point of its own (cuts the box), or around the geometry
                let own;
                let fit: &[[u64; 3]] = if g.chance(1, 4) {
                    own = [point(g, f, &c_min, &c_max)];
                    &own
                } else {
                    &pts
                };
                let best = fit
                    .iter()
                    .map(|p| height(f, pf, n, p, &r))
                    .fold(f64::NEG_INFINITY, f64::max);
                let w = convert(FloatFormat::BINARY64, pf, best.to_bits(), RoundingMode::Up);
                let w = if w & !pf.sign_bit() == pf.inf(false) {
                    pf.max_finite(w & pf.sign_bit() != 0)
                } else {
                    w
                };
                if g.chance(1, 6) {
                    nudge(pf, w, g.range(-3, 3))
                } else {
                    w
                }
            })
            .collect();
        ChildIn {
            t_lo,
            t_hi,
            w,
            terms: terms.terms,
        }
    }
}

impl sim::Golden for CullBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let out = eval(&self.cfg, &self.unpack(inputs));
        let record = CullOut {
            keep: out.keep as u64,
            invalid: out.invalid as u64,
        };
        ports::pack(&self.unit, &record, outputs)
    }
}

impl sim::Stimulus for CullBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (f, pf, k) = (self.cfg.ray, self.cfg.plane, self.cfg.k);
        let cf = self.cfg.crossing();
        let mut rng = VectorRng::new(seed, index);
        let kind = index % 16;
        if kind == 12 {
            let raw: CullIn<u64> = ports::from_fn(&self.unit, |ty| rng.bits(ty.width()));
            return ports::pack(&self.unit, &raw, v);
        }
        let mut g = Gen { r: &mut rng };
        let s = if kind == 15 {
            let lo = f.emin() + g.range(0, 4) as i32;
            let hi = f.emax() - 5 - g.range(0, 3) as i32;
            2f64.powi(g.pick(&[lo, hi]))
        } else {
            scale(&mut g, f)
        };
        let mut x = self.compose(&mut g, s, kind == 7);
        let mut dir: Vec<u64> = x.terms.iter().map(|t| t.dir.code()).collect();
        let j = g.r.below(k as u64) as usize;
        match kind {
            8 => {
                // D = w − no_lo = 0 exactly (and signed zeros)
                for jj in 0..k {
                    if jj == j || g.chance(1, 3) {
                        if g.chance(1, 4) {
                            x.w[jj] = pf.zero(g.chance(1, 2));
                            x.terms[jj].no_lo = f.zero(g.chance(1, 2));
                        } else {
                            x.terms[jj].no_lo = convert(pf, f, x.w[jj], RoundingMode::NearestEven);
                        }
                    }
                }
            }
            9 => {
                let ends = [
                    cf.zero(false),
                    cf.min_subnormal(false),
                    cf.max_subnormal(false),
                    cf.min_normal(false),
                    cf.max_finite(false),
                    cf.inf(false),
                ];
                for jj in 0..k {
                    if jj == j || g.chance(1, 2) {
                        let a = g.pick(&ends);
                        let b = g.pick(&ends);
                        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
                        let neg = if g.chance(1, 8) { cf.sign_bit() } else { 0 };
                        x.terms[jj].rcp_lo = lo | neg;
                        x.terms[jj].rcp_hi = hi | if g.chance(1, 8) { cf.sign_bit() } else { 0 };
                    }
                }
            }
            10 => {
                x.terms[j].no_lo = if g.chance(1, 2) {
                    f.inf(true)
                } else {
                    nudge(f, f.max_finite(g.chance(1, 2)), -g.range(0, 2))
                };
            }
            11 => {
                let sf = specials(f);
                let sp = specials(pf);
                let sc = specials(cf);
                for _ in 0..g.range(1, 3) {
                    let jj = g.r.below(k as u64) as usize;
                    match g.r.below(6) {
                        0 => x.t_lo = g.pick(&sf),
                        1 => x.t_hi = g.pick(&sf),
                        2 => x.w[jj] = g.pick(&sp),
                        3 => x.terms[jj].no_lo = g.pick(&sf),
                        4 => x.terms[jj].rcp_lo = g.pick(&sc),
                        _ => x.terms[jj].rcp_hi = g.pick(&sc),
                    }
                }
            }
            13 => match g.r.below(5) {
                0 => x.t_lo = from_f64(f, -g.unit() * 4.0),
                1 => x.t_lo = f.zero(true),
                2 => std::mem::swap(&mut x.t_lo, &mut x.t_hi),
                3 => x.t_hi = f.inf(g.chance(1, 4)),
                _ => x.t_lo = f.inf(g.chance(1, 2)),
            },
            14 => {
                for d in dir.iter_mut() {
                    if g.chance(1, 2) {
                        *d = g.r.below(4);
                    }
                }
                dir[j] = g.pick(&[0, 3]);
                let no_lo = convert(pf, f, x.w[j], RoundingMode::NearestEven);
                if no_lo & !f.sign_bit() != f.inf(false) && no_lo & !f.sign_bit() <= f.inf(false) {
                    x.terms[j].no_lo = nudge(f, no_lo, g.range(-2, 2));
                }
            }
            15 => {
                for w in x.w.iter_mut() {
                    if g.chance(1, 3) {
                        *w = tiny(&mut g, pf);
                    }
                }
                if g.chance(1, 3) {
                    x.t_lo = tiny(&mut g, f);
                }
            }
            _ => {}
        }
        self.pack(&x, &dir, v);
    }
}

impl Testbench for CullBench {}
