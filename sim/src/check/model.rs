//! What a cross-check compares against and feeds: the golden model and the
//! stimulus of a unit, as traits.

use super::*;

/// A bit-accurate reference model of the unit.
pub trait Golden: Send + Sync {
    /// Computes one value per output port, in port-list order, for one
    /// vector of inputs in port-list order.
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]);

    /// Evaluates consecutive vectors (`n_in` inputs and `n_out` outputs
    /// each). The default loops over [`Golden::eval`], statically
    /// dispatched; override it to vectorise.
    fn eval_batch(&self, inputs: &[u64], n_in: usize, outputs: &mut [u64], n_out: usize) {
        for (i, o) in inputs
            .chunks_exact(n_in)
            .zip(outputs.chunks_exact_mut(n_out))
        {
            self.eval(i, o);
        }
    }
}

impl<F> Golden for F
where
    F: Fn(&[u64], &mut [u64]) + Send + Sync,
{
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self(inputs, outputs)
    }
}

/// A deterministic source of input vectors.
pub trait Stimulus: Send + Sync {
    /// Writes vector number `index` of the sequence selected by `seed` into
    /// `inputs` (one value per input port, each within its width). Must
    /// return the same vector for the same `(seed, index)`; corner cases
    /// first, then random, is the usual pattern.
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]);

    /// Writes consecutive vectors from index `first`, `n_in` values each.
    /// The default loops over [`Stimulus::vector`].
    fn vectors(&self, seed: u64, first: u64, n_in: usize, inputs: &mut [u64]) {
        for (k, v) in inputs.chunks_exact_mut(n_in).enumerate() {
            self.vector(seed, first + k as u64, v);
        }
    }

    /// Writes the vectors `first`, `first + stride`, `first + 2·stride`, ...
    /// (`n_in` values each): the slice of the index space one worker or one
    /// shard runs. The default calls [`Stimulus::vectors`] for `stride == 1`
    /// and loops over [`Stimulus::vector`] otherwise.
    fn vectors_strided(&self, seed: u64, first: u64, stride: u64, n_in: usize, inputs: &mut [u64]) {
        if stride == 1 {
            return self.vectors(seed, first, n_in, inputs);
        }
        for (k, v) in inputs.chunks_exact_mut(n_in).enumerate() {
            self.vector(seed, first + k as u64 * stride, v);
        }
    }
}

impl<F> Stimulus for F
where
    F: Fn(u64, u64, &mut [u64]) + Send + Sync,
{
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self(seed, index, inputs)
    }
}

/// The splitmix64 finaliser: a fast, well-mixed 64-bit hash for building
/// index-addressed stimulus.
#[inline]
pub fn mix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Generic stimulus: [`RandomStimulus::CORNERS`] corner vectors (all zero,
/// all ones, all one-valued, alternating bit patterns, maximum/zero mixes),
/// then uniformly random values within each port's width.
#[derive(Clone, Debug)]
pub struct RandomStimulus {
    masks: Vec<u64>,
}

impl RandomStimulus {
    /// Number of leading corner-case vectors.
    pub const CORNERS: u64 = 7;

    /// Stimulus for these input ports.
    pub fn new(inputs: &[Port]) -> RandomStimulus {
        RandomStimulus {
            masks: inputs.iter().map(Port::mask).collect(),
        }
    }
}

impl Stimulus for RandomStimulus {
    #[inline]
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        let base = mix64(seed ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        for (k, (v, &m)) in inputs.iter_mut().zip(&self.masks).enumerate() {
            *v = m & match index {
                0 => 0,
                1 => u64::MAX,
                2 => 1,
                3 => 0x5555_5555_5555_5555,
                4 => 0xaaaa_aaaa_aaaa_aaaa,
                5 if k % 2 == 0 => u64::MAX,
                5 => 0,
                6 if k % 2 == 0 => 0,
                6 => u64::MAX,
                _ => mix64(base.wrapping_add(k as u64)),
            };
        }
    }
}
