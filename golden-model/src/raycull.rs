//! Golden model of the `raycull` unit (seed 002, US 10,068,367 B2, issue 38):
//! depth-based culling of rays whose emitting surface is no longer visible,
//! and the contribution check before a ray result is written. The
//! specification is `docs/raycull.md`; this is its bit-exact twin.
//!
//! **Depth codes** ([`DepthFormat`]): `unorm16` and `unorm24` are integers
//! `0..=2^N − 1`; `binary32` is the raw bits of an IEEE binary32 value in
//! `[+0, 1.0]`. Every valid code satisfies `code <= far_code` (`2^N − 1`, or
//! `0x3F80_0000` = 1.0), and for valid binary32 codes the unsigned order of
//! the bits is the numeric order, so every comparison is an unsigned integer
//! comparison. A binary32 code above `0x3F80_0000` is **bad**: NaN, ±∞,
//! any negative value (−0.0 included) and any value beyond the far plane.
//! [`quantize`] produces the code from a view-space depth and the near/far
//! planes.
//!
//! **Compare modes** ([`Compare`]): the depth test of the raster.
//! `Less`/`LEqual` keep the nearer (smaller code) surface, `Greater`/`GEqual`
//! (reversed depth) the larger code. "Closer" below means smaller code under
//! `Less`/`LEqual` and larger under `Greater`/`GEqual`. At equal depth
//! `Less`/`Greater` keep the surface with the smaller primitive id (so the
//! final surface does not depend on the primitive order), `LEqual`/`GEqual`
//! the later one. The cull rules are the same for the strict and the
//! non-strict mode of a direction: equal depth is decided by the generation.
//!
//! **One transaction** ([`cull`]) takes the tile's range `[tile_min,
//! tile_max]` and its drop-farther bit (all samples of the tile opaque), the
//! culling switch `enable`, and a group of `G` slots, each `valid`, with a
//! ray tag (emitting depth, generation, primitive id) and the state of the
//! ray's sample (current depth, generation, primitive id, drop-farther bit).
//! Per valid slot, with `bad` its depth flag:
//! 1. **tile stage** (claims 1-2): `tile_cull = enable ∧ ¬bad ∧
//!    tile_drop_farther ∧ (ray_depth > tile_max)` (`< tile_min` when
//!    reversed). Only the far side culls: with a consistent buffer the ray's
//!    depth is never on the near side of its own sample, and culling there
//!    would be a false cull in an inconsistent one.
//! 2. **sample stage** (claims 5-8), only when the tile stage kept the ray:
//!    `depth_cull = … ∧ sample_drop_farther ∧ sample closer than ray`,
//!    `generation_cull = … ∧ sample_drop_farther ∧ depths equal ∧
//!    generations differ`.
//! 3. `cull = tile_cull ∨ depth_cull ∨ generation_cull`.
//! 4. **contribution check** (`current`, the description's verification
//!    logic): `valid ∧ ¬id_bad ∧ sample_prim = ray_prim ∧ sample_gen =
//!    ray_gen`; the renderer evaluates it again with the sample's state when
//!    the result arrives and writes only a current result. It never looks at
//!    a depth and does not depend on `enable`.
//!
//! **Group** (claims 3-4, 11-12): `group_cull = enable ∧ tile_drop_farther ∧
//! some slot valid ∧ no valid slot bad ∧ min over valid slots of ray_depth >
//! tile_max` (`max < tile_min` reversed): the group's depth range against
//! the tile's, the same decision as "every valid slot tile-culled".
//!
//! **Bad input**: `bad` per slot is a depth code that is not valid (ray,
//! sample, tile min or max); `id_bad` a generation or primitive id wider
//! than its field. A bad slot is never culled; `group_bad` is the OR.
//!
//! [`TileBuffer`] is the state the unit reads: a tile's samples, their depth
//! test in the chosen mode, the generation incremented (wrapping) each time
//! a sample's surface changes, and the tile range recomputed after each
//! write.

/// Depth format of the codes (`depth` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DepthFormat {
    /// 16-bit unsigned normalised
    Unorm16,
    /// 24-bit unsigned normalised
    Unorm24,
    /// IEEE binary32 in `[+0, 1.0]`
    Binary32,
}

