//! Hardware cost per ray on the shipped scenes (issue #16 §3): each unit's
//! area (Xilinx 7-series LUT, `synth_xilinx -flatten` synthesis estimate)
//! times the transactions it handles per ray in a golden render, summed over
//! the units, with and without cull planes and bundles. Every unit takes one
//! transaction per clock, so the sum is the area-time product of a ray in
//! LUT-cycles: what a design spends per ray, and where planes and bundles
//! pay for themselves.

use crate::synth;
use golden_model::wide::WideFormat;
use scene::bvh::Accel;
use scene::render::{render, render_with};
use scene::scene::Scene;
use scene::stats::{KindStats, RayKind};
use scene::tester::Golden;
use scene::trace::{BundleOpts, TraceOpts, Tracer};
use scene::wide::{Boxes, WideAccel};
use std::fmt::Write as _;
use std::path::Path;

/// A unit in the per-ray sum: its role, unit name and parameters (binary32).
pub struct Role {
    /// what it does for a ray
    pub role: &'static str,
    /// unit name
    pub unit: &'static str,
    /// parameters besides the defaults
    pub params: &'static [&'static str],
}

/// The units of a ray's traversal, in the order of the table. The cull
/// test folds its planes into the child's box interval, which a conservative
/// slab beside it computes from the ray's reciprocal direction (three
/// reciprocals per instance entry): both are counted.
pub const ROLES: [Role; 8] = [
    Role {
        role: "box test, single ray",
        unit: "silhouette",
        params: &["mode=ray", "stages=4"],
    },
    Role {
        role: "box test, bundle",
        unit: "silhouette",
        params: &["mode=bundle", "origin=shared", "stages=4"],
    },
    Role {
        role: "cull test (per child)",
        unit: "cull",
        params: &["k=4", "plane_exp_bits=5", "plane_frac_bits=10", "stages=4"],
    },
    Role {
        role: "box interval for a cull test",
        unit: "slab",
        params: &["rounding=conservative", "stages=4"],
    },
    Role {
        role: "reciprocal direction for the interval (3 per instance entry)",
        unit: "frecip",
        params: &["round=rtz", "stages=4"],
    },
    Role {
        role: "cull terms (per ray and parent)",
        unit: "cull_ray",
        params: &["k=4", "plane_exp_bits=5", "plane_frac_bits=10", "stages=4"],
    },
    Role {
        role: "instance transform",
        unit: "transform",
        params: &["stages=8"],
    },
    Role {
        role: "triangle test",
        unit: "triangle",
        params: &["stages=8"],
    },
];

/// The area of one unit: Xilinx 7-series LUTs and DSP48E1 blocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Area {
    /// LUT1..LUT6
    pub luts: u64,
    /// DSP48E1
    pub dsps: u64,
}

/// The Xilinx estimate of each role's unit ([`synth::xilinx_estimate`];
/// `cached_only`: never run Yosys).
pub fn unit_areas(cached_only: bool) -> Result<Vec<Area>, String> {
    ROLES
        .iter()
        .map(|r| {
            let p: Vec<String> = r.params.iter().map(|s| s.to_string()).collect();
            let g = rtl_flow::generate(r.unit, &p).map_err(|e| format!("{}: {e}", r.unit))?;
            let x = synth::xilinx_estimate(&g, cached_only)?;
            Ok(Area {
                luts: x.luts,
                dsps: x.dsps,
            })
        })
        .collect()
}

/// Transactions per role (in [`ROLES`] order) and rays of one render.
#[derive(Debug, Clone, PartialEq)]
pub struct Workload {
    /// scene file name
    pub scene: String,
    /// cull planes on
    pub planes: bool,
    /// bundles on
    pub bundles: bool,
    /// rays traced
    pub rays: u64,
    /// transactions per role
    pub tests: [u64; 8],
}

