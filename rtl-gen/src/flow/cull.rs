//! Stimulus and golden-model adapter for `cull`.
//!
//! Port order: `p_min_{x,y,z}`, `p_max_{x,y,z}`, `o_{x,y,z}`, `d_{x,y,z}`,
//! `t_min`, `t_max`, then per plane `plane<j>_n{x,y,z}`, `plane<j>_w`;
//! outputs `box_hit`, `keep`, `invalid`.
//!
//! Vectors (each computed from `(seed, index)` alone), by `index % 8`:
//! random boxes and rays aimed into the box; planes fitted exactly around a
//! few points of the box (as the builder fits them) with rays aimed at such a
//! point and nudged by ulps; rays exactly parallel to a plane through its
//! support point; origins on a plane; random bit patterns (NaN, infinities,
//! subnormals); small-exponent and near-overflow scales.

use super::stimulus::{mask, VectorRng};
use super::Testbench;
use crate::params::Params;
use golden_model::cull::exact::Dyadic;
use golden_model::cull::tester::{eval, Config, CullIn, Plane};
use golden_model::float::{convert, sub, FloatFormat, RoundingMode};

const RNE: RoundingMode = RoundingMode::NearestEven;

/// Testbench of one `cull` configuration.
pub struct CullBench {
    cfg: Config,
    f: FloatFormat,
    pf: FloatFormat,
    k: usize,
}

impl CullBench {
    /// The testbench for resolved `cull` parameters.
    pub fn new(p: &Params) -> Self {
        let f = FloatFormat::new(p.u32("exp_bits"), p.u32("frac_bits")).expect("checked");
        let pf =
            FloatFormat::new(p.u32("plane_exp_bits"), p.u32("plane_frac_bits")).expect("checked");
        let k = p.u32("k") as usize;
        CullBench {
            cfg: Config::new(f, pf, k).expect("checked"),
            f,
            pf,
            k,
        }
    }

    /// The golden model's input from port values.
    pub fn unpack(&self, v: &[u64]) -> CullIn {
        let g = |i: usize| [v[i], v[i + 1], v[i + 2]];
        CullIn {
            p_min: g(0),
            p_max: g(3),
            o: g(6),
            d: g(9),
            t_min: v[12],
            t_max: v[13],
            planes: (0..self.k)
                .map(|j| Plane {
                    n: [v[14 + 4 * j], v[15 + 4 * j], v[16 + 4 * j]],
                    w: v[17 + 4 * j],
                })
                .collect(),
        }
    }

    fn pack(&self, x: &CullIn, v: &mut [u64]) {
        let (fm, pm) = (self.f.mask(), self.pf.mask());
        for i in 0..3 {
            v[i] = x.p_min[i] & fm;
            v[3 + i] = x.p_max[i] & fm;
            v[6 + i] = x.o[i] & fm;
            v[9 + i] = x.d[i] & fm;
        }
        v[12] = x.t_min & fm;
        v[13] = x.t_max & fm;
        for j in 0..self.k {
            let p = x.planes.get(j).copied().unwrap_or_default();
            for i in 0..3 {
                v[14 + 4 * j + i] = p.n[i] & pm;
            }
            v[17 + 4 * j] = p.w & pm;
        }
    }
}

impl sim::Golden for CullBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let out = eval(&self.cfg, &self.unpack(inputs));
        outputs[0] = out.box_hit as u64;
        outputs[1] = out.keep as u64;
        outputs[2] = out.invalid as u64;
    }
}

struct G<'a> {
    r: &'a mut VectorRng,
    f: FloatFormat,
}

impl G<'_> {
    fn unit(&mut self) -> f64 {
        (self.r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.r.below((hi - lo + 1) as u64) as i64
    }
    fn chance(&mut self, n: u64, d: u64) -> bool {
        self.r.below(d) < n
    }
}

fn from_f64(fmt: FloatFormat, v: f64) -> u64 {
    let r = convert(FloatFormat::BINARY64, fmt, v.to_bits(), RNE);
    if r & !fmt.sign_bit() == fmt.inf(false) {
        fmt.max_finite(r & fmt.sign_bit() != 0)
    } else {
        r
    }
}

fn key(fmt: FloatFormat, b: u64) -> i64 {
    let mag = (b & fmt.mask() & !fmt.sign_bit()) as i64;
    if b & fmt.sign_bit() != 0 {
        -mag - 1
    } else {
        mag
    }
}

fn from_key(fmt: FloatFormat, k: i64) -> u64 {
    if k < 0 {
        ((-(k + 1)) as u64) | fmt.sign_bit()
    } else {
        k as u64
    }
}

fn nudge(fmt: FloatFormat, b: u64, n: i64) -> u64 {
    let lim = key(fmt, fmt.max_finite(false));
    from_key(fmt, (key(fmt, b) + n).clamp(-lim - 1, lim))
}

fn between(g: &mut G, lo: u64, hi: u64) -> u64 {
    let (a, b) = (key(g.f, lo), key(g.f, hi));
    let (a, b) = (a.min(b), a.max(b));
    from_key(g.f, a + g.r.below((b - a + 1) as u64) as i64)
}

fn val(g: &mut G, fmt: FloatFormat, scale: i32, spread: i32) -> u64 {
    if g.chance(1, 30) {
        return fmt.zero(g.chance(1, 2));
    }
    let k = scale + g.range(-(spread as i64), spread as i64) as i32;
    let v = (1.0 + g.unit()) * 2f64.powi(k.clamp(-1070, 1020));
    from_f64(fmt, if g.chance(1, 2) { -v } else { v })
}