impl DepthFormat {
    /// Bits of a code.
    pub fn bits(self) -> u32 {
        match self {
            DepthFormat::Unorm16 => 16,
            DepthFormat::Unorm24 => 24,
            DepthFormat::Binary32 => 32,
        }
    }
    /// The largest valid code: the far plane.
    pub fn far_code(self) -> u32 {
        match self {
            DepthFormat::Unorm16 => 0xFFFF,
            DepthFormat::Unorm24 => 0xFF_FFFF,
            DepthFormat::Binary32 => 0x3F80_0000,
        }
    }
    /// A code is valid iff `code <= far_code` (binary32: not NaN, not
    /// negative, −0.0 included, not above 1.0).
    pub fn valid(self, code: u32) -> bool {
        code <= self.far_code()
    }
}

/// The raster's depth compare mode (`compare` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Compare {
    /// smaller code wins; ties to the smaller primitive id
    Less,
    /// smaller or equal code wins (the later of equal ones)
    LEqual,
    /// larger code wins (reversed depth); ties to the smaller primitive id
    Greater,
    /// larger or equal code wins (the later of equal ones)
    GEqual,
}

impl Compare {
    /// Larger codes are closer (reversed depth).
    pub fn reversed(self) -> bool {
        matches!(self, Compare::Greater | Compare::GEqual)
    }
    /// `a` is strictly closer than `b`.
    pub fn closer(self, a: u32, b: u32) -> bool {
        if self.reversed() {
            a > b
        } else {
            a < b
        }
    }
    /// The depth test: a fragment `(depth, prim)` replaces the current
    /// surface `(cur, cur_prim)`.
    pub fn passes(self, depth: u32, prim: u32, cur: u32, cur_prim: u32) -> bool {
        match self {
            Compare::Less | Compare::Greater => {
                self.closer(depth, cur) || (depth == cur && prim < cur_prim)
            }
            Compare::LEqual | Compare::GEqual => self.closer(depth, cur) || depth == cur,
        }
    }
}

/// The unit's configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Config {
    /// depth code format
    pub format: DepthFormat,
    /// compare mode
    pub compare: Compare,
    /// generation bits (FIG. 13/14: 3)
    pub gen_bits: u32,
    /// primitive id bits of the contribution check
    pub prim_bits: u32,
    /// rays per group G
    pub group: usize,
}

impl Config {
    /// The code of an empty sample (the cleared depth): the far plane, or 0
    /// when reversed.
    pub fn clear_depth(&self) -> u32 {
        if self.compare.reversed() {
            0
        } else {
            self.format.far_code()
        }
    }
    /// Generation mask.
    pub fn gen_mask(&self) -> u32 {
        mask(self.gen_bits)
    }
    /// Primitive id mask.
    pub fn prim_mask(&self) -> u32 {
        mask(self.prim_bits)
    }
}

fn mask(bits: u32) -> u32 {
    if bits >= 32 {
        u32::MAX
    } else {
        (1 << bits) - 1
    }
}

/// What a ray carries: the emitting surface's depth, the sample's generation
/// at emission, the emitting primitive's id.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RayTag {
    /// emitting depth code
    pub depth: u32,
    /// generation
    pub gen: u32,
    /// primitive id
    pub prim: u32,
}

/// A sample's current state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SampleState {
    /// current depth code
    pub depth: u32,
    /// current generation
    pub gen: u32,
    /// current primitive id
    pub prim: u32,
    /// the current surface is opaque: rays of farther surfaces may be dropped
    pub drop_farther: bool,
}

/// A tile's current depth range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TileRange {
    /// smallest depth code of the tile's samples
    pub min: u32,
    /// largest depth code
    pub max: u32,
    /// every sample's surface is opaque
    pub drop_farther: bool,
}

/// One slot of a group: a ray and its sample's state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Slot {
    /// the slot holds a ray
    pub valid: bool,
    /// the ray
    pub ray: RayTag,
    /// its sample
    pub sample: SampleState,
}

/// The inputs of one transaction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullIn {
    /// culling switch (0: nothing is culled; the contribution check still runs)
    pub enable: bool,
    /// the tile of every ray of the group
    pub tile: TileRange,
    /// `G` slots
    pub slots: Vec<Slot>,
}

/// One slot's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Verdict {
    /// culled by the tile range (stage 1)
    pub tile_cull: bool,
    /// culled by the sample depth (stage 2)
    pub depth_cull: bool,
    /// culled by the generation at equal depth (stage 2)
    pub generation_cull: bool,
    /// culled by either stage
    pub cull: bool,
    /// contribution check: the ray's surface is the sample's current one
    pub current: bool,
    /// a depth code is not valid (never culled)
    pub bad: bool,
    /// a generation or primitive id wider than its field (never culled, not current)
    pub id_bad: bool,
}

