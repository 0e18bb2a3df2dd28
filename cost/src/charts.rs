//! Charts (PNG + SVG) of cost against accuracy, drawn with plotters (no
//! system font: DejaVu Sans is embedded and registered with ab_glyph).

use crate::sweep::{self, Sweep};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};

const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// One plotted point.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    /// x
    pub x: f64,
    /// y
    pub y: f64,
    /// text drawn beside it
    pub label: String,
    /// false misses of the design it stands for (a design with any is never
    /// on the Pareto front)
    pub false_misses: u64,
}

impl Point {
    /// A point of a design without false misses.
    pub fn new(x: f64, y: f64, label: impl Into<String>) -> Self {
        Point {
            x,
            y,
            label: label.into(),
            false_misses: 0,
        }
    }
}

/// One series of points.
pub struct Series {
    /// legend name
    pub name: String,
    /// colour
    pub color: RGBColor,
    /// points
    pub points: Vec<Point>,
    /// hollow markers instead of filled ones
    pub hollow: bool,
    /// join the points in order (a design over its formats)
    pub line: bool,
}

/// A scatter chart on log-log (or lin-log) axes.
pub struct Chart {
    /// file stem
    pub stem: String,
    /// title
    pub title: String,
    /// x label
    pub x_label: String,
    /// y label
    pub y_label: String,
    /// logarithmic x
    pub x_log: bool,
    /// values below this are drawn at it (zero on a log axis)
    pub y_floor: f64,
    /// series
    pub series: Vec<Series>,
    /// mark the Pareto front (smaller x and smaller y are better) among the
    /// points without false misses ([`sound_front`])
    pub pareto: bool,
    /// where the legend goes
    pub legend: SeriesLabelPosition,
    /// vertical reference lines `(x, label)` (published figures without a
    /// measured y), with the legend entry `refs_name`
    pub refs: Vec<(f64, String)>,
    /// legend entry of the reference lines
    pub refs_name: String,
}

impl Chart {
    /// A chart on linear x and log y with the usual settings (legend upper
    /// left, no Pareto front, no reference lines): what the sweep tools draw.
    pub fn plain(
        stem: &str,
        title: &str,
        x_label: &str,
        y_label: &str,
        series: Vec<Series>,
    ) -> Chart {
        Chart {
            stem: stem.to_string(),
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            x_log: false,
            y_floor: 1.0,
            series,
            pareto: false,
            legend: SeriesLabelPosition::UpperLeft,
            refs: Vec::new(),
            refs_name: String::new(),
        }
    }
}

/// The points no other point beats in both coordinates, sorted by x.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut p: Vec<(f64, f64)> = points.to_vec();
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for q in p {
        if front.last().is_none_or(|l| q.1 < l.1) {
            front.push(q);
        }
    }
    front
}

/// The Pareto front among the points whose design has no false miss (y
/// drawn at least at `y_floor`): a tester that loses hits is not compared
/// with one that never does, however few false hits it reports.
pub fn sound_front(points: &[Point], y_floor: f64) -> Vec<(f64, f64)> {
    let sound: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.false_misses == 0)
        .map(|p| (p.x, p.y.max(y_floor)))
        .collect();
    pareto_front(&sound)
}

/// A short tick label: `10k`, `20k`, `1.5k`, `2M`, `500`, `0.5`, `1e-3`.
pub fn tick_label(v: f64) -> String {
    fn trim(x: f64) -> String {
        let t = format!("{x:.2}");
        let t = t.trim_end_matches('0').trim_end_matches('.');
        t.to_string()
    }
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if a >= 1e6 {
        format!("{}M", trim(v / 1e6))
    } else if a >= 1e3 {
        format!("{}k", trim(v / 1e3))
    } else if a >= 0.01 {
        trim(v)
    } else {
        let e = a.log10().floor() as i32;
        let m = v / 10f64.powi(e);
        let m = (m * 10.0).round() / 10.0;
        if (m - m.round()).abs() < 1e-9 {
            format!("{}e{e}", m.round() as i64)
        } else {
            format!("{m}e{e}")
        }
    }
}

