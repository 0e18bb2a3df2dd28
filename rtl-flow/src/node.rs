//! Stimulus and golden-model adapter for `node`, the node tester
//! (`golden_model::node_reorigin::eval`).

use super::fstim::golden_format;
use super::slab::recip_rtz;
use super::stimulus::{mask, specials, VectorRng};
use super::Testbench;
use golden_model::float::{from_f64, nudge, FloatFormat};
use golden_model::node::{Bound, Dyadic, NodeIn as GoldenNode, NodeOut as GoldenOut, Ray, SlotOut};
use golden_model::node_reorigin::{eval, ReoriginParams};
use golden_model::wide::MAX_CHILDREN;
use rtl_gen::units::node::{Config, NodeIn, NodeOut, CELL_BITS, POS_FRAC, WINDOW_FLOOR};
use rtl_gen::units::ports;

/// Vectors, all seeded random. 7 in 8 are real nodes: a frame of random
/// scale (usually near 1, 1 in 8 at the ends of the format's exponent
/// range) and place (1 in 8 far from the origin), a ray aimed at a point of
/// it (components sometimes zero, tiny or huge), its start a lower bound of
/// the aimed point's `t` nudged down, `t_min` or `−∞`, the slots boxes
/// around the aimed point or anywhere. 1 in 8 draw every float from the
/// format's special values and random bits and every integer anywhere.
pub struct NodeBench {
    unit: Config,
    params: ReoriginParams,
    fmt: FloatFormat,
    specials: Vec<u64>,
}

impl NodeBench {
    /// The testbench of a `node` configuration.
    pub fn new(u: &Config) -> Self {
        let fmt = golden_format(u.fmt);
        let mut params = ReoriginParams::new(fmt, u.children as usize, u.box_bits);
        params.slope_bits = u.slope_bits;
        params.start_bits = u.start_bits;
        assert_eq!(
            params.pos_frac, POS_FRAC,
            "the position fraction is the model's"
        );
        assert_eq!(params.cell_bits, CELL_BITS, "the cell bits are the model's");
        assert_eq!(
            params.window_floor, WINDOW_FLOOR,
            "the window floor is the model's"
        );
        assert_eq!(
            params.window_bits(),
            u.window_bits(),
            "the window is the model's"
        );
        assert_eq!(
            params.end_window_bits(),
            u.end_window_bits(),
            "the window end's window is the model's"
        );
        NodeBench {
            unit: *u,
            params,
            fmt,
            specials: specials(fmt),
        }
    }

    fn float(&self, rng: &mut VectorRng, v: f64) -> u64 {
        let b = from_f64(self.fmt, v);
        match rng.below(8) {
            0 => nudge(self.fmt, b, rng.below(5) as i64 - 2),
            _ => b,
        }
    }

    fn wild(&self, rng: &mut VectorRng) -> u64 {
        if rng.below(2) == 0 {
            self.specials[rng.below(self.specials.len() as u64) as usize]
        } else {
            rng.bits(self.fmt.width())
        }
    }

