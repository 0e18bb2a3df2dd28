//! Stimulus and golden-model adapter for `raycull`, seed 002's ray-cull
//! unit (`golden_model::raycull::cull`).

use super::stimulus::{mask, VectorRng};
use super::Testbench;
use golden_model::raycull::{self as model, CullIn, RayTag, SampleState, Slot, TileRange};
use rtl_gen::units::ports;
use rtl_gen::units::raycull::{Compare, Config, Depth, RayCullIn, RayCullOut};

/// Vectors: first 256 with every slot alike, the ray, sample and tile-end
/// codes each one of {0, the middle, far − 1, far} and the generation and
/// primitive equal or not; then seeded random vectors whose codes come
/// mostly from a handful of values (0, 1, the middle and its neighbours,
/// far − 1, far) so equal depths and range ends are common, with empty
/// slots, translucent samples and tiles, the switch off, and (binary32) bad
/// codes: NaN, −0.0, negative, beyond 1.0, ∞.
pub struct RayCullBench {
    unit: Config,
    model: model::Config,
}

/// The golden model's configuration of a unit configuration.
pub fn model_config(u: &Config) -> model::Config {
    model::Config {
        format: match u.depth {
            Depth::Unorm16 => model::DepthFormat::Unorm16,
            Depth::Unorm24 => model::DepthFormat::Unorm24,
            Depth::Binary32 => model::DepthFormat::Binary32,
        },
        compare: match u.compare {
            Compare::Less => model::Compare::Less,
            Compare::LEqual => model::Compare::LEqual,
            Compare::Greater => model::Compare::Greater,
            Compare::GEqual => model::Compare::GEqual,
        },
        gen_bits: u.gen_bits,
        prim_bits: u.prim_bits,
        group: u.group as usize,
    }
}

/// The unit configuration of a golden-model configuration (the inverse of
/// [`model_config`]), with `stages` pipeline stages.
pub fn unit_config(m: &model::Config, stages: u32) -> Config {
    Config {
        depth: match m.format {
            model::DepthFormat::Unorm16 => Depth::Unorm16,
            model::DepthFormat::Unorm24 => Depth::Unorm24,
            model::DepthFormat::Binary32 => Depth::Binary32,
        },
        compare: match m.compare {
            model::Compare::Less => Compare::Less,
            model::Compare::LEqual => Compare::LEqual,
            model::Compare::Greater => Compare::Greater,
            model::Compare::GEqual => Compare::GEqual,
        },
        gen_bits: m.gen_bits,
        prim_bits: m.prim_bits,
        group: m.group as u32,
        stages,
    }
}

/// The unit's input record of a golden-model transaction.
pub fn to_record(x: &CullIn) -> RayCullIn<u64> {
    let s = &x.slots;
    let f = |g: fn(&Slot) -> u64| s.iter().map(g).collect::<Vec<u64>>();
    RayCullIn {
        enable: x.enable as u64,
        tile_min: u64::from(x.tile.min),
        tile_max: u64::from(x.tile.max),
        tile_drop_farther: x.tile.drop_farther as u64,
        valid: f(|s| s.valid as u64),
        ray_depth: f(|s| u64::from(s.ray.depth)),
        ray_gen: f(|s| u64::from(s.ray.gen)),
        ray_prim: f(|s| u64::from(s.ray.prim)),
        sample_depth: f(|s| u64::from(s.sample.depth)),
        sample_gen: f(|s| u64::from(s.sample.gen)),
        sample_prim: f(|s| u64::from(s.sample.prim)),
        sample_drop_farther: f(|s| s.sample.drop_farther as u64),
    }
}

/// The golden-model transaction of the unit's input record.
pub fn from_record(r: &RayCullIn<u64>) -> CullIn {
    CullIn {
        enable: r.enable != 0,
        tile: TileRange {
            min: r.tile_min as u32,
            max: r.tile_max as u32,
            drop_farther: r.tile_drop_farther != 0,
        },
        slots: (0..r.valid.len())
            .map(|i| Slot {
                valid: r.valid[i] != 0,
                ray: RayTag {
                    depth: r.ray_depth[i] as u32,
                    gen: r.ray_gen[i] as u32,
                    prim: r.ray_prim[i] as u32,
                },
                sample: SampleState {
                    depth: r.sample_depth[i] as u32,
                    gen: r.sample_gen[i] as u32,
                    prim: r.sample_prim[i] as u32,
                    drop_farther: r.sample_drop_farther[i] != 0,
                },
            })
            .collect(),
    }
}

/// The unit's output record of a golden-model verdict.
pub fn out_record(u: &Config, o: &model::CullOut) -> RayCullOut<u64> {
    let f = |g: fn(&model::Verdict) -> bool| o.slots.iter().map(|v| g(v) as u64).collect();
    let flags = u.depth == Depth::Binary32;
    RayCullOut {
        group_cull: o.group_cull as u64,
        group_bad: flags.then_some(o.group_bad as u64),
        tile_cull: f(|v| v.tile_cull),
        depth_cull: f(|v| v.depth_cull),
        generation_cull: f(|v| v.generation_cull),
        cull: f(|v| v.cull),
        current: f(|v| v.current),
        bad: flags.then(|| f(|v| v.bad)),
    }
}

impl RayCullBench {
    /// The testbench of a `raycull` configuration.
    pub fn new(u: &Config) -> Self {
        RayCullBench {
            unit: *u,
            model: model_config(u),
        }
    }

