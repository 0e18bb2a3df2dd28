//! The `rtl-gen` subcommands that render scenes ([`Command`], run by
//! [`main`]): the golden-model ray tracer (or the hybrid renderer) writes a
//! PNG and prints statistics; `bench` compares rays/s with a plain f32 slab
//! renderer; `rtl-loop` answers a render's tests from the Verilated units.
// clap reads doc comments as help text: the flattened argument groups of the
// variants stay without one.
#![allow(missing_docs)]

use crate::bvh::Accel;
use crate::hybrid::{orders, render_async, render_sync, HybridOpts, Mode};
use crate::output::Staged;
use crate::render::{render, render_with};
use crate::scene::{ao_rays_in_range, Scene};
use crate::stats::{bundle_savings, plane_savings, table, wide_table};
use crate::tester::{BoxTester, Exact, Golden, Reduced, Slab};
use crate::trace::{BundleOpts, TraceOpts, Tracer, TriTest};
use crate::wide::{Boxes, DopSelect, WideAccel};
use clap::{Subcommand, ValueEnum};
use golden_model::float::FloatFormat;
use golden_model::raycull::{Compare, DepthFormat};
use golden_model::wide::WideFormat;
use std::path::PathBuf;
use std::process::ExitCode;

/// The box tester of a render.
#[derive(Clone, Copy, ValueEnum)]
pub enum BoxKind {
    /// silhouette unit golden model (conservative), with bundles
    Golden,
    /// exact rational box test (single rays)
    Exact,
    /// plain f32 slab test (single rays, f32 transforms, no planes)
    Slab,
}

/// The options every render takes.
#[derive(clap::Args, Clone)]
pub struct Common {
    /// scene file (TOML)
    scene: PathBuf,
    /// image width (default: the scene's)
    #[arg(long)]
    width: Option<u32>,
    /// image height (default: the scene's, scaled with --width)
    #[arg(long)]
    height: Option<u32>,
    /// maximum rays per bundle (seed 000: 4, 16, 32, 64); 0 or 1 disables bundles
    /// [default: 16; none with --wide, whose traversal is single-ray]
    #[arg(long)]
    bundle: Option<usize>,
    /// do not place or use cull planes
    #[arg(long)]
    no_planes: bool,
    /// AO rays per pixel (default: the scene's)
    #[arg(long)]
    ao: Option<u32>,
    /// ray/triangle test [default: f64; rtl-loop: golden, the `outputs=full` unit]
    #[arg(long, value_enum)]
    tri: Option<TriKind>,
}

impl Common {
    /// `--bundle`, or its default.
    fn bundle_size(&self) -> usize {
        self.bundle.unwrap_or(DEFAULT_BUNDLE)
    }

    /// Refuses `--bundle` beside `--wide`: the wide traversal is single-ray, and a bundle
    /// size it would not use is a request it cannot honour.
    fn single_ray(&self, wide: &WideOpts) -> Result<(), String> {
        match (wide.wide, self.bundle) {
            (Some(n), Some(b)) => Err(format!(
                "--wide {n} traces single rays: no --bundle (given {b})"
            )),
            _ => Ok(()),
        }
    }
}

/// Rays per bundle when `--bundle` is not given.
const DEFAULT_BUNDLE: usize = 16;

