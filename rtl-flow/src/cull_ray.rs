//! Stimulus and golden-model adapter for `cull_ray`, and the scene
//! generator both cull benches share.
//!
//! Ports (`units::cull::CullRayIn` / `CullRayOut`): `o_*`, `d_*`,
//! `r_*` (ray format), `n<j>_*` (plane format); outputs per normal `no_lo<j>`,
//! `rcp_lo<j>`, `rcp_hi<j>`, `dir<j>`.
//!
//! Vectors (each computed from `(seed, index)` alone), by `index % 12`:
//! 0-5 a realistic parent: a random box (its lower corner is `r`), a ray
//! aimed into it or anywhere, quantised unit normals (some with zero or
//! ±1 components, some nearly perpendicular to the ray), at ordinary and at
//! extreme scales; 6 zero direction components and normals exactly
//! perpendicular to the direction (`b_lo = 0`); 7 tiny and huge directions
//! (`b_lo` and the reciprocals under- and overflow); 8 a NaN, an infinity, a
//! zero of either sign or a subnormal in some inputs; 9 raw bit patterns;
//! 10 subnormal and signed-zero inputs throughout; 11 origins and corners
//! near the top of the range (`o − r` overflows, `no_lo = ±∞`).

use super::stimulus::{specials, VectorRng};
use super::Testbench;
use golden_model::cull::tester::{ray_terms, Config, Crossing, NormalTerm, RayIn};
use golden_model::float::{convert, nudge, to_f64, FloatFormat, RoundingMode};
use rtl_gen::units::cull::{Config as UnitConfig, CullRayIn, CullRayOut, Terms};
use rtl_gen::units::ports;

const RNE: RoundingMode = RoundingMode::NearestEven;

/// The golden configuration of a unit configuration.
pub(super) fn golden_config(unit: &UnitConfig) -> Config {
    let g = |f: rtl_gen::arith::float::Format| {
        FloatFormat::new(f.exp_bits, f.frac_bits).expect("a unit format is a golden format")
    };
    let cfg = Config::new(g(unit.ray), g(unit.plane), unit.k as usize).expect("checked");
    assert_eq!(
        g(unit.crossing()),
        cfg.crossing(),
        "the generator's crossing format (units::cull::CROSSING_GUARD_BITS) is the golden model's"
    );
    cfg
}

/// Random helpers for one vector.
pub(super) struct Gen<'a> {
    pub r: &'a mut VectorRng,
}

impl Gen<'_> {
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi].
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.r.below((hi - lo + 1) as u64) as i64
    }
    /// True with probability n/d.
    pub fn chance(&mut self, n: u64, d: u64) -> bool {
        self.r.below(d) < n
    }
    /// Uniform in [-1, 1).
    pub fn signed(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
    /// One of `xs`.
    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.r.below(xs.len() as u64) as usize]
    }
}

/// `v` rounded to nearest into `fmt`, overflow saturated to the largest finite value.
pub(super) fn from_f64(fmt: FloatFormat, v: f64) -> u64 {
    let r = golden_model::float::from_f64(fmt, v);
    if r & !fmt.sign_bit() == fmt.inf(false) {
        fmt.max_finite(r & fmt.sign_bit() != 0)
    } else {
        r
    }
}

/// A random subnormal or zero of `fmt`, either sign.
pub(super) fn tiny(g: &mut Gen, fmt: FloatFormat) -> u64 {
    let frac = g.r.bits(fmt.frac_bits()) >> g.range(0, fmt.frac_bits() as i64 - 1);
    frac | if g.chance(1, 2) { fmt.sign_bit() } else { 0 }
}

/// A box, a ray and a parent's normals.
#[derive(Debug, Clone)]
pub(super) struct Scene {
    /// the parent box's lower corner (the reference point `r`)
    pub p_min: [u64; 3],
    /// the two children (min, max), inside the parent
    pub children: [([u64; 3], [u64; 3]); 2],
    /// the child the ray is aimed at (mostly)
    pub aim: usize,
    /// ray origin
    pub o: [u64; 3],
    /// ray direction
    pub d: [u64; 3],
    /// K quantised normals
    pub normals: Vec<[u64; 3]>,
}

