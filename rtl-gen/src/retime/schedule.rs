//! Schedules: a stage for every node of the graph, as soon or as late as a
//! clock period allows, and what a schedule costs (its period, its register
//! bits).

use super::graph::Graph;
use crate::ir::Op;

/// A stage per node (`None` for constants) and the period it was built for.
pub(super) struct Schedule {
    pub(super) stage: Vec<Option<u32>>,
}

/// Every node as early as the period allows.
pub(super) fn as_soon_as_possible(g: &Graph, period: f64, force: bool) -> Schedule {
    let (flat, live, d) = (&g.flat, &g.live, &g.delay);
    let n = flat.nodes.len();
    let mut stage: Vec<Option<u32>> = vec![None; n];
    let mut arrival = vec![0.0f64; n];
    for i in 0..n {
        if !live[i] {
            continue;
        }
        match flat.nodes[i].op {
            Op::Const(_) => continue,
            Op::Input(_) => {
                stage[i] = Some(0);
                continue;
            }
            _ => {}
        }
        let ops = flat.nodes[i].op.operands();
        let s = ops
            .iter()
            .filter_map(|o| stage[o.0 as usize])
            .max()
            .unwrap_or(0);
        let before = ops
            .iter()
            .filter(|o| stage[o.0 as usize] == Some(s))
            .map(|o| arrival[o.0 as usize])
            .fold(0.0, f64::max);
        if (force && flat.nodes[i].wire) || (before > 0.0 && before + d[i] > period) {
            stage[i] = Some(s + 1);
            arrival[i] = d[i];
        } else {
            stage[i] = Some(s);
            arrival[i] = before + d[i];
        }
    }
    Schedule { stage }
}

/// The mirror image: every node as late as its users allow, outputs at `last`.
pub(super) fn as_late_as_possible(
    g: &Graph,
    period: f64,
    last: u32,
    force: bool,
) -> Option<Schedule> {
    let (flat, live, users, is_output, d) = (&g.flat, &g.live, &g.users, &g.is_output, &g.delay);
    let n = flat.nodes.len();
    // stages counted back from the last one, and delay from the node to its stage's end
    let mut back: Vec<Option<u32>> = vec![None; n];
    let mut after = vec![0.0f64; n];
    for i in (0..n).rev() {
        if !live[i] || matches!(flat.nodes[i].op, Op::Const(_) | Op::Input(_)) {
            continue;
        }
        // a wire starts a stage: its operand is one stage earlier, at the stage's end
        let at = |u: usize| match force && flat.nodes[u].wire {
            true => back[u].map(|r| (r + 1, 0.0)),
            false => back[u].map(|r| (r, after[u])),
        };
        let mut r = if is_output[i] { Some(0) } else { None };
        for &u in &users[i] {
            r = r.max(at(u).map(|(r, _)| r));
        }
        let r = r.unwrap_or(0);
        let behind = users[i]
            .iter()
            .filter_map(|&u| at(u))
            .filter(|&(ru, _)| ru == r)
            .map(|(_, a)| a)
            .fold(0.0, f64::max);
        if behind > 0.0 && behind + d[i] > period {
            back[i] = Some(r + 1);
            after[i] = d[i];
        } else {
            back[i] = Some(r);
            after[i] = behind + d[i];
        }
    }
    let mut stage = vec![None; n];
    for i in 0..n {
        if !live[i] {
            continue;
        }
        match flat.nodes[i].op {
            Op::Const(_) => {}
            Op::Input(_) => stage[i] = Some(0),
            _ => stage[i] = Some(last.checked_sub(back[i]?)?),
        }
    }
    Some(Schedule { stage })
}

pub(super) fn last_stage(s: &Schedule) -> u32 {
    s.stage.iter().flatten().copied().max().unwrap_or(0)
}

/// Register bits a schedule carries: each value from its stage to its last user's.
pub(super) fn register_bits(g: &Graph, s: &Schedule, last: u32) -> u64 {
    let (flat, users, is_output) = (&g.flat, &g.users, &g.is_output);
    let mut bits = 0u64;
    for (i, node) in flat.nodes.iter().enumerate() {
        let Some(own) = s.stage[i] else { continue };
        let mut until = if is_output[i] { last } else { own };
        for &u in &users[i] {
            if let Some(su) = s.stage[u] {
                until = until.max(su);
            }
        }
        bits += u64::from(until - own) * u64::from(node.ty.width());
    }
    bits
}

/// The longest in-stage chain of `flat` under the stages of `s`.
pub(super) fn period_of(g: &Graph, s: &Schedule) -> f64 {
    let n = g.flat.nodes.len();
    let mut arrival = vec![0.0f64; n];
    let mut worst = 0.0f64;
    for i in 0..n {
        let Some(si) = s.stage[i] else { continue };
        if !g.live[i] {
            continue;
        }
        let before = g.flat.nodes[i]
            .op
            .operands()
            .iter()
            .filter(|o| s.stage[o.0 as usize] == Some(si))
            .map(|o| arrival[o.0 as usize])
            .fold(0.0, f64::max);
        arrival[i] = before + g.delay[i];
        worst = worst.max(arrival[i]);
    }
    worst
}
