//! Parametric IEEE-754 binary floating-point operators.
//!
//! A format is (E, F): E exponent bits (2..=11), F fraction bits (1..=52),
//! 1 + E + F <= 64. Subnormals are fully supported; every NaN result is the
//! canonical quiet NaN (sign 0, exponent all ones, fraction MSB 1, rest 0);
//! rounding modes RNE, RTZ, RUP, RDN; no exception flags. docs/float.md is
//! the contract, the golden twins in `golden-model` implement it.
//!
//! Every rounding operator computes an exact raw result (a [`round::Raw`]:
//! sign, exponent, significand and sticky bit) and instantiates the one
//! shared rounder of [`round`]. Helpers built from the DSL's primitives
//! (leading-zero count, shift with sticky) are in [`bits`].
//!
//! Pipelining: each operator is a list of logical steps; `stages` registers
//! are spread over the step boundaries by [`spread`] (one at the outputs
//! first), and the part that falls into the rounder is its own stage count.

pub mod add;
pub mod add_down_up;
pub mod bits;
pub mod classify;
pub mod compare;
pub mod convert;
pub mod dot3;
pub mod dot3_floor;
pub mod fma;
pub mod minmax;
pub mod mul;
pub mod mul_exact;
pub mod product_compare;
pub mod round;
pub mod sum;
pub mod unpack;

use crate::builder::{ModuleBuilder, Sig};
use crate::ir::Module;
use crate::ports::Record;
use std::fmt;
use std::sync::Arc;

/// A binary floating-point format: `exp_bits` exponent bits and `frac_bits`
/// stored fraction bits (the hidden bit is not counted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Format {
    /// E, exponent field width
    pub exp_bits: u32,
    /// F, fraction field width
    pub frac_bits: u32,
}

impl Format {
    /// Starts the module of an operator on this format, with its description
    /// and the `exp_bits`, `frac_bits` and `stages` parameters of its header.
    pub fn operator_module(self, name: String, description: String, stages: u32) -> ModuleBuilder {
        let mut m = ModuleBuilder::new(name);
        m.describe(description);
        m.param("exp_bits", self.exp_bits)
            .param("frac_bits", self.frac_bits)
            .param("stages", stages);
        m
    }

    /// IEEE binary16.
    pub const BINARY16: Format = Format {
        exp_bits: 5,
        frac_bits: 10,
    };
    /// IEEE binary32.
    pub const BINARY32: Format = Format {
        exp_bits: 8,
        frac_bits: 23,
    };
    /// IEEE binary64.
    pub const BINARY64: Format = Format {
        exp_bits: 11,
        frac_bits: 52,
    };
    /// bfloat16.
    pub const BFLOAT16: Format = Format {
        exp_bits: 8,
        frac_bits: 7,
    };

    /// The format (E, F) if it is supported: E in 2..=11, F in 1..=52, 1 + E + F <= 64.
    pub fn new(exp_bits: u32, frac_bits: u32) -> Result<Format, String> {
        if !(2..=11).contains(&exp_bits) {
            return Err(format!("exponent width {exp_bits} outside 2..=11"));
        }
        if !(1..=52).contains(&frac_bits) {
            return Err(format!("fraction width {frac_bits} outside 1..=52"));
        }
        if 1 + exp_bits + frac_bits > 64 {
            return Err(format!(
                "format e{exp_bits}m{frac_bits} is {} bits wide, more than 64",
                1 + exp_bits + frac_bits
            ));
        }
        Ok(Format {
            exp_bits,
            frac_bits,
        })
    }

    /// Total width 1 + E + F.
    pub fn width(self) -> u32 {
        1 + self.exp_bits + self.frac_bits
    }

    /// The type of an encoding: `UInt(width)`.
    pub fn ty(self) -> crate::ir::Ty {
        crate::ir::Ty::UInt(self.width())
    }

    /// Exponent bias 2^(E-1) - 1.
    pub fn bias(self) -> i64 {
        (1i64 << (self.exp_bits - 1)) - 1
    }

    /// Smallest normal exponent, 1 - bias.
    pub fn emin(self) -> i64 {
        1 - self.bias()
    }

    /// Largest finite exponent, bias.
    pub fn emax(self) -> i64 {
        self.bias()
    }

    /// The all-ones exponent field.
    pub fn exp_ones(self) -> u128 {
        (1u128 << self.exp_bits) - 1
    }

    /// Encoding of +infinity.
    pub fn inf_bits(self) -> u128 {
        self.exp_ones() << self.frac_bits
    }

    /// Encoding of the canonical quiet NaN.
    pub fn nan_bits(self) -> u128 {
        self.inf_bits() | (1u128 << (self.frac_bits - 1))
    }

    /// The tag used in module names, e.g. `e8m23`.
    pub fn tag(self) -> String {
        format!("e{}m{}", self.exp_bits, self.frac_bits)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.tag())
    }
}

