//! The flow: a unit, its parameters, its golden model and stimulus; writing
//! the Verilog, port list and constraints; lint, Verilator build, cross-check.
//!
//! This is the only place that knows both the generator and the golden model;
//! the DSL layers below never see either `sim` or `golden-model`.

pub mod byo;
pub mod cli;
pub mod cocotb;
pub mod cull;
pub mod cull_ray;
pub mod float_ops;
pub mod fstim;
pub mod mulcmp;
pub mod node;
pub mod node_child;
pub mod node_sort;
pub mod package;
pub mod params;
pub mod raycull;
pub mod rays;
pub mod regress;
pub mod report;
pub mod silhouette;
pub mod slab;
pub mod stimulus;
pub mod testfloat;
pub mod tilerange;
pub mod transform;
pub mod triangle;

use params::{Dsp, FlowParams, Handshake, Pipeline};
use rtl_gen::emit::{emit, VerilogFile};
use rtl_gen::ir::{control, Module, Ty};
use rtl_gen::params::{ParamError, ParamSet, ParamSpec, Params};
use rtl_gen::units::{self, Description, Unit};
use std::fmt;
use std::path::{Path, PathBuf};

/// Golden model plus stimulus of one unit, for resolved parameters.
pub trait Testbench: sim::Golden + sim::Stimulus {}

/// A testbench whose vector `k` is vector `first + k` of `of`: to run
/// vectors from far beyond the corner list.
pub struct Skipped<'a> {
    /// the testbench
    pub of: &'a dyn Testbench,
    /// its first vector taken
    pub first: u64,
}

impl sim::Golden for Skipped<'_> {
    fn eval(&self, inputs: &[u64], outputs: &mut [u64]) {
        self.of.eval(inputs, outputs)
    }
}

impl sim::Stimulus for Skipped<'_> {
    fn vector(&self, seed: u64, index: u64, inputs: &mut [u64]) {
        self.of.vector(seed, self.first + index, inputs)
    }
}

impl Testbench for Skipped<'_> {}

/// A unit the CLI offers: its generator and its testbench.
pub struct Entry {
    /// the generator
    pub unit: &'static dyn Unit,
    /// makes the testbench for resolved parameters
    pub testbench: fn(&Params) -> Box<dyn Testbench>,
}

/// One line of the catalog: the unit's description (from `rtl_gen::units`)
/// and its testbench type, built by `Bench::new(&config)` from the
/// description's one parse of the parameters; a float operator alone (its
/// testbench is [`float_ops::FloatOpBench`]).
macro_rules! entry {
    ($unit:expr, $bench:path) => {
        Entry {
            unit: &$unit,
            testbench: |p| Box::new(<$bench>::new(&configured(&$unit, p))),
        }
    };
    ($op:expr) => {
        Entry {
            unit: &$op,
            testbench: |p| {
                let c = $op.configured(p).expect("parameters the operator accepted");
                Box::new(float_ops::FloatOpBench::new(&c))
            },
        }
    };
}

/// The configuration of parameters the unit has accepted (a testbench is
/// made only for a unit that was built from the same parameters).
pub fn configured<D: Description>(unit: &D, p: &Params) -> D::Config {
    unit.config(&D::Params::from_params(p))
        .unwrap_or_else(|e| panic!("{}: parameters the unit accepted: {e}", D::NAME))
}

/// Every unit, in the order `rtl-gen list` shows them: registering a unit
/// is its line here.
pub fn catalog() -> Vec<Entry> {
    vec![
        entry!(units::mulcmp::MulCmp, mulcmp::MulCmpBench),
        entry!(units::silhouette::Silhouette, silhouette::SilhouetteBench),
        entry!(units::slab::Slab, slab::SlabBench),
        entry!(units::cull::Cull, cull::CullBench),
        entry!(units::cull_ray::CullRay, cull_ray::CullRayBench),
        entry!(units::transform::Transform, transform::TransformBench),
        entry!(units::triangle::Triangle, triangle::TriangleBench),
        entry!(units::node::Node, node::NodeBench),
        entry!(units::node_child::NodeChild, node_child::NodeChildBench),
        entry!(units::node_sort::NodeSort, node_sort::NodeSortBench),
        entry!(units::raycull::RayCull, raycull::RayCullBench),
        entry!(units::tilerange::TileRange, tilerange::TileRangeBench),
        entry!(units::float_ops::FADD),
        entry!(units::float_ops::FADD_DOWN_UP),
        entry!(units::float_ops::FMUL),
        entry!(units::float_ops::FMUL_EXACT),
        entry!(units::float_ops::FCMP),
        entry!(units::float_ops::FMINMAX),
        entry!(units::float_ops::FCVT),
        entry!(units::float_ops::FFMA),
        entry!(units::float_ops::FDOT3),
        entry!(units::float_ops::FRECIP),
        entry!(units::float_ops::FUNPACK),
    ]
}