    fn far(&self) -> u32 {
        self.model.format.far_code()
    }

    fn mid(&self) -> u32 {
        middle(self.model.format)
    }

    fn code(&self, rng: &mut VectorRng) -> u32 {
        depth_code(self.model.format, rng)
    }
}

/// The middle code of a format (0.5 in binary32).
fn middle(format: model::DepthFormat) -> u32 {
    match format {
        model::DepthFormat::Binary32 => 0.5f32.to_bits(),
        _ => format.far_code() / 2,
    }
}

/// A stimulus depth code: mostly one of a handful of values (0, 1, the
/// middle and its neighbours, far − 1, far) so equal codes and range ends
/// are common; binary32 sometimes a bad code (NaN, −0.0, negative, beyond
/// 1.0, ∞, all ones); otherwise uniform in `0..=far`.
pub fn depth_code(format: model::DepthFormat, rng: &mut VectorRng) -> u32 {
    let (far, mid) = (format.far_code(), middle(format));
    match rng.below(12) {
        0 => 0,
        1 => 1,
        2 => far - 1,
        3 => far,
        4 | 5 => mid,
        6 => mid + 1,
        7 => mid - 1,
        8 if format == model::DepthFormat::Binary32 && rng.below(4) == 0 => [
            f32::NAN.to_bits(),
            (-0.0f32).to_bits(),
            (-0.25f32).to_bits(),
            1.0000001f32.to_bits(),
            f32::INFINITY.to_bits(),
            u32::MAX,
        ][rng.below(6) as usize],
        _ => rng.below(u64::from(far) + 1) as u32,
    }
}

impl sim::Golden for RayCullBench {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        let r: RayCullIn<u64> = ports::unpack(&self.unit, inputs);
        let o = model::cull(&self.model, &from_record(&r));
        ports::pack(&self.unit, &out_record(&self.unit, &o), outputs)
    }
}

impl sim::Stimulus for RayCullBench {
    fn vector(&self, seed: u64, index: u64, v: &mut [u64]) {
        let (gm, pm) = (mask(self.unit.gen_bits), mask(self.unit.prim_bits));
        let g = self.unit.group as usize;
        if index < 256 {
            let pool = [0, self.mid(), self.far() - 1, self.far()];
            let pick = |k: u64| pool[(index >> k & 3) as usize];
            let slot = Slot {
                valid: true,
                ray: RayTag {
                    depth: pick(0),
                    gen: 1,
                    prim: 1,
                },
                sample: SampleState {
                    depth: pick(2),
                    gen: if index >> 6 & 1 == 1 { 1 } else { 0 },
                    prim: if index >> 7 & 1 == 1 { 1 } else { 0 },
                    drop_farther: true,
                },
            };
            let x = CullIn {
                enable: true,
                tile: TileRange {
                    min: if !self.unit.reversed() { 0 } else { pick(4) },
                    max: if !self.unit.reversed() {
                        pick(4)
                    } else {
                        self.far()
                    },
                    drop_farther: true,
                },
                slots: vec![slot; g],
            };
            return ports::pack(&self.unit, &to_record(&x), v);
        }
        let mut rng = VectorRng::new(seed, index);
        let (a, b) = (self.code(&mut rng), self.code(&mut rng));
        let (min, max) = if rng.below(8) == 0 || a <= b {
            (a, b)
        } else {
            (b, a)
        };
        let slots = (0..g)
            .map(|_| {
                let ray = RayTag {
                    depth: self.code(&mut rng),
                    gen: rng.bits(self.unit.gen_bits) as u32,
                    prim: rng.bits(self.unit.prim_bits) as u32,
                };
                let same = rng.below(4);
                let sample = SampleState {
                    depth: if same == 0 {
                        ray.depth
                    } else {
                        self.code(&mut rng)
                    },
                    gen: if rng.below(2) == 0 {
                        ray.gen
                    } else {
                        (rng.bits(self.unit.gen_bits) & gm) as u32
                    },
                    prim: if rng.below(2) == 0 {
                        ray.prim
                    } else {
                        (rng.bits(self.unit.prim_bits) & pm) as u32
                    },
                    drop_farther: rng.below(8) != 0,
                };
                Slot {
                    valid: rng.below(8) != 0,
                    ray,
                    sample,
                }
            })
            .collect();
        let x = CullIn {
            enable: rng.below(16) != 0,
            tile: TileRange {
                min,
                max,
                drop_farther: rng.below(8) != 0,
            },
            slots,
        };
        ports::pack(&self.unit, &to_record(&x), v)
    }
}

impl Testbench for RayCullBench {}

/// The golden-model verdict of the unit's output record (the flags a port
/// cannot carry, `id_bad`, are false; `bad` false when the format has none).
pub fn from_out_record(r: &RayCullOut<u64>) -> model::CullOut {
    let bad = |i: usize| r.bad.as_ref().is_some_and(|b| b[i] != 0);
    model::CullOut {
        group_cull: r.group_cull != 0,
        group_bad: r.group_bad.is_some_and(|b| b != 0),
        slots: (0..r.cull.len())
            .map(|i| model::Verdict {
                tile_cull: r.tile_cull[i] != 0,
                depth_cull: r.depth_cull[i] != 0,
                generation_cull: r.generation_cull[i] != 0,
                cull: r.cull[i] != 0,
                current: r.current[i] != 0,
                bad: bad(i),
                id_bad: false,
            })
            .collect(),
    }
}