    fn real(&self, rng: &mut VectorRng) -> NodeIn<u64> {
        let fmt = self.fmt;
        let u = &self.unit;
        let unif = |rng: &mut VectorRng| rng.below(1 << 24) as f64 / (1u64 << 24) as f64;
        let q = mask(u.box_bits) as f64;
        let (emin, emax) = (fmt.emin() as i64, fmt.emax() as i64);
        let exp: [i64; 3] = if rng.below(8) == 0 {
            // an end of the format's range, the frame's extent still finite
            // where the format can hold one (not in e3m2 with q = 8)
            let top = (emax - u.box_bits as i64 - 1).max(emin);
            let e = if rng.below(2) == 0 {
                emin + rng.below(4) as i64
            } else {
                top - rng.below(4) as i64
            };
            [e; 3].map(|e| (e + rng.below(3) as i64 - 1).clamp(emin, top))
        } else {
            let base = rng.below(20) as i64 - 12;
            [0; 3].map(|_| (base + rng.below(5) as i64 - 2).clamp(emin, emax))
        };
        let size = |e: i64| 2f64.powi(e as i32);
        let far = rng.below(8) == 0;
        let origin: [f64; 3] = std::array::from_fn(|a| {
            let span = size(exp[a]) * q;
            let place = if far { 1e6 } else { 4.0 };
            (unif(rng) - 0.5) * span * place
        });
        let origin_bits = origin.map(|v| from_f64(fmt, v));
        let origin = origin_bits.map(|b| golden_model::float::to_f64(fmt, b));
        let steps = [0; 3].map(|_| unif(rng) * q);
        let target: [f64; 3] = std::array::from_fn(|a| origin[a] + steps[a] * size(exp[a]));
        let scale = size(exp[0]) * q;
        let d: [f64; 3] = std::array::from_fn(|_| match rng.below(12) {
            0 => 0.0,
            1 => -0.0,
            2 => (unif(rng) - 0.5) * 1e-6,
            3 => (unif(rng) - 0.5) * 1e6,
            _ => unif(rng) - 0.5,
        });
        let d_bits = d.map(|v| from_f64(fmt, v));
        let t = unif(rng) * 4.0 * (scale / 0.5).max(1e-30);
        let o: [f64; 3] = std::array::from_fn(|a| target[a] - t * d[a]);
        let o_bits = o.map(|v| from_f64(fmt, v));
        let inv_d = d_bits.map(|b| recip_rtz(fmt, b));
        let (t_min, t_max) = match rng.below(4) {
            0 => (t * unif(rng), t * (1.0 + unif(rng))),
            1 => (f64::NEG_INFINITY, f64::INFINITY),
            2 => (t * (1.0 + unif(rng)), f64::INFINITY),
            _ => (0.0, f64::INFINITY),
        };
        let t_start = match rng.below(4) {
            0 => f64::NEG_INFINITY,
            1 => t_min,
            _ => t * (1.0 - unif(rng) * 0.25),
        };
        let valid = rng.bits(u.children) | 1;
        let mut lo = vec![[0u64; 3]; u.children as usize];
        let mut hi = vec![[0u64; 3]; u.children as usize];
        let q_max = mask(u.box_bits);
        for i in 0..u.children as usize {
            for a in 0..3 {
                let (x, y) = if rng.below(2) == 0 {
                    let c = steps[a] as u64;
                    let r = 1u64 << rng.below(u64::from(u.box_bits));
                    (
                        c.saturating_sub(rng.below(r)),
                        (c + rng.below(r)).min(q_max),
                    )
                } else {
                    let (x, y) = (rng.below(q_max + 1), rng.below(q_max + 1));
                    (x.min(y), x.max(y))
                };
                lo[i][a] = x;
                hi[i][a] = y;
            }
        }
        let ew = u.frame_exp_bits();
        let mut r = NodeIn {
            o: o_bits,
            d: d_bits,
            inv_d,
            t_min: self.float(rng, t_min),
            t_max: self.float(rng, t_max),
            t_start: self.float(rng, t_start),
            origin: origin_bits,
            exp: exp.map(|e| (e as u64) & mask(ew)),
            valid,
            lo,
            hi,
        };
        if rng.below(8) == 0 {
            // on the grid: directions ±2^j (or zero), an origin a whole number of half or
            // quarter frame steps from the frame origin, the segment from 0: every slope a power
            // of two, so entries and exits fall exactly on cell boundaries and rays meet the
            // boxes' planes, edges and corners exactly
            for a in 0..3 {
                let d = match rng.below(6) {
                    0 => 0.0,
                    k => 2f64.powi(k as i32 - 3),
                };
                let d = if rng.below(2) == 0 { -d } else { d };
                r.d[a] = from_f64(fmt, d);
                r.inv_d[a] = recip_rtz(fmt, r.d[a]);
                let frame = golden_model::float::to_f64(fmt, r.origin[a]);
                let step = size(exp[a]) / f64::from(1u32 << rng.below(3));
                let k = rng.below(3 * (q_max + 1)) as f64 - (q_max + 1) as f64;
                r.o[a] = from_f64(fmt, frame + k * step);
            }
            r.t_min = 0;
            r.t_start = if rng.below(2) == 0 { 0 } else { r.t_start };
        }
        if rng.below(16) == 0 {
            // an axis whose origin and frame origin are zeros and a start below the normal
            // range (rounded to +0): every window term of that axis zero
            let a = rng.below(3) as usize;
            let sign = 1u64 << (fmt.width() - 1);
            r.o[a] = if rng.below(2) == 0 { 0 } else { sign };
            r.origin[a] = if rng.below(2) == 0 { 0 } else { sign };
            let subnormal = 1 + rng.below(mask(fmt.frac_bits()));
            r.t_min = subnormal;
            r.t_start = subnormal;
        }
        r
    }

    fn random(&self, rng: &mut VectorRng) -> NodeIn<u64> {
        let u = &self.unit;
        let mut r: NodeIn<u64> = ports::from_fn(u, |_| 0);
        let ew = u.frame_exp_bits();
        for a in 0..3 {
            r.o[a] = self.wild(rng);
            r.d[a] = self.wild(rng);
            r.inv_d[a] = match rng.below(3) {
                0 => self.wild(rng),
                _ => recip_rtz(self.fmt, r.d[a]),
            };
            r.origin[a] = self.wild(rng);
            r.exp[a] = rng.bits(ew);
        }
        r.t_min = self.wild(rng);
        r.t_max = self.wild(rng);
        r.t_start = self.wild(rng);
        r.valid = rng.bits(u.children);
        for i in 0..u.children as usize {
            r.lo[i] = [0; 3].map(|_| rng.bits(u.box_bits));
            r.hi[i] = [0; 3].map(|_| rng.bits(u.box_bits));
        }
        r
    }
}

