//! `--solver structural`: an `equiv` proof that bit-blasts no pipeline
//! state, for the units whose k-induction does not finish (the triangle,
//! whose products cross stages).
//!
//! It rests on a fact about pipelines: if every register is a plain
//! rising-edge flip-flop of `clk` (no enable, no feedback, no clock used as
//! data) and every path from an input to an output crosses the same number
//! `L` of them, then after the first `L` cycles each output equals the
//! register-free circuit (every register replaced by a wire) applied to the
//! inputs of `L` cycles before. So three checks make the proof, each small:
//!
//! 1. **Balance** (this file, on the netlist Yosys reads from the Verilog,
//!    `netlist.json`): every cell gets a stage, the inputs 0, a register's
//!    output its input's stage + 1, a combinational cell the one stage all its
//!    inputs share (constants and `rst` fit any stage: `rst` is low on every
//!    cycle the comparison looks at, step 3); every output at the latency.
//!    Both designs are checked, each at its own latency.
//! 2. **The combinational miter** (Yosys `miter -equiv` and `sat`): the two
//!    designs with their registers made wires, `rst` low, equal on every
//!    output for every input.
//! 3. **`out_valid`** by temporal induction on the wrapper with the data
//!    outputs left out (the valid chain is all that is left after Yosys drops
//!    the unread datapath): `out_valid` agrees with the reference's, delayed,
//!    on every cycle after the reset. The reset is only on the first cycle, so
//!    a valid output at cycle `t` means `rst` was low on cycles `t − L .. t`.
//!
//! Together: on every cycle after the reset `out_valid` agrees and, while it
//! is high, every output agrees, which is what k-induction proves. A
//! pipeline that is not balanced gets no verdict from here (`not proved`,
//! naming the cell where two stages meet): k-induction may still prove it.

use super::Outcome;
use serde_json::Value;
use std::collections::BTreeMap;

/// A bit of the netlist: a net number, or a constant (`"0"`, `"1"`, `"x"`).
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Debug)]
enum Bit {
    Net(u64),
    Constant,
}

fn bits(v: &Value) -> Vec<Bit> {
    v.as_array()
        .map(|a| {
            a.iter()
                .map(|b| b.as_u64().map(Bit::Net).unwrap_or(Bit::Constant))
                .collect()
        })
        .unwrap_or_default()
}

/// The combinational cells Yosys's `proc` and `flatten` leave; anything else
/// (an enable or reset flip-flop, a latch, a memory, an instance of a
/// vendor primitive) is not a plain pipeline.
const COMBINATIONAL: &[&str] = &[
    "$not",
    "$pos",
    "$neg",
    "$and",
    "$or",
    "$xor",
    "$xnor",
    "$reduce_and",
    "$reduce_or",
    "$reduce_xor",
    "$reduce_xnor",
    "$reduce_bool",
    "$shl",
    "$shr",
    "$sshl",
    "$sshr",
    "$shift",
    "$shiftx",
    "$lt",
    "$le",
    "$eq",
    "$ne",
    "$eqx",
    "$nex",
    "$ge",
    "$gt",
    "$add",
    "$sub",
    "$mul",
    "$div",
    "$mod",
    "$divfloor",
    "$modfloor",
    "$logic_not",
    "$logic_and",
    "$logic_or",
    "$mux",
    "$pmux",
    "$bmux",
    "$demux",
    "$bwmux",
    "$bweqx",
];

/// Where a bit stands: a pipeline stage, or any stage (a constant, `rst`).
type Stage = Option<u32>;

struct Module<'a> {
    name: &'a str,
    cells: Vec<(&'a str, &'a Value)>,
    /// the cell driving each net, by index into `cells`
    driver: BTreeMap<u64, usize>,
    /// a readable name of each net
    net_name: BTreeMap<u64, String>,
    inputs: BTreeMap<u64, Stage>,
    clock: u64,
}

impl<'a> Module<'a> {
    fn name_of(&self, b: Bit) -> String {
        match b {
            Bit::Constant => "a constant".into(),
            Bit::Net(n) => self
                .net_name
                .get(&n)
                .cloned()
                .unwrap_or_else(|| format!("net {n}")),
        }
    }

