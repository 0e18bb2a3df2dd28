//! Stimulus and golden-model adapter for `triangle` (golden
//! `golden_model::triangle::eval_with`). Rays come with their shear constants
//! from the golden `shear`; kinds of vector: rays aimed at a random point
//! of the triangle (two in three) or of its plane around it, rays aimed at an
//! edge's midpoint and a few ulps beside it, vertices and edge ends, segment
//! bounds around the hit, degenerate triangles (a repeated vertex, three
//! collinear vertices), special values (NaN, ±∞, ±0, subnormals, raw bits)
//! in any input and `kz = 3`, at scales from 2^-20 to 2^20 and, one in
//! eight, at the ends of the format's range (2^emin .. 2^(emin+6) and
//! 2^(emax-6) .. 2^(emax-3)).
//! Ports: `o_{x,y,z}`, `kz`, `s_{x,y,z}`, `a_*`, `b_*`, `c_*`, `t_min`,
//! `t_max`; outputs `hit`, `invalid` and, with `outputs=full`, `t`, `u`, `v`.

use super::rays::from_f64;
use super::stimulus::VectorRng;
use super::Testbench;
use golden_model::float::{nudge, to_f64};
use golden_model::float::{FloatFormat, RoundingMode};
use golden_model::triangle::{
    eval_tnum_with, eval_with, other_axes, shear, Segment, TriIn, TriNum, TriOut,
};
use rtl_gen::units::ports;
use rtl_gen::units::triangle::{Config, Outputs, TriangleIn, TriangleOut};

/// Vectors and golden model of one `triangle` configuration.
pub struct TriangleBench {
    unit: Config,
    fmt: FloatFormat,
    mode: RoundingMode,
}

/// Input values per transaction.
pub const INPUTS: usize = 18;

impl TriangleBench {
    /// The testbench of a `triangle` configuration.
    pub fn new(cfg: &Config) -> Self {
        assert_eq!(
            ports::list::<TriangleIn<()>>(cfg).len(),
            INPUTS,
            "triangle inputs"
        );
        TriangleBench {
            unit: *cfg,
            fmt: FloatFormat::new(cfg.fmt.exp_bits, cfg.fmt.frac_bits)
                .expect("format checked by the unit"),
            mode: super::fstim::golden_mode(cfg.round),
        }
    }

