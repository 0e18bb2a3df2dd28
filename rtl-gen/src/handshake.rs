//! The valid/ready handshake (`handshake=ready`, docs/handshake.md): one
//! wrapper, for every unit, around its fixed-latency core.
//!
//! The core has no clock enable: a transaction it has taken comes out
//! `latency` cycles later whatever the consumer does. So the wrapper hands
//! out credits: `occupancy` counts the transactions taken and not yet
//! delivered (in the core or in the output FIFO), and `in_ready` is high
//! while it is below the FIFO's depth, `latency + 1`. Whatever is in flight
//! then always finds a free FIFO entry, and a stalled consumer loses
//! nothing. The FIFO falls through when empty, so while `out_ready` stays
//! high a result leaves in the cycle it leaves the core: latency unchanged,
//! one transaction per cycle (`occupancy` stays at `latency`). `in_ready`
//! is a register's decode: no combinational path from `out_ready`.

use crate::arith::int::{bits_for, dec, inc, is};
use crate::builder::{BuildErrors, ModuleBuilder, Sig};
use crate::ir::{control, Module, Ty};
use std::sync::Arc;

/// Entries of the output FIFO of a core of `latency` cycles: every
/// transaction in flight plus one, so that `in_ready` can stay high while the
/// consumer takes one result per cycle.
pub fn fifo_depth(latency: u32) -> u32 {
    latency + 1
}

/// The module name of the valid/ready wrapper of `core`.
pub fn ready_name(core: &Module) -> String {
    format!("{}_rdy", core.name)
}

/// `core` (a module with the valid handshake) behind the valid/ready
/// handshake: the same data ports and latency, plus `in_ready` out and
/// `out_ready` in. Named [`ready_name`]; its parameters are the core's.
pub fn with_ready(core: &Module) -> Result<Module, BuildErrors> {
    let latency = core.latency;
    let depth = fifo_depth(latency);
    let core = Arc::new(core.clone());
    let (mut m, in_valid, out_ready) =
        ModuleBuilder::with_ready_handshake(ready_name(&core), latency);
    m.describe(format!(
        "{} Valid/ready handshake around {}: credits for {depth} transactions, an output \
         FIFO of {depth} entries that falls through when empty.",
        core.description, core.name
    ));
    for (k, v) in &core.params {
        m.param(k.clone(), v);
    }

    // credits: taken and not yet delivered never exceed the FIFO's depth
    let count_w = bits_for(depth as u64);
    let occupancy = m.reg("occupancy", Ty::UInt(count_w), Some(0));
    let full = is(&mut m, occupancy.q, depth as u64);
    let has_credit = m.not(full);
    let has_credit = m.name(has_credit, "has_credit");
    let accept = m.and(in_valid, has_credit);
    let accept = m.name(accept, "accept");

    let mut conns: Vec<(String, Sig)> = vec![(control::IN_VALID.into(), accept)];
    for p in core.data_inputs() {
        let s = m.input(&p.name, p.ty);
        conns.push((p.name.clone(), s));
    }
    let outs = m.instance_unstaged("u_core", &core, &conns);
    let (&core_valid, core_data) = outs.all().split_first().expect("the core has out_valid");

    // the output FIFO: a result goes straight out when the FIFO is empty and
    // the consumer is ready, else into the FIFO
    let stored = m.reg("fifo_count", Ty::UInt(count_w), Some(0));
    let fifo_empty = is(&mut m, stored.q, 0);
    let fifo_empty = m.name(fifo_empty, "fifo_empty");
    let fifo_holds = m.not(fifo_empty);
    let fifo_holds = m.name(fifo_holds, "fifo_holds");
    let out_valid = m.or(core_valid, fifo_holds);
    let out_valid = m.name(out_valid, "result_valid");
    let deliver = m.and(out_valid, out_ready);
    let deliver = m.name(deliver, "deliver");
    let bypass = m.and(fifo_empty, out_ready);
    let not_bypass = m.not(bypass);
    let push = m.and(core_valid, not_bypass);
    let push = m.name(push, "push");
    let pop = m.and(fifo_holds, out_ready);
    let pop = m.name(pop, "pop");
    count(&mut m, occupancy, accept, deliver);
    count(&mut m, stored, push, pop);
    let write_at = ring_pointer(&mut m, "write_at", depth, push);
    let read_at = ring_pointer(&mut m, "read_at", depth, pop);

    let write_slot: Vec<Sig> = (0..depth)
        .map(|i| match write_at {
            Some(at) => {
                let hit = is(&mut m, at, i as u64);
                let here = m.and(push, hit);
                m.name(here, &format!("write_slot{i}"))
            }
            None => push,
        })
        .collect();
    let mut results = Vec::with_capacity(core_data.len());
    let names = core.data_outputs().iter().map(|(p, _)| &p.name);
    for (name, &value) in names.zip(core_data) {
        let slots: Vec<Sig> = write_slot
            .iter()
            .enumerate()
            .map(|(i, &here)| {
                let slot = m.reg(&format!("fifo{i}_{name}"), value.ty(), None);
                m.set_next(slot, value, Some(here));
                slot.q
            })
            .collect();
        let head = pick(&mut m, &slots, read_at);
        let head = m.name(head, &format!("fifo_{name}_head"));
        results.push((name.clone(), m.mux(fifo_empty, value, head)));
    }
    m.ready_outputs(out_valid, has_credit);
    for (name, value) in results {
        m.output(&name, value);
    }
    m.finish()
}

