//! Charts (PNG + SVG) of cost against accuracy, drawn with plotters (no
//! system font: DejaVu Sans is embedded and registered with ab_glyph).

use crate::sweep::{self, Sweep};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::{Path, PathBuf};

const FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// One series of points `(x, y, label)`.
pub struct Series {
    /// legend name
    pub name: String,
    /// colour
    pub color: RGBColor,
    /// points
    pub points: Vec<(f64, f64, String)>,
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
    /// mark the Pareto front (smaller x and smaller y are better)
    pub pareto: bool,
    /// legend in the lower right corner instead of the upper right
    pub legend_low: bool,
}

/// The points no other point beats in both coordinates, sorted by x.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut p: Vec<(f64, f64)> = points.to_vec();
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for q in p {
        if front.last().map_or(true, |l| q.1 < l.1) {
            front.push(q);
        }
    }
    front
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    c: &Chart,
) -> Result<(), Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let pts: Vec<(f64, f64)> = c
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| (p.0, p.1.max(c.y_floor))))
        .collect();
    if pts.is_empty() {
        return Ok(());
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
        let pad = (x1 - x0).max(1.0) * 0.08;
        x0 -= pad;
        x1 += pad;
    }
    y0 /= 3.0;
    y1 *= 3.0;
    let mut chart = ChartBuilder::on(&root);
    chart
        .caption(&c.title, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70);
    let y_range = (y0..y1).log_scale();
    if c.x_log {
        let mut ch = chart.build_cartesian_2d((x0..x1).log_scale(), y_range)?;
        ch.configure_mesh()
            .x_desc(&c.x_label)
            .y_desc(&c.y_label)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()?;
        plot(&mut ch, c)?;
        ch.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .position(if c.legend_low {
                SeriesLabelPosition::LowerRight
            } else {
                SeriesLabelPosition::UpperRight
            })
            .draw()?;
    } else {
        let mut ch = chart.build_cartesian_2d(x0..x1, y_range)?;
        ch.configure_mesh()
            .x_desc(&c.x_label)
            .y_desc(&c.y_label)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 14))
            .draw()?;
        plot(&mut ch, c)?;
        ch.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .position(if c.legend_low {
                SeriesLabelPosition::LowerRight
            } else {
                SeriesLabelPosition::UpperRight
            })
            .draw()?;
    }
    root.present()?;
    Ok(())
}

