//! Stimulus and golden-model adapter for `slab`, from the same ray
//! generators as the silhouette testbench ([`super::silhouette`]); the
//! reciprocal direction is `1/d` rounded to nearest (±∞ for ±0), or toward
//! zero for `rounding=conservative` (the contract of that design), sometimes
//! moved by an ulp or replaced by a special value or random bits (for the
//! conservative slab also by ±max_finite and ±0, the reciprocals whose
//! widened interval ends at ∞ or starts at 0). The golden
//! model is `golden_model::slab::eval` or `eval_conservative`.

use super::fstim::golden_format;
use super::rays::{corner_cases, from_f64, gen_ray, RayCase, KINDS};
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float::{nudge, to_f64};
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::slab::{eval, eval_conservative, SlabIn, SlabOut};
use rtl_gen::arith::float::Format;
use rtl_gen::units::ports;
use rtl_gen::units::slab::{self, Config, SlabRounding};

/// Vectors and golden model of one `slab` configuration.
pub struct SlabBench {
    fmt: FloatFormat,
    conservative: bool,
    corners: Vec<SlabIn>,
    unit: Format,
}

/// `1/d` in `fmt` (±∞ for ±0, NaN for NaN).
pub fn recip(fmt: FloatFormat, d: u64) -> u64 {
    from_f64(fmt, 1.0 / to_f64(fmt, d))
}

/// `1/d` in `fmt` rounded toward zero (±∞ for ±0 only, NaN for NaN): the
/// reciprocal the conservative slab expects.
pub fn recip_rtz(fmt: FloatFormat, d: u64) -> u64 {
    golden_model::transform::recip(fmt, d, RoundingMode::TowardZero)
}

impl SlabBench {
    /// The testbench of a `slab` configuration.
    pub fn new(u: &Config) -> Self {
        let fmt = golden_format(u.fmt);
        let conservative = u.rounding == SlabRounding::Conservative;
        let recip = if conservative { recip_rtz } else { recip };
        // the single rays of the silhouette corner list (bundles dropped)
        let corners = corner_cases(fmt, false)
            .into_iter()
            .filter(|b| b.d_lo == b.d_hi)
            .map(|b| SlabIn {
                p_min: b.p_min,
                p_max: b.p_max,
                o: b.o_lo,
                inv_d: b.d_lo.map(|d| recip(fmt, d)),
                t_min: b.t_min,
                t_max: b.t_max,
            })
            .collect();
        SlabBench {
            fmt,
            conservative,
            corners,
            unit: u.fmt,
        }
    }

    /// The golden model's answer for `x`.
    pub fn golden(&self, x: &SlabIn) -> SlabOut {
        if self.conservative {
            eval_conservative(self.fmt, x)
        } else {
            eval(self.fmt, x)
        }
    }

    /// Number of corner-case vectors before the random ones.
    pub fn corner_count(&self) -> u64 {
        self.corners.len() as u64
    }

    /// The transaction of vector `index` under `seed`.
    pub fn case(&self, seed: u64, index: u64) -> SlabIn {
        if index < self.corner_count() {
            return self.corners[index as usize];
        }
        let fmt = self.fmt;
        let mut rng = VectorRng::new(seed, index);
        let kind = KINDS[rng.below(KINDS.len() as u64) as usize];
        let c: RayCase = gen_ray(fmt, &mut rng, kind);
        let recip = if self.conservative { recip_rtz } else { recip };
        let mut inv_d = c.d.map(|d| recip(fmt, d));
        for v in inv_d.iter_mut() {
            match rng.below(16) {
                0 => *v = nudge(fmt, *v, if rng.below(2) == 0 { -1 } else { 1 }),
                1 => *v = rng.bits(fmt.width()),
                2 => *v = fmt.inf(rng.below(2) == 0),
                // the conservative slab's interval ends: next_up(max_finite) = ∞, and 0
                3 if self.conservative => *v = fmt.max_finite(rng.below(2) == 0),
                4 if self.conservative => *v = fmt.zero(rng.below(2) == 0),
                _ => {}
            }
        }
        SlabIn {
            p_min: c.p_min,
            p_max: c.p_max,
            o: c.o,
            inv_d,
            t_min: c.t_min,
            t_max: c.t_max,
        }
    }
}

impl sim::Golden for SlabBench {
    fn eval(&self, v: &[u64], outputs: &mut [u64]) {
        let x: slab::SlabIn<u64> = ports::unpack(&self.unit, v);
        let x = SlabIn {
            p_min: x.p_min,
            p_max: x.p_max,
            o: x.o,
            inv_d: x.inv_d,
            t_min: x.t_min,
            t_max: x.t_max,
        };
        let out = self.golden(&x);
        let out = slab::SlabOut {
            hit: out.hit as u64,
            t_enter: out.t_enter,
            t_exit: out.t_exit,
        };
        ports::pack(&self.unit, &out, outputs)
    }
}

impl sim::Stimulus for SlabBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let x = self.case(seed, index);
        let x = slab::SlabIn {
            p_min: x.p_min,
            p_max: x.p_max,
            o: x.o,
            inv_d: x.inv_d,
            t_min: x.t_min,
            t_max: x.t_max,
        };
        ports::pack(&self.unit, &x, v)
    }
}

impl Testbench for SlabBench {}