/// The outputs of one transaction.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CullOut {
    /// the whole group is culled by the tile range
    pub group_cull: bool,
    /// some valid slot is bad (depth or id)
    pub group_bad: bool,
    /// per slot
    pub slots: Vec<Verdict>,
}

/// One slot's verdict (see the module header).
pub fn verdict(cfg: &Config, enable: bool, tile: &TileRange, s: &Slot) -> Verdict {
    if !s.valid {
        return Verdict::default();
    }
    let f = cfg.format;
    let bad = ![s.ray.depth, s.sample.depth, tile.min, tile.max]
        .iter()
        .all(|&d| f.valid(d));
    let id_bad = s.ray.gen > cfg.gen_mask()
        || s.sample.gen > cfg.gen_mask()
        || s.ray.prim > cfg.prim_mask()
        || s.sample.prim > cfg.prim_mask();
    let may = enable && !bad && !id_bad;
    let far_side = if cfg.compare.reversed() {
        s.ray.depth < tile.min
    } else {
        s.ray.depth > tile.max
    };
    let tile_cull = may && tile.drop_farther && far_side;
    let sample_may = may && !tile_cull && s.sample.drop_farther;
    let depth_cull = sample_may && cfg.compare.closer(s.sample.depth, s.ray.depth);
    let generation_cull = sample_may && s.sample.depth == s.ray.depth && s.sample.gen != s.ray.gen;
    Verdict {
        tile_cull,
        depth_cull,
        generation_cull,
        cull: tile_cull || depth_cull || generation_cull,
        current: !id_bad && s.sample.prim == s.ray.prim && s.sample.gen == s.ray.gen,
        bad,
        id_bad,
    }
}

/// One transaction of the unit (see the module header).
pub fn cull(cfg: &Config, x: &CullIn) -> CullOut {
    let slots: Vec<Verdict> = x
        .slots
        .iter()
        .map(|s| verdict(cfg, x.enable, &x.tile, s))
        .collect();
    let group_bad = slots.iter().any(|v| v.bad || v.id_bad);
    let valid: Vec<u32> = x
        .slots
        .iter()
        .filter(|s| s.valid)
        .map(|s| s.ray.depth)
        .collect();
    let outside = if cfg.compare.reversed() {
        valid.iter().max().is_some_and(|&hi| hi < x.tile.min)
    } else {
        valid.iter().min().is_some_and(|&lo| lo > x.tile.max)
    };
    CullOut {
        group_cull: x.enable && x.tile.drop_farther && !group_bad && outside,
        group_bad,
        slots,
    }
}

/// A sample of a [`TileBuffer`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BufferSample {
    /// the unit's view of the sample
    pub state: SampleState,
    /// a surface has been written
    pub covered: bool,
}

/// Why a write was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BufferError {
    /// the sample index is not in the tile
    SampleOutOfTile,
    /// the depth code is not valid
    BadDepth,
    /// the primitive id is wider than its field
    PrimTooWide,
}

/// A tile's depth buffer with generations and its range.
#[derive(Debug, Clone)]
pub struct TileBuffer {
    cfg: Config,
    /// the samples
    pub samples: Vec<BufferSample>,
    /// the range the unit reads
    pub range: TileRange,
}

impl TileBuffer {
    /// A cleared tile of `n` samples: every sample at the clear depth,
    /// generation 0, primitive 0, opaque.
    pub fn new(cfg: Config, n: usize) -> Self {
        let clear = cfg.clear_depth();
        TileBuffer {
            cfg,
            samples: vec![
                BufferSample {
                    state: SampleState {
                        depth: clear,
                        gen: 0,
                        prim: 0,
                        drop_farther: true,
                    },
                    covered: false,
                };
                n
            ],
            range: TileRange {
                min: clear,
                max: clear,
                drop_farther: true,
            },
        }
    }