    fn cell_place(&self, i: usize) -> String {
        let (name, cell) = self.cells[i];
        let src = cell["attributes"]["src"].as_str().unwrap_or("");
        format!(
            "{} cell `{name}`{}",
            cell["type"].as_str().unwrap_or("?"),
            if src.is_empty() {
                String::new()
            } else {
                format!(" ({src})")
            }
        )
    }
}

/// The stage of every output bit of `module` in Yosys's JSON netlist, or why
/// the module is not a balanced pipeline.
fn output_stages(
    netlist: &Value,
    module: &str,
    clock: &str,
    reset: &str,
) -> Result<BTreeMap<String, Vec<Stage>>, String> {
    let m = &netlist["modules"][module];
    if m.is_null() {
        return Err(format!("{module} is not in the netlist"));
    }
    let ports = m["ports"]
        .as_object()
        .ok_or(format!("{module}: no ports"))?;
    let mut inputs = BTreeMap::new();
    let mut clock_bit = None;
    for (name, p) in ports {
        if p["direction"] != "input" {
            continue;
        }
        for b in bits(&p["bits"]) {
            if let Bit::Net(n) = b {
                let stage = if name == clock {
                    clock_bit = Some(n);
                    None
                } else if name == reset {
                    None
                } else {
                    Some(0)
                };
                inputs.insert(n, stage);
            }
        }
    }
    let clock_bit = clock_bit.ok_or(format!("{module}: no clock input `{clock}`"))?;
    let cells: Vec<(&str, &Value)> = m["cells"]
        .as_object()
        .map(|c| c.iter().map(|(k, v)| (k.as_str(), v)).collect())
        .unwrap_or_default();
    let mut driver = BTreeMap::new();
    for (i, (_, cell)) in cells.iter().enumerate() {
        let dirs = &cell["port_directions"];
        for (port, conn) in cell["connections"].as_object().into_iter().flatten() {
            if dirs[port] == "output" {
                for b in bits(conn) {
                    if let Bit::Net(n) = b {
                        driver.insert(n, i);
                    }
                }
            }
        }
    }
    let mut net_name = BTreeMap::new();
    for (name, n) in m["netnames"].as_object().into_iter().flatten() {
        let hidden = n["hide_name"].as_u64() == Some(1);
        for (k, b) in bits(&n["bits"]).into_iter().enumerate() {
            if let Bit::Net(id) = b {
                let shown = format!("{name}[{k}]");
                let e = net_name.entry(id).or_insert((hidden, shown.clone()));
                if e.0 && !hidden {
                    *e = (hidden, shown);
                }
            }
        }
    }
    let module = Module {
        name: module,
        cells,
        driver,
        net_name: net_name.into_iter().map(|(k, (_, n))| (k, n)).collect(),
        inputs,
        clock: clock_bit,
    };
    let mut memo: Vec<Option<Stage>> = vec![None; module.cells.len()];
    let mut on_path = vec![false; module.cells.len()];
    let mut out = BTreeMap::new();
    for (name, p) in ports {
        if p["direction"] != "output" {
            continue;
        }
        let stages = bits(&p["bits"])
            .into_iter()
            .map(|b| bit_stage(&module, b, &mut memo, &mut on_path))
            .collect::<Result<Vec<_>, _>>()?;
        out.insert(name.clone(), stages);
    }
    Ok(out)
}

fn bit_stage(
    m: &Module,
    b: Bit,
    memo: &mut Vec<Option<Stage>>,
    on_path: &mut Vec<bool>,
) -> Result<Stage, String> {
    let Bit::Net(n) = b else { return Ok(None) };
    if n == m.clock {
        return Err(format!(
            "{}: the clock {} is read as data",
            m.name,
            m.name_of(b)
        ));
    }
    if let Some(s) = m.inputs.get(&n) {
        return Ok(*s);
    }
    // an undriven net is a free value in the miter: any stage here
    let Some(&i) = m.driver.get(&n) else {
        return Ok(None);
    };
    cell_stage(m, i, memo, on_path)
}

