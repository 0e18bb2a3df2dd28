//! Stimulus and golden-model adapter for `transform` (issue #5).
//!
//! Vectors: first every combination of special instances (the seed's M1–M3,
//! identity, pure rotations, scales of 1e-3 and 1e3, translations up to 1e6,
//! near-singular and singular `R`, non-finite, zero and subnormal entries)
//! with special rays (origin at `T` and one ulp away, ±0, ±inf, NaN,
//! subnormal and huge components, NaN-payload `t` values); then seeded random
//! vectors: random placements of several scale classes (one at the ends of
//! the format, where the inversion's determinant overflows or underflows),
//! origins at offsets
//! `10^U(−4, 6)` from `T`, random directions, and one input in eight replaced
//! by a special value or random bits. For `inverse=hw` the input is `R`, and
//! the rotation hint is set on half of the pure rotations, one in sixteen of
//! the others and on a copy of every corner instance. For `inverse=pre` the
//! `R⁻¹` input of the
//! corner cases is the scene builder's (the exact inverse rounded once); for
//! random vectors it is the binary64 inverse rounded, which is as good a
//! stimulus and much cheaper.

use super::fstim::{golden_format, golden_mode};
use super::stimulus::{mask, specials, VectorRng};
use super::Testbench;
use golden_model::transform::accuracy::{forward, from_f64, rotation, Placement, SEED_MATRICES};
use golden_model::transform::exact::scene_builder_inverse;
use golden_model::transform::{
    transform, Config, DotStyle, InstanceTransform, InverseSource, ModelRay, WorldRay,
};
use rtl_gen::units::ports;
use rtl_gen::units::transform::{self as unit, Dot, TransformIn, TransformOut};

/// One transaction before packing into ports.
#[derive(Debug, Clone, Copy)]
struct Case {
    ray: WorldRay,
    inst: InstanceTransform,
    /// half throughput: the vector is the origin (else the direction)
    is_origin: bool,
}

/// The testbench of one `transform` configuration.
pub struct TransformBench {
    cfg: Config,
    instances: Vec<InstanceTransform>,
    rays: Vec<WorldRay>,
    unit: unit::Config,
}

impl TransformBench {
    /// The testbench of a `transform` configuration (mapped onto the
    /// golden model's).
    pub fn new(u: &unit::Config) -> Self {
        let cfg = Config {
            fmt: golden_format(u.fmt),
            mode: golden_mode(u.mode),
            dot: match u.dot {
                Dot::Separate => DotStyle::Separate,
                Dot::Fma => DotStyle::Fma,
                Dot::Dot3 => DotStyle::Dot3,
                Dot::Wide => DotStyle::Wide,
            },
            source: if u.hw {
                InverseSource::Hardware
            } else {
                InverseSource::PreInverted
            },
        };
        let mut bench = TransformBench {
            cfg,
            instances: Vec::new(),
            rays: Vec::new(),
            unit: *u,
        };
        bench.instances = bench.corner_instances();
        bench.rays = bench.corner_rays();
        bench
    }

    /// The instance input for forward `(R, T)`: `R` or the scene builder's `R⁻¹`.
    fn instance(&self, r: [u64; 9], t: [u64; 3], exact: bool) -> InstanceTransform {
        let linear = match self.cfg.source {
            InverseSource::Hardware => r,
            InverseSource::PreInverted if exact => {
                scene_builder_inverse(self.cfg.fmt, self.cfg.mode, &r)
            }
            InverseSource::PreInverted => self.f64_inverse(&r),
        };
        InstanceTransform {
            linear,
            translation: t,
            rotation_hint: false,
        }
    }

    /// `R⁻¹` by the binary64 adjugate, rounded to the format (NaN if singular).
    fn f64_inverse(&self, r: &[u64; 9]) -> [u64; 9] {
        let fmt = self.cfg.fmt;
        let a: [f64; 9] = r.map(|x| golden_model::float::to_f64(fmt, x));
        let at = |i: usize, j: usize| a[3 * (i % 3) + (j % 3)];
        let adj: [f64; 9] = std::array::from_fn(|k| {
            let (i, j) = (k / 3, k % 3);
            at(j + 1, i + 1) * at(j + 2, i + 2) - at(j + 1, i + 2) * at(j + 2, i + 1)
        });
        let det = a[0] * adj[0] + a[1] * adj[3] + a[2] * adj[6];
        adj.map(|x| from_f64(fmt, x / det))
    }