/// The catalog entry called `name`.
pub fn find(name: &str) -> Result<Entry, ParamError> {
    let known: Vec<String> = catalog()
        .iter()
        .map(|e| e.unit.name().to_string())
        .collect();
    catalog()
        .into_iter()
        .find(|e| e.unit.name() == name)
        .ok_or(ParamError::UnknownUnit {
            name: name.to_string(),
            known,
        })
}

/// Anything that stops the flow.
#[derive(Debug)]
pub enum FlowError {
    /// bad unit or parameters
    Params(ParamError),
    /// writing the outputs failed
    Io(PathBuf, std::io::Error),
    /// Verilator, the harness or the cross-check failed
    Sim(sim::SimError),
}

impl fmt::Display for FlowError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FlowError::Params(e) => write!(f, "{e}"),
            FlowError::Io(p, e) => write!(f, "{}: {e}", p.display()),
            FlowError::Sim(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for FlowError {}

impl From<ParamError> for FlowError {
    fn from(e: ParamError) -> Self {
        FlowError::Params(e)
    }
}

impl From<sim::SimError> for FlowError {
    fn from(e: sim::SimError) -> Self {
        FlowError::Sim(e)
    }
}

/// A generated unit: the module, its Verilog files and its port list.
pub struct Generated {
    /// unit name
    pub unit: String,
    /// resolved parameters
    pub params: Params,
    /// the top module
    pub module: Module,
    /// Verilog, submodules first
    pub files: Vec<VerilogFile>,
    /// the contract with the harness
    pub ports: sim::PortList,
    /// what `pipeline=balanced` did (`None` for the unit's own plan)
    pub balance: Option<rtl_gen::retime::Balance>,
}

impl Generated {
    /// The delay model's clock period of the emitted module, LUT levels.
    pub fn modelled_period(&self) -> Result<f64, String> {
        match &self.balance {
            // measured on the schedule itself: re-reading the emitted module
            // would put each DSP block's routes back into the block's stage
            Some(b) => Ok(b.period),
            None => rtl_gen::retime::modelled_period(&self.module),
        }
    }
}

fn port_width(ty: Ty) -> u32 {
    ty.width()
}

/// Every parameter of `entry`: its own and the flow's ([`FlowParams`]).
pub fn param_specs(entry: &Entry) -> Vec<ParamSpec> {
    let mut specs = entry.unit.params().to_vec();
    specs.extend_from_slice(FlowParams::SPECS);
    specs
}

/// Builds `unit` with `given` parameters (`key=value` strings) and emits it.
///
/// `pipeline=balanced` builds the unit with `stages=0` (its datapath without
/// registers, and without the structure a plan adds for its registers, such
/// as multipliers cut into slices) and lets [`rtl_gen::retime::balance`] place
/// `stages` registers; the module keeps the plan's name with `_bal` added.
pub fn generate(unit: &str, given: &[String]) -> Result<Generated, FlowError> {
    let entry = find(unit)?;
    let specs = param_specs(&entry);
    let params = params::resolve(unit, &specs, given)?;
    let flow = FlowParams::from_params(&params);
    // the budget of blocks applies to dsp=xc7 alone (refused below otherwise)
    let params = match flow.dsp {
        Dsp::Xc7 => params,
        _ => params.without("dsp_blocks"),
    };
    let mut module = entry.unit.build(&params)?;
    let mut balance = None;
    if flow.pipeline == Pipeline::Balanced {
        let datapath = entry.unit.build_datapath(&params)?.ok_or_else(|| {
            ParamError::Combination(format!(
                "unit `{unit}` has no `stages`: pipeline=balanced does not apply"
            ))
        })?;
        let (mut balanced, report) = rtl_gen::retime::balance(&datapath, module.latency)
            .map_err(|e| ParamError::Combination(format!("pipeline=balanced: {e}")))?;
        balanced.name = format!("{}_bal", module.name);
        balanced.params = module.params.clone();
        balanced
            .params
            .insert("pipeline".into(), flow.pipeline.word().into());
        balanced.description = format!(
            "{} Registers placed by rtl-gen's delay model (pipeline=balanced): modelled period {:.1} LUT levels.",
            module.description, report.period
        );
        module = balanced;
        balance = Some(report);
    }
    if flow.dsp == Dsp::Ecp5 {
        let (hard, done) = rtl_gen::retime::hard_dsp::ecp5_hard_registers(&module);
        if done.products == 0 {
            return Err(ParamError::Combination(format!(
                "dsp=ecp5: `{}` has no registered product of at most 18x18 bits to put in a \
                 MULT18X18D (give it stages, or pipeline=balanced)",
                module.name
            ))
            .into());
        }
        module = hard;
        module.params.insert("dsp".into(), flow.dsp.word().into());
        module.description = format!(
            "{} {} products in ECP5 MULT18X18D blocks with their output registers (dsp=ecp5).",
            module.description, done.products
        );
    }
    if flow.dsp == Dsp::Xc7 {
        let budget = (flow.dsp_blocks > 0).then_some(flow.dsp_blocks);
        let (hard, done) = rtl_gen::retime::xc7_dsp::xc7_hand_map(&module, budget)
            .map_err(ParamError::Combination)?;
        if done.products == 0 && budget.is_none() {
            return Err(ParamError::Combination(format!(
                "dsp=xc7: `{}` has no 24x24 unsigned product to put on one DSP48E1 (a unit's \
                 products=whole keeps its significand products whole)",
                module.name
            ))
            .into());
        }
        module = hard;
        let suffix = budget.map_or(String::new(), |b| b.to_string());
        module.name = format!("{}_xc7dsp{suffix}", module.name);
        module.params.insert("dsp".into(), flow.dsp.word().into());
        if let Some(b) = budget {
            module.params.insert("dsp_blocks".into(), b.to_string());
        }
        module.description = format!(
            "{} {} products of 24x24 bits on one DSP48E1 each (dsp=xc7): {} blocks as Yosys maps \
             the unit, {} before.",
            module.description, done.products, done.blocks_after, done.blocks_before
        );
    } else if flow.dsp_blocks > 0 {
        return Err(ParamError::Combination("dsp_blocks applies to dsp=xc7".into()).into());
    }
    if flow.handshake == Handshake::Ready {
        module = rtl_gen::handshake::with_ready(&module)
            .map_err(|e| ParamError::Combination(format!("handshake=ready: {e}")))?;
        module
            .params
            .insert("handshake".into(), flow.handshake.word().into());
    }
    let files = emit(&module, rtl_gen::GENERATOR);
    let ready = module.handshake.is_some_and(|hs| hs.ready);
    let ports = sim::PortList {
        top: module.name.clone(),
        files: files.iter().map(|f| f.file_name.clone()).collect(),
        generator: rtl_gen::GENERATOR.to_string(),
        unit: unit.to_string(),
        params: params.values().clone(),
        latency: module.latency,
        clock: control::CLOCK.into(),
        reset: control::RESET.into(),
        in_valid: control::IN_VALID.into(),
        out_valid: control::OUT_VALID.into(),
        ready: ready.then(|| sim::ReadyPorts {
            in_ready: control::IN_READY.into(),
            out_ready: control::OUT_READY.into(),
        }),
        inputs: module
            .data_inputs()
            .iter()
            .map(|p| sim::Port {
                name: p.name.clone(),
                width: port_width(p.ty),
            })
            .collect(),
        outputs: module
            .data_outputs()
            .iter()
            .map(|(p, _)| sim::Port {
                name: p.name.clone(),
                width: port_width(p.ty),
            })
            .collect(),
    };
    Ok(Generated {
        unit: unit.to_string(),
        params,
        module,
        files,
        ports,
        balance,
    })
}

/// A timing constraints file (SDC) for the top module: one clock, and I/O
/// delays of a fifth of the period so the unit's registers see a real budget.
pub fn sdc(g: &Generated, period_ns: f64) -> String {
    let io = period_ns / 5.0;
    // every port but clk and rst: the handshake's, then the data
    let data_in: Vec<&str> = g.module.inputs.iter().map(|p| p.name.as_str()).collect();
    let data_out: Vec<&str> = g
        .module
        .outputs
        .iter()
        .map(|(p, _)| p.name.as_str())
        .collect();
    format!(
        "# Timing constraints for {top}, generated by {gen}.\n\
         # Parameters: {params}\n\
         # Latency {lat} cycle(s); every path is register to register inside the unit\n\
         # except the input and output stages, budgeted below.\n\
         create_clock -name clk -period {period_ns:.3} [get_ports clk]\n\
         set_input_delay -clock clk {io:.3} [get_ports {{rst {ins}}}]\n\
         set_output_delay -clock clk {io:.3} [get_ports {{{outs}}}]\n",
        top = g.module.name,
        gen = rtl_gen::GENERATOR,
        params = rtl_gen::emit::lower::params_line(g.params.values()),
        lat = g.module.latency,
        ins = data_in.join(" "),
        outs = data_out.join(" "),
    )
}

impl Generated {
    /// Writes the Verilog files, `<top>.ports.json` and `<top>.sdc` into `dir`.
    pub fn write(&self, dir: &Path, clock_period_ns: f64) -> Result<Vec<PathBuf>, FlowError> {
        let created = (!dir.exists()).then_some(dir);
        std::fs::create_dir_all(dir).map_err(|e| FlowError::Io(dir.to_path_buf(), e))?;
        let mut written = Vec::new();
        let mut put = |name: String, text: &str| -> Result<(), FlowError> {
            let path = dir.join(name);
            std::fs::write(&path, text).map_err(|e| FlowError::Io(path.clone(), e))?;
            written.push(path);
            Ok(())
        };
        let json = serde_json::to_string_pretty(&self.ports).expect("port list serialises");
        let outcome = (|| {
            for f in &self.files {
                put(f.file_name.clone(), &f.text)?;
            }
            put(
                format!("{}.sdc", self.module.name),
                &sdc(self, clock_period_ns),
            )?;
            put(format!("{}.ports.json", self.module.name), &(json + "\n"))
        })();
        match outcome {
            Ok(()) => Ok(written),
            Err(e) => {
                // nothing half-written: a design is all of its files or none
                remove_written(&written, created);
                Err(e)
            }
        }
    }

    /// Takes the text of every module file present in `dir` (same file name)
    /// instead of the generated one: an engineer's edited copy of the design,
    /// simulated (`rtl-gen sim --verilog`) or proved (`rtl-gen prove
    /// --verilog`) as the unit. The top module's file must be there; returns
    /// how many files were taken.
    pub fn use_verilog_from(&mut self, dir: &Path) -> Result<usize, FlowError> {
        let top = format!("{}.v", self.module.name);
        if !dir.join(&top).is_file() {
            return Err(FlowError::Sim(sim::SimError::Invalid(format!(
                "--verilog {}: no {top} there (the top module of {} {})",
                dir.display(),
                self.unit,
                self.param_args()
            ))));
        }
        let mut taken = 0;
        for f in &mut self.files {
            let path = dir.join(&f.file_name);
            if path.is_file() {
                f.text = std::fs::read_to_string(&path).map_err(|e| FlowError::Io(path, e))?;
                taken += 1;
            }
        }
        Ok(taken)
    }

    /// The testbench of this unit and parameters.
    pub fn testbench(&self) -> Box<dyn Testbench> {
        let entry = find(&self.unit).expect("generated from a catalog unit");
        (entry.testbench)(&self.params)
    }

    /// The command line that regenerates this unit.
    pub fn param_args(&self) -> String {
        self.params.to_args()
    }
}

/// A failing vector: its index, inputs, golden outputs and evaluator outputs.
pub type FailingVector = (u64, Vec<u64>, Vec<u64>, Vec<u64>);

/// Result of running vectors through the IR evaluator against the golden model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EvalReport {
    /// vectors compared
    pub vectors: u64,
    /// vectors with at least one differing output
    pub mismatches: u64,
    /// the first failing vector
    pub first: Option<FailingVector>,
}