fn cell_stage(
    m: &Module,
    i: usize,
    memo: &mut Vec<Option<Stage>>,
    on_path: &mut Vec<bool>,
) -> Result<Stage, String> {
    if let Some(s) = memo[i] {
        return Ok(s);
    }
    if on_path[i] {
        return Err(format!(
            "{}: a loop through {}: not a feed-forward pipeline",
            m.name,
            m.cell_place(i)
        ));
    }
    on_path[i] = true;
    let (_, cell) = m.cells[i];
    let kind = cell["type"].as_str().unwrap_or("");
    let conn = &cell["connections"];
    let stage = if kind == "$dff" {
        if cell["parameters"]["CLK_POLARITY"]
            .as_str()
            .map(|p| p.trim_start_matches('0'))
            != Some("1")
        {
            return Err(format!(
                "{}: {} is clocked on the falling edge",
                m.name,
                m.cell_place(i)
            ));
        }
        if bits(&conn["CLK"]) != [Bit::Net(m.clock)] {
            return Err(format!(
                "{}: {} is not clocked by the clock",
                m.name,
                m.cell_place(i)
            ));
        }
        let mut s: Stage = None;
        for b in bits(&conn["D"]) {
            s = meet(m, i, s, b, bit_stage(m, b, memo, on_path)?)?;
        }
        s.map(|s| s + 1)
    } else if COMBINATIONAL.contains(&kind) {
        let dirs = &cell["port_directions"];
        let mut s: Stage = None;
        for (port, c) in conn.as_object().into_iter().flatten() {
            if dirs[port] != "input" {
                continue;
            }
            for b in bits(c) {
                s = meet(m, i, s, b, bit_stage(m, b, memo, on_path)?)?;
            }
        }
        s
    } else {
        return Err(format!(
            "{}: {} is neither a plain flip-flop nor combinational logic",
            m.name,
            m.cell_place(i)
        ));
    };
    on_path[i] = false;
    memo[i] = Some(stage);
    Ok(stage)
}

/// The stage a cell's inputs share so far (`s`), met by one more input.
fn meet(m: &Module, i: usize, s: Stage, b: Bit, t: Stage) -> Result<Stage, String> {
    match (s, t) {
        (Some(x), Some(y)) if x != y => Err(format!(
            "{}: {} reads {} at stage {y} beside inputs at stage {x}: not a balanced pipeline",
            m.name,
            m.cell_place(i),
            m.name_of(b)
        )),
        (None, t) => Ok(t),
        (s, _) => Ok(s),
    }
}