    fn corner_instances(&self) -> Vec<InstanceTransform> {
        let fmt = self.cfg.fmt;
        let f = |x: f64| from_f64(fmt, x);
        let mut v = Vec::new();
        for (_, p) in SEED_MATRICES {
            let (r, t) = forward(fmt, &p);
            v.push(self.instance(r, t, true));
        }
        let one = f(1.0);
        let id = [one, 0, 0, 0, one, 0, 0, 0, one];
        v.push(self.instance(id, [0; 3], true));
        v.push(self.instance(id, [f(1e6), f(-1e6), f(3.5)], true));
        let placements = [
            ([0.0, 0.0, 1.0], 90.0, [1.0; 3], [10.0, -20.0, 30.0]),
            ([1.0, 0.0, 0.0], 180.0, [1.0; 3], [-1e6, 0.0, 1e6]),
            ([0.3, -0.5, 0.8], 37.0, [1.0; 3], [123.25, 4567.5, -8.0]),
            ([0.2, 0.9, -0.1], 211.0, [1e-3; 3], [1e5, -3e5, 7e5]),
            ([-0.7, 0.1, 0.4], 77.0, [1e3; 3], [-1e6, 1e6, -1e6]),
            ([0.0, 1.0, 1.0], 45.0, [1.0, 1.0, 1e-6], [5.0, 6.0, 7.0]),
        ];
        for (axis, angle_deg, scale, translation) in placements {
            let (r, t) = forward(
                fmt,
                &Placement {
                    axis,
                    angle_deg,
                    scale,
                    translation,
                },
            );
            v.push(self.instance(r, t, true));
        }
        // near-singular: [[1,2,3],[4,5,6],[7,8,9+2^-20]]; singular: rows 1 and 2 proportional
        let near = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0 + 2f64.powi(-20)].map(f);
        v.push(self.instance(near, [f(1.0), f(2.0), f(3.0)], true));
        let sing = [1.0, 2.0, 3.0, 2.0, 4.0, 6.0, 0.0, 0.0, 1.0].map(f);
        v.push(self.instance(sing, [0; 3], true));
        // raw specials in the linear input and in T
        let s = specials(fmt);
        for (k, &x) in s.iter().enumerate() {
            let mut lin = [one, 0, 0, 0, one, 0, 0, 0, one];
            lin[(k * 4) % 9] = x;
            v.push(InstanceTransform {
                linear: lin,
                translation: [0; 3],
                rotation_hint: false,
            });
            v.push(InstanceTransform {
                linear: [one, 0, 0, 0, one, 0, 0, 0, one],
                translation: [f(2.0), x, f(-2.0)],
                rotation_hint: false,
            });
        }
        v.push(InstanceTransform {
            linear: [0; 9],
            translation: [0; 3],
            rotation_hint: false,
        });
        if self.cfg.source == InverseSource::Hardware {
            // the rotation hint on every instance (a hint on a non-rotation is
            // the caller's promise: the unit uses the transpose all the same)
            let hinted: Vec<_> = v
                .iter()
                .map(|i| InstanceTransform {
                    rotation_hint: true,
                    ..*i
                })
                .collect();
            v.extend(hinted);
        }
        v
    }

    fn corner_rays(&self) -> Vec<WorldRay> {
        let fmt = self.cfg.fmt;
        let f = |x: f64| from_f64(fmt, x);
        let ray = |o: [u64; 3], d: [u64; 3]| WorldRay {
            origin: o,
            dir: d,
            t_min: f(0.0),
            t_max: fmt.inf(false),
            id: 0x5a5a_5a5a_5a5a_5a5a & mask(self.unit.id_bits),
        };
        let mut v = vec![
            ray([0; 3], [f(1.0), 0, 0]),
            ray([fmt.sign_bit(); 3], [fmt.sign_bit(), 0, fmt.sign_bit()]),
            ray([f(1.0), f(-2.0), f(3.0)], [f(0.0), f(0.0), f(-1.0)]),
            ray([f(1e6), f(-1e6), f(1e6)], [f(1e-3), f(1e3), f(-1.0)]),
            ray([fmt.max_finite(false); 3], [fmt.max_finite(true); 3]),
            ray([fmt.min_subnormal(false); 3], [fmt.max_subnormal(true); 3]),
            ray([fmt.inf(false), 0, 0], [0, fmt.inf(true), 0]),
            ray([0, 0, fmt.canonical_nan()], [0, 0, fmt.canonical_nan() | 3]),
        ];
        let mut r = ray([f(0.5); 3], [f(0.25); 3]);
        r.t_min = fmt.canonical_nan() | fmt.sign_bit() | 1;
        r.t_max = fmt.sign_bit();
        r.id = mask(self.unit.id_bits);
        v.push(r);
        v
    }

    /// Corner rays relative to an instance: origin at `T`, one ulp above `T`.
    fn relative_rays(&self, inst: &InstanceTransform) -> [WorldRay; 2] {
        let fmt = self.cfg.fmt;
        let t = inst.translation;
        let up = t.map(|x| {
            if fmt.is_nan(x) {
                x
            } else {
                (x + 1) & fmt.mask()
            }
        });
        let d = [from_f64(fmt, 0.6), from_f64(fmt, -0.8), 0];
        let r = |o| WorldRay {
            origin: o,
            dir: d,
            t_min: from_f64(fmt, 1e-3),
            t_max: from_f64(fmt, 1e4),
            id: 1,
        };
        [r(t), r(up)]
    }

    fn rays_per_instance(&self) -> u64 {
        self.rays.len() as u64 + 2
    }

    fn corner_count(&self) -> u64 {
        let n = self.instances.len() as u64 * self.rays_per_instance();
        if self.unit.full {
            n
        } else {
            2 * n
        }
    }

    fn corner(&self, index: u64) -> Case {
        let (index, is_origin) = if self.unit.full {
            (index, true)
        } else {
            (index / 2, index.is_multiple_of(2))
        };
        let per = self.rays_per_instance();
        let inst = self.instances[(index / per) as usize];
        let k = (index % per) as usize;
        let ray = if k < self.rays.len() {
            self.rays[k]
        } else {
            self.relative_rays(&inst)[k - self.rays.len()]
        };
        Case {
            ray,
            inst,
            is_origin,
        }
    }

    fn random(&self, seed: u64, index: u64) -> Case {
        let fmt = self.cfg.fmt;
        let mut rng = VectorRng::new(seed, index);
        let unit = |rng: &mut VectorRng| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let range = |rng: &mut VectorRng, lo: f64, hi: f64| lo + (hi - lo) * unit(rng);
        let sign = |rng: &mut VectorRng| if rng.below(2) == 0 { 1.0 } else { -1.0 };
        let dir3 = |rng: &mut VectorRng| {
            let z = range(rng, -1.0, 1.0);
            let phi = range(rng, 0.0, std::f64::consts::TAU);
            let r = (1.0 - z * z).sqrt();
            [r * phi.cos(), r * phi.sin(), z]
        };
        // scales as powers of ten; class 6, the ends of the format: |det| ~ scale^3
        // around the largest or smallest normal (the inversion's overflow in every mode)
        let edge = f64::from(fmt.emax()) / 3.0 * std::f64::consts::LOG10_2;
        let (lo, hi) = match rng.below(7) {
            0 => (-3.5, -2.5),
            1 => (2.5, 3.5),
            2 => (0.0, 0.0),
            6 if rng.below(2) == 0 => (edge - 0.5, edge + 0.5),
            6 => (-edge - 0.5, -edge + 0.5),
            _ => (-1.0, 1.0),
        };
        let mut scale = [(); 3].map(|_| sign(&mut rng) * 10f64.powf(range(&mut rng, lo, hi)));
        if rng.below(8) == 0 {
            scale[rng.below(3) as usize] *= 10f64.powf(range(&mut rng, -7.0, -4.0));
        }
        let tmag = range(&mut rng, -3.0, 6.0);
        let p = Placement {
            axis: dir3(&mut rng),
            angle_deg: range(&mut rng, 0.0, 360.0),
            scale,
            translation: [(); 3]
                .map(|_| sign(&mut rng) * 10f64.powf(tmag + range(&mut rng, -1.0, 0.0))),
        };
        let rot = rotation(p.axis, p.angle_deg);
        let r = std::array::from_fn(|k| from_f64(fmt, p.scale[k / 3] * rot[k]));
        let t = p.translation.map(|x| from_f64(fmt, x));
        let mut inst = self.instance(r, t, false);
        let pure_rotation = lo == 0.0 && hi == 0.0;
        inst.rotation_hint = self.cfg.source == InverseSource::Hardware
            && rng.below(if pure_rotation { 2 } else { 16 }) == 0;
        let off = if rng.below(8) == 0 {
            0.0
        } else {
            10f64.powf(range(&mut rng, -4.0, 6.0))
        };
        let u = dir3(&mut rng);
        let origin = [0, 1, 2].map(|k| from_f64(fmt, p.translation[k] + off * u[k]));
        let dmag = 10f64.powf(range(&mut rng, -3.0, 3.0));
        let dir = dir3(&mut rng).map(|x| from_f64(fmt, x * dmag));
        let mut ray = WorldRay {
            origin,
            dir,
            t_min: from_f64(fmt, range(&mut rng, 0.0, 1.0)),
            t_max: from_f64(fmt, 10f64.powf(range(&mut rng, 0.0, 6.0))),
            id: rng.bits(self.unit.id_bits),
        };
        // one vector in eight: one input replaced by a special value or random bits
        if rng.below(8) == 0 {
            let s = specials(fmt);
            let x = if rng.below(4) == 0 {
                rng.bits(fmt.width())
            } else {
                s[rng.below(s.len() as u64) as usize]
            };
            match rng.below(5) {
                0 => ray.origin[rng.below(3) as usize] = x,
                1 => ray.dir[rng.below(3) as usize] = x,
                2 => inst.linear[rng.below(9) as usize] = x,
                3 => inst.translation[rng.below(3) as usize] = x,
                _ => {
                    ray.t_min = x;
                    ray.t_max = rng.bits(fmt.width());
                }
            }
        }
        Case {
            ray,
            inst,
            is_origin: rng.below(2) == 0,
        }
    }

    fn case(&self, seed: u64, index: u64) -> Case {
        if index < self.corner_count() {
            self.corner(index)
        } else {
            self.random(seed, index)
        }
    }

    /// Packs a case in the unit's input port order.
    fn pack(&self, c: &Case, v: &mut [u64]) {
        let (origin_or_vector, direction) = match (self.unit.full, c.is_origin) {
            (true, _) => (c.ray.origin, Some(c.ray.dir)),
            (false, true) => (c.ray.origin, None),
            (false, false) => (c.ray.dir, None),
        };
        let record = TransformIn {
            origin_or_vector,
            direction,
            is_origin: Some(c.is_origin as u64),
            t_min: c.ray.t_min,
            t_max: c.ray.t_max,
            id: c.ray.id & mask(self.unit.id_bits),
            linear: c.inst.linear,
            translation: c.inst.translation,
            rotation_hint: Some(c.inst.rotation_hint as u64),
        };
        ports::pack(&self.unit, &record, v)
    }

    /// Unpacks the input ports into a case.
    fn unpack(&self, v: &[u64]) -> Case {
        let r: TransformIn<u64> = ports::unpack(&self.unit, v);
        let first = r.origin_or_vector;
        Case {
            ray: WorldRay {
                origin: first,
                dir: r.direction.unwrap_or(first),
                t_min: r.t_min,
                t_max: r.t_max,
                id: r.id,
            },
            inst: InstanceTransform {
                linear: r.linear,
                translation: r.translation,
                rotation_hint: r.rotation_hint.is_some_and(|x| x != 0),
            },
            is_origin: r.is_origin.is_none_or(|x| x != 0),
        }
    }

    /// The input ports of one transaction of a full-throughput unit (origin
    /// and direction together: the renderer's call of `transform`).
    pub fn to_ports(&self, ray: &WorldRay, inst: &InstanceTransform, v: &mut [u64]) {
        assert!(
            self.unit.full,
            "one transaction per ray needs throughput=full"
        );
        self.pack(
            &Case {
                ray: *ray,
                inst: *inst,
                is_origin: true,
            },
            v,
        );
    }

    /// The output ports of `m` (of the origin or the direction alone at
    /// half throughput).
    fn outputs_of(&self, m: &ModelRay, is_origin: bool, outputs: &mut [u64]) {
        let record = TransformOut {
            origin_or_vector: if self.unit.full || is_origin {
                m.origin
            } else {
                m.dir
            },
            direction: Some(m.dir),
            t_min: m.t_min,
            t_max: m.t_max,
            id: m.id,
            singular: m.singular as u64,
        };
        ports::pack(&self.unit, &record, outputs)
    }

    /// The model ray of a full-throughput unit's output ports (the inverse
    /// of the golden side's packing).
    pub fn model_ray_from_ports(&self, out: &[u64]) -> ModelRay {
        assert!(
            self.unit.full,
            "one transaction per ray needs throughput=full"
        );
        let r: TransformOut<u64> = ports::unpack(&self.unit, out);
        ModelRay {
            origin: r.origin_or_vector,
            dir: r.direction.expect("full throughput has a direction output"),
            t_min: r.t_min,
            t_max: r.t_max,
            id: r.id,
            singular: r.singular != 0,
        }
    }

    /// The golden configuration.
    pub fn config(&self) -> &Config {
        &self.cfg
    }
}