impl fmt::Display for EvalReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} vectors, {} mismatches",
            self.vectors, self.mismatches
        )?;
        if let Some((index, inputs, expected, got)) = &self.first {
            let hex = |v: &[u64]| {
                v.iter()
                    .map(|x| format!("{x:#x}"))
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            write!(
                f,
                "; first at index {index}: inputs {} golden {} evaluator {}",
                hex(inputs),
                hex(expected),
                hex(got)
            )?;
        }
        Ok(())
    }
}

impl Generated {
    /// Runs vectors `0..vectors` of `seed` through the cycle-based IR evaluator,
    /// back to back with the handshake, and compares every output with the
    /// golden model: the third leg of the check, next to Verilator. When
    /// Verilator disagrees with the golden model but the evaluator agrees,
    /// the emitter (or the harness) is at fault; when both disagree, the
    /// generator or the golden model is.
    pub fn evaluate(&self, tb: &dyn Testbench, vectors: u64, seed: u64) -> EvalReport {
        let m = &self.module;
        let n_in = self.ports.inputs.len();
        let n_out = self.ports.outputs.len();
        // in_valid (and out_ready, held high: the consumer never stalls), then the data
        let control = m.handshake.map_or(1, |hs| hs.control_ports());
        let mut ev = rtl_gen::eval::Evaluator::new(m);
        ev.set_reset(true);
        ev.step(&vec![0; n_in + control]);
        ev.set_reset(false);
        let mut report = EvalReport {
            vectors: 0,
            mismatches: 0,
            first: None,
        };
        let mut next_out = 0u64;
        let (mut inputs, mut expected) = (vec![0u64; n_in], vec![0u64; n_out]);
        for cycle in 0..vectors + m.latency as u64 {
            let mut drive = vec![0u128; n_in + control];
            drive[1..control].fill(1);
            if cycle < vectors {
                tb.vector(seed, cycle, &mut inputs);
                drive[0] = 1;
                for (d, v) in drive[control..].iter_mut().zip(&inputs) {
                    *d = *v as u128;
                }
            }
            let out = ev.step(&drive);
            if out[0] == 1 {
                tb.vector(seed, next_out, &mut inputs);
                tb.eval(&inputs, &mut expected);
                let got: Vec<u64> = out[control..].iter().map(|v| *v as u64).collect();
                if got != expected {
                    report.mismatches += 1;
                    if report.first.is_none() {
                        report.first = Some((next_out, inputs.clone(), expected.clone(), got));
                    }
                }
                next_out += 1;
            }
        }
        report.vectors = next_out;
        report
    }
}