/// Renders `scene` (golden models) at `width` pixels with and without planes
/// and bundles; one [`Workload`] each, or with `by_kind` one per ray type
/// (primary, shadow, AO; the scene named `cornell.toml shadow`), whose
/// transactions and rays are that type's alone.
pub fn workloads(scene: &Path, width: u32, by_kind: bool) -> Result<Vec<Workload>, String> {
    let s = Scene::load(scene).map_err(|e| e.to_string())?;
    let (_, h) = s.render.image_size(Some(width), None)?;
    let with_planes = Accel::build(&s, true);
    let name = scene
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut out = Vec::new();
    for planes in [true, false] {
        for bundles in [true, false] {
            let opts = TraceOpts {
                planes,
                bundles: BundleOpts {
                    enabled: bundles,
                    ..BundleOpts::default()
                },
                ..TraceOpts::default()
            };
            let f = render(&s, &with_planes, &Golden::default(), opts, width, h, false);
            let groups: Vec<(String, KindStats)> = if by_kind {
                RayKind::ALL
                    .iter()
                    .map(|&k| (format!("{name} {}", k.name()), f.stats.kinds[k as usize]))
                    .collect()
            } else {
                vec![(name.clone(), f.stats.total())]
            };
            for (scene, t) in groups {
                out.push(Workload {
                    scene,
                    planes,
                    bundles,
                    rays: t.rays,
                    tests: [
                        t.ray_box_tests,
                        t.bundle_tests,
                        t.cull_tests,
                        t.cull_tests,
                        if planes { 3 * t.transforms } else { 0 },
                        t.cull_ray_terms,
                        t.transforms,
                        t.tri_tests,
                    ],
                });
            }
        }
    }
    Ok(out)
}

/// One scene's render over a wide BVH (`per-ray --wide N`): the same tree
/// traced with its compressed nodes through the `node` unit's model,
/// and with exact binary32 child boxes (the denominator that keeps a looser
/// node test from hiding behind an identical image).
#[derive(Debug, Clone)]
pub struct WideWorkload {
    /// scene file name
    pub scene: String,
    /// the node shape (BLAS)
    pub format: WideFormat,
    /// q of the TLAS nodes
    pub tlas_box_bits: u32,
    /// counters with the compressed nodes (node tester)
    pub node: KindStats,
    /// counters with exact binary32 child boxes
    pub exact: KindStats,
    /// both renders equal the binary32 single-ray render (hits, `t`, colour)
    pub same_image: bool,
}

impl WideWorkload {
    /// Child tests per ray with the compressed nodes over those with exact boxes.
    pub fn child_test_ratio(&self) -> f64 {
        self.node.child_tests as f64 / self.exact.child_tests.max(1) as f64
    }
}

/// Renders `scene` (golden models, single rays, no planes) at `width` pixels
/// over its wide BVH of `format`, with the compressed nodes and with exact
/// boxes, and checks both against the binary BVH's render.
pub fn wide_workload(
    scene: &Path,
    width: u32,
    format: WideFormat,
    tlas_box_bits: u32,
) -> Result<WideWorkload, String> {
    let s = Scene::load(scene).map_err(|e| e.to_string())?;
    let name = scene
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    wide_workload_of(&s, &name, width, format, tlas_box_bits)
}

/// [`wide_workload`] of a loaded scene called `name`.
pub fn wide_workload_of(
    s: &Scene,
    name: &str,
    width: u32,
    format: WideFormat,
    tlas_box_bits: u32,
) -> Result<WideWorkload, String> {
    let (_, h) = s.render.image_size(Some(width), None)?;
    let acc = Accel::build(s, false);
    let wide = WideAccel::build(&acc, format, tlas_box_bits)?;
    let opts = TraceOpts::single_rays();
    let golden = Golden::default();
    let binary = render(s, &acc, &golden, opts, width, h, false);
    let run = |boxes: Boxes| {
        let tracer = Tracer::new(s, &acc, &golden, opts).with_wide(&wide, boxes);
        render_with(s, &acc, &tracer, width, h, false)
    };
    let (node, exact) = (run(Boxes::Node), run(Boxes::Exact));

    Ok(WideWorkload {
        scene: name.to_string(),
        format,
        tlas_box_bits,
        same_image: node.same_image(&binary) && exact.same_image(&binary),
        node: node.stats.total(),
        exact: exact.stats.total(),
    })
}

/// The node unit's `products` at q box bits and its default slope bits.
pub(crate) fn node_products(q: u32) -> rtl_gen::retime::Products {
    use rtl_gen::params::ParamSet;
    let slope_bits = rtl_gen::units::node::NodeParams::defaults().slope_bits;
    rtl_gen::units::node::xc7_products(q, slope_bits)
}