/// IEEE-754 rounding-direction attributes supported by the operators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rounding {
    /// to nearest, ties to even
    Rne,
    /// toward zero
    Rtz,
    /// toward +infinity
    Rup,
    /// toward -infinity
    Rdn,
}

impl Rounding {
    /// Every mode, in parameter order.
    pub const ALL: [Rounding; 4] = [Rounding::Rne, Rounding::Rtz, Rounding::Rup, Rounding::Rdn];
    /// Parameter words, in [`Rounding::ALL`] order.
    pub const WORDS: &'static [&'static str] = &["rne", "rtz", "rup", "rdn"];

    /// The parameter word (`rne`, `rtz`, `rup`, `rdn`), also used in module names.
    pub const fn word(self) -> &'static str {
        match self {
            Rounding::Rne => "rne",
            Rounding::Rtz => "rtz",
            Rounding::Rup => "rup",
            Rounding::Rdn => "rdn",
        }
    }

    /// The mode named by `word`.
    pub fn parse(word: &str) -> Option<Rounding> {
        Rounding::ALL.into_iter().find(|r| r.word() == word)
    }
}

impl crate::params::ParamValue for Rounding {
    fn parse_word(word: &str) -> Option<Self> {
        Rounding::parse(word)
    }
    fn to_word(self) -> String {
        self.word().to_string()
    }
}

impl fmt::Display for Rounding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

/// Where an operator's rounding mode comes from: fixed when the module is
/// generated, or a 2-bit input port `rm` (the golden model's encoding, that
/// of RISC-V `frm`: 0 RNE, 1 RTZ, 2 RDN, 3 RUP), so one module serves all
/// four modes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RoundSel {
    /// one mode, built in
    Fixed(Rounding),
    /// the `rm` input port
    Port,
}

impl RoundSel {
    /// Parameter words: the four fixed modes and `dyn` for the `rm` port.
    pub const WORDS: &'static [&'static str] = &["rne", "rtz", "rup", "rdn", "dyn"];

    /// The mode named by `word` (one of [`RoundSel::WORDS`]).
    pub fn parse(word: &str) -> Option<RoundSel> {
        match word {
            "dyn" => Some(RoundSel::Port),
            w => Rounding::parse(w).map(RoundSel::Fixed),
        }
    }

    /// The mode is the `rm` input port.
    pub fn is_port(self) -> bool {
        self == RoundSel::Port
    }

    /// The parameter word: the fixed mode's, or `dyn`.
    pub const fn word(self) -> &'static str {
        match self {
            RoundSel::Fixed(r) => r.word(),
            RoundSel::Port => "dyn",
        }
    }
}

impl crate::params::ParamValue for RoundSel {
    fn parse_word(word: &str) -> Option<Self> {
        RoundSel::parse(word)
    }
    fn to_word(self) -> String {
        self.word().to_string()
    }
}

impl From<Rounding> for RoundSel {
    fn from(r: Rounding) -> Self {
        RoundSel::Fixed(r)
    }
}

impl fmt::Display for RoundSel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.word())
    }
}

impl Rounding {
    /// The 2-bit `rm` code of the mode: 0 RNE, 1 RTZ, 2 RDN, 3 RUP.
    pub fn rm_code(self) -> u128 {
        match self {
            Rounding::Rne => 0,
            Rounding::Rtz => 1,
            Rounding::Rdn => 2,
            Rounding::Rup => 3,
        }
    }
}

/// Name of the rounding-mode input port of a `dyn` operator.
pub const RM_PORT: &str = "rm";

/// The rounding mode inside a module being built: fixed, or read from the
/// `rm` input port.
#[derive(Debug, Clone, Copy)]
pub struct Rm {
    /// where the mode comes from
    pub sel: RoundSel,
    /// the `rm` input (UInt(2)) when `sel` is [`RoundSel::Port`]
    pub port: Option<crate::builder::Sig>,
}

impl Rm {
    /// The mode `sel` of an operator whose inputs record gave `port` (its
    /// `rm` input, there when `sel` is [`RoundSel::Port`]).
    pub fn new(sel: RoundSel, port: Option<Sig>) -> Rm {
        assert_eq!(port.is_some(), sel.is_port(), "an rm port exactly for dyn");
        Rm { sel, port }
    }

    /// A fixed mode (no port).
    pub fn fixed(r: Rounding) -> Rm {
        Rm {
            sel: RoundSel::Fixed(r),
            port: None,
        }
    }

    /// Bool: the mode is `r` (a constant for a fixed mode).
    #[track_caller]
    pub fn is(&self, m: &mut crate::builder::ModuleBuilder, r: Rounding) -> crate::builder::Sig {
        match (self.sel, self.port) {
            (RoundSel::Fixed(x), _) => m.bool(x == r),
            (RoundSel::Port, Some(p)) => {
                let k = m.uint(2, r.rm_code());
                m.eq(p, k)
            }
            (RoundSel::Port, None) => unreachable!("a dyn mode has its port"),
        }
    }
}