    fn unit(r: &mut VectorRng) -> f64 {
        (r.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The transaction of vector `index` under `seed`.
    pub fn case(&self, seed: u64, index: u64) -> TriIn {
        let fmt = self.fmt;
        let mut r = VectorRng::new(seed, index);
        let q = |v: f64| from_f64(fmt, v);
        // a scale the format can hold: small formats stay near 1; one in
        // eight at an end of the range (vertices near the smallest normal,
        // or the origin's distance near the largest finite value)
        let span = (fmt.bias() / 4).clamp(1, 20);
        let exp = match r.below(16) {
            0 => fmt.emin() + r.below(7) as i32,
            1 => fmt.emax() - 6 + r.below(4) as i32,
            _ => (r.below(2 * span as u64 + 1) as i32) - span,
        };
        let scale = (2f64).powi(exp);
        let rnd = |r: &mut VectorRng, lo: f64, hi: f64| lo + (hi - lo) * Self::unit(r);
        let tri: [[u64; 3]; 3] = [0; 3].map(|_| [0; 3].map(|_| q(rnd(&mut r, -1.0, 1.0) * scale)));
        let v = |k: usize, i: usize| to_f64(fmt, tri[k][i]);
        let o_f: [f64; 3] = {
            let dist = rnd(&mut r, 1.5, 6.0) * scale;
            let dir = [0; 3].map(|_| rnd(&mut r, -1.0, 1.0));
            let n = (dir.iter().map(|x| x * x).sum::<f64>()).sqrt().max(1e-3);
            dir.map(|x| x / n * dist)
        };
        let o = o_f.map(q);
        let kind = r.below(10);
        // where the ray is aimed
        let aim: [f64; 3] = match kind {
            // an edge's midpoint, or a vertex, nudged by a few ulps below
            0..=2 => {
                let (p, qv) = (r.below(3) as usize, r.below(3) as usize);
                [0, 1, 2].map(|i| 0.5 * (v(p, i) + v((p + 1 + qv % 2) % 3, i)))
            }
            3 => {
                let k = r.below(3) as usize;
                [0, 1, 2].map(|i| v(k, i))
            }
            _ => {
                let (mut b1, mut b2) = (rnd(&mut r, -0.3, 1.3), rnd(&mut r, -0.3, 1.3));
                if r.below(3) != 0 {
                    // inside: a uniform point of the triangle
                    (b1, b2) = (Self::unit(&mut r), Self::unit(&mut r));
                    if b1 + b2 > 1.0 {
                        (b1, b2) = (1.0 - b1, 1.0 - b2);
                    }
                }
                [0, 1, 2].map(|i| v(0, i) + b1 * (v(1, i) - v(0, i)) + b2 * (v(2, i) - v(0, i)))
            }
        };
        let mut aim = aim.map(q);
        if kind <= 3 {
            let axis = r.below(3) as usize;
            let n = r.below(7) as i64 - 3;
            aim[axis] = nudge(fmt, aim[axis], n);
        }
        let d = [0, 1, 2].map(|i| q(to_f64(fmt, aim[i]) - to_f64(fmt, o[i])));
        let (kz, s) = shear(fmt, d);
        let mut x = TriIn {
            o,
            kz,
            s,
            a: tri[0],
            b: tri[1],
            c: tri[2],
            t_min: fmt.zero(false),
            t_max: fmt.inf(false),
        };
        // segment bounds, degenerate triangles, special values
        match r.below(8) {
            0 => {
                // bounds around the distance to the aim point (t = 1 there)
                let one = from_f64(fmt, 1.0);
                x.t_min = nudge(fmt, one, r.below(9) as i64 - 4);
                x.t_max = nudge(fmt, one, r.below(9) as i64 - 4);
                // bounds a few per cent around t, where `segment=log` decides by
                // its margin; or the ray reversed, t = -1 between negative bounds
                match r.below(4) {
                    0 => {
                        x.t_min = q(rnd(&mut r, 0.7, 1.0));
                        x.t_max = q(rnd(&mut r, 1.0, 1.35));
                    }
                    1 => {
                        let back = d.map(|c| c ^ (1u64 << (fmt.width() - 1)));
                        (x.kz, x.s) = shear(fmt, back);
                        x.t_min = q(-rnd(&mut r, 0.7, 1.35));
                        x.t_max = q(-rnd(&mut r, 0.7, 1.35));
                    }
                    _ => {}
                }
            }
            1 => {
                x.t_min = q(rnd(&mut r, -2.0, 1.5));
                x.t_max = q(rnd(&mut r, 0.0, 3.0));
            }
            2 => match r.below(3) {
                0 => x.b = x.a,
                1 => x.c = x.b,
                _ => {
                    // c on the line through a and b
                    let f = rnd(&mut r, -1.0, 2.0);
                    x.c = [0, 1, 2].map(|i| q(v(0, i) + f * (v(1, i) - v(0, i))));
                }
            },
            3 => {
                let specials = [
                    fmt.canonical_nan(),
                    fmt.inf(false),
                    fmt.inf(true),
                    fmt.zero(false),
                    fmt.zero(true),
                    fmt.min_subnormal(r.below(2) == 1),
                    fmt.max_finite(r.below(2) == 1),
                    r.bits(fmt.width()),
                ];
                let value = specials[r.below(specials.len() as u64) as usize];
                let slot = r.below(INPUTS as u64) as usize;
                let mut flat = [0u64; INPUTS];
                self.to_ports(&x, &mut flat);
                if slot == self.kz_port() {
                    flat[slot] = r.below(4);
                } else {
                    flat[slot] = value;
                }
                x = self.from_ports(&flat);
            }
            5 if r.below(2) == 0 => {
                // a sliver within a rounding of a plane holding an axis ray from the
                // origin (ray space exact: X = p_kx, Y = p_ky): its edge functions
                // often all round to zero, which the unit flags
                let kz = r.below(3) as u32;
                let (kx, ky) = other_axes(kz);
                let z = fmt.zero(false);
                let along = if r.below(2) == 0 { 1.0 } else { -1.0 };
                x.o = [z; 3];
                x.kz = kz;
                x.s = [z, z, q(along)];
                x.t_min = fmt.inf(true);
                let vertex = |r: &mut VectorRng, side: f64| {
                    let px = nudge(fmt, q(side * scale), r.below(16) as i64);
                    let mut p = [z; 3];
                    p[kx] = px;
                    p[ky] = nudge(fmt, px, r.below(3) as i64 - 1);
                    p[kz as usize] = q(rnd(r, -4.0, 4.0) * scale);
                    p
                };
                x.a = vertex(&mut r, 1.0);
                x.b = vertex(&mut r, -1.0);
                x.c = vertex(&mut r, 1.0);
            }
            4 if r.below(8) == 0 => {
                let mut flat = [0u64; INPUTS];
                for (k, f) in flat.iter_mut().enumerate() {
                    *f = if k == self.kz_port() {
                        r.below(4)
                    } else {
                        r.bits(fmt.width())
                    };
                }
                x = self.from_ports(&flat);
            }
            _ => {}
        }
        x
    }
}

impl TriangleBench {
    /// The position of `kz` among the inputs.
    fn kz_port(&self) -> usize {
        ports::positions::<TriangleIn<usize>>(&self.unit).kz
    }

    /// Writes a transaction's values into port order.
    pub fn to_ports(&self, x: &TriIn, v: &mut [u64]) {
        let record = TriangleIn {
            o: x.o,
            kz: x.kz as u64,
            s: x.s,
            a: x.a,
            b: x.b,
            c: x.c,
            t_min: x.t_min,
            t_max: x.t_max,
        };
        ports::pack(&self.unit, &record, v)
    }

    /// The transaction of the ports' values.
    pub fn from_ports(&self, v: &[u64]) -> TriIn {
        let x: TriangleIn<u64> = ports::unpack(&self.unit, v);
        TriIn {
            o: x.o,
            kz: (x.kz & 3) as u32,
            s: x.s,
            a: x.a,
            b: x.b,
            c: x.c,
            t_min: x.t_min,
            t_max: x.t_max,
        }
    }

    /// The result of an `outputs=full` unit's output ports.
    pub fn result_from_ports(&self, out: &[u64]) -> TriOut {
        let r: TriangleOut<u64> = ports::unpack(&self.unit, out);
        let [t, u, v] = r.t_u_v.expect("t, u, v need outputs=full");
        TriOut {
            hit: r.hit & 1 != 0,
            invalid: r.invalid & 1 != 0,
            t,
            u,
            v,
        }
    }

    /// The result of an `outputs=tnum` (or `hit`) unit's output ports.
    pub fn tnum_from_ports(&self, out: &[u64]) -> TriNum {
        let r: TriangleOut<u64> = ports::unpack(&self.unit, out);
        let [t_num, t_den] = r.t_num_den.expect("T and det need outputs=tnum or hit");
        TriNum {
            hit: r.hit & 1 != 0,
            invalid: r.invalid & 1 != 0,
            t_num,
            t_den,
        }
    }
}

impl TriangleBench {
    /// The format.
    pub fn format(&self) -> FloatFormat {
        self.fmt
    }
    /// The rounding of every operation.
    pub fn mode(&self) -> RoundingMode {
        self.mode
    }
    /// What the unit outputs.
    pub fn outputs(&self) -> Outputs {
        self.unit.outputs
    }
    /// How `hit` and `tnum` test the segment.
    pub fn segment(&self) -> Segment {
        match self.unit.segment {
            rtl_gen::units::triangle::Segment::Exact => Segment::Exact,
            rtl_gen::units::triangle::Segment::Log => Segment::Log,
        }
    }
}

/// The `triangle` build a renderer's `--tri tnum` answers from, that
/// `rtl-loop` streams through and `per-ray` costs (issue 42's cost target:
/// binary32, `t` as `T/det` divided in software per hit, the segment by
/// logarithms, 24 DSP48E1 blocks on xc7).
pub const RENDER_TNUM: &[&str] = &[
    "outputs=tnum",
    "products=whole",
    "segment=log",
    "stages=8",
    "dsp=xc7",
    "dsp_blocks=24",
];

impl sim::Golden for TriangleBench {
    fn eval(&self, v: &[u64], outputs: &mut [u64]) {
        let x = self.from_ports(v);
        let record = match self.unit.outputs {
            Outputs::Full => {
                let out = eval_with(self.fmt, self.mode, &x);
                TriangleOut {
                    hit: out.hit as u64,
                    invalid: out.invalid as u64,
                    t_u_v: Some([out.t, out.u, out.v]),
                    t_num_den: None,
                }
            }
            Outputs::Hit | Outputs::Tnum => {
                let out = eval_tnum_with(self.fmt, self.mode, self.segment(), &x);
                TriangleOut {
                    hit: out.hit as u64,
                    invalid: out.invalid as u64,
                    t_u_v: None,
                    t_num_den: Some([out.t_num, out.t_den]),
                }
            }
        };
        ports::pack(&self.unit, &record, outputs)
    }
}

impl sim::Stimulus for TriangleBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        self.to_ports(&self.case(seed, index), v)
    }
}

impl Testbench for TriangleBench {}