/// The units of a ray's traversal over a wide BVH: role, unit and parameters
/// (binary32): the `node` unit at the BLAS and the TLAS shape, the
/// conservative slab of each tree's root, the transform, and the triangle
/// test the renderer's `--tri tnum` answers from
/// ([`rtl_flow::triangle::RENDER_TNUM`]: it gives the `full` image bit for
/// bit, the division in software); the node unit's products whole where its
/// child products stay one block, `rtl_gen::units::node::xc7_products`.
pub fn wide_roles(
    format: WideFormat,
    tlas_box_bits: u32,
) -> Vec<(&'static str, &'static str, Vec<String>)> {
    let node = |q: u32| {
        vec![
            format!("children={}", format.children()),
            format!("box_bits={q}"),
            "stages=4".to_string(),
            format!("products={}", node_products(q)),
        ]
    };
    let fixed = |p: &[&str]| p.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        ("node test, BLAS", "node", node(format.box_bits())),
        ("node test, TLAS", "node", node(tlas_box_bits)),
        (
            "root box test (one per tree entered)",
            "slab",
            fixed(&["rounding=conservative", "stages=4"]),
        ),
        ("instance transform", "transform", fixed(&["stages=8"])),
        (
            "triangle test (t as T/det, divided in software per hit)",
            "triangle",
            fixed(rtl_flow::triangle::RENDER_TNUM),
        ),
    ]
}

/// Transactions of a wide render in [`wide_roles`] order.
fn wide_tests(k: &KindStats) -> [u64; 5] {
    [
        k.node_visits - k.tlas_node_visits,
        k.tlas_node_visits,
        k.root_box_tests,
        k.transforms,
        k.tri_tests,
    ]
}

/// The Xilinx estimate of each of [`wide_roles`]'s units.
pub fn wide_areas(
    format: WideFormat,
    tlas_box_bits: u32,
    cached_only: bool,
) -> Result<Vec<Area>, String> {
    wide_roles(format, tlas_box_bits)
        .into_iter()
        .map(|(_, unit, p)| {
            let g = rtl_flow::generate(unit, &p).map_err(|e| format!("{unit}: {e}"))?;
            let x = synth::xilinx_estimate(&g, cached_only)?;
            Ok(Area {
                luts: x.luts,
                dsps: x.dsps,
            })
        })
        .collect()
}

/// What the culling oracle (`scene::oracle`: perfect and free culling inside the node tests
/// of the same tree) would still spend, in [`wide_roles`] order: root box tests priced 0.
fn wide_oracle_tests(k: &KindStats) -> [u64; 5] {
    [
        k.oracle_blas_node_tests,
        k.oracle_tlas_node_tests,
        0,
        k.oracle_transforms,
        k.oracle_tri_tests,
    ]
}

/// LUT-cycles and DSP-cycles per ray of `rays` rays making `tests` transactions.
fn cycles_per_ray(tests: [u64; 5], rays: u64, areas: &[Area]) -> (f64, f64) {
    let sum = |f: fn(&Area) -> u64| {
        tests
            .iter()
            .zip(areas)
            .map(|(&n, a)| n as f64 * f(a) as f64)
            .sum::<f64>()
            / rays.max(1) as f64
    };
    (sum(|a| a.luts), sum(|a| a.dsps))
}

/// LUT-cycles and DSP-cycles per ray of a wide render with [`wide_areas`].
pub fn wide_cost_per_ray(k: &KindStats, areas: &[Area]) -> (f64, f64) {
    cycles_per_ray(wide_tests(k), k.rays, areas)
}

/// LUT-cycles and DSP-cycles per ray of the culling oracle on a wide render, priced as
/// [`wide_cost_per_ray`] prices the render itself.
pub fn wide_oracle_cost_per_ray(k: &KindStats, areas: &[Area]) -> (f64, f64) {
    cycles_per_ray(wide_oracle_tests(k), k.rays, areas)
}