/// `reg` counts up on `up`, down on `down`, and holds when both or neither.
#[track_caller]
fn count(m: &mut ModuleBuilder, reg: crate::builder::RegHandle, up: Sig, down: Sig) {
    let moves = m.xor(up, down);
    let moves = m.name_after(moves, reg.q, "moves");
    let plus = inc(m, reg.q);
    let plus = m.name_after(plus, reg.q, "up");
    let minus = dec(m, reg.q);
    let minus = m.name_after(minus, reg.q, "down");
    let next = m.mux(up, plus, minus);
    m.set_next(reg, next, Some(moves));
}

/// A FIFO index `0..depth` that steps (and wraps) on `advance`; `None` for a
/// FIFO of one entry, which needs no index.
#[track_caller]
fn ring_pointer(m: &mut ModuleBuilder, name: &str, depth: u32, advance: Sig) -> Option<Sig> {
    if depth == 1 {
        return None;
    }
    let w = bits_for(depth as u64 - 1);
    let at = m.reg(name, Ty::UInt(w), Some(0));
    let last = is(m, at.q, depth as u64 - 1);
    let last = m.name_after(last, at.q, "at_end");
    let zero = m.uint(w, 0);
    let step = inc(m, at.q);
    let step = m.name_after(step, at.q, "step");
    let next = m.mux(last, zero, step);
    m.set_next(at, next, Some(advance));
    Some(at.q)
}

/// `items[index]`, a tree of multiplexers on the bits of `index` (the first
/// item when there is no index); an index past the end is never given.
#[track_caller]
fn pick(m: &mut ModuleBuilder, items: &[Sig], index: Option<Sig>) -> Sig {
    let mut level = items.to_vec();
    let mut bit = 0;
    while level.len() > 1 {
        let index = index.expect("more than one item has an index");
        let sel = m.bit_at(index, bit);
        level = level
            .chunks(2)
            .map(|pair| match pair {
                [lo, hi] => m.mux(sel, *hi, *lo),
                [only] => *only,
                _ => unreachable!("chunks of two"),
            })
            .collect();
        bit += 1;
    }
    level[0]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::Evaluator;

    /// A core of latency 2 that adds one to `a`.
    fn core() -> Module {
        let mut m = ModuleBuilder::with_handshake("plus1_s2");
        let a = m.input("a", Ty::UInt(8));
        let one = m.uint(8, 1);
        let s = m.add(a, one);
        m.stage();
        m.stage();
        m.output("z", s);
        m.finish().unwrap()
    }

    /// Pushes 0..n through the wrapper with the consumer stalled on a
    /// pattern: every result comes out once, in order, and never while a
    /// stall holds it; with no stall, one per cycle after the latency.
    #[test]
    fn stalls_lose_nothing_and_no_stall_keeps_full_rate() {
        let m = with_ready(&core()).unwrap();
        assert_eq!(m.name, "plus1_s2_rdy");
        assert_eq!(m.latency, 2);
        let hs = m.handshake.unwrap();
        assert!(hs.ready);
        let names: Vec<_> = m.outputs.iter().map(|(p, _)| p.name.as_str()).collect();
        assert_eq!(names, ["out_valid", "in_ready", "z"]);
        for stall_every in [0u32, 2, 3, 7] {
            let mut ev = Evaluator::new(&m);
            ev.set_reset(true);
            ev.step(&[0, 0, 0]);
            ev.set_reset(false);
            let (mut sent, mut got, n) = (0u128, Vec::new(), 40u128);
            for cycle in 0..400u32 {
                let ready = stall_every == 0 || cycle % stall_every != 0;
                let valid = sent < n;
                let out = ev.eval(&[valid as u128, ready as u128, sent]);
                if stall_every == 0 && valid {
                    assert_eq!(out[1], 1, "in_ready fell with no stall at cycle {cycle}");
                }
                if valid && out[1] == 1 {
                    sent += 1;
                }
                if out[0] == 1 && ready {
                    got.push(out[2]);
                }
                ev.clock();
            }
            let want: Vec<u128> = (1..=n).collect();
            assert_eq!(got, want, "stall every {stall_every}");
        }
    }
}