/// Tick positions of a log axis over `[lo, hi]`: `(labelled, unlabelled)`.
/// Labelled: 1, 2, 5 × 10^k if at most `max_labels` of them fall in the
/// range (1, 2, 3, 5 × 10^k if fewer than 4 would), else the powers of ten (every second, third, ... one if there are
/// still more than `max_labels`); unlabelled: the other 1..9 × 10^k. A range
/// holding no labelled tick gets its ends' 1..9 × 10^k values as labels.
pub fn log_ticks(lo: f64, hi: f64, max_labels: usize) -> (Vec<f64>, Vec<f64>) {
    if !(lo > 0.0 && hi > lo) {
        return (Vec::new(), Vec::new());
    }
    let (e0, e1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let inside = |v: &f64| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12);
    let at = |m: u32, e: i32| m as f64 * 10f64.powi(e);
    let all: Vec<(u32, i32)> = (e0..=e1)
        .flat_map(|e| (1..=9).map(move |m| (m, e)))
        .filter(|&(m, e)| inside(&at(m, e)))
        .collect();
    let pick = |f: &dyn Fn(u32, i32) -> bool| -> Vec<f64> {
        all.iter()
            .filter(|&&(m, e)| f(m, e))
            .map(|&(m, e)| at(m, e))
            .collect()
    };
    let mut bold = pick(&|m, _| matches!(m, 1 | 2 | 5));
    if bold.len() < 4 {
        bold = pick(&|m, _| matches!(m, 1 | 2 | 3 | 5));
    }
    if bold.len() > max_labels {
        let n = pick(&|m, _| m == 1).len();
        let step = n.div_ceil(max_labels.max(1)).max(1) as i32;
        bold = pick(&|m, e| m == 1 && e.rem_euclid(step) == 0);
    }
    if bold.is_empty() {
        bold = all.iter().map(|&(m, e)| at(m, e)).collect();
    }
    let light = all
        .iter()
        .map(|&(m, e)| at(m, e))
        .filter(|v| !bold.iter().any(|b| (b / v - 1.0).abs() < 1e-9))
        .collect();
    (bold, light)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    c: &Chart,
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let mut pts: Vec<(f64, f64)> = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| (p.x, p.y.max(c.y_floor))))
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    if let Some(y) = pts.first().map(|p| p.1) {
        pts.extend(c.refs.iter().map(|r| (r.0, y)));
    }
    let (mut x0, mut x1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.0), a.1.max(p.0)));
    let (mut y0, mut y1) = pts
        .iter()
        .fold((f64::MAX, f64::MIN), |a, p| (a.0.min(p.1), a.1.max(p.1)));
    if c.x_log {
        x0 /= 1.4;
        x1 *= 1.4;
    } else {
        // labels are drawn right of their markers: more room on that side
        let pad = (x1 - x0).max(1.0) * 0.08;
        x0 -= pad;
        x1 += 2.5 * pad;
    }
    y0 /= 3.0;
    y1 *= 3.0;
    let mut chart = ChartBuilder::on(&root);
    chart
        .caption(&c.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70);
    let (yb, yl) = log_ticks(y0, y1, 12);
    let y_range = (y0..y1)
        .log_scale()
        .with_key_points(yb)
        .with_light_points(yl);
    if c.x_log {
        let (xb, xl) = log_ticks(x0, x1, 12);
        let x_range = (x0..x1)
            .log_scale()
            .with_key_points(xb)
            .with_light_points(xl);
        let mut ch = chart.build_cartesian_2d(x_range, y_range)?;
        axes_series_legend(&mut ch, c, (y0, y1))?;
    } else {
        let mut ch = chart.build_cartesian_2d(x0..x1, y_range)?;
        axes_series_legend(&mut ch, c, (y0, y1))?;
    }
    root.present()?;
    Ok(())
}

/// Everything drawn inside a built chart: the labelled axes, the series
/// and the legend; generic because a log and a linear x axis are
/// different coordinate types.
fn axes_series_legend<'a, DB: DrawingBackend + 'a, X, Y>(
    ch: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: &Chart,
    y_span: (f64, f64),
) -> Result<(), Box<dyn std::error::Error>>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    DB::ErrorType: 'static,
{
    // on a rate axis the floor stands for zero
    let zero_floor = c.y_floor == RATE_FLOOR;
    let fmt = |v: &f64| tick_label(*v);
    let y_fmt = move |v: &f64| {
        if zero_floor && (*v / RATE_FLOOR - 1.0).abs() < 1e-9 {
            "0".to_string()
        } else {
            tick_label(*v)
        }
    };
    ch.configure_mesh()
        .x_desc(&c.x_label)
        .y_desc(&c.y_label)
        .x_label_formatter(&fmt)
        .y_label_formatter(&y_fmt)
        .label_style(("sans-serif", 14))
        .draw()?;
    plot(ch, c, y_span)?;
    legend(ch, c)
}

fn legend<'a, DB: DrawingBackend + 'a, X, Y>(
    ch: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: &Chart,
) -> Result<(), Box<dyn std::error::Error>>
where
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    DB::ErrorType: 'static,
{
    ch.configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(c.legend.clone())
        .draw()?;
    Ok(())
}