    /// Rasterises one fragment: `Ok(Some(generation))` when it becomes the
    /// sample's surface (the generation is incremented, wrapping), `Ok(None)`
    /// when the depth test rejects it.
    pub fn write(
        &mut self,
        index: usize,
        depth: u32,
        prim: u32,
        translucent: bool,
    ) -> Result<Option<u32>, BufferError> {
        let cfg = self.cfg;
        let s = self
            .samples
            .get_mut(index)
            .ok_or(BufferError::SampleOutOfTile)?;
        if !cfg.format.valid(depth) {
            return Err(BufferError::BadDepth);
        }
        if prim > cfg.prim_mask() {
            return Err(BufferError::PrimTooWide);
        }
        if s.covered && !cfg.compare.passes(depth, prim, s.state.depth, s.state.prim) {
            return Ok(None);
        }
        let gen = (s.state.gen + 1) & cfg.gen_mask();
        s.state = SampleState {
            depth,
            gen,
            prim,
            drop_farther: !translucent,
        };
        s.covered = true;
        // the range recomputed from the samples (a tile-based deferred
        // renderer gets it from hidden surface removal); only widening it by
        // each write would never lower the far end, and under LESS the tile
        // stage would never cull
        let states: Vec<SampleState> = self.samples.iter().map(|s| s.state).collect();
        self.range = tile_range(&states);
        Ok(Some(gen))
    }
}

/// A tile's range from its samples (the `tilerange` unit): the smallest and
/// the largest depth code as unsigned integers (either end is the near one,
/// depending on the compare mode; a bad binary32 code is carried through,
/// and `raycull` flags it), and drop-farther when every sample's surface is
/// opaque. `samples` must not be empty.
pub fn tile_range(samples: &[SampleState]) -> TileRange {
    let d = samples.iter().map(|s| s.depth);
    TileRange {
        min: d.clone().min().expect("a tile has samples"),
        max: d.max().expect("a tile has samples"),
        drop_farther: samples.iter().all(|s| s.drop_farther),
    }
}

/// The depth code of a fragment at view-space depth `z` (distance along the
/// view direction) between the near and far planes: `d = far·(z − near) /
/// (z·(far − near))` in f64 (0 at near, 1 at far, the usual perspective
/// depth); unorm: `round(d·(2^N − 1))`; binary32: `d` rounded to nearest.
/// Reversed (`Greater`/`GEqual`): `1 − d` the same way. `None` (clipped) when
/// `z` is NaN or outside `[near, far]`. `far` may be `+∞` (`d = 1 − near/z`).
/// Where the two products leave f64's normal range (planes near 10^±154 and
/// beyond) `d` is formed as `(z − near)/z · far/(far − near)`, whose factors
/// stay in range: the direct form gave NaN there, which the clamp made 0.
pub fn quantize(format: DepthFormat, reversed: bool, z: f64, near: f64, far: f64) -> Option<u32> {
    if z.is_nan() || !(near..=far).contains(&z) || near <= 0.0 || far <= near {
        return None;
    }
    let (num, den) = (far * (z - near), z * (far - near));
    let d = if num.is_normal() && den.is_normal() {
        num / den
    } else if far.is_infinite() {
        (z - near) / z
    } else {
        (z - near) / z * (far / (far - near))
    };
    let d = d.clamp(0.0, 1.0);
    let d = if reversed { 1.0 - d } else { d };
    Some(match format {
        DepthFormat::Binary32 => (d as f32).to_bits(),
        _ => (d * format.far_code() as f64).round() as u32,
    })
}

/// Packs a FIG. 13 ray id: tile 16 | pixel 8 | sample 3 | generation 3
/// bits (bit 29 down to 0); `None` when a field is wider than its bits.
pub fn pack_fig13(tile: u32, pixel: u32, sample: u32, gen: u32) -> Option<u32> {
    (tile < 1 << 16 && pixel < 1 << 8 && sample < 8 && gen < 8)
        .then_some(tile << 14 | pixel << 6 | sample << 3 | gen)
}

/// Packs a FIG. 14 ray id: pixel 26 | sample 3 | generation 3 bits (bit 31
/// down to 0); `None` when a field is wider than its bits.
pub fn pack_fig14(pixel: u32, sample: u32, gen: u32) -> Option<u32> {
    (pixel < 1 << 26 && sample < 8 && gen < 8).then_some(pixel << 6 | sample << 3 | gen)
}