/// The wide report: with `areas`, the units and per scene the LUT-cycles and
/// DSP-cycles per ray of the `node` unit's render; per scene the
/// transactions per ray with the compressed nodes and with exact boxes, then
/// one line per scene `child tests per ray q=<q> / binary32: <scene> <ratio>`
/// (and with areas `LUT-cycles per ray: <scene> <LUT> <DSP>`).
pub fn wide_markdown(loads: &[WideWorkload], areas: Option<&[Area]>) -> String {
    let mut s = String::new();
    if let (Some(areas), Some(w)) = (areas, loads.first()) {
        s += "Units (binary32; Xilinx 7-series, `synth_xilinx -flatten` synthesis estimates):\n\n\
              | role | unit | parameters | xc7 LUT | DSP48E1 |\n|---|---|---|---|---|\n";
        for ((role, unit, p), a) in wide_roles(w.format, w.tlas_box_bits).iter().zip(areas) {
            let _ = writeln!(
                s,
                "| {role} | `{unit}` | {} | {} | {} |",
                p.join(" "),
                a.luts,
                a.dsps
            );
        }
        s += "\nPer ray with the `node` unit (every unit one transaction per clock):\n\n\
              | scene | rays |";
        for (role, _, _) in wide_roles(w.format, w.tlas_box_bits) {
            let _ = write!(s, " {role} / ray |");
        }
        s += " LUT-cycles / ray | DSP-cycles / ray |\n|---|---|---|---|---|---|---|---|---|\n";
        for w in loads {
            let k = &w.node;
            let _ = write!(s, "| {} | {} |", w.scene, k.rays);
            for n in wide_tests(k) {
                let _ = write!(s, " {:.2} |", k.per_ray(n));
            }
            let (l, d) = wide_cost_per_ray(k, areas);
            let _ = writeln!(s, " {l:.0} | {d:.1} |");
        }
        s.push('\n');
    }
    s += &String::from(
        "Per ray over a wide BVH (golden render, single rays, no planes; the `node` unit's \
         model, its root box tests among the child tests):\n\n\
         | scene | N | q | TLAS q | rays | node tests / ray | child tests / ray | node bytes / ray | transforms / ray | triangle tests / ray | binary32 boxes: child tests / ray | node bytes / ray | image = binary32 single-ray render |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for w in loads {
        let (k, e) = (&w.node, &w.exact);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {:.2} | {:.2} | {:.0} | {:.2} | {:.2} | {:.2} | {:.0} | {} |",
            w.scene,
            w.format.children(),
            w.format.box_bits(),
            w.tlas_box_bits,
            k.rays,
            k.per_ray(k.node_visits),
            k.per_ray(k.child_tests),
            k.per_ray(k.node_bytes),
            k.per_ray(k.transforms),
            k.per_ray(k.tri_tests),
            e.per_ray(e.child_tests),
            e.per_ray(e.node_bytes),
            if w.same_image { "yes" } else { "NO" }
        );
    }
    s.push('\n');
    for w in loads {
        let _ = writeln!(
            s,
            "child tests per ray q={} / binary32: {} {:.4}",
            w.format.box_bits(),
            w.scene,
            w.child_test_ratio()
        );
    }
    if let Some(areas) = areas {
        for w in loads {
            let (l, d) = wide_cost_per_ray(&w.node, areas);
            let _ = writeln!(
                s,
                "LUT-cycles per ray, node unit N={} q={}: {} {l:.0} LUT, {d:.1} DSP48E1",
                w.format.children(),
                w.format.box_bits(),
                w.scene
            );
        }
    }
    s += &oracle_markdown(loads, areas);
    s
}

/// The culling oracle against the render without planes (`scene::oracle`): per scene the
/// transactions per ray of both, then with `areas` the lines
/// `oracle culling (free, perfect) / no planes LUT-cycles per ray: <scene> <ratio>` and the
/// same of DSP-cycles.
fn oracle_markdown(loads: &[WideWorkload], areas: Option<&[Area]>) -> String {
    let mut s = String::from(
        "\nCulling oracle (perfect, free culling inside the node tests of the same tree; root box \
         tests 0) against the render without planes, per ray, no planes → oracle:\n\n\
         | scene | BLAS node tests | TLAS node tests | root box tests | transforms | triangle tests |\n\
         |---|---|---|---|---|---|\n",
    );
    for w in loads {
        let k = &w.node;
        let _ = write!(s, "| {} |", w.scene);
        for (a, o) in wide_tests(k).iter().zip(wide_oracle_tests(k)) {
            let _ = write!(s, " {:.3} → {:.3} |", k.per_ray(*a), k.per_ray(o));
        }
        s.push('\n');
    }
    if let Some(areas) = areas {
        s.push('\n');
        for w in loads {
            let (l, d) = wide_cost_per_ray(&w.node, areas);
            let (ol, od) = wide_oracle_cost_per_ray(&w.node, areas);
            for (what, ratio) in [("LUT", ol / l), ("DSP", od / d)] {
                let _ = writeln!(
                    s,
                    "oracle culling (free, perfect) / no planes {what}-cycles per ray: {} {ratio:.4}",
                    w.scene
                );
            }
        }
    }
    s
}

/// LUT-cycles and DSP-cycles per ray of `w` with the units' `areas`.
pub fn cost_per_ray(w: &Workload, areas: &[Area]) -> (f64, f64) {
    let rays = w.rays.max(1) as f64;
    let sum = |f: fn(&Area) -> u64| {
        w.tests
            .iter()
            .zip(areas)
            .map(|(&n, a)| n as f64 * f(a) as f64)
            .sum::<f64>()
            / rays
    };
    (sum(|a| a.luts), sum(|a| a.dsps))
}