/// A traversal over a wide BVH instead of the binary one (docs/wide.md, docs/node.md).
#[derive(clap::Args, Clone, Copy)]
pub struct WideOpts {
    /// trace through a wide BVH of N = 2, 4 or 8 children per compressed node, each node
    /// tested by the node tester's golden model (single rays: no bundles, no cull planes)
    #[arg(long, value_name = "N")]
    wide: Option<usize>,
    /// with --wide: bits per child box integer, q = 4..=16
    #[arg(long, default_value_t = 8, requires = "wide")]
    box_bits: u32,
    /// with --wide: bits per child box integer of the TLAS nodes (finer than --box-bits by
    /// default: instance boxes are often thin, docs/node.md §9)
    #[arg(long, default_value_t = crate::wide::TLAS_BOX_BITS, requires = "wide")]
    tlas_box_bits: u32,
    /// with --wide: test the exact binary32 child boxes of the same tree (conservative slab)
    /// instead of the compressed node
    #[arg(long, requires = "wide")]
    exact_boxes: bool,
    /// with --wide: test the compressed nodes with the earlier window-and-anchors model
    /// (docs/node.md §1-9, no RTL) instead of the node unit
    #[arg(long, requires = "wide", conflicts_with = "exact_boxes")]
    anchors: bool,
    /// with --wide: BLAS nodes also carry each slot's extent along diagonal directions,
    /// tested in the same cells (the cull-plane study, docs/node.md §11; the model only):
    /// `all` (the default) the four body diagonals at every node, a 14-DOP with the box;
    /// `one` one direction per node of the ten body and face diagonals, chosen by the builder;
    /// `normal` one per node of those ten and the node's own quantised normals
    #[arg(long, requires = "wide", conflicts_with_all = ["exact_boxes", "anchors"],
          num_args = 0..=1, default_missing_value = "all", value_name = "all|one|normal")]
    dop: Option<DopArg>,
    /// with --wide: the carried-position study (docs/node.md §12; the model only): each
    /// node's ray position computed from its parent's, kept to F fraction bits below the
    /// position grid's, instead of the node unit's window sums
    #[arg(long, requires = "wide", conflicts_with_all = ["exact_boxes", "anchors", "dop"],
          value_name = "F", value_parser = clap::value_parser!(u32).range(0..=32))]
    carried: Option<u32>,
}

/// `--dop`'s directions ([`DopSelect`]).
#[derive(Clone, Copy, ValueEnum)]
enum DopArg {
    All,
    One,
    Normal,
}

impl DopArg {
    fn select(self) -> DopSelect {
        match self {
            DopArg::All => DopSelect::All,
            DopArg::One => DopSelect::One,
            DopArg::Normal => DopSelect::Normal,
        }
    }
}

impl WideOpts {
    /// The wide shape, the TLAS's q and the boxes tested, if `--wide` is given.
    pub fn shape(&self) -> Result<Option<(WideFormat, u32, Boxes)>, String> {
        let Some(n) = self.wide else {
            return Ok(None);
        };
        let format = WideFormat::new(FloatFormat::BINARY32, n, self.box_bits)
            .map_err(|e| format!("--wide {n} --box-bits {}: {e}", self.box_bits))?;
        let boxes = if self.exact_boxes {
            Boxes::Exact
        } else if self.anchors {
            Boxes::Anchored
        } else if let Some(f) = self.carried {
            Boxes::Carried(f)
        } else {
            Boxes::Node
        };
        Ok(Some((format, self.tlas_box_bits, boxes)))
    }
}

/// What a wide render's boxes are, for its summary line.
fn wide_name(format: WideFormat, tlas_box_bits: u32, boxes: Boxes) -> String {
    match boxes {
        Boxes::Anchored => format!(
            "window-and-anchors node model N={} q={} (TLAS q={tlas_box_bits})",
            format.children(),
            format.box_bits()
        ),
        Boxes::Node => format!(
            "node unit N={} q={} (TLAS q={tlas_box_bits})",
            format.children(),
            format.box_bits()
        ),
        Boxes::Carried(f) => format!(
            "node model with carried positions F={f} N={} q={} (TLAS q={tlas_box_bits})",
            format.children(),
            format.box_bits()
        ),
        Boxes::Exact => format!(
            "conservative slab on exact binary32 child boxes, wide BVH N={}",
            format.children()
        ),
    }
}

/// The ray/triangle test of a render.
#[derive(Clone, Copy, ValueEnum)]
pub enum TriKind {
    /// software watertight test, f64 arithmetic on the binary32 data
    F64,
    /// the `triangle` unit's golden model at binary32 (bit for bit what the RTL computes)
    Golden,
    /// the same unit with `outputs=tnum` (no divider): `t = T/det` divided in software once
    /// per hit, as a shader would
    Tnum,
    /// exact rational test (slow)
    Exact,
}