/// A command's output files, checked before it does any work, so that a
/// bad path fails first and leaves nothing: each one's directory exists, it
/// is not a directory or a device, and no two are the same file (one would
/// overwrite the other).
pub fn check_outputs(paths: &[Option<&std::path::Path>]) -> Result<(), FlowError> {
    let paths: Vec<&std::path::Path> = paths.iter().flatten().copied().collect();
    for (i, p) in paths.iter().enumerate() {
        if let Some(problem) = sim::output_problem(p) {
            return Err(cli::bad_usage(problem));
        }
        if paths[..i].iter().any(|q| same_file(q, p)) {
            return Err(cli::bad_usage(format!(
                "{}: given as two outputs of one command",
                p.display()
            )));
        }
    }
    Ok(())
}

/// Whether two output paths name one file: the same after their links are
/// followed (where a write goes, [`sim::through_links`]) and their folders
/// resolved (`./a` and `a`).
fn same_file(a: &Path, b: &Path) -> bool {
    let resolved = |p: &Path| {
        let p = sim::through_links(p);
        let dir = p.parent().filter(|d| !d.as_os_str().is_empty());
        let dir = dir.unwrap_or(Path::new("."));
        (
            std::fs::canonicalize(dir).ok(),
            p.file_name().map(|n| n.to_owned()),
        )
    };
    a == b || resolved(a) == resolved(b)
}

/// Removes the files a failed command wrote, and the directory it created for
/// them when that is left empty (best effort: the error that stopped it is the
/// one reported), so that nothing half-written is left.
pub fn remove_written(paths: &[PathBuf], created_dir: Option<&Path>) {
    for p in paths {
        let _ = std::fs::remove_file(p);
    }
    if let Some(dir) = created_dir {
        let _ = std::fs::remove_dir(dir);
    }
}
