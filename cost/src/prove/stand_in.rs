//! `equiv` of a `handshake=ready` unit with a **stand-in core**
//! (`--solver structural`, docs/proofs.md): for a unit whose datapath is too
//! deep for the k-induction of the whole wrapper (the triangle), the proof
//! is split in three, each a proof:
//!
//! 1. the core (the `handshake=valid` module the wrapper instantiates as
//!    `u_core`, from the design's own files) against the reference by the
//!    structural proof: with a reset in the first cycle only, `out_valid` is
//!    `in_valid` delayed by the latency, and while it is high the outputs are
//!    the reference's function of the inputs of `latency` cycles before;
//! 2. the wrapper's data inputs are read by its core alone (checked on the
//!    wrapper's netlist), so what the wrapper sees of a transaction is the
//!    core's outputs;
//! 3. the wrapper, its Verilog unchanged, around a stand-in core with the
//!    core's module name, ports and latency that has exactly that contract
//!    for a function whose results are free: `out_valid` the same delay line,
//!    the outputs the low input bits of `latency` cycles before while valid
//!    and other input bits of the current cycle while not (any value, and
//!    independent of every result); the reference a stand-in too, the same
//!    low bits. Then step 3 is `handshake`'s k-induction with invariants.
//!
//! Why the three make the proof: every output sequence the real core can
//! show the wrapper under its contract (step 1) the stand-in shows it too
//! for some inputs (each transaction's result and each invalid cycle's
//! outputs are free there), and the wrapper reads nothing else of the data
//! (step 2); the properties of step 3 (in order, none lost or duplicated,
//! credits) hold for every such sequence, so for the real core's. The
//! stand-in needs at least twice as many input bits as output bits (results
//! and the invalid cycles' outputs from disjoint bits).

use rtl_flow::Generated;
use std::fmt::Write as _;

/// The stand-in core (module doc): the module `name` with `ports`' clock,
/// reset, valid and data ports, `latency` ≥ 1.
pub(super) fn core(ports: &sim::PortList, name: &str) -> Result<String, String> {
    let (in_w, out_w) = widths(ports)?;
    let l = ports.latency;
    let mut v = header(ports, name, "stand-in core", (in_w, out_w));
    let _ = writeln!(
        v,
        "    // the results: the low input bits, delayed; the valid bits as the core's"
    );
    for j in 1..=l {
        let _ = writeln!(
            v,
            "    reg valid_s{j};\n    reg [{}:0] result_s{j};",
            out_w - 1
        );
    }
    v += "    always @(posedge clk) begin\n";
    for j in 1..=l {
        let (valid, result) = if j == 1 {
            (
                ports.in_valid.clone(),
                format!("stand_in_in[{}:0]", out_w - 1),
            )
        } else {
            (format!("valid_s{}", j - 1), format!("result_s{}", j - 1))
        };
        let _ = writeln!(
            v,
            "        valid_s{j} <= {reset} ? 1'b0 : {valid};\n        result_s{j} <= {result};",
            reset = ports.reset
        );
    }
    v += "    end\n";
    let _ = writeln!(
        v,
        "    // not valid: other bits of the inputs, a value unrelated to any result\n    \
         assign {} = valid_s{l};\n    assign stand_in_out = valid_s{l} ? result_s{l} : stand_in_in[{}:{}];\nendmodule",
        ports.out_valid,
        in_w - 1,
        in_w - out_w
    );
    Ok(v)
}

/// The stand-in reference (module doc): the module `name`, combinational,
/// the low input bits.
pub(super) fn reference(ports: &sim::PortList, name: &str) -> Result<String, String> {
    let (in_w, out_w) = widths(ports)?;
    let mut v = header(ports, name, "stand-in reference", (in_w, out_w));
    let _ = writeln!(
        v,
        "    assign {} = {};\n    assign stand_in_out = stand_in_in[{}:0];\nendmodule",
        ports.out_valid,
        ports.in_valid,
        out_w - 1
    );
    Ok(v)
}