/// The renderer's subcommands.
#[derive(Subcommand)]
pub enum Command {
    /// Ray-trace a scene, write a PNG, print statistics per ray type.
    Render {
        #[command(flatten)]
        c: Common,
        /// output PNG
        #[arg(long, short)]
        out: PathBuf,
        /// box tester
        #[arg(long = "box", value_enum, default_value = "golden")]
        box_kind: BoxKind,
        /// also render without cull planes and report what the planes saved
        #[arg(long, conflicts_with = "no_planes")]
        plane_savings: bool,
        /// also render without bundles and report the box tests the bundles saved, net
        #[arg(long)]
        bundle_savings: bool,
        /// box tests in a reduced format eXmY (e.g. e6m9) instead of binary32: the
        /// silhouette unit with ray and boxes rounded outward (--box golden only)
        #[arg(long, value_name = "eXmY")]
        box_format: Option<String>,
        /// write every pixel's primary hit (instance, primitive, t) as text
        #[arg(long, value_name = "FILE")]
        dump_hits: Option<PathBuf>,
        #[command(flatten)]
        wide: WideOpts,
    },
    /// Hybrid raster + ray tracing (seed 002): synchronous and asynchronous
    /// renders for several primitive orders, counts of emitted/culled/traced rays.
    Hybrid {
        #[command(flatten)]
        c: Common,
        /// output PNG (the synchronous image)
        #[arg(long, short)]
        out: PathBuf,
        /// rays the ray processor handles after each primitive
        #[arg(long, default_value_t = 64)]
        rays_per_step: usize,
        /// primitives rasterised while a traced batch's results are in flight (the
        /// contribution check then sees a later depth buffer than the cull)
        #[arg(long, default_value_t = 0)]
        result_latency: usize,
        /// depth code format of the raster and the ray-cull unit: unorm16, unorm24, binary32
        #[arg(long, default_value = "unorm24")]
        depth: String,
        /// depth test of the raster and the ray-cull unit: less, lequal, greater,
        /// gequal (greater and gequal: reversed depth, 1 at near)
        #[arg(long, default_value = "less")]
        compare: String,
        /// when surfaces are shaded: immediate (as soon as visible), partial:N
        /// (after each partial render of N primitives), deferred (after all)
        #[arg(long, default_value = "immediate")]
        mode: String,
        /// rays per cull group (consecutive queued rays of one tile)
        #[arg(long, default_value_t = 4)]
        group: usize,
        /// turn culling off (every ray traced; the contribution check still runs)
        #[arg(long)]
        no_cull: bool,
        /// answer every cull and contribution check from the Verilated `raycull` unit
        /// (each order's render is recorded with the golden model, run through the RTL,
        /// and rendered again from the RTL's answers)
        #[arg(long)]
        rtl: bool,
        /// shuffled orders to run (shuffle seeds 1..=N), besides the four fixed orders
        #[arg(long, default_value_t = 1)]
        shuffles: u64,
        /// with --rtl: directory for the generated Verilog and the vector streams
        /// (default: target/rtl-loop/<pid>)
        #[arg(long, requires = "rtl")]
        work: Option<PathBuf>,
    },
    /// RTL in the loop: record every box, transform, cull and triangle test of
    /// a (small) golden render, run them through the Verilated binary32 units
    /// (one stream per unit), render again answering every test from the RTL
    /// outputs and check the image is bit-identical. `--tri golden` (the
    /// default) runs the triangle tests through the `outputs=full` unit, `--tri
    /// tnum` through the `outputs=tnum products=whole` one. Prints one line per
    /// unit; exit 1 when a unit or the image differs (or a unit the render uses
    /// got no test).
    RtlLoop {
        #[command(flatten)]
        c: Common,
        /// trace through a wide BVH (--wide N, --box-bits, --tlas-box-bits), every node test
        /// answered by the `node` unit
        #[command(flatten)]
        wide: WideOpts,
        /// output PNG (the image answered by the RTL)
        #[arg(long, short)]
        out: Option<PathBuf>,
        /// directory for the generated Verilog and the vector streams
        /// (default: target/rtl-loop/<pid>)
        #[arg(long)]
        work: Option<PathBuf>,
    },
    /// Wide BVH with compressed nodes (docs/wide.md): per scene and node shape, the nodes,
    /// bytes per node, node bytes, and the node bytes fetched per camera ray (record bytes ×
    /// node visits), with the decoded child boxes and, as the baseline, with exact binary32
    /// child boxes in the same wide BVH (child tests per ray q / binary32). Exit 1 when the two
    /// find different hits.
    Wide {
        /// scene files (TOML)
        #[arg(required = true)]
        scenes: Vec<PathBuf>,
        /// child slots per node, 2, 4 or 8 (a comma-separated list reports each)
        #[arg(long, value_delimiter = ',', default_value = "4")]
        children: Vec<usize>,
        /// bits per child box integer, 4..=16 (a comma-separated list reports each)
        #[arg(long, value_delimiter = ',', default_value = "8")]
        box_bits: Vec<u32>,
        /// bits per child box integer of the TLAS nodes
        #[arg(long, default_value_t = crate::wide::TLAS_BOX_BITS)]
        tlas_box_bits: u32,
        /// width of the camera-ray image (default: the scene's)
        #[arg(long)]
        width: Option<u32>,
        /// height (default: the scene's, scaled with --width)
        #[arg(long)]
        height: Option<u32>,
        /// also bound what a bundle mode of the node tester could save: the camera rays in
        /// T×T pixel tiles, an oracle bundle test per node two or more of a tile's rays test
        /// (one line per scene and shape: tests per ray, the break-even cost of a bundle
        /// node test in single node tests; docs/wide.md §6)
        #[arg(long, value_name = "T")]
        bundle_tile: Option<u32>,
    },
    /// rays/s of the golden-model renderer and of a plain f32 slab renderer, same scene, same
    /// run; the last line is `golden/slab rays/s ratio: R` (golden with bundles).
    Bench {
        #[command(flatten)]
        c: Common,
        /// rounds: each round renders with every renderer once, in turn; each renderer's time
        /// is its median over the rounds (short renders vary by tens of percent)
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=99))]
        rounds: u32,
    },
}

