//! Register placement by delay: a module's pipeline registers moved to where
//! its logic is cut into stages of about equal delay.
//!
//! Units place their `stage()` calls by logical steps (after the alignment,
//! after the products, ...); a step that is long, or registers that meet at a
//! module boundary, set the clock. [`balance`] keeps a module's function and
//! ports, removes its pipeline registers and places the requested number
//! again where they cut the logic evenly (the flow's `pipeline=balanced`
//! hands it the unit's combinational build):
//!
//! 1. the module is flattened (instances inlined, their names prefixed with the
//!    instance name) and its pipeline registers removed, which leaves one
//!    combinational graph of the transaction; unsigned products wider than a
//!    DSP block's 18 bits are split into 18x18 blocks and a sum, so that
//!    registers can go between the blocks and the sum;
//! 2. each operation gets a delay from [`delay`], a model of an FPGA with
//!    4-input LUTs, carry chains and 18x18 multipliers (one LUT level = 1.0);
//! 3. the smallest period `P` whose as-soon-as-possible schedule fits in
//!    the requested latency is found by bisection (no stage longer than `P`
//!    except where one operation alone is longer); in it and in the
//!    as-late-as-possible schedule of the same `P`, each stage boundary is
//!    moved by a minimum cut to where the values crossing it are narrowest
//!    ([`registers`]), and the one that carries fewer register bits is kept;
//! 4. the graph is replayed through a [`ModuleBuilder`] stage by stage, so the
//!    registers that carry values, and the valid chain, are the builder's own.
//!
//! Only feed-forward pipelines are re-timed: a module with a register that has
//! an enable or reads a later value (state) is refused.

mod delay_model;
mod flatten;
mod graph;
pub mod hard_dsp;
mod registers;
mod schedule;
mod split;
pub mod xc7_dsp;

pub use delay_model::delay;

use crate::builder::{BuildErrors, ModuleBuilder, Sig};
use crate::ir::{Module, Node, Op, Ty};
use graph::{analyse, Graph};
use schedule::{
    as_late_as_possible, as_soon_as_possible, last_stage, period_of, register_bits, Schedule,
};
use split::on_dsp;

crate::choice! {
    /// How [`balance_with`] flattens a product wider than a DSP block (a
    /// unit parameter `products`).
    pub enum Products {
        /// unsigned products wider than 18 bits become 18x18 blocks and their
        /// sum (ECP5's MULT18X18D; registers can go between blocks and sum)
        Split = "split",
        /// every product stays one `*`, for the synthesis tool to map (a 7-series
        /// DSP48E1 takes 25x18 and sums the pieces of a wider product in its
        /// cascade, so a split there costs blocks and LUT adders)
        Whole = "whole",
    }
}

/// What [`balance`] did, for the reports.
#[derive(Debug, Clone, PartialEq)]
pub struct Balance {
    /// longest register-to-register chain of the delay model, LUT levels
    pub period: f64,
}

/// The delay model's clock period of `m` as it is pipelined: the longest
/// chain of [`delay`]s between two registers, in LUT levels.
pub fn modelled_period(m: &Module) -> Result<f64, String> {
    let g = analyse(m, Products::Split)?;
    let built = Schedule {
        stage: g.flat.nodes.iter().map(|n| n.built).collect(),
    };
    Ok(period_of(&g, &built))
}

/// Re-places the pipeline registers of `m` so that it has `latency` of them
/// (see the module documentation). The result has the same ports and
/// function, `latency` cycles of latency, and no instances.
pub fn balance(m: &Module, latency: u32) -> Result<(Module, Balance), String> {
    balance_with(m, latency, Products::Split)
}