fn plot<'a, DB: DrawingBackend + 'a, X, Y>(
    ch: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    c: &Chart,
) -> Result<(), Box<dyn std::error::Error>>
where
    X: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    Y: plotters::coord::ranged1d::Ranged<ValueType = f64>,
    DB::ErrorType: 'static,
{
    if c.pareto {
        let all: Vec<(f64, f64)> = c
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| (p.0, p.1.max(c.y_floor))))
            .collect();
        let front = pareto_front(&all);
        let grey = RGBColor(120, 120, 120);
        ch.draw_series(LineSeries::new(front.clone(), grey.stroke_width(2)))?
            .label("Pareto front")
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
        let pts: Vec<(f64, f64)> = s.points.iter().map(|p| (p.0, p.1.max(c.y_floor))).collect();
        ch.draw_series(LineSeries::new(pts.clone(), color.mix(0.5).stroke_width(1)))?;
        ch.draw_series(pts.iter().map(|p| Circle::new(*p, 5, color.filled())))?
            .label(&s.name)
            .legend(move |(x, y)| Circle::new((x + 9, y), 5, color.filled()));
        ch.draw_series(s.points.iter().map(|p| {
            Text::new(
                p.2.clone(),
                (p.0, p.1.max(c.y_floor)),
                ("sans-serif", 13).into_font().color(&color),
            )
        }))?;
    }
    Ok(())
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir`.
pub fn write_chart(c: &Chart, dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let _ = register_font("sans-serif", FontStyle::Normal, FONT);
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

/// Draws every chart into `dir`; returns the files written.
pub fn draw_all(s: &Sweep, dir: &Path) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    std::fs::create_dir_all(dir)?;
    let mut out = Vec::new();
    let scene_rate = |f: u32, sil: bool| {
        s.boxes
            .iter()
            .find(|b| b.frac_bits == f && b.workload == "scene")
            .map(|b| {
                if sil {
                    b.silhouette.false_hit_rate()
                } else {
                    // the slab errs both ways: count both against it
                    (b.slab.false_hits + b.slab.false_misses) as f64 / b.slab.n.max(1) as f64
                }
            })
    };
    // 1. box testers: iCE40 LUT4 against scene false-hit rate
    let mut series = Vec::new();
    for (unit, name, color) in [
        (
            "silhouette",
            "silhouette (conservative): false hits / misses",
            BLUE_,
        ),
        (
            "slab",
            "slab (RNE): (false hits + false misses) / rays",
            ORANGE_,
        ),
    ] {
        let mut pts = Vec::new();
        for f in sweep::FRACS {
            if let (Some(r), Some(rate)) =
                (sweep::find(s, unit, f), scene_rate(f, unit == "silhouette"))
            {
                if let Some(i) = &r.ice40 {
                    pts.push((i.luts as f64, rate, format!("m{f}")));
                }
            }
        }
        series.push(Series {
            name: name.into(),
            color,
            points: pts,
        });
    }
    out.extend(write_chart(
        &Chart {
            stem: "boxes_luts_vs_false_hits".into(),
            title: "Ray/box testers, e8mF: iCE40 LUT4 vs error rate on scene rays".into(),
            x_label: "iCE40 LUT4 (Yosys synth_ice40)".into(),
            y_label: format!("error rate (0 drawn at {RATE_FLOOR:.0e})"),
            x_log: true,
            y_floor: RATE_FLOOR,
            series,
            pareto: true,
            legend_low: false,
        },
        dir,
    )?);
    // 2. error rate against fraction bits, per workload
    let mut series = Vec::new();
    for (wl, color) in [("random", GREEN_), ("scene", BLUE_), ("grazing", RED_)] {
        for sil in [true, false] {
            let pts: Vec<(f64, f64, String)> = s
                .boxes
                .iter()
                .filter(|b| b.workload == wl)
                .map(|b| {
                    let r = if sil {
                        b.silhouette.false_hit_rate()
                    } else {
                        b.slab.false_hit_rate()
                    };
                    (b.frac_bits as f64, r, String::new())
                })
                .collect();
            series.push(Series {
                name: format!(
                    "{wl}: {} false-hit rate",
                    if sil { "silhouette" } else { "slab" }
                ),
                color: if sil {
                    color
                } else {
                    RGBColor(color.0 / 2 + 100, color.1 / 2 + 100, color.2 / 2 + 100)
                },
                points: pts,
            });
        }
    }
    out.extend(write_chart(
        &Chart {
            stem: "boxes_false_hits_vs_frac".into(),
            title: "False-hit rate against fraction bits (exponent 8)".into(),
            x_label: "fraction bits F".into(),
            y_label: format!("false hits / exact misses (0 at {RATE_FLOOR:.0e})"),
            x_log: false,
            y_floor: RATE_FLOOR,
            series,
            pareto: false,
            legend_low: true,
        },
        dir,
    )?);
    // 3. Fmax / logic depth against LUTs for every synthesised unit
    let mut depth = Vec::new();
    let mut fmax = Vec::new();
    for r in &s.cost {
        if let Some(i) = &r.ice40 {
            let f = r.params.get("frac_bits").cloned().unwrap_or_default();
            depth.push((i.luts as f64, i.depth as f64, format!("{} m{f}", r.unit)));
        }
        if let (Some(i), Some(p)) = (&r.ice40, &r.pnr) {
            if let Some(fm) = p.fmax_mhz {
                let f = r.params.get("frac_bits").cloned().unwrap_or_default();
                fmax.push((i.luts as f64, fm, format!("{} m{f}", r.unit)));
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
            }],
            pareto: false,
            legend_low: true,
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
                }],
                pareto: false,
                legend_low: false,
            },
            dir,
        )?);
    }
    // 4. transform: LUT4 against median relative error far from the instance
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
            two.push((r.luts as f64, far.two_step_med, format!("m{f} far")));
            two.push((r.luts as f64, near.two_step_med, format!("m{f} near")));
        }
        if let Some(l) = sweep::conventional_luts(s, f) {
            conv.push((l as f64, far.conv_med, format!("m{f} far")));
            conv.push((l as f64, near.conv_med.min(1e3), format!("m{f} near")));
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
                },
                Series {
                    name: "conventional [S | u] (composed)".into(),
                    color: RED_,
                    points: conv,
                },
            ],
            pareto: true,
            legend_low: true,
        },
        dir,
    )?);
    Ok(out)
}