fn setup(c: &Common) -> Result<(Scene, u32, u32, TraceOpts), String> {
    let mut s = Scene::load(&c.scene).map_err(|e| e.to_string())?;
    if let Some(a) = c.ao {
        s.render.ao_rays = ao_rays_in_range(a).map_err(|e| format!("--ao {e}"))?;
    }
    let (w, h) = s.render.image_size(c.width, c.height)?;
    let opts = TraceOpts {
        planes: !c.no_planes,
        bundles: BundleOpts {
            enabled: c.bundle_size() >= 2,
            max_size: c.bundle_size().max(2),
            ..BundleOpts::default()
        },
        f32_transform: false,
        tri: match c.tri.unwrap_or(TriKind::F64) {
            TriKind::F64 => TriTest::F64,
            TriKind::Golden => TriTest::Golden,
            TriKind::Tnum => TriTest::GoldenTnum,
            TriKind::Exact => TriTest::Exact,
        },
    };
    Ok((s, w, h, opts))
}

fn build(s: &Scene, planes: bool) -> Accel {
    let acc = Accel::build(s, planes);
    eprintln!(
        "{}: {} meshes, {} instances, {} instanced triangles",
        s.path.display(),
        s.meshes.len(),
        s.instances.len(),
        s.instanced_triangles()
    );
    eprintln!("{}", acc.describe());
    acc
}