/// Input and output bits; an error when the inputs are too few.
fn widths(ports: &sim::PortList) -> Result<(u32, u32), String> {
    let in_w: u32 = ports.inputs.iter().map(|p| p.width).sum();
    let out_w: u32 = ports.outputs.iter().map(|p| p.width).sum();
    if in_w < 2 * out_w {
        return Err(format!(
            "{}: a stand-in core needs twice as many input bits as output bits ({in_w} and \
             {out_w}); prove the wrapper with its own core (--solver boolector)",
            ports.top
        ));
    }
    Ok((in_w, out_w))
}

/// The module's ports, `stand_in_in` (every data input, the first one's bits
/// lowest, `in_w` bits) and `stand_in_out` (every data output, likewise,
/// `out_w` bits) as wires.
fn header(ports: &sim::PortList, name: &str, what: &str, (in_w, out_w): (u32, u32)) -> String {
    let range = super::verilog_range;
    let mut decl = vec![
        format!("input wire {}", ports.clock),
        format!("input wire {}", ports.reset),
        format!("input wire {}", ports.in_valid),
    ];
    decl.extend(
        ports
            .inputs
            .iter()
            .map(|p| format!("input wire {}{}", range(p.width), p.name)),
    );
    decl.push(format!("output wire {}", ports.out_valid));
    decl.extend(
        ports
            .outputs
            .iter()
            .map(|p| format!("output wire {}{}", range(p.width), p.name)),
    );
    let concat = |ps: &[sim::Port]| {
        let names: Vec<&str> = ps.iter().rev().map(|p| p.name.as_str()).collect();
        format!("{{{}}}", names.join(", "))
    };
    let mut v = format!(
        "// Generated by rtl-gen prove: the {what} of {} (docs/proofs.md).\n\
         `default_nettype none\nmodule {name} (\n    {}\n);\n",
        ports.top,
        decl.join(",\n    ")
    );
    let _ = writeln!(
        v,
        "    wire [{}:0] stand_in_in = {};\n    wire [{}:0] stand_in_out;\n    assign {} = stand_in_out;",
        in_w - 1,
        concat(&ports.inputs),
        out_w - 1,
        concat(&ports.outputs)
    );
    v
}

/// Step 2 (module doc) on the wrapper's netlist `json` (Yosys `write_json`,
/// not flattened): every bit of a data input of module `top` reaches no cell
/// but `u_core` and no output port. `None` when it holds, else what reads it.
pub(super) fn inputs_read_only_by_core(
    json: &serde_json::Value,
    top: &str,
    dut: &Generated,
) -> Result<Option<String>, String> {
    let module = &json["modules"][top];
    let bits = |port: &str| -> Result<Vec<serde_json::Value>, String> {
        module["ports"][port]["bits"]
            .as_array()
            .cloned()
            .ok_or_else(|| format!("{top}: no port {port} in the wrapper's netlist"))
    };
    let mut data_bits = Vec::new();
    for p in &dut.ports.inputs {
        data_bits.extend(bits(&p.name)?.into_iter().map(|b| (b, p.name.clone())));
    }
    let reads = |conn: &serde_json::Value| -> Option<String> {
        let conn = conn.as_array()?;
        data_bits
            .iter()
            .find(|(b, _)| conn.contains(b))
            .map(|(_, name)| name.clone())
    };
    for p in &dut.ports.outputs {
        if let Some(input) = reads(&module["ports"][&p.name]["bits"]) {
            return Ok(Some(format!("output {} carries input {input}", p.name)));
        }
    }
    let cells = module["cells"]
        .as_object()
        .ok_or_else(|| format!("{top}: no cells in the wrapper's netlist"))?;
    if !cells.contains_key("u_core") {
        return Err(format!("{top}: the wrapper has no instance u_core"));
    }
    for (name, cell) in cells.iter().filter(|(n, _)| n.as_str() != "u_core") {
        let conns = cell["connections"].as_object().into_iter().flatten();
        for (pin, conn) in conns {
            if let Some(input) = reads(conn) {
                return Ok(Some(format!(
                    "cell {name} ({}) reads input {input} on {pin}",
                    cell["type"].as_str().unwrap_or("?")
                )));
            }
        }
    }
    Ok(None)
}
