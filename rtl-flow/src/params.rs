//! Parameters as the command line gives them: `key=value` words read into
//! the (key, value) pairs a unit's table checks ([`rtl_gen::params`]), and
//! the flow's own table, which every unit takes besides its own
//! ([`FlowParams`]: where the pipeline registers go, how products map to
//! DSP blocks, the handshake).

use rtl_gen::params::{ParamError, ParamSpec, Params};

rtl_gen::choice! {
    /// Where a unit's pipeline registers go (`rtl_gen::retime`).
    pub enum Pipeline {
        /// the unit's own per-step plan, hierarchical
        Plan = "plan",
        /// the combinational datapath, flattened, cut into stages of equal
        /// modelled delay
        Balanced = "balanced",
    }
}

rtl_gen::choice! {
    /// How registered products are written (`rtl_gen::retime::hard_dsp`).
    pub enum Dsp {
        /// plain `*`, any synthesis tool maps it
        Infer = "infer",
        /// ECP5 MULT18X18D cells with their output registers
        Ecp5 = "ecp5",
        /// 7-series: a 24x24 product on one DSP48E1 and hand-placed LUT rows
        Xc7 = "xc7",
    }
}

rtl_gen::choice! {
    /// The unit's handshake (`rtl_gen::handshake`, docs/handshake.md).
    pub enum Handshake {
        /// in_valid/out_valid, fixed latency, no backpressure
        Valid = "valid",
        /// in_valid/in_ready and out_valid/out_ready around the same core
        Ready = "ready",
    }
}

rtl_gen::params! {
    /// The parameters every unit takes besides its own.
    pub struct FlowParams {
        /// register placement: plan (the unit's own per-step plan, hierarchical) or balanced
        /// (the combinational datapath, flattened, cut into `stages` stages of equal modelled
        /// delay: one module, a shorter clock period)
        pipeline: Pipeline = Pipeline::Plan,
        /// multiplier blocks: infer (plain `*`, any synthesis tool maps it) or ecp5 (each
        /// registered product of at most 18x18 bits written as an ECP5 MULT18X18D with its own
        /// output register, so the route back from the DSP row is a path of its own; Verilog
        /// for ECP5 synthesis, same function and latency) or xc7 (a 24x24 unsigned product of a
        /// flat datapath on one DSP48E1, which takes a*signed(b[17:0]), the rest
        /// a*(b[23:18] + b[17]) in hand-placed LUT6/CARRY4 rows, about 87 LUT per block saved;
        /// Verilog for 7-series synthesis, same function and latency)
        dsp: Dsp = Dsp::Infer,
        /// dsp=xc7 only: at most this many DSP48E1 blocks as Yosys maps the unit, the earliest
        /// products in the datapath moved to one block first; 0: every 24x24 product on one
        dsp_blocks: u32 [0..=100000] = 0,
        /// interface: valid (in_valid/out_valid, fixed latency, no backpressure) or ready
        /// (adds in_ready and out_ready: the consumer may stall; credits and an output FIFO of
        /// latency + 1 entries around the same core, same latency and one transaction per cycle
        /// while out_ready stays high; docs/handshake.md)
        handshake: Handshake = Handshake::Valid,
    }
}

/// Reads `key=value` words and checks them against `specs` (missing keys
/// take their defaults).
pub fn resolve(unit: &str, specs: &[ParamSpec], given: &[String]) -> Result<Params, ParamError> {
    let pairs = given
        .iter()
        .map(|g| {
            g.split_once('=')
                .ok_or_else(|| ParamError::Syntax(g.clone()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Params::check(unit, specs, pairs)
}

/// Refuses a key given twice in what a user typed (`-p k=1 -p k=2`, or `-p`
/// beside the `--format` or `--round` that stands for it): which one should
/// win is a guess. Internal callers override a user's value by appending
/// after this check, so [`resolve`] itself keeps the last value.
pub fn given_once(given: &[String]) -> Result<(), ParamError> {
    let key = |g: &String| {
        g.split_once('=')
            .map_or(g.trim(), |(k, _)| k.trim())
            .to_string()
    };
    for (i, a) in given.iter().enumerate() {
        if let Some(b) = given[..i].iter().find(|b| key(b) == key(a)) {
            return Err(ParamError::Combination(format!(
                "parameter `{}` is given twice ({b} and {a}; --format sets exp_bits and \
                 frac_bits, --round sets round)",
                key(a)
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use rtl_gen::params::ParamSet;

    #[test]
    fn a_key_given_twice_is_refused() {
        let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert!(given_once(&words(&["stages=2", "pipeline=plan"])).is_ok());
        let e = given_once(&words(&["stages=2", "dsp=infer", " stages = 5"])).unwrap_err();
        assert!(e.to_string().contains("`stages` is given twice"), "{e}");
    }

    #[test]
    fn words_are_read_and_checked() {
        let p = resolve("u", FlowParams::SPECS, &["pipeline = balanced".into()]).unwrap();
        assert_eq!(FlowParams::from_params(&p).pipeline, Pipeline::Balanced);
        assert!(matches!(
            resolve("u", FlowParams::SPECS, &["pipeline".into()]),
            Err(ParamError::Syntax(_))
        ));
        let e = resolve("u", FlowParams::SPECS, &["dsp=xilinx".into()]).unwrap_err();
        assert!(e.to_string().contains("one of infer, ecp5"), "{e}");
    }
}