fn plot<'a, DB: DrawingBackend + 'a, X, Y>(
    ch: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: &Chart,
    (y0, y1): (f64, f64),
) -> Result<(), Box<dyn std::error::Error>>
where
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    DB::ErrorType: 'static,
{
    if !c.refs.is_empty() {
        let grey = RGBColor(90, 90, 90);
        for (k, (x, label)) in c.refs.iter().enumerate() {
            let line = ch.draw_series(DashedLineSeries::new(
                vec![(*x, y0), (*x, y1)],
                6,
                4,
                grey.stroke_width(2),
            ))?;
            if k == 0 {
                line.label(&c.refs_name).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(2))
                });
            }
            ch.draw_series(std::iter::once(Text::new(
                label.clone(),
                (*x * 1.015, y0 * 1.5),
                ("sans-serif", 13).into_font().color(&grey),
            )))?;
        }
    }
    if c.pareto {
        let all: Vec<Point> = c.series.iter().flat_map(|s| s.points.clone()).collect();
        let front = sound_front(&all, c.y_floor);
        let grey = RGBColor(120, 120, 120);
        ch.draw_series(LineSeries::new(front.clone(), grey.stroke_width(2)))?
            .label(if all.iter().any(|p| p.false_misses > 0) {
                "Pareto front (designs with 0 false misses)"
            } else {
                "Pareto front"
            })
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 18, y)], grey.stroke_width(2))
            });
        ch.draw_series(
            front
                .iter()
                .map(|p| Circle::new(*p, 9, grey.stroke_width(2))),
        )?;
    }
    for s in &c.series {
        let color = s.color;
        let hollow = s.hollow;
        let style = move || {
            if hollow {
                color.stroke_width(2)
            } else {
                color.filled()
            }
        };
        let pts: Vec<(f64, f64)> = s.points.iter().map(|p| (p.x, p.y.max(c.y_floor))).collect();
        if s.line {
            ch.draw_series(LineSeries::new(pts.clone(), color.mix(0.5).stroke_width(1)))?;
        }
        ch.draw_series(pts.iter().map(|p| Circle::new(*p, 5, style())))?
            .label(&s.name)
            .legend(move |(x, y)| Circle::new((x + 9, y), 5, style()));
        ch.draw_series(s.points.iter().map(|p| {
            Text::new(
                p.label.clone(),
                (p.x, p.y.max(c.y_floor)),
                ("sans-serif", 13).into_font().color(&color),
            )
        }))?;
    }
    Ok(())
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir`.
pub fn write_chart(c: &Chart, dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let _ = register_font("sans-serif", FontStyle::Normal, FONT);
    std::fs::create_dir_all(dir)?;
    let png = dir.join(format!("{}.png", c.stem));
    let svg = dir.join(format!("{}.svg", c.stem));
    let (w, h) = (900u32, 600u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    draw(
        BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area(),
        c,
    )?;
    image::RgbImage::from_raw(w, h, buf)
        .expect("buffer size")
        .save_with_format(&png, image::ImageFormat::Png)?;
    draw(SVGBackend::new(&svg, (900, 600)).into_drawing_area(), c)?;
    Ok(vec![png, svg])
}

const BLUE_: RGBColor = RGBColor(31, 119, 180);
const ORANGE_: RGBColor = RGBColor(230, 110, 14);
const GREEN_: RGBColor = RGBColor(44, 150, 44);
const RED_: RGBColor = RGBColor(200, 40, 40);

/// Lower bound drawn for a zero rate on a log axis.
pub const RATE_FLOOR: f64 = 1e-6;

const PURPLE_: RGBColor = RGBColor(120, 70, 170);

/// The box testers' colours, in the order of [`sweep::BOX_DESIGNS`].
fn design_color(label: &str) -> RGBColor {
    match label {
        "silhouette ray" => BLUE_,
        "silhouette bundle" => PURPLE_,
        "slab conservative" => GREEN_,
        _ => ORANGE_,
    }
}

/// Legend name of a box tester.
fn design_name(label: &str) -> &'static str {
    match label {
        "silhouette ray" => "silhouette mode=ray (never misses)",
        "silhouette bundle" => "silhouette mode=bundle (never misses)",
        "slab conservative" => "slab rounding=conservative (never misses)",
        _ => "slab RNE (misses hits: never on the front)",
    }
}

/// One series per box tester: `(Xilinx LUT, y(tester stats at format f), "mF")`
/// with the design's false misses over all workloads attached.
fn box_series(s: &Sweep, y: &dyn Fn(&str, u32) -> Option<f64>) -> Vec<Series> {
    sweep::BOX_DESIGNS
        .iter()
        .map(|(label, _, _)| {
            let points = sweep::FRACS
                .iter()
                .filter_map(|&f| {
                    let r = sweep::find_design(s, label, f)?;
                    let luts = r.xilinx.as_ref()?.luts as f64;
                    Some(Point {
                        x: luts,
                        y: y(label, f)?,
                        label: format!("m{f}"),
                        false_misses: sweep::false_misses(s, label, f).0,
                    })
                })
                .collect();
            Series {
                name: design_name(label).into(),
                color: design_color(label),
                points,
                hollow: false,
                line: true,
            }
        })
        .collect()
}

/// RAABB's published LUTs as reference lines.
fn raabb_refs() -> Vec<(f64, String)> {
    sweep::RAABB
        .iter()
        .map(|(f, lut, _, _)| (*lut as f64, format!("RAABB m={f}")))
        .collect()
}

const RAABB_NAME: &str = "RAABB, published LUT (Xilinx XST estimates, exponent 11 bits)";

/// Draws every chart into `dir`; returns the files written.
pub fn draw_all(s: &Sweep, dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let mut out = Vec::new();
    let on = |wl: &'static str| {
        move |label: &str, f: u32| {
            s.boxes
                .iter()
                .find(|b| b.frac_bits == f && b.workload == wl)
                .map(|b| b.stats(label).clone())
        }
    };
    let scene = on("scene");
    // 1. box testers: Xilinx LUT against the scene false-hit rate
    out.extend(write_chart(
        &Chart {
            stem: "boxes_luts_vs_false_hits".into(),
            title: "Ray/box testers, e8mF, stages=4: Xilinx LUT vs false hits on scene rays".into(),
            x_label: "Xilinx LUT (synth_xilinx -flatten, synthesis estimate)".into(),
            y_label: "false hits / exact misses (log axis; none at the 0 tick)".to_string(),
            x_log: true,
            y_floor: RATE_FLOOR,
            series: box_series(s, &|l, f| scene(l, f).map(|r| r.false_hit_rate())),
            pareto: true,
            legend: SeriesLabelPosition::UpperRight,
            refs: raabb_refs(),
            refs_name: RAABB_NAME.into(),
        },
        dir,
    )?);
    // 2. box testers: Xilinx LUT against false misses (all workloads)
    out.extend(write_chart(
        &Chart {
            stem: "boxes_luts_vs_false_misses".into(),
            title: "Ray/box testers, e8mF, stages=4: Xilinx LUT vs false misses (lost hits)".into(),
            x_label: "Xilinx LUT (synth_xilinx -flatten, synthesis estimate)".into(),
            y_label: "false misses / exact hits, all workloads (none at the 0 tick)".into(),
            x_log: true,
            y_floor: RATE_FLOOR,
            series: box_series(s, &|l, f| {
                let (fm, hits) = sweep::false_misses(s, l, f);
                (hits > 0).then(|| fm as f64 / hits as f64)
            }),
            pareto: false,
            legend: SeriesLabelPosition::UpperRight,
            refs: raabb_refs(),
            refs_name: RAABB_NAME.into(),
        },
        dir,
    )?);
    // 3. false-hit rate against fraction bits, per workload, for the two
    //    testers that never miss (the RNE slab's rates are in the tables)
    let mut series = Vec::new();
    for (wl, color) in [("random", GREEN_), ("scene", BLUE_), ("grazing", RED_)] {
        for label in ["silhouette ray", "slab conservative"] {
            let sil = label.starts_with("silhouette");
            let pts: Vec<Point> = s
                .boxes
                .iter()
                .filter(|b| b.workload == wl)
                .map(|b| Point::new(b.frac_bits as f64, b.stats(label).false_hit_rate(), ""))
                .collect();
            series.push(Series {
                name: format!(
                    "{wl}: {}",
                    if sil {
                        "silhouette"
                    } else {
                        "conservative slab"
                    }
                ),
                color,
                points: pts,
                hollow: !sil,
                line: true,
            });
        }
    }
    out.extend(write_chart(
        &Chart {
            stem: "boxes_false_hits_vs_frac".into(),
            title: "False-hit rate against fraction bits (exponent 8), testers that never miss"
                .into(),
            x_label: "fraction bits F".into(),
            y_label: "false hits / exact misses (log axis; none at the 0 tick)".to_string(),
            x_log: false,
            y_floor: RATE_FLOOR,
            series,
            pareto: false,
            legend: SeriesLabelPosition::MiddleRight,
            refs: Vec::new(),
            refs_name: String::new(),
        },
        dir,
    )?);
    // 4. Fmax / logic depth against LUTs for every synthesised unit
    let mut depth = Vec::new();
    let mut fmax = Vec::new();
    for r in &s.cost {
        let f = r.params.get("frac_bits").cloned().unwrap_or_default();
        let name = match (r.params.get("mode"), r.params.get("rounding")) {
            (Some(m), _) if r.unit == "silhouette" => format!("{} {m} m{f}", r.unit),
            (_, Some(rd)) if r.unit == "slab" => format!("{} {rd} m{f}", r.unit),
            _ => format!("{} m{f}", r.unit),
        };
        if let Some(i) = &r.ice40 {
            depth.push(Point::new(i.luts as f64, i.depth as f64, name.clone()));
        }
        if let (Some(i), Some(p)) = (&r.ice40, &r.pnr) {
            if let Some(fm) = p.fmax_mhz {
                fmax.push(Point::new(i.luts as f64, fm, name.clone()));
            }
        }
    }
    out.extend(write_chart(
        &Chart {
            stem: "units_luts_vs_depth".into(),
            title: "Every synthesised unit: iCE40 LUT4 vs longest path (cells)".into(),
            x_label: "iCE40 LUT4".into(),
            y_label: "LUT + carry cells on the longest path (ltp -noff)".into(),
            x_log: true,
            y_floor: 1.0,
            series: vec![Series {
                name: "unit (stages as swept)".into(),
                color: BLUE_,
                points: depth,
                hollow: false,
                line: false,
            }],
            pareto: false,
            legend: SeriesLabelPosition::LowerRight,
            refs: Vec::new(),
            refs_name: String::new(),
        },
        dir,
    )?);
    if !fmax.is_empty() {
        out.extend(write_chart(
            &Chart {
                stem: "units_luts_vs_fmax".into(),
                title: "Units that fit an iCE40: LUT4 vs Fmax (nextpnr-ice40, timing shell)".into(),
                x_label: "iCE40 LUT4".into(),
                y_label: "Fmax, MHz".into(),
                x_log: true,
                y_floor: 1.0,
                series: vec![Series {
                    name: "Fmax after routing".into(),
                    color: GREEN_,
                    points: fmax,
                    hollow: false,
                    line: false,
                }],
                pareto: false,
                legend: SeriesLabelPosition::UpperRight,
                refs: Vec::new(),
                refs_name: String::new(),
            },
            dir,
        )?);
    }
    // 5. transform: LUT4 against median relative error far from the instance
    let mut two = Vec::new();
    let mut conv = Vec::new();
    for f in sweep::TRANSFORM_FRACS {
        let Some(acc) = s.transform.iter().find(|t| t.frac_bits == f) else {
            continue;
        };
        let Some(far) = acc.rows.iter().find(|r| r.offset > 1.0) else {
            continue;
        };
        let Some(near) = acc.rows.iter().find(|r| r.offset < 1.0) else {
            continue;
        };
        if let Some(r) = sweep::find(s, "transform", f).and_then(|r| r.ice40.as_ref()) {
            two.push(Point::new(
                r.luts as f64,
                far.two_step_med,
                format!("m{f} far"),
            ));
            two.push(Point::new(
                r.luts as f64,
                near.two_step_med,
                format!("m{f} near"),
            ));
        }
        if let Some(l) = sweep::conventional_luts(s, f) {
            conv.push(Point::new(l as f64, far.conv_med, format!("m{f} far")));
            conv.push(Point::new(
                l as f64,
                near.conv_med.min(1e3),
                format!("m{f} near"),
            ));
        }
    }
    out.extend(write_chart(
        &Chart {
            stem: "transform_luts_vs_error".into(),
            title: "Instance transform, e8mF: LUT4 vs median relative error of O_m".into(),
            x_label: "iCE40 LUT4 (conventional: composed from synthesised operators)".into(),
            y_label: "median relative error (|O−T| = 0.01 near, 1000 far)".into(),
            x_log: true,
            y_floor: 1e-9,
            series: vec![
                Series {
                    name: "two-step (RTL unit, chained fma)".into(),
                    color: BLUE_,
                    points: two,
                    hollow: false,
                    line: false,
                },
                Series {
                    name: "conventional [S | u] (composed)".into(),
                    color: RED_,
                    points: conv,
                    hollow: false,
                    line: false,
                },
            ],
            pareto: true,
            legend: SeriesLabelPosition::LowerRight,
            refs: Vec::new(),
            refs_name: String::new(),
        },
        dir,
    )?);
    Ok(out)
}
