//! Stimulus and golden-model adapter for `node_child`, the node tester's
//! per-child test (`golden_model::node::child`).

use super::stimulus::{mask, VectorRng};
use super::Testbench;
use golden_model::float::{from_f64, FloatFormat};
use golden_model::node::{self, ChildAxis, NodeIn, NodeParams, NodeTerms, Ray, SlabTerms};
use rtl_gen::units::node_child::{Config, NodeChildIn, NodeChildOut, GRID_FRAC};
use rtl_gen::units::ports;

/// Vectors, all seeded random: 3 in 4 from real nodes (a binary32 ray aimed
/// at a point of a random frame, sometimes parallel to an axis or with a
/// cut segment, its per-node integers from `golden_model::node::terms`, the
/// slot a random box, often around the aimed point), 1 in 4 per-node
/// integers drawn anywhere in their ranges (extremes, infinities, anchors at
/// the ends) with a random slot.
pub struct NodeChildBench {
    unit: Config,
    params: NodeParams,
}

impl NodeChildBench {
    /// The testbench of a `node_child` configuration.
    pub fn new(u: &Config) -> Self {
        let params = NodeParams::new(FloatFormat::BINARY32, 4, u.box_bits)
            .expect("node_child accepts only configurations of the model");
        assert_eq!(params.grid_bits(), u.grid_bits(), "the grid is the model's");
        assert_eq!(params.grid_frac(), GRID_FRAC, "the grid is the model's");
        NodeChildBench { unit: *u, params }
    }

    fn q_max(&self) -> u64 {
        mask(self.unit.box_bits)
    }

    /// Per-node integers of a real node and a ray through it, if the input
    /// is not bad.
    fn real_terms(&self, rng: &mut VectorRng) -> Option<(NodeTerms, [f64; 3])> {
        let fmt = FloatFormat::BINARY32;
        let unif = |rng: &mut VectorRng| rng.below(1 << 24) as f64 / (1u64 << 24) as f64;
        let q = self.q_max() as f64;
        let exp = [0; 3].map(|_| rng.below(12) as i32 - 8);
        let origin = [0; 3].map(|_| (unif(rng) - 0.5) * 64.0);
        // the aimed point, in frame steps
        let steps = [0; 3].map(|_| unif(rng) * q);
        let target: [f64; 3] = std::array::from_fn(|a| origin[a] + steps[a] * (2f64).powi(exp[a]));
        let dir: [f64; 3] = std::array::from_fn(|_| match rng.below(10) {
            0 => 0.0,
            1 => -0.0,
            2 => (unif(rng) - 0.5) * 1e-6,
            _ => unif(rng) - 0.5,
        });
        let t = unif(rng) * 100.0;
        let o: [f64; 3] = std::array::from_fn(|a| target[a] - t * dir[a]);
        let inv = |d: f64| {
            if d == 0.0 {
                // ±∞: the sign of the zero
                from_f64(
                    fmt,
                    if rng_sign(d) {
                        f64::NEG_INFINITY
                    } else {
                        f64::INFINITY
                    },
                )
            } else {
                from_f64(fmt, 1.0 / d)
            }
        };
        let (t_min, t_max) = match rng.below(4) {
            0 => (t * unif(rng), t * (1.0 + unif(rng))),
            1 => (f64::NEG_INFINITY, f64::INFINITY),
            2 => (t * (1.0 + unif(rng)), f64::INFINITY),
            _ => (0.0, f64::INFINITY),
        };
        let ray = Ray {
            o: o.map(|v| from_f64(fmt, v)),
            inv_d: dir.map(inv),
            t_min: from_f64(fmt, t_min),
            t_max: from_f64(fmt, t_max),
        };
        let n = NodeIn {
            origin: origin.map(|v| from_f64(fmt, v)),
            exp,
            valid: 1,
            lo: Default::default(),
            hi: Default::default(),
        };
        node::terms(self.params, &ray, &n).map(|t| (t, steps))
    }

    /// Per-node integers anywhere in their ranges.
    fn random_terms(&self, rng: &mut VectorRng) -> NodeTerms {
        let k = self.params.grid_bits();
        let z = 1i64 << (k + GRID_FRAC + 1);
        let q_max = self.q_max() as i64;
        let top = 1i64 << k;
        let value = |rng: &mut VectorRng, lo: i64, hi: i64| -> i64 {
            match rng.below(6) {
                0 => lo,
                1 => hi,
                2 => (lo + rng.below(4) as i64).min(hi),
                3 => (hi - rng.below(4) as i64).max(lo),
                4 => (rng.below(64) as i64 - 32).clamp(lo, hi),
                _ => lo + rng.below((hi - lo + 1) as u64) as i64,
            }
        };
        let far_top = value(rng, 0, top);
        let axes = [0; 3].map(|_| {
            if rng.below(4) == 0 {
                ChildAxis::Parallel {
                    lo: value(rng, -1, q_max + 1),
                    hi: value(rng, -1, q_max + 1),
                }
            } else {
                let at = |rng: &mut VectorRng| (rng.below(8) != 0).then(|| value(rng, -z, z));
                ChildAxis::Slab(SlabTerms {
                    mirror: rng.below(2) == 1,
                    near_n0: value(rng, 0, q_max),
                    near_at: [at(rng), at(rng)],
                    near_slope: value(rng, 0, z),
                    far_n0: value(rng, 0, q_max),
                    far_at: [at(rng), at(rng), at(rng)],
                    far_slope_dn: value(rng, 0, z),
                    far_slope_up: (rng.below(8) != 0).then(|| value(rng, 0, z)),
                })
            }
        });
        NodeTerms {
            miss: rng.below(16) == 0,
            far_top,
            axes,
        }
    }