/// The common end of an operator's module: `stages` registers carry the
/// pipeline to the `outputs` (the record its instances read, of `ports`),
/// then the module is finished; `what` names the generator in the message
/// of a type error, which would be a bug of the generator.
#[track_caller]
pub fn finish_operator<O: Record<Sig>>(
    mut m: ModuleBuilder,
    stages: u32,
    ports: &O::Config,
    outputs: &O,
    what: &str,
) -> Arc<Module> {
    for _ in 0..stages {
        m.stage();
    }
    crate::ports::declare_outputs(&mut m, ports, outputs);
    Arc::new(
        m.finish()
            .unwrap_or_else(|e| panic!("{what} generator is type-correct for every format: {e}")),
    )
}

/// Spreads `stages` pipeline registers over the boundaries after `steps`
/// logical steps: element `i` is the number of registers placed after step
/// `i`. One register goes after the last step first (registered outputs),
/// the others are spread evenly; stages beyond `steps` also go at the end.
pub fn spread(stages: u32, steps: u32) -> Vec<u32> {
    assert!(steps > 0, "an operator has at least one step");
    let mut after = vec![0u32; steps as usize];
    for k in 0..stages {
        // the number of steps done before register k: ceil((k + 1) * steps / stages)
        let done = ((k + 1) * steps).div_ceil(stages).clamp(1, steps);
        after[done as usize - 1] += 1;
    }
    if stages > steps {
        // keep at most one register per boundary before the end, the rest at the end
        let extra: u32 = after.iter().map(|&a| a.saturating_sub(1)).sum();
        for a in after.iter_mut() {
            *a = (*a).min(1);
        }
        *after.last_mut().unwrap() += extra;
    }
    after
}

/// [`spread`] over consecutive segments of steps: element `i` is the number
/// of registers placed inside or after segment `i` (`segments[i]` steps),
/// so a unit names its phases instead of slicing the step list.
pub fn spread_over<const N: usize>(stages: u32, segments: [u32; N]) -> [u32; N] {
    let after = spread(stages, segments.iter().sum());
    let mut at = 0usize;
    segments.map(|n| {
        let sum = after[at..at + n as usize].iter().sum();
        at += n as usize;
        sum
    })
}

/// `x` (an encoding of `fmt`) with its sign bit flipped: exact negation, a
/// NaN stays a NaN.
pub fn negate(m: &mut ModuleBuilder, fmt: Format, x: crate::builder::Sig) -> crate::builder::Sig {
    let sign = m.uint(fmt.width(), 1u128 << (fmt.width() - 1));
    m.xor(x, sign)
}

/// Smallest width of a two's complement value holding every integer in `lo..=hi`.
pub fn sint_width(lo: i64, hi: i64) -> u32 {
    let mut w = 1;
    while lo < -(1i64 << (w - 1)) || hi >= (1i64 << (w - 1)) {
        w += 1;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_registers_outputs_first_and_balances() {
        assert_eq!(spread(0, 3), vec![0, 0, 0]);
        assert_eq!(spread(1, 3), vec![0, 0, 1]);
        assert_eq!(spread(2, 6), vec![0, 0, 1, 0, 0, 1]);
        assert_eq!(spread(3, 3), vec![1, 1, 1]);
        assert_eq!(spread(5, 3), vec![1, 1, 3]);
        assert_eq!(spread_over(2, [2, 3, 1]), [0, 1, 1]);
        assert_eq!(spread_over(5, [1, 1, 1]), [1, 1, 3]);
        for steps in 1..8 {
            for stages in 0..12 {
                assert_eq!(spread(stages, steps).iter().sum::<u32>(), stages);
            }
        }
    }

    #[test]
    fn formats_and_widths() {
        assert_eq!(Format::BINARY32.bias(), 127);
        assert_eq!(Format::BINARY32.nan_bits(), 0x7fc0_0000);
        assert_eq!(Format::BINARY16.inf_bits(), 0x7c00);
        assert!(Format::new(11, 53).is_err());
        assert!(Format::new(12, 20).is_err());
        assert!(Format::new(11, 52).is_ok());
        assert_eq!(sint_width(-128, 127), 8);
        assert_eq!(sint_width(-129, 0), 9);
        assert_eq!(sint_width(0, 128), 9);
    }

    /// The `Display` of a format is its module-name tag (test messages print it).
    #[test]
    fn a_format_displays_as_its_tag() {
        assert_eq!(Format::BINARY32.to_string(), "e8m23");
        assert_eq!(Format::new(2, 1).unwrap().to_string(), "e2m1");
    }
}