/// Unpacks a FIG. 14 ray id into (pixel, sample, generation).
pub fn unpack_fig14(id: u32) -> (u32, u32, u32) {
    (id >> 6, id >> 3 & 7, id & 7)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cfg(format: DepthFormat, compare: Compare) -> Config {
        Config {
            format,
            compare,
            gen_bits: 3,
            prim_bits: 16,
            group: 2,
        }
    }

    #[test]
    fn fig13_and_fig14_layouts() {
        assert_eq!(pack_fig14(1, 2, 3), Some(0b1_010_011));
        assert_eq!(unpack_fig14(0b1_010_011), (1, 2, 3));
        assert_eq!(pack_fig14(1 << 26, 0, 0), None);
        assert_eq!(pack_fig14(0, 8, 0), None);
        assert_eq!(pack_fig13(1, 1, 1, 1), Some(1 << 14 | 1 << 6 | 1 << 3 | 1));
        assert_eq!(pack_fig13(0, 256, 0, 0), None);
    }

    #[test]
    fn binary32_bad_codes_are_flagged_and_never_culled() {
        let c = cfg(DepthFormat::Binary32, Compare::Less);
        let one = 1.0f32.to_bits();
        for bad in [
            f32::NAN.to_bits(),
            (-0.0f32).to_bits(),
            (-0.5f32).to_bits(),
            1.0000001f32.to_bits(),
            f32::INFINITY.to_bits(),
        ] {
            let tile = TileRange {
                min: 0,
                max: 0,
                drop_farther: true,
            };
            let s = Slot {
                valid: true,
                ray: RayTag {
                    depth: bad,
                    gen: 1,
                    prim: 1,
                },
                sample: SampleState {
                    depth: 0,
                    gen: 2,
                    prim: 2,
                    drop_farther: true,
                },
            };
            let o = cull(
                &c,
                &CullIn {
                    enable: true,
                    tile,
                    slots: vec![s, Slot::default()],
                },
            );
            assert!(o.slots[0].bad && !o.slots[0].cull && o.group_bad && !o.group_cull);
        }
        assert!(DepthFormat::Binary32.valid(one) && DepthFormat::Binary32.valid(0));
    }

    #[test]
    fn buffer_refuses_out_of_tile_and_wide_ids() {
        let c = cfg(DepthFormat::Unorm16, Compare::Less);
        let mut b = TileBuffer::new(c, 4);
        assert_eq!(b.write(4, 0, 0, false), Err(BufferError::SampleOutOfTile));
        assert_eq!(b.write(0, 0, 1 << 16, false), Err(BufferError::PrimTooWide));
        let c = cfg(DepthFormat::Binary32, Compare::Less);
        let mut b = TileBuffer::new(c, 4);
        assert_eq!(
            b.write(0, f32::NAN.to_bits(), 0, false),
            Err(BufferError::BadDepth)
        );
    }

    #[test]
    fn quantize_maps_near_to_zero_and_far_to_one() {
        for f in [
            DepthFormat::Unorm16,
            DepthFormat::Unorm24,
            DepthFormat::Binary32,
        ] {
            assert_eq!(quantize(f, false, 1.0, 1.0, 100.0), Some(0));
            assert_eq!(quantize(f, false, 100.0, 1.0, 100.0), Some(f.far_code()));
            assert_eq!(quantize(f, true, 1.0, 1.0, 100.0), Some(f.far_code()));
            assert_eq!(quantize(f, false, 0.5, 1.0, 100.0), None);
            assert_eq!(quantize(f, false, f64::NAN, 1.0, 100.0), None);
            let a = quantize(f, false, 10.0, 1.0, 100.0).unwrap();
            let b = quantize(f, false, 20.0, 1.0, 100.0).unwrap();
            assert!(a < b);
        }
    }

    /// Planes at the ends of f64's range and an infinite far plane: the
    /// codes of the formula's value, not the near code (found by an
    /// independent audit: the direct form's products overflowed or
    /// underflowed to NaN, which the clamp turned into 0).
    #[test]
    fn quantize_holds_at_the_ends_of_the_range() {
        let u = DepthFormat::Unorm16;
        // d = 1e300·(1e300 − 1)/(1e300·(1e300 − 1)) = 1: the far code
        assert_eq!(quantize(u, false, 1e300, 1.0, 1e300), Some(0xffff));
        // d = 2e-300·0.5e-300/(1.5e-300·1e-300) = 2/3: 43,690
        assert_eq!(quantize(u, false, 1.5e-300, 1e-300, 2e-300), Some(0xaaaa));
        assert_eq!(quantize(u, true, 1.5e-300, 1e-300, 2e-300), Some(0x5555));
        // far = +inf: d = 1 − 1/50 = 0.98, round(0.98·65,535) = 64,224
        assert_eq!(quantize(u, false, 50.0, 1.0, f64::INFINITY), Some(64_224));
        let b = DepthFormat::Binary32;
        assert_eq!(
            quantize(b, false, 1.5e-300, 1e-300, 2e-300),
            Some((2.0f32 / 3.0).to_bits())
        );
        assert_eq!(
            quantize(b, false, 50.0, 1.0, f64::INFINITY),
            Some(0.98f32.to_bits())
        );
    }
}