/// Checks that `module` is a balanced pipeline of latency `latency` (module
/// doc, step 1); `Err` says where it is not.
pub(super) fn check_balance(
    netlist: &Value,
    module: &str,
    clock: &str,
    reset: &str,
    latency: u32,
) -> Result<(), String> {
    for (port, stages) in output_stages(netlist, module, clock, reset)? {
        for (k, s) in stages.iter().enumerate() {
            if let Some(s) = s {
                if *s != latency {
                    return Err(format!(
                        "{module}: output {port}[{k}] is {s} register(s) from the inputs, not the latency {latency}"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The Yosys script of step 2: both designs read, flattened, written as
/// `netlist.json` for step 1, their registers made wires, compared by a
/// miter with `rst` low.
pub(super) fn miter_script(files: &[String], reference: &str, dut: &str, reset: &str) -> String {
    let mut s = String::new();
    for f in files {
        s += &format!("read_verilog -sv {f}\n");
    }
    s += &format!(
        "hierarchy -check\nproc\nflatten\nopt_clean\nwrite_json netlist.json\n\
         # every register a wire (module doc, step 2)\n\
         techmap -map registers_as_wires.v\nopt_clean\n\
         miter -equiv -flatten -make_outputs {reference} {dut} miter\n\
         hierarchy -top miter\nopt\n\
         sat -prove trigger 0 -set in_{reset} 0 -show-inputs -show-outputs -dump_vcd structure.vcd miter\n"
    );
    s
}

/// The techmap file that makes every `$dff` a wire.
pub(super) const REGISTERS_AS_WIRES: &str = "\
// rtl-gen prove --solver structural: every flip-flop replaced by a wire
(* techmap_celltype = \"$dff\" *)
module _register_as_wire (CLK, D, Q);
    parameter WIDTH = 1;
    parameter CLK_POLARITY = 1;
    input CLK;
    input [WIDTH-1:0] D;
    output [WIDTH-1:0] Q;
    assign Q = D;
endmodule
";

/// `Outcome::Unknown` for a design the structural proof does not apply to.
pub(super) fn not_balanced(what: &str, why: String) -> Outcome {
    Outcome::Unknown(format!(
        "{what}: the structural proof does not apply ({why}); try --solver boolector"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A netlist of one module `m`: inputs clk, rst, a, b; output y; the cells given.
    fn netlist(cells: Value, y: Value) -> Value {
        serde_json::json!({"modules": {"m": {
            "ports": {
                "clk": {"direction": "input", "bits": [2]},
                "rst": {"direction": "input", "bits": [3]},
                "a": {"direction": "input", "bits": [4]},
                "b": {"direction": "input", "bits": [5]},
                "y": {"direction": "output", "bits": y},
            },
            "cells": cells,
            "netnames": {"a_r": {"hide_name": 0, "bits": [10]}, "b": {"hide_name": 0, "bits": [5]}},
        }}})
    }

    fn dff(d: u64, q: u64) -> Value {
        serde_json::json!({"type": "$dff", "parameters": {"CLK_POLARITY": "1"},
            "port_directions": {"CLK": "input", "D": "input", "Q": "output"},
            "connections": {"CLK": [2], "D": [d], "Q": [q]}})
    }

    fn and(a: Value, b: Value, y: u64) -> Value {
        serde_json::json!({"type": "$and",
            "port_directions": {"A": "input", "B": "input", "Y": "output"},
            "connections": {"A": [a], "B": [b], "Y": [y]}})
    }

    #[test]
    fn a_balanced_pipeline_passes_at_its_latency_only() {
        // y = (a & b) registered, with rst and a constant mixed in
        let n = netlist(
            serde_json::json!({"g": and(4.into(), 5.into(), 6), "r": and(6.into(), "1".into(), 7),
                "s": and(7.into(), 3.into(), 8), "q": dff(8, 9)}),
            serde_json::json!([9, "0"]),
        );
        check_balance(&n, "m", "clk", "rst", 1).unwrap();
        let e = check_balance(&n, "m", "clk", "rst", 2).unwrap_err();
        assert!(e.contains("output y[0] is 1 register(s)"), "{e}");
    }

    #[test]
    fn a_register_on_one_input_only_is_not_balanced() {
        let n = netlist(
            serde_json::json!({"q": dff(4, 10), "g": and(10.into(), 5.into(), 11)}),
            serde_json::json!([11]),
        );
        let e = check_balance(&n, "m", "clk", "rst", 1).unwrap_err();
        assert!(
            e.contains("not a balanced pipeline")
                && e.contains("b[0] at stage 0")
                && e.contains("stage 1"),
            "{e}"
        );
    }

    #[test]
    fn feedback_enables_and_clocks_as_data_are_refused() {
        let looped = netlist(
            serde_json::json!({"q": dff(11, 10), "g": and(10.into(), 4.into(), 11)}),
            serde_json::json!([10]),
        );
        let e = check_balance(&looped, "m", "clk", "rst", 1).unwrap_err();
        assert!(e.contains("a loop"), "{e}");
        let mut enabled = dff(4, 10);
        enabled["type"] = "$dffe".into();
        let e = check_balance(
            &netlist(serde_json::json!({"q": enabled}), serde_json::json!([10])),
            "m",
            "clk",
            "rst",
            1,
        )
        .unwrap_err();
        assert!(e.contains("neither a plain flip-flop"), "{e}");
        let clocked = netlist(
            serde_json::json!({"g": and(2.into(), 4.into(), 10)}),
            serde_json::json!([10]),
        );
        let e = check_balance(&clocked, "m", "clk", "rst", 0).unwrap_err();
        assert!(e.contains("clock"), "{e}");
    }
}