/// The power-of-two scale of a scene: mostly ordinary, sometimes near the
/// bottom or the top of the ray format's range.
pub(super) fn scale(g: &mut Gen, f: FloatFormat) -> f64 {
    let e = match g.r.below(12) {
        0 => f.emax() - 4 - g.range(0, 3) as i32,
        1 => f.emin() + g.range(0, 6) as i32,
        _ => g.range(-6, 6) as i32,
    };
    2f64.powi(e)
}

/// A unit normal quantised to the plane format: random, axis-aligned,
/// with zero components, or nearly perpendicular to `d`.
pub(super) fn normal(g: &mut Gen, pf: FloatFormat, d: &[f64; 3]) -> [u64; 3] {
    let mut n = match g.r.below(8) {
        0 => {
            let mut n = [0.0; 3];
            n[g.r.below(3) as usize] = if g.chance(1, 2) { 1.0 } else { -1.0 };
            n
        }
        1 => {
            // perpendicular to d (up to the quantisation)
            let a = [g.signed(), g.signed(), g.signed()];
            [
                d[1] * a[2] - d[2] * a[1],
                d[2] * a[0] - d[0] * a[2],
                d[0] * a[1] - d[1] * a[0],
            ]
        }
        2 => [g.signed(), g.signed(), 0.0],
        3 => g.pick(&[
            [1.0, 1.0, 0.0],
            [1.0, -1.0, 1.0],
            [0.0, -1.0, 1.0],
            [-1.0, -1.0, -1.0],
        ]),
        _ => [g.signed(), g.signed(), g.signed()],
    };
    if g.chance(1, 8) {
        n[g.r.below(3) as usize] = 0.0;
    }
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    let n = if len > 0.0 && len.is_finite() {
        n.map(|c| c / len)
    } else {
        [0.0, 0.0, 1.0]
    };
    n.map(|c| convert(FloatFormat::BINARY64, pf, c.to_bits(), RNE))
}

/// A realistic scene at scale `s`: a parent box split into two children,
/// a ray aimed into the parent (or anywhere), `k` normals.
pub(super) fn scene(g: &mut Gen, f: FloatFormat, pf: FloatFormat, k: usize, s: f64) -> Scene {
    let c = [0, 1, 2].map(|_| g.signed() * 8.0 * s);
    let h = [0, 1, 2].map(|_| {
        if g.chance(1, 16) {
            0.0
        } else {
            (0.05 + 2.0 * g.unit()) * s
        }
    });
    let lo = [0, 1, 2].map(|i| c[i] - h[i]);
    let hi = [0, 1, 2].map(|i| c[i] + h[i]);
    let p_min = lo.map(|v| from_f64(f, v));
    let axis = g.r.below(3) as usize;
    let split = lo[axis] + g.unit() * (hi[axis] - lo[axis]);
    let mut a_max = hi;
    a_max[axis] = split;
    let mut b_min = lo;
    b_min[axis] = split;
    let shrink = |g: &mut Gen, lo: [f64; 3], hi: [f64; 3]| {
        let t = [0, 1, 2].map(|_| g.unit() * 0.3);
        let u = [0, 1, 2].map(|_| g.unit() * 0.3);
        let l = [0, 1, 2].map(|i| lo[i] + t[i] * (hi[i] - lo[i]));
        let r = [0, 1, 2].map(|i| hi[i] - u[i] * (hi[i] - lo[i]));
        (l.map(|v| from_f64(f, v)), r.map(|v| from_f64(f, v)))
    };
    let boxes = [(lo, a_max), (b_min, hi)];
    let children = boxes.map(|(l, h)| shrink(g, l, h));
    let aim = g.r.below(2) as usize;
    let inside = g.chance(1, 8);
    let dist = (1.0 + 20.0 * g.unit()) * s;
    let dir0 = [g.signed(), g.signed(), g.signed()];
    let o = if inside {
        [0, 1, 2].map(|i| lo[i] + g.unit() * (hi[i] - lo[i]))
    } else {
        [0, 1, 2].map(|i| c[i] + dir0[i] * dist)
    };
    let (t_lo, t_hi) = if g.chance(3, 4) {
        let (l, h) = children[aim];
        (l.map(|v| to_f64(f, v)), h.map(|v| to_f64(f, v)))
    } else {
        (lo, hi)
    };
    let target = [0, 1, 2].map(|i| t_lo[i] + g.unit() * (t_hi[i] - t_lo[i]));
    let len = 2f64.powi(g.range(-4, 4) as i32) / s.max(f64::MIN_POSITIVE);
    let mut d = if g.chance(7, 8) {
        [0, 1, 2].map(|i| (target[i] - o[i]) * len)
    } else {
        [g.signed(), g.signed(), g.signed()]
    };
    if g.chance(1, 8) {
        d[g.r.below(3) as usize] = 0.0;
    }
    let normals = (0..k).map(|_| normal(g, pf, &d)).collect();
    Scene {
        p_min,
        children,
        aim,
        o: o.map(|v| from_f64(f, v)),
        d: d.map(|v| from_f64(f, v)),
        normals,
    }
}