impl sim::Stimulus for CullBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (f, pf, k) = (self.f, self.pf, self.k);
        let mut rng = VectorRng::new(seed, index);
        let kind = index % 8;
        if kind == 7 {
            // raw bit patterns: specials, subnormals, anything
            for (i, x) in v.iter_mut().enumerate() {
                let w = if i < 14 { f.width() } else { pf.width() };
                *x = rng.bits(w) & mask(w);
            }
            return;
        }
        let mut g = G { r: &mut rng, f };
        let scale = match g.r.below(10) {
            0 => f.emax() - g.range(0, 3) as i32,
            1 => f.emin() - f.frac_bits() as i32 + g.range(0, 6) as i32,
            _ => g.range(-5, 5) as i32,
        };
        let mut x = CullIn::default();
        for i in 0..3 {
            let a = val(&mut g, f, scale, 2);
            let b = if g.chance(1, 12) {
                a
            } else {
                val(&mut g, f, scale, 2)
            };
            let (lo, hi) = if key(f, a) <= key(f, b) {
                (a, b)
            } else {
                (b, a)
            };
            x.p_min[i] = lo;
            x.p_max[i] = hi;
        }
        let c: [Dyadic; 3] = [0, 1, 2].map(|i| {
            Dyadic::from_bits(f, x.p_min[i])
                .unwrap()
                .add(&Dyadic::from_bits(f, x.p_max[i]).unwrap())
                .half()
        });
        let np = g.range(1, 3) as usize;
        let pts: Vec<[u64; 3]> = (0..np)
            .map(|_| [0, 1, 2].map(|i| between(&mut g, x.p_min[i], x.p_max[i])))
            .collect();
        let fit = |n: &[u64; 3]| {
            let mut best: Option<Dyadic> = None;
            for p in &pts {
                let mut s = Dyadic::zero();
                for i in 0..3 {
                    let ni = Dyadic::from_bits(pf, n[i]).unwrap();
                    s = s.add(&ni.mul(&Dyadic::from_bits(f, p[i]).unwrap().sub(&c[i])));
                }
                if best.as_ref().is_none_or(|b| s.cmp(b).is_gt()) {
                    best = Some(s);
                }
            }
            let w = best.unwrap().round_to(pf, RoundingMode::Up);
            if w & !pf.sign_bit() == pf.inf(false) {
                pf.max_finite(false)
            } else {
                w
            }
        };
        for _ in 0..k {
            if g.chance(1, 10) {
                x.planes.push(Plane::default());
                continue;
            }
            let n = [0, 1, 2].map(|_| {
                if g.chance(1, 4) {
                    from_f64(pf, [-1.0, 0.0, 1.0][g.r.below(3) as usize])
                } else {
                    from_f64(pf, 2.0 * g.unit() - 1.0)
                }
            });
            let w = if kind == 0 && g.chance(1, 2) {
                val(&mut g, pf, scale.clamp(pf.emin(), pf.emax() - 1), 3)
            } else {
                fit(&n)
            };
            x.planes.push(Plane { n, w });
        }
        let far = scale + g.range(-1, 3) as i32;
        x.o = [0, 1, 2].map(|_| val(&mut g, f, far, 2));
        x.d = [0, 1, 2].map(|_| {
            let s = g.range(-4, 4) as i32;
            val(&mut g, f, s, 3)
        });
        x.t_min = f.zero(false);
        x.t_max = f.inf(false);
        if g.chance(1, 4) {
            x.t_min = from_f64(f, g.unit() * 2.0 - 0.25);
            if g.chance(1, 2) {
                x.t_max = from_f64(f, g.unit() * 4.0);
            }
        }
        let target = pts[g.r.below(pts.len() as u64) as usize];
        match kind {
            0 | 1 => {
                let t = [0, 1, 2].map(|i| between(&mut g, x.p_min[i], x.p_max[i]));
                let t = if kind == 1 { target } else { t };
                for i in 0..3 {
                    x.d[i] = sub(f, t[i], x.o[i], RNE);
                    if g.chance(1, 2) {
                        x.d[i] = nudge(f, x.d[i], g.range(-2, 2));
                    }
                }
            }
            2 | 3 => {
                // parallel to plane 0 (exactly, small-integer normal), through the support point
                let n = [0, 1, 2]
                    .map(|_| from_f64(pf, [-1.0, 0.0, 1.0, 2.0, -0.5][g.r.below(5) as usize]));
                x.planes[0] = Plane { n, w: fit(&n) };
                let nf = n.map(|b| f64::from_bits(convert(pf, FloatFormat::BINARY64, b, RNE)));
                let r = [0, 1, 2].map(|_| g.range(-3, 3) as f64);
                let s = 2f64.powi(g.range(-3, 3) as i32);
                let dd = [
                    nf[1] * r[2] - nf[2] * r[1],
                    nf[2] * r[0] - nf[0] * r[2],
                    nf[0] * r[1] - nf[1] * r[0],
                ];
                x.d = dd.map(|c| from_f64(f, c * s));
                x.o = target;
                if kind == 3 {
                    let i = g.r.below(3) as usize;
                    x.o[i] = nudge(f, x.o[i], g.range(-1, 1));
                }
            }
            4 | 5 => {
                x.o = target;
                if kind == 5 {
                    for i in 0..3 {
                        x.o[i] = nudge(f, x.o[i], g.range(-1, 1));
                    }
                }
            }
            _ => {}
        }
        self.pack(&x, v);
    }
}

impl Testbench for CullBench {}