impl sim::Golden for TransformBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let c = self.unpack(inputs);
        let m = transform(&self.cfg, &c.ray, &c.inst);
        self.outputs_of(&m, c.is_origin, outputs);
    }
}

impl sim::Stimulus for TransformBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let c = self.case(seed, index);
        self.pack(&c, v);
    }
}

impl Testbench for TransformBench {}

#[cfg(test)]
mod tests {
    use super::*;
    use sim::{Golden, Stimulus};

    /// The stimulus reaches both sides of the flag, NaN and infinite
    /// results, exact zeros (origin at `T`) and, with `inverse=hw`, the hint.
    #[test]
    fn stimulus_covers_flag_specials_and_hint() {
        use rtl_gen::params::ParamSet;
        use rtl_gen::units::transform::{Inverse, Throughput, TransformParams};
        let pre = TransformParams::defaults();
        let hw_half = TransformParams {
            inverse: Inverse::Hw,
            throughput: Throughput::Half,
            ..pre
        };
        for p in [pre, hw_half] {
            let spec = rtl_gen::units::transform::Transform;
            let unit = rtl_gen::units::Description::config(&spec, &p).unwrap();
            let tb = TransformBench::new(&unit);
            let fmt = tb.cfg.fmt;
            let n_in = ports::list::<TransformIn<()>>(&unit).len();
            let n_out = ports::list::<TransformOut<()>>(&unit).len();
            let (mut v, mut o) = (vec![0u64; n_in], vec![0u64; n_out]);
            let out: TransformOut<usize> = ports::positions(&unit);
            let hint_at = ports::positions::<TransformIn<usize>>(&unit).rotation_hint;
            let vecs: Vec<usize> = out
                .origin_or_vector
                .into_iter()
                .chain(out.direction.into_iter().flatten())
                .collect();
            let (mut singular, mut nan, mut inf, mut zero, mut hint) = (0, 0, 0, 0, 0);
            let total = 50_000u64;
            for i in 0..total {
                tb.vector(3, i, &mut v);
                tb.eval(&v, &mut o);
                let is_singular = o[out.singular] == 1;
                singular += is_singular as u64;
                nan += (!is_singular && vecs.iter().any(|&k| fmt.is_nan(o[k]))) as u64;
                inf += vecs
                    .iter()
                    .any(|&k| o[k] & !fmt.sign_bit() == fmt.inf(false))
                    as u64;
                zero += (!is_singular
                    && out
                        .origin_or_vector
                        .iter()
                        .all(|&k| o[k] & !fmt.sign_bit() == 0)) as u64;
                hint += hint_at.is_some_and(|k| v[k] == 1) as u64;
            }
            let pct = |x: u64| 100.0 * x as f64 / total as f64;
            eprintln!(
                "{p:?}: corners {}, singular {:.1}%, NaN without flag {:.1}%, inf {:.1}%, zero vector {:.1}%, hint {:.1}%",
                tb.corner_count(), pct(singular), pct(nan), pct(inf), pct(zero), pct(hint)
            );
            assert!(pct(singular) > 1.0 && pct(singular) < 30.0);
            assert!(nan > 100 && inf > 100 && zero > 100);
            if tb.cfg.source == InverseSource::Hardware {
                assert!(pct(hint) > 5.0);
            }
        }
    }
}