/// A ray and normals exactly perpendicular: small integer normals, a
/// direction whose products with them cancel (`b_lo = 0`), zero
/// components, any scale.
pub(super) fn parallel(
    g: &mut Gen,
    f: FloatFormat,
    pf: FloatFormat,
    k: usize,
) -> ([u64; 3], Vec<[u64; 3]>) {
    let n0 = [0, 1, 2].map(|_| g.pick(&[-1.0, 0.0, 1.0, 2.0, -0.5]));
    let a = [0, 1, 2].map(|_| g.range(-3, 3) as f64);
    let s = 2f64.powi(g.range(-8, 8) as i32);
    let d = [
        n0[1] * a[2] - n0[2] * a[1],
        n0[2] * a[0] - n0[0] * a[2],
        n0[0] * a[1] - n0[1] * a[0],
    ]
    .map(|c| from_f64(f, c * s));
    let mut normals = vec![n0.map(|c| from_f64(pf, c))];
    for _ in 1..k {
        let n = if g.chance(1, 2) {
            n0.map(|c| from_f64(pf, -c))
        } else {
            [0, 1, 2].map(|_| from_f64(pf, g.pick(&[-1.0, 0.0, 1.0, 0.25])))
        };
        normals.push(n);
    }
    (d, normals)
}

/// Testbench of one `cull_ray` configuration.
pub struct CullRayBench {
    cfg: Config,
    unit: UnitConfig,
}

impl CullRayBench {
    /// The testbench of a `cull_ray` configuration (the `cull` unit's).
    pub fn new(unit: &UnitConfig) -> Self {
        CullRayBench {
            cfg: golden_config(unit),
            unit: *unit,
        }
    }

    /// The golden model's input from port values.
    pub fn unpack(&self, v: &[u64]) -> RayIn {
        let x: CullRayIn<u64> = ports::unpack(&self.unit, v);
        RayIn {
            o: x.o,
            d: x.d,
            r: x.r,
            normals: x.n,
        }
    }

    fn pack(&self, x: &RayIn, v: &mut [u64]) {
        self.to_ports(&x.o, &x.d, &x.r, &x.normals, v);
    }

    /// The input ports of one transaction (the renderer's call of
    /// `normal_terms_into`), each value masked to its port; normals beyond
    /// `normals.len()` read as 0, as in the golden model.
    pub fn to_ports(
        &self,
        o: &[u64; 3],
        d: &[u64; 3],
        r: &[u64; 3],
        normals: &[[u64; 3]],
        v: &mut [u64],
    ) {
        let (fm, pm) = (self.cfg.ray.mask(), self.cfg.plane.mask());
        let record = CullRayIn {
            o: o.map(|x| x & fm),
            d: d.map(|x| x & fm),
            r: r.map(|x| x & fm),
            n: (0..self.cfg.k)
                .map(|j| normals.get(j).map_or([0; 3], |n| n.map(|x| x & pm)))
                .collect(),
        };
        ports::pack(&self.unit, &record, v)
    }