/// Runs a command; `Ok` carries the exit code (1: the RTL in the loop differs).
fn run(command: Command) -> Result<ExitCode, String> {
    match command {
        Command::Render {
            c,
            out,
            box_kind,
            plane_savings: ps,
            bundle_savings: bs,
            box_format,
            dump_hits,
            wide,
        } => {
            c.single_ray(&wide)?;
            let (s, w, h, mut opts) = setup(&c)?;
            let dop = wide.dop.map(DopArg::select);
            let wide = wide.shape()?;
            if wide.is_some() && (box_format.is_some() || !matches!(box_kind, BoxKind::Golden)) {
                return Err(
                    "--wide tests boxes with the node tester: no --box or --box-format".into(),
                );
            }
            if wide.is_some() && (ps || bs) {
                return Err("--wide traces single rays without cull planes: no --plane-savings or --bundle-savings".into());
            }
            if wide.is_some() {
                opts.planes = false;
                opts.bundles.enabled = false;
            }
            let reduced = match &box_format {
                None => None,
                Some(name) => {
                    if !matches!(box_kind, BoxKind::Golden) {
                        return Err("--box-format needs --box golden (the silhouette unit)".into());
                    }
                    let fmt =
                        FloatFormat::from_name(name).map_err(|e| format!("--box-format {e}"))?;
                    Some(Reduced::new(fmt).map_err(|e| format!("--box-format {name}: {e}"))?)
                }
            };
            if matches!(box_kind, BoxKind::Slab) {
                opts.planes = false;
                opts.f32_transform = true;
            }
            let png = Staged::png(&out)?;
            let hits_file = dump_hits.as_deref().map(Staged::new).transpose()?;
            let acc = build(&s, opts.planes);
            let tester: Box<dyn BoxTester> = match box_kind {
                BoxKind::Golden => match reduced {
                    Some(r) => Box::new(r.with_world_anchor(Reduced::scene_anchor(&acc))),
                    None => Box::new(Golden::default()),
                },
                BoxKind::Exact => Box::new(Exact),
                BoxKind::Slab => Box::new(Slab),
            };
            let tracer = Tracer::new(&s, &acc, tester.as_ref(), opts);
            let wide_accel = match wide {
                Some((format, tlas_q, _)) => {
                    let w = WideAccel::build(&acc, format, tlas_q)?;
                    Some(match dop {
                        Some(select) => {
                            let meshes: Vec<_> = s.meshes.iter().map(|(_, m)| m).collect();
                            w.with_dop(&meshes, select)
                        }
                        None => w,
                    })
                }
                None => None,
            };
            let tracer = match (&wide_accel, wide) {
                (Some(wa), Some((_, _, boxes))) => tracer.with_wide(wa, boxes),
                _ => tracer,
            };
            let f = render_with(&s, &acc, &tracer, w, h, true);
            let tester_name = match wide {
                Some((format, tlas_q, boxes)) => wide_name(format, tlas_q, boxes),
                None => tester.name().to_string(),
            };
            f.save_png(png.temp_path())?;
            if let Some(staged) = &hits_file {
                let header = format!(
                    "render --dump-hits: {} {w}x{h}, box tester {}{}\ncamera: pixel (x, y) looks along forward + sx*right + sy*up, sx, sy the pixel centre on the image plane at distance 1 (x right, y down); t in units of that direction",
                    s.path.display(),
                    tester_name,
                    box_format.as_deref().map(|b| format!(" {b}")).unwrap_or_default()
                );
                std::fs::write(staged.temp_path(), f.hits_text(&header))
                    .map_err(|e| format!("{}: {e}", staged.temp_path().display()))?;
            }
            println!(
                "{} {}x{}, box tester {}{}, bundles {}: {} rays in {:.2} s = {:.0} rays/s -> {}",
                s.path.display(),
                w,
                h,
                tester_name,
                box_format
                    .as_deref()
                    .map(|b| format!(" {b}"))
                    .unwrap_or_default(),
                if opts.bundles.enabled {
                    format!("≤ {}", opts.bundles.max_size)
                } else {
                    "off".into()
                },
                f.rays(),
                f.time.as_secs_f64(),
                f.rays() as f64 / f.time.as_secs_f64(),
                out.display()
            );
            if wide.is_some() {
                println!("\n{}", wide_table(&f.stats));
            } else {
                println!("\n{}", table(&f.stats));
            }
            if matches!(opts.tri, TriTest::Golden | TriTest::GoldenTnum) {
                let t = f.stats.total();
                println!(
                    "triangle tests the unit flagged invalid (decided by the exact test): {} of {}",
                    t.tri_flagged, t.tri_tests
                );
            }
            if ps && opts.planes {
                let g = render(
                    &s,
                    &acc,
                    tester.as_ref(),
                    TraceOpts {
                        planes: false,
                        ..opts
                    },
                    w,
                    h,
                    true,
                );
                let same = g.ids == f.ids && g.t == f.t;
                println!(
                    "cull planes (same render without them; identical image: {same}):\n\n{}",
                    plane_savings(&f.stats, &g.stats)
                );
            }
            if bs && opts.bundles.enabled {
                let single = TraceOpts {
                    bundles: BundleOpts {
                        enabled: false,
                        ..opts.bundles
                    },
                    ..opts
                };
                let g = render(&s, &acc, tester.as_ref(), single, w, h, true);
                println!(
                    "bundles (same render with single rays; identical image: {}):\n\n{}",
                    g.same_hits(&f),
                    bundle_savings(&f.stats, &g.stats)
                );
            }
            png.commit()?;
            if let Some(staged) = hits_file {
                staged.commit()?;
            }
        }
        Command::Hybrid {
            c,
            out,
            rays_per_step,
            result_latency,
            depth,
            compare,
            mode,
            group,
            no_cull,
            rtl,
            shuffles,
            work,
        } => {
            let work = work.unwrap_or_else(crate::rtl::default_work_dir);
            let mut tally = crate::hybrid_rtl::RtlTally::default();
            let depth = match depth.as_str() {
                "unorm16" => DepthFormat::Unorm16,
                "unorm24" => DepthFormat::Unorm24,
                "binary32" => DepthFormat::Binary32,
                other => {
                    return Err(format!(
                        "--depth: `{other}` is not a depth format (unorm16, unorm24, binary32)"
                    ))
                }
            };
            let compare = match compare.as_str() {
                "less" => Compare::Less,
                "lequal" => Compare::LEqual,
                "greater" => Compare::Greater,
                "gequal" => Compare::GEqual,
                other => {
                    return Err(format!(
                        "--compare: `{other}` is not a compare mode (less, lequal, greater, gequal)"
                    ))
                }
            };
            let mode = Mode::parse(&mode).map_err(|e| format!("--mode: {e}"))?;
            if !(1..=8).contains(&group) {
                return Err(format!("--group: {group} is not in 1..=8"));
            }
            let (s, w, h, opts) = setup(&c)?;
            let png = Staged::png(&out)?;
            let acc = build(&s, opts.planes);
            let g = Golden::default();
            let base = HybridOpts {
                rays_per_step,
                result_latency,
                depth,
                compare,
                mode,
                group,
                cull: !no_cull,
                ..HybridOpts::default()
            };
            let sync = render_sync(&s, &acc, &g, opts, w, h, &base);
            sync.save_png(png.temp_path())?;
            println!(
                "{} {}x{} hybrid; synchronous: {} rays traced in {:.2} s -> {}\n",
                s.path.display(),
                w,
                h,
                sync.rays(),
                sync.time.as_secs_f64(),
                out.display()
            );
            if matches!(compare, Compare::LEqual | Compare::GEqual) {
                println!("{compare:?}: the last of equal-depth fragments wins, so each order is compared with the synchronous render in that order\n");
            }
            println!("| order | shaded | emitted | culled: tile range | sample depth | generation | groups culled (rays) | kept by translucency | traced | discarded (contribution check) | superseded | used | raycull transactions | identical to sync |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
            let mut differ = Vec::new();
            let mut runs = Vec::new();
            for seed in 1..=shuffles.max(1) {
                for (name, order) in orders(&s, &acc, seed) {
                    if name == "shuffled" {
                        runs.push((format!("shuffled {seed}"), order));
                    } else if seed == 1 {
                        runs.push((name.to_string(), order));
                    }
                }
            }
            for (name, order) in runs {
                let hopts = HybridOpts {
                    order,
                    ..base.clone()
                };
                // lequal, gequal: the final surface depends on the order
                let order_sync;
                let sync = if matches!(compare, Compare::LEqual | Compare::GEqual) {
                    order_sync = render_sync(&s, &acc, &g, opts, w, h, &hopts);
                    &order_sync
                } else {
                    &sync
                };
                let (f, k) = if rtl {
                    crate::hybrid_rtl::hybrid_rtl(
                        &s, &acc, &g, opts, w, h, &hopts, &work, &mut tally,
                    )?
                } else {
                    render_async(&s, &acc, &g, opts, w, h, &hopts)
                };
                let same = k.lost == 0 && f.same_image(sync);
                println!(
                    "| {name} | {} | {} | {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} | {} |",
                    k.shaded,
                    k.emitted,
                    k.culled_tile,
                    k.culled_depth,
                    k.culled_generation,
                    k.culled_groups,
                    k.culled_group_rays,
                    k.kept_translucent,
                    k.traced,
                    k.discarded,
                    k.superseded,
                    k.used,
                    k.unit_calls,
                    if same { "yes" } else { "NO" }
                );
                if !same {
                    differ.push(name);
                }
            }
            println!();
            // the image is the synchronous render's: kept also when an order differs (exit 1)
            png.commit()?;
            let rtl_ok = tally.mismatches == 0 && tally.renders_differ == 0;
            if rtl && rtl_ok {
                println!("raycull: {} tests through RTL, identical", tally.tests);
            } else if rtl {
                println!(
                    "raycull: {} tests through RTL, {} outputs differ from the golden model, {} replayed renders differ",
                    tally.tests, tally.mismatches, tally.renders_differ
                );
            }
            if differ.is_empty() && rtl_ok {
                println!("hybrid: every order identical to the synchronous render");
            } else {
                if !differ.is_empty() {
                    println!(
                        "hybrid: order(s) {} differ from the synchronous render",
                        differ.join(", ")
                    );
                }
                return Ok(ExitCode::from(1));
            }
        }
        Command::RtlLoop { c, wide, out, work } => {
            c.single_ray(&wide)?;
            let (s, w, h, mut opts) = setup(&c)?;
            opts.tri = match c.tri {
                None | Some(TriKind::Golden) => TriTest::Golden,
                Some(TriKind::Tnum) => TriTest::GoldenTnum,
                Some(TriKind::F64 | TriKind::Exact) => {
                    return Err(
                        "rtl-loop runs the triangle unit: --tri golden (outputs=full) or tnum"
                            .into(),
                    )
                }
            };
            if wide.exact_boxes || wide.anchors || wide.dop.is_some() || wide.carried.is_some() {
                return Err(
                    "rtl-loop --wide runs the node unit: no --exact-boxes, --anchors, --dop or --carried"
                        .into(),
                );
            }
            let shape = wide.shape()?;
            let png = out.as_deref().map(Staged::png).transpose()?;
            if shape.is_some() {
                // single rays without cull planes, as `render --wide`
                opts.planes = false;
                opts.bundles.enabled = false;
            }
            let acc = build(&s, opts.planes);
            let wide_accel = match shape {
                Some((format, tlas_q, _)) => Some(WideAccel::build(&acc, format, tlas_q)?),
                None => None,
            };
            let work = work.unwrap_or_else(crate::rtl::default_work_dir);
            eprintln!(
                "building (or finding in {}) the Verilated harnesses of the units the render uses; a first build takes minutes",
                sim::default_cache_root().display()
            );
            let r = crate::rtl::rtl_loop(&s, &acc, wide_accel.as_ref(), opts, w, h, &work, true)?;
            if let Some(png) = &png {
                r.rtl.save_png(png.temp_path())?;
            }
            println!(
                "{} {}x{}, bundles {}: {} rays; golden render {:.2} s, RTL-answered render {:.2} s{}\n",
                s.path.display(),
                w,
                h,
                if opts.bundles.enabled {
                    format!("≤ {}", opts.bundles.max_size)
                } else {
                    "off".into()
                },
                r.golden.rays(),
                r.golden.time.as_secs_f64(),
                r.rtl.time.as_secs_f64(),
                out.map(|o| format!(" -> {}", o.display()))
                    .unwrap_or_default()
            );
            println!("{r}");
            if let Some(png) = png {
                png.commit()?;
            }
            if !r.ok() {
                return Ok(ExitCode::from(1));
            }
        }
        Command::Wide {
            scenes,
            children,
            box_bits,
            tlas_box_bits,
            width,
            height,
            bundle_tile,
        } => {
            if bundle_tile == Some(0) {
                return Err("--bundle-tile must be at least 1".into());
            }
            let mut shapes = Vec::new();
            for &n in &children {
                for &q in &box_bits {
                    let f =
                        WideFormat::new(FloatFormat::BINARY32, n, q).map_err(|e| e.to_string())?;
                    // before anything is printed: the TLAS's shape too
                    crate::wide::tlas_format(f, tlas_box_bits)?;
                    shapes.push(f);
                }
            }
            let mut rows = Vec::new();
            for path in &scenes {
                let s = Scene::load(path).map_err(|e| e.to_string())?;
                let (w, h) = s
                    .render
                    .image_size(width, height)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                let acc = Accel::build(&s, false);
                let binary: usize = acc.tlas.nodes.len()
                    + acc.blas.iter().map(|b| b.bvh.nodes.len()).sum::<usize>();
                println!(
                    "{}: {w}x{h} camera rays; binary BVH {binary} nodes",
                    path.display()
                );
                let name = path.file_stem().map_or_else(
                    || path.display().to_string(),
                    |x| x.to_string_lossy().into(),
                );
                for r in crate::wide::report(&s, &acc, &shapes, tlas_box_bits, w, h, bundle_tile)
                    .map_err(|e| format!("{}: {e}", path.display()))?
                {
                    if let Some((t, b)) = &r.bundle {
                        let (alone, bundle, single) = b.per_ray();
                        println!(
                            "bundle bound N={} q={} tile {t}x{t}: {name} node tests/ray {alone:.2} alone; \
                             with an oracle bundle test {bundle:.2} bundle + {single:.2} single, {:.1} % \
                             of bundle tests answer every ray; break-even {:.2} node tests per bundle test",
                            r.format.children(),
                            r.format.box_bits(),
                            100.0 * b.resolved_share(),
                            b.break_even()
                        );
                    }
                    rows.push((name.clone(), r));
                }
            }
            println!("\n{}", crate::wide::report_table(&rows));
            if rows.iter().any(|(_, r)| !r.same_hits) {
                return Ok(ExitCode::from(1));
            }
        }
        Command::Bench { c, rounds } => {
            let (s, w, h, opts) = setup(&c)?;
            let acc = build(&s, opts.planes);
            let singles = TraceOpts {
                bundles: BundleOpts {
                    enabled: false,
                    ..opts.bundles
                },
                ..opts
            };
            let slab_opts = TraceOpts {
                planes: false,
                bundles: singles.bundles,
                f32_transform: true,
                tri: TriTest::F64,
            };
            let run = |k: usize| match k {
                0 => render(&s, &acc, &Golden::default(), opts, w, h, true),
                1 => render(&s, &acc, &Golden::default(), singles, w, h, true),
                _ => render(&s, &acc, &Slab, slab_opts, w, h, true),
            };
            // every renderer once per round, in turn, so that a slow spell of the machine
            // falls on all of them; each keeps the frame of its median time
            let mut frames: [Vec<crate::render::Frame>; 3] = Default::default();
            for _ in 0..rounds {
                for (k, f) in frames.iter_mut().enumerate() {
                    f.push(run(k));
                }
            }
            let [g, g1, f] = frames.map(|mut v| {
                v.sort_by_key(|f| f.time);
                v.swap_remove(v.len() / 2)
            });
            let rate = |f: &crate::render::Frame| f.rays() as f64 / f.time.as_secs_f64();
            let diff = f.ids.iter().zip(&g.ids).filter(|(a, b)| a != b).count();
            println!(
                "{} {}x{}, {} threads, median of {rounds} rounds\n\n| renderer | rays | seconds | rays/s | box tests/ray |\n|---|---|---|---|---|",
                s.path.display(),
                w,
                h,
                rayon::current_num_threads()
            );
            for (name, fr) in [
                ("golden models, bundles", &g),
                ("golden models, single rays", &g1),
                ("plain f32 slab, f32 transform, no planes", &f),
            ] {
                println!(
                    "| {name} | {} | {:.2} | {:.0} | {:.2} |",
                    fr.rays(),
                    fr.time.as_secs_f64(),
                    rate(fr),
                    fr.stats.total().box_tests_per_ray()
                );
            }
            println!(
                "\nslab / golden speed ratio: {:.1}x; primary hits differing from the golden image: {diff} of {} pixels",
                rate(&f) / rate(&g),
                g.ids.len()
            );
            // the golden-model renderer as `render` runs it (bundles) against the slab renderer
            println!("golden/slab rays/s ratio: {:.2}", rate(&g) / rate(&f));
        }
    }
    Ok(ExitCode::SUCCESS)
}

/// Runs one subcommand: exit 0, 1 (the RTL in the loop differs) or 2 (an
/// error, printed).
pub fn main(command: Command) -> ExitCode {
    match run(command) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