/// `v` of `w` bits, two's complement, as an integer.
fn signed(v: u64, w: u32) -> i64 {
    ((v << (64 - w)) as i64) >> (64 - w)
}

impl NodeBench {
    /// The model's parameters this configuration is the hardware of.
    pub fn params(&self) -> &ReoriginParams {
        &self.params
    }

    /// One node test as the unit's input port values (the renderer's calls
    /// packed as the testbench packs its vectors).
    pub fn to_ports(
        &self,
        ray: &Ray,
        d: &[u64; 3],
        t_start: u64,
        node: &GoldenNode,
        v: &mut [u64],
    ) {
        let u = &self.unit;
        let n = u.children as usize;
        let r = NodeIn {
            o: ray.o,
            d: *d,
            inv_d: ray.inv_d,
            t_min: ray.t_min,
            t_max: ray.t_max,
            t_start,
            origin: node.origin,
            exp: node.exp.map(|e| (e as u64) & mask(u.frame_exp_bits())),
            valid: u64::from(node.valid) & mask(u.children),
            lo: node.lo[..n].iter().map(|b| b.map(u64::from)).collect(),
            hi: node.hi[..n].iter().map(|b| b.map(u64::from)).collect(),
        };
        ports::pack(u, &r, v)
    }

    /// The unit's output port values as the model's result.
    pub fn result_from_ports(&self, out: &[u64]) -> GoldenOut {
        let u = &self.unit;
        let o: NodeOut<u64> = ports::unpack(u, out);
        let t_base = if o.t_base == self.fmt.inf(true) {
            Bound::NegInf
        } else {
            let v = golden_model::float::to_f64(self.fmt, o.t_base);
            let (m, e) = exact_f64(v);
            Bound::Fin(Dyadic::new(m.into(), e))
        };
        GoldenOut {
            bad: o.bad != 0,
            t_base,
            grid_exp: signed(o.grid_exp, u.grid_exp_bits()),
            slots: (0..u.children as usize)
                .map(|j| SlotOut {
                    hit: o.hit[j] != 0,
                    entry: o.entry[j] as u32,
                    child: o.child[j] as u8,
                })
                .collect(),
        }
    }

    /// The model's answer to one vector of port values.
    fn model(&self, inputs: &[u64]) -> GoldenOut {
        let u = &self.unit;
        let r: NodeIn<u64> = ports::unpack(u, inputs);
        let ray = Ray {
            o: r.o,
            inv_d: r.inv_d,
            t_min: r.t_min,
            t_max: r.t_max,
        };
        let mut node = GoldenNode {
            origin: r.origin,
            exp: r.exp.map(|e| signed(e, u.frame_exp_bits()) as i32),
            valid: r.valid as u8,
            lo: [[0; 3]; MAX_CHILDREN],
            hi: [[0; 3]; MAX_CHILDREN],
        };
        for i in 0..u.children as usize {
            node.lo[i] = r.lo[i].map(|v| v as u16);
            node.hi[i] = r.hi[i].map(|v| v as u16);
        }
        eval(&self.params, &ray, r.d, r.t_start, &node)
    }
}

/// A finite binary64 value as `m · 2^e` (`m` an integer of at most 53 bits).
fn exact_f64(v: f64) -> (i64, i64) {
    if v == 0.0 {
        return (0, 0);
    }
    let bits = v.to_bits();
    let exp = ((bits >> 52) & 0x7ff) as i64;
    let frac = (bits & ((1 << 52) - 1)) as i64;
    let (m, e) = if exp == 0 {
        (frac, -1074)
    } else {
        (frac | 1 << 52, exp - 1075)
    };
    (if v < 0.0 { -m } else { m }, e)
}

impl sim::Golden for NodeBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let u = &self.unit;
        let fmt = self.fmt;
        let out = self.model(inputs);
        let t_base = match &out.t_base {
            Bound::NegInf => fmt.inf(true),
            // T is a value of the format: exact in binary64
            Bound::Fin(t) => {
                let m = i64::try_from(t.m.clone()).expect("a significand of the format");
                let v = m as f64 * 2f64.powi(t.e as i32);
                from_f64(fmt, v)
            }
        };
        let o = NodeOut {
            bad: out.bad as u64,
            t_base,
            grid_exp: (out.grid_exp as u64) & mask(u.grid_exp_bits()),
            hit: out.slots.iter().map(|s| s.hit as u64).collect(),
            entry: out.slots.iter().map(|s| u64::from(s.entry)).collect(),
            child: out.slots.iter().map(|s| u64::from(s.child)).collect(),
        };
        ports::pack(u, &o, outputs)
    }
}

impl sim::Stimulus for NodeBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let mut rng = VectorRng::new(seed, index);
        let r = if rng.below(8) == 0 {
            self.random(&mut rng)
        } else {
            self.real(&mut rng)
        };
        ports::pack(&self.unit, &r, v)
    }
}

impl Testbench for NodeBench {}