    /// The per-normal terms of the output ports (the first `k` of `terms`).
    pub fn terms_from_ports(&self, out: &[u64], terms: &mut [NormalTerm]) {
        let x: CullRayOut<u64> = ports::unpack(&self.unit, out);
        for (t, x) in terms.iter_mut().zip(x.terms) {
            *t = NormalTerm {
                no_lo: x.no_lo,
                rcp_lo: x.rcp_lo,
                rcp_hi: x.rcp_hi,
                dir: Crossing::from_code(x.dir),
            };
        }
    }

    /// The golden configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }
}

impl sim::Golden for CullRayBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let t = ray_terms(&self.cfg, &self.unpack(inputs));
        let record = CullRayOut {
            terms: t
                .terms
                .iter()
                .map(|t| Terms {
                    no_lo: t.no_lo,
                    rcp_lo: t.rcp_lo,
                    rcp_hi: t.rcp_hi,
                    dir: t.dir.code(),
                })
                .collect(),
        };
        ports::pack(&self.unit, &record, outputs)
    }
}

impl sim::Stimulus for CullRayBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (f, pf, k) = (self.cfg.ray, self.cfg.plane, self.cfg.k);
        let mut rng = VectorRng::new(seed, index);
        let kind = index % 12;
        if kind == 9 {
            let raw: CullRayIn<u64> = ports::from_fn(&self.unit, |ty| rng.bits(ty.width()));
            return ports::pack(&self.unit, &raw, v);
        }
        let mut g = Gen { r: &mut rng };
        let s = if kind == 7 { 1.0 } else { scale(&mut g, f) };
        let sc = scene(&mut g, f, pf, k, s);
        let mut x = RayIn {
            o: sc.o,
            d: sc.d,
            r: sc.p_min,
            normals: sc.normals,
        };
        match kind {
            6 => {
                let (d, normals) = parallel(&mut g, f, pf, k);
                x.d = d;
                x.normals = normals;
            }
            7 => {
                // directions at the ends of the range
                let e = if g.chance(1, 2) {
                    f.emax() - g.range(0, 4) as i32
                } else {
                    f.emin() - g.range(0, f.frac_bits() as i64) as i32
                };
                for i in 0..3 {
                    let m = (1.0 + g.unit()) * if g.chance(1, 2) { -1.0 } else { 1.0 };
                    x.d[i] = from_f64(f, m * 2f64.powi(e.clamp(-1070, 1020)));
                    if g.chance(1, 4) {
                        x.d[i] = tiny(&mut g, f);
                    }
                }
            }
            8 => {
                let sf = specials(f);
                let sp = specials(pf);
                for _ in 0..g.range(1, 3) {
                    match g.r.below(4) {
                        0 => x.o[g.r.below(3) as usize] = g.pick(&sf),
                        1 => x.d[g.r.below(3) as usize] = g.pick(&sf),
                        2 => x.r[g.r.below(3) as usize] = g.pick(&sf),
                        _ => {
                            let j = g.r.below(k as u64) as usize;
                            x.normals[j][g.r.below(3) as usize] = g.pick(&sp);
                        }
                    }
                }
            }
            10 => {
                for i in 0..3 {
                    if g.chance(1, 2) {
                        x.d[i] = tiny(&mut g, f);
                    }
                    if g.chance(1, 3) {
                        x.o[i] = tiny(&mut g, f);
                    }
                    if g.chance(1, 3) {
                        x.r[i] = tiny(&mut g, f);
                    }
                    for n in x.normals.iter_mut() {
                        if g.chance(1, 3) {
                            n[i] = tiny(&mut g, pf);
                        }
                    }
                }
            }
            11 => {
                for i in 0..3 {
                    let big = |g: &mut Gen| nudge(f, f.max_finite(g.chance(1, 2)), -g.range(0, 3));
                    x.o[i] = big(&mut g);
                    if g.chance(1, 2) {
                        x.r[i] = big(&mut g);
                    }
                }
            }
            _ => {}
        }
        self.pack(&x, v);
    }
}

impl Testbench for CullRayBench {}