/// [`balance`] with the products flattened as `products` says.
pub fn balance_with(
    m: &Module,
    latency: u32,
    products: Products,
) -> Result<(Module, Balance), String> {
    let g = analyse(m, products)?;
    let last = latency;
    // with the DSP output routes starting a stage (a register at every
    // block's pins) where the latency allows it, else as plain logic
    let mut best: Option<(f64, Schedule)> = None;
    for force in [true, false] {
        let asap = |period: f64| as_soon_as_possible(&g, period, force);
        if last_stage(&asap(f64::INFINITY)) > last {
            continue;
        }
        // bisection on the period: the shortest whose ASAP schedule fits the latency
        let longest = period_of(&g, &asap(f64::INFINITY));
        let (mut lo, mut hi) = (
            g.delay.iter().copied().fold(0.0, f64::max),
            longest.max(1e-9),
        );
        if last_stage(&asap(lo)) <= last {
            hi = lo;
        }
        for _ in 0..48 {
            if hi - lo < 1e-3 {
                break;
            }
            let mid = 0.5 * (lo + hi);
            if last_stage(&asap(mid)) <= last {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let period = hi;
        // from both ends of the schedules of this period, the boundaries moved
        // to narrow values; the one with fewer register bits is kept
        let mut schedule: Option<(u64, Schedule)> = None;
        let alap = as_late_as_possible(&g, period, last, force);
        for mut s in std::iter::once(asap(period)).chain(alap) {
            let within = period.max(period_of(&g, &s));
            registers::minimise(&g, &mut s, last, within, force);
            let bits = register_bits(&g, &s, last);
            if schedule.as_ref().is_none_or(|(b, _)| bits < *b) {
                schedule = Some((bits, s));
            }
        }
        let (_, schedule) = schedule.expect("the ASAP schedule");
        let achieved = period_of(&g, &schedule);
        if best.as_ref().is_none_or(|(p, _)| achieved < *p - 1e-6) {
            best = Some((achieved, schedule));
        }
    }
    let (period, best) = best.expect("without forced registers every latency fits");
    let module = replay(m, &g, &best, last).map_err(|e| e.to_string())?;
    Ok((module, Balance { period }))
}

/// Builds the module again from the graph, stage by stage.
fn replay(m: &Module, g: &Graph, s: &Schedule, last: u32) -> Result<Module, BuildErrors> {
    let (flat, live) = (&g.flat, &g.live);
    let mut b = match m.handshake {
        Some(_) => ModuleBuilder::with_handshake(m.name.clone()),
        None => ModuleBuilder::new(m.name.clone()),
    };
    b.describe(m.description.clone());
    for (k, v) in &m.params {
        b.param(k, v);
    }
    let mut order: Vec<usize> = (0..flat.nodes.len())
        .filter(|&i| live[i] || matches!(flat.nodes[i].op, Op::Input(_)))
        .collect();
    order.sort_by_key(|&i| (s.stage[i].unwrap_or(0), i));
    let mut sig: Vec<Option<Sig>> = vec![None; flat.nodes.len()];
    for i in order {
        let node = &flat.nodes[i];
        while b.current_stage() < s.stage[i].unwrap_or(0) {
            b.stage();
        }
        let new = match &node.op {
            Op::Input(_) if Some(i) == flat.in_valid => b.in_valid().expect("handshake"),
            Op::Input(_) => b.input(&node.name, node.ty),
            op => {
                let op = op
                    .clone()
                    .map_operands(|id| sig[id.0 as usize].expect("operands precede users").id());
                b.replay(op, node.ty, &node.name, node.named)
            }
        };
        sig[i] = Some(new);
    }
    while b.current_stage() < last {
        b.stage();
    }
    for (port, o) in &flat.outputs {
        b.output(&port.name, sig[*o].expect("outputs are live"));
    }
    b.finish()
}

/// A named node of a small behavioural module written here (a hard block's
/// behaviour), located at its caller.
#[track_caller]
fn cell_node(op: Op, ty: Ty, name: &str) -> Node {
    Node {
        op,
        ty,
        name: name.into(),
        named: true,
        location: std::panic::Location::caller(),
    }
}