/// The report: the units' areas (when synthesised), then per scene and
/// configuration the transactions per ray and, with areas, the LUT-cycles
/// and DSP-cycles per ray (a design must not meet a LUT figure by moving
/// logic into DSP blocks unreported).
pub fn markdown(areas: Option<&[Area]>, loads: &[Workload]) -> String {
    let mut s = String::new();
    if let Some(areas) = areas {
        s += "Units (binary32; Xilinx 7-series, `synth_xilinx -flatten` synthesis estimates):\n\n\
              | role | unit | parameters | xc7 LUT | DSP48E1 |\n|---|---|---|---|---|\n";
        for (r, a) in ROLES.iter().zip(areas) {
            let p = r.params.join(" ");
            let _ = writeln!(
                s,
                "| {} | `{}` | {p} | {} | {} |",
                r.role, r.unit, a.luts, a.dsps
            );
        }
        s.push('\n');
    }
    s += "Per ray (golden render; every unit takes one transaction per clock, so LUT x \
          transactions = LUT-cycles):\n\n| scene | planes | bundles | rays |";
    for r in &ROLES {
        let _ = write!(s, " {} / ray |", r.role);
    }
    s += if areas.is_some() {
        " LUT-cycles / ray | DSP-cycles / ray |\n|---|---|---|---|---|---|"
    } else {
        "\n|---|---|---|---|"
    };
    for _ in &ROLES {
        s += "---|";
    }
    s.push('\n');
    for w in loads {
        let on = |b: bool| if b { "on" } else { "off" };
        let _ = write!(
            s,
            "| {} | {} | {} | {} |",
            w.scene,
            on(w.planes),
            on(w.bundles),
            w.rays
        );
        for &n in &w.tests {
            let _ = write!(s, " {:.2} |", n as f64 / w.rays.max(1) as f64);
        }
        if let Some(a) = areas {
            let (luts, dsps) = cost_per_ray(w, a);
            let _ = write!(s, " {luts:.0} | {dsps:.1} |");
        }
        s.push('\n');
    }
    s
}

/// Bars of LUT-cycles per ray, one series per configuration, one group per
/// scene: `<dir>/cost_per_ray.png` and `.svg`.
pub fn chart(
    areas: &[Area],
    loads: &[Workload],
    dir: &Path,
) -> Result<Vec<std::path::PathBuf>, Box<dyn std::error::Error>> {
    use crate::charts::{write_chart, Chart, Point, Series};
    use plotters::prelude::RGBColor;
    let mut scenes: Vec<&str> = Vec::new();
    for w in loads {
        if !scenes.contains(&w.scene.as_str()) {
            scenes.push(&w.scene);
        }
    }
    let configs = [(true, true), (true, false), (false, true), (false, false)];
    let colors = [
        RGBColor(31, 119, 180),
        RGBColor(44, 160, 44),
        RGBColor(230, 110, 14),
        RGBColor(120, 120, 120),
    ];
    let series = configs
        .iter()
        .zip(colors)
        .enumerate()
        .map(|(k, (&(p, b), color))| Series {
            name: format!(
                "planes {}, bundles {}",
                if p { "on" } else { "off" },
                if b { "on" } else { "off" }
            ),
            color,
            points: loads
                .iter()
                .filter(|w| w.planes == p && w.bundles == b)
                .map(|w| {
                    // the four configurations side by side around the scene's index
                    let x = scenes.iter().position(|s| *s == w.scene).unwrap_or(0) as f64;
                    let v = cost_per_ray(w, areas).0;
                    let x = x + 1.0 + (k as f64 - 1.5) * 0.12;
                    // (leading spaces: the label starts under the marker)
                    let label = if v >= 1e6 {
                        format!("  {:.2}M", v / 1e6)
                    } else {
                        format!("  {:.0}k", v / 1e3)
                    };
                    Point::new(x, v, label)
                })
                .collect(),
            hollow: false,
            line: false,
        })
        .collect();
    let c = Chart::plain(
        "cost_per_ray",
        "Hardware per ray: sum over units of xc7 LUT x transactions",
        &format!(
            "scene: {}",
            scenes
                .iter()
                .enumerate()
                .map(|(i, s)| format!("{} {s}", i + 1))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        "LUT-cycles per ray",
        series,
    );
    write_chart(&c, dir)
}