    fn pack_terms(
        &self,
        t: &NodeTerms,
        valid: bool,
        lo: [u64; 3],
        hi: [u64; 3],
    ) -> NodeChildIn<u64> {
        let u = &self.unit;
        let s = |v: i64, w: u32| (v as u64) & mask(w);
        let mut r = NodeChildIn {
            valid: valid as u64,
            miss: t.miss as u64,
            far_top: t.far_top as u64,
            lo,
            hi,
            ..ports::from_fn(u, |_| 0u64)
        };
        for (a, ax) in t.axes.iter().enumerate() {
            match ax {
                ChildAxis::Parallel { lo, hi } => {
                    r.parallel[a] = 1;
                    r.pos_lo[a] = s(*lo, u.pos_bits());
                    r.pos_hi[a] = s(*hi, u.pos_bits());
                }
                ChildAxis::Slab(sa) => {
                    let at = |v: Option<i64>| (s(v.unwrap_or(0), u.at_bits()), v.is_none() as u64);
                    r.mirror[a] = sa.mirror as u64;
                    r.near_n0[a] = sa.near_n0 as u64;
                    (r.near_at_n0[a], r.near_inf_n0[a]) = at(sa.near_at[0]);
                    (r.near_at_next[a], r.near_inf_next[a]) = at(sa.near_at[1]);
                    r.near_slope[a] = sa.near_slope as u64;
                    r.far_n0[a] = sa.far_n0 as u64;
                    (r.far_at_prev[a], r.far_inf_prev[a]) = at(sa.far_at[0]);
                    (r.far_at_n0[a], r.far_inf_n0[a]) = at(sa.far_at[1]);
                    (r.far_at_next[a], r.far_inf_next[a]) = at(sa.far_at[2]);
                    r.far_slope_dn[a] = sa.far_slope_dn as u64;
                    r.far_slope_up[a] = sa.far_slope_up.unwrap_or(0) as u64;
                    r.far_slope_up_inf[a] = sa.far_slope_up.is_none() as u64;
                }
            }
        }
        r
    }
}

/// The sign bit of a zero.
fn rng_sign(d: f64) -> bool {
    d.is_sign_negative()
}

/// `v` of `w` bits, two's complement, as an integer.
fn signed(v: u64, w: u32) -> i64 {
    ((v << (64 - w)) as i64) >> (64 - w)
}

impl sim::Golden for NodeChildBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let u = &self.unit;
        let r: NodeChildIn<u64> = ports::unpack(u, inputs);
        let axes = [0, 1, 2].map(|a| {
            if r.parallel[a] != 0 {
                return ChildAxis::Parallel {
                    lo: signed(r.pos_lo[a], u.pos_bits()),
                    hi: signed(r.pos_hi[a], u.pos_bits()),
                };
            }
            let at = |v: u64, inf: u64| (inf == 0).then(|| signed(v, u.at_bits()));
            ChildAxis::Slab(SlabTerms {
                mirror: r.mirror[a] != 0,
                near_n0: r.near_n0[a] as i64,
                near_at: [
                    at(r.near_at_n0[a], r.near_inf_n0[a]),
                    at(r.near_at_next[a], r.near_inf_next[a]),
                ],
                near_slope: r.near_slope[a] as i64,
                far_n0: r.far_n0[a] as i64,
                far_at: [
                    at(r.far_at_prev[a], r.far_inf_prev[a]),
                    at(r.far_at_n0[a], r.far_inf_n0[a]),
                    at(r.far_at_next[a], r.far_inf_next[a]),
                ],
                far_slope_dn: r.far_slope_dn[a] as i64,
                far_slope_up: (r.far_slope_up_inf[a] == 0).then_some(r.far_slope_up[a] as i64),
            })
        });
        let t = NodeTerms {
            miss: r.miss != 0,
            far_top: r.far_top as i64,
            axes,
        };
        let box_of = |v: [u64; 3]| v.map(|x| x as u16);
        let entry = node::child(self.params, &t, r.valid != 0, box_of(r.lo), box_of(r.hi));
        let out = NodeChildOut {
            hit: entry.is_some() as u64,
            entry: u64::from(entry.unwrap_or(self.params.miss_entry())),
        };
        ports::pack(u, &out, outputs)
    }
}

impl sim::Stimulus for NodeChildBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let mut rng = VectorRng::new(seed, index);
        let q_max = self.q_max();
        let real = if rng.below(4) != 0 {
            self.real_terms(&mut rng)
        } else {
            None
        };
        let (terms, around) = match real {
            Some((t, steps)) => (t, Some(steps)),
            None => (self.random_terms(&mut rng), None),
        };
        let mut lo = [0u64; 3];
        let mut hi = [0u64; 3];
        for a in 0..3 {
            let (x, y) = match around {
                // a box around the aimed point, or next to it
                Some(steps) if rng.below(2) == 0 => {
                    let c = steps[a] as u64;
                    let r = 1u64 << rng.below(u64::from(self.unit.box_bits));
                    (
                        c.saturating_sub(rng.below(r)),
                        (c + rng.below(r)).min(q_max),
                    )
                }
                _ => {
                    let (x, y) = (rng.below(q_max + 1), rng.below(q_max + 1));
                    (x.min(y), x.max(y))
                }
            };
            lo[a] = x;
            hi[a] = y;
        }
        let valid = rng.below(16) != 0;
        let r = self.pack_terms(&terms, valid, lo, hi);
        ports::pack(&self.unit, &r, v)
    }
}

impl Testbench for NodeChildBench {}
