//! PNG plots with plotters, text drawn with the bundled DejaVu Sans (no
//! system font libraries needed).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::Once;

static FONT: Once = Once::new();

fn register_font() {
    FONT.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/DejaVuSans.ttf");
        if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_err() {
            eprintln!("warning: could not register the plot font");
        }
    });
}

/// Plots are drawn at this many times their size and averaged down: the
/// bitmap backend draws lines without anti-aliasing, so a straight wire at
/// a slight slope showed 1-pixel steps that read as vibrations.
const SUPERSAMPLE: u32 = 3;

/// The drawing area of a supersampled plot.
type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws a `size` (pixels) PNG at `path`: `draw` paints on an area
/// [`SUPERSAMPLE`] times larger, whose pixel sizes it multiplies by the
/// factor it is given; the result is box-filtered down.
fn save_png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&Area, u32) -> Result<(), String>,
) -> Result<(), String> {
    register_font();
    let s = SUPERSAMPLE;
    let (w, h) = (size.0 * s, size.1 * s);
    // White from the start: what `fill(&WHITE)` would paint, without a
    // pass over the whole supersampled area.
    let mut big = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut big, (w, h)).into_drawing_area();
        draw(&root, s)?;
        root.present()
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    let small = average_down(&big, size, s);
    image::save_buffer(path, &small, size.0, size.1, image::ColorType::Rgb8)
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// The mean of each `s` × `s` block of the RGB image `big` (`s` times
/// `size`), rounded: `size`'s pixels. Row by row, so that the big image is
/// read once in order.
fn average_down(big: &[u8], size: (u32, u32), s: u32) -> Vec<u8> {
    let (width, s) = (size.0 as usize, s as usize);
    let big_row = 3 * width * s;
    let n = (s * s) as u32;
    let mut small = vec![0u8; 3 * width * size.1 as usize];
    let mut sums = vec![0u32; 3 * width];
    for (y, out) in small.chunks_exact_mut(3 * width).enumerate() {
        sums.fill(0);
        for row in big[y * s * big_row..][..s * big_row].chunks_exact(big_row) {
            for (sum, block) in sums.chunks_exact_mut(3).zip(row.chunks_exact(3 * s)) {
                for pixel in block.chunks_exact(3) {
                    for c in 0..3 {
                        sum[c] += u32::from(pixel[c]);
                    }
                }
            }
        }
        for (o, sum) in out.iter_mut().zip(&sums) {
            *o = ((sum + n / 2) / n) as u8;
        }
    }
    small
}

/// One curve: a label and (x, y) points.
pub struct Series<'a> {
    pub label: &'a str,
    pub points: Vec<(f64, f64)>,
}

const COLORS: [RGBColor; 9] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(0, 0, 0),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Tick labels readable at any scale: plain for ordinary magnitudes,
/// engineering notation (exponents in steps of 3: 12e-6, 3.5e3) when the
/// axis spans tiny or huge values; as many decimals as the axis' span
/// needs; a tick at zero to round-off is "0".
fn tick_label(v: &f64, lo: f64, hi: f64) -> String {
    let m = lo.abs().max(hi.abs());
    let span = (hi - lo).abs().max(f64::MIN_POSITIVE);
    let text = if v.abs() <= 1e-9 * span {
        "0".to_string()
    } else if !(1e-2..1e4).contains(&m) {
        let exponent = 3 * (m.log10() / 3.0).floor() as i32;
        let scale = 10f64.powi(exponent);
        let digits = (-(span / scale).log10().floor() + 1.0).clamp(0.0, 4.0) as usize;
        format!("{:.digits$}e{exponent}", v / scale)
    } else {
        // A tick step is about a fifth of the span.
        let digits = (-(0.2 * span).log10().floor()).clamp(0.0, 6.0) as usize;
        format!("{v:.digits$}")
    };
    // A tick that rounds to zero has no sign ("-0.0" reads as a value).
    match text.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => text,
    }
}

/// An axis description `label` ending in a unit in parentheses, with the
/// SI prefix that keeps values of largest magnitude `m` short where the
/// unit takes one ("force (N)" at 25 kN: "force (kN)", ticks divided by
/// 10³; a strain "(-)" in 10⁻³ or 10⁻⁶), and the divisor; the label and 1
/// otherwise.
fn prefixed(label: &str, m: f64) -> (String, f64) {
    let Some((name, unit)) = label.strip_suffix(')').and_then(|l| l.rsplit_once(" (")) else {
        return (label.to_string(), 1.0);
    };
    let (big, small) = (["N", "J", "N m", "Pa", "W"].contains(&unit), unit == "m");
    let prefix = match m {
        m if big && (1e4..1e7).contains(&m) => Some(("k", 1e3)),
        m if big && (1e7..1e10).contains(&m) => Some(("M", 1e6)),
        m if small && (1e-5..1e-2).contains(&m) => Some(("m", 1e-3)),
        m if small && (1e-8..1e-5).contains(&m) => Some(("µ", 1e-6)),
        _ => None,
    };
    // A dimensionless quantity (a strain) in thousandths or millionths.
    let dimensionless = match m {
        m if unit == "-" && (1e-4..1e-1).contains(&m) => Some(("10⁻³", 1e-3)),
        m if unit == "-" && (1e-7..1e-4).contains(&m) => Some(("10⁻⁶", 1e-6)),
        _ => None,
    };
    match (prefix, dimensionless) {
        (Some((p, scale)), _) => (format!("{name} ({p}{unit})"), scale),
        (None, Some((times, scale))) => (format!("{name} ({times})"), scale),
        (None, None) => (label.to_string(), 1.0),
    }
}

/// Values whose magnitude stays below this are zero to round-off in every
/// quantity the plots show (strains, m, N, J): a panel of them says so
/// instead of drawing ticks like 1e-44.
pub const ROUNDOFF_ZERO: f64 = 1e-12;

/// The viridis colour map at `f` ∈ [0, 1] (dark purple to yellow): the
/// shades stay distinguishable, in grey too.
fn viridis(f: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = f.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let t = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + t * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// One chart of a multi-panel figure.
#[derive(Default)]
pub struct Panel<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: Vec<Series<'a>>,
    /// Points marked with a circle and a label (e.g. a peak).
    pub marks: Vec<(f64, f64, String)>,
    /// Every point of every series drawn as a dot (a few runs' values,
    /// not a sampled curve).
    pub markers: bool,
}

fn bounds(series: &[Series]) -> Option<(f64, f64, f64, f64)> {
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for s in series {
        for &(x, y) in &s.points {
            if x.is_finite() && y.is_finite() {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
        }
    }
    if !x0.is_finite() {
        return None;
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let pad = 0.05 * (y1 - y0).abs().max(1e-12 * y1.abs().max(1e-30));
    Some((x0, x1, y0 - pad, y1 + pad))
}

/// A line plot of several series with labelled axes and a legend.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<(), String> {
    let panel = Panel {
        title,
        x_label,
        y_label,
        series: series
            .iter()
            .map(|s| Series {
                label: s.label,
                points: s.points.clone(),
            })
            .collect(),
        ..Default::default()
    };
    save_png(path, (960, 600), |root, s| {
        let e = |err: DrawingAreaErrorKind<_>| format!("{}: {err}", path.display());
        if !draw_panel(root, &panel, 1.25 * s as f64).map_err(e)? {
            return Err(format!("{}: nothing to plot", path.display()));
        }
        Ok(())
    })
}

/// The series legend: a framed box at `position`, font `font` px, every
/// pixel size times `scale` (the supersampling factor, or a panel's scale).
fn draw_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    scale: f64,
    font: f64,
    position: SeriesLabelPosition,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let px = |v: f64| (v * scale).round() as u32;
    chart
        .configure_series_labels()
        .legend_area_size(px(30.0))
        .margin(px(10.0))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", px(font)))
        .position(position)
        .draw()
}

/// Draw one chart into `area` (fonts scaled by `scale`); false when there is nothing to draw.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: &Panel,
    scale: f64,
) -> Result<bool, DrawingAreaErrorKind<DB::ErrorType>> {
    let Some((x0, mut x1, mut y0, mut y1)) = bounds(&p.series) else {
        return Ok(false);
    };
    let all_zero = (p.series.iter())
        .flat_map(|s| &s.points)
        .all(|&(_, y)| !y.is_finite() || y.abs() < ROUNDOFF_ZERO);
    if all_zero {
        (y0, y1) = (-1.0, 1.0);
    }
    let size = |px: f64| (px * scale).round() as u32;
    // The legend (upper corner) never covers a curve: it gets room of its
    // own, above the data while that costs at most a fifth of the plot's
    // height, else beside it on the right (many series: an energy plot's
    // six rows took 60 % of its height above the data).
    let mut beside = false;
    if p.series.len() > 1 {
        let (width, height) = area.dim_in_pixel();
        let plot_height = height as f64 - (45.0 + 50.0) * scale;
        let legend = (p.series.len() as f64 * 19.0 + 30.0) * scale;
        let frac = (legend / plot_height.max(1.0)).min(0.6);
        if frac <= 0.2 {
            y1 += (y1 - y0) * frac / (1.0 - frac);
        } else {
            // Its width: the line sample, margins and the longest label
            // (about 6.5 px a character at 13 px).
            let chars = p
                .series
                .iter()
                .map(|s| s.label.chars().count())
                .max()
                .unwrap_or(0);
            let legend_width = (45.0 + 6.5 * chars as f64) * scale;
            let plot_width = width as f64 - (80.0 + 20.0) * scale;
            let room = legend_width / (plot_width - legend_width).max(1.0);
            x1 += (x1 - x0) * room.min(1.0);
            beside = true;
        }
    }
    let mut chart = ChartBuilder::on(area)
        .caption(p.title, ("sans-serif", size(20.0)))
        .margin(size(10.0))
        .x_label_area_size(size(45.0))
        .y_label_area_size(size(80.0))
        .build_cartesian_2d(x0..x1, y0..y1)?;
    // Large forces in kN, small lengths in mm: ticks of a few digits.
    let (y_desc, y_scale) = prefixed(p.y_label, y0.abs().max(y1.abs()));
    chart
        .configure_mesh()
        .x_desc(p.x_label)
        .y_desc(y_desc)
        .y_label_formatter(&|v| tick_label(&(v / y_scale), y0 / y_scale, y1 / y_scale))
        .x_label_formatter(&|v| tick_label(v, x0, x1))
        .x_labels(6)
        .label_style(("sans-serif", size(14.0)))
        .axis_desc_style(("sans-serif", size(15.0)))
        .draw()?;
    if all_zero {
        let font = ("sans-serif", size(16.0)).into_font().color(&BLACK);
        chart.draw_series(std::iter::once(Text::new(
            format!("zero throughout (|values| < {ROUNDOFF_ZERO:.0e})"),
            (x0 + 0.5 * (x1 - x0), 0.5),
            font.pos(Pos::new(HPos::Center, VPos::Center)),
        )))?;
    }
    for (i, s) in p.series.iter().enumerate() {
        let color = COLORS[i % COLORS.len()];
        // A series denser than the pixels (a force or a moment at every
        // step) is drawn segment by segment: a thick polyline's mitred
        // joins at its steep turns overshoot the data by far (beyond the
        // largest value, below zero on a magnitude, into the next panel);
        // separate segments have no joins. With spikes it is drawn thinner,
        // so that the spikes' fill does not hide the curve over it.
        let dense = s.points.len() > area.dim_in_pixel().0 as usize;
        let spiky =
            (s.points.windows(3)).any(|w| (w[2].1 - 2.0 * w[1].1 + w[0].1).abs() > 0.3 * (y1 - y0));
        let width = if dense && spiky {
            scale.round().max(1.0) as u32
        } else {
            size(2.0)
        };
        let style = color.stroke_width(width);
        let legend = size(20.0) as i32;
        let drawn = if dense {
            let segments = (s.points.windows(2)).map(|w| PathElement::new(vec![w[0], w[1]], style));
            chart.draw_series(segments)?
        } else {
            chart.draw_series(LineSeries::new(s.points.iter().copied(), style))?
        };
        drawn
            .label(s.label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + legend, y)], style));
        if p.markers {
            let dot = size(4.0);
            chart.draw_series(
                s.points
                    .iter()
                    .map(|&pt| Circle::new(pt, dot, color.filled())),
            )?;
        }
    }
    for (x, y, label) in &p.marks {
        chart.draw_series(std::iter::once(Circle::new(
            (*x, *y),
            size(6.0),
            BLACK.stroke_width(size(2.0)),
        )))?;
        // The label on the side of the mark with more room.
        let side = if *x > 0.5 * (x0 + x1) {
            HPos::Right
        } else {
            HPos::Left
        };
        let font = ("sans-serif", size(13.0)).into_font().color(&BLACK);
        chart.draw_series(std::iter::once(Text::new(
            format!(" {label} "),
            (*x, *y),
            font.pos(Pos::new(side, VPos::Bottom)),
        )))?;
    }
    if p.series.len() > 1 {
        // Marks label the largest values, usually near the top right; a
        // legend beside the data is right of them all.
        let position = if p.marks.is_empty() || beside {
            SeriesLabelPosition::UpperRight
        } else {
            SeriesLabelPosition::UpperLeft
        };
        draw_legend(&mut chart, scale, 13.0, position)?;
    }
    Ok(true)
}

/// Several line charts on a grid of `rows × cols`, each `panel` pixels (width, height).
pub fn panels_plot(
    path: &Path,
    rows: usize,
    cols: usize,
    panel: (u32, u32),
    panels: &[Panel],
) -> Result<(), String> {
    let size = (panel.0 * cols as u32, panel.1 * rows as u32);
    save_png(path, size, |root, s| {
        let e = |err: DrawingAreaErrorKind<_>| format!("{}: {err}", path.display());
        for (area, p) in root.split_evenly((rows, cols)).iter().zip(panels) {
            draw_panel(area, p, s as f64).map_err(e)?;
        }
        Ok(())
    })
}

/// Wire shapes in the x–z plane at several instants, with rods seen end-on
/// as circles (center x, center z, radius), equal scales on both axes.
pub fn configurations_plot(
    path: &Path,
    shapes: &[(f64, Vec<(f64, f64)>)],
    rods: &[(f64, f64, f64)],
) -> Result<(), String> {
    let mut all: Vec<(f64, f64)> = shapes.iter().flat_map(|(_, p)| p.iter().copied()).collect();
    for &(x, z, r) in rods {
        all.push((x - r, z - r));
        all.push((x + r, z + r));
    }
    let (mut x0, mut x1, mut z0, mut z1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for (x, z) in &all {
        x0 = x0.min(*x);
        x1 = x1.max(*x);
        z0 = z0.min(*z);
        z1 = z1.max(*z);
    }
    if !x0.is_finite() {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let pad = 0.05 * (x1 - x0).max(z1 - z0);
    let (x0, mut x1, z0, z1) = (x0 - pad, x1 + pad, z0 - pad, z1 + pad);
    // The legend goes right of the shapes, in room of its own.
    let (width, legend_px) = (1100u32, 170.0);
    let plot_px = width as f64 - 100.0;
    let data_px = plot_px - legend_px;
    x1 += (x1 - x0) * legend_px / data_px;
    let rows = shapes.len() as f64 * 19.0 + 150.0;
    let height = (data_px * (z1 - z0) / (x1 - x0) * (plot_px / data_px) + 120.0)
        .max(rows)
        .clamp(300.0, 1400.0) as u32;
    save_png(path, (width, height), |root, s| {
        let e = |err: DrawingAreaErrorKind<_>| format!("{}: {err}", path.display());
        let px = |v: u32| v * s;
        let mut chart = ChartBuilder::on(root)
            .caption("Wire configurations (x–z plane)", ("sans-serif", px(24)))
            .margin(px(15))
            .x_label_area_size(px(45))
            .y_label_area_size(px(70))
            .build_cartesian_2d(x0..x1, z0..z1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("x (m)")
            .y_desc("z (m)")
            .x_label_formatter(&|v| tick_label(v, x0, x1))
            .y_label_formatter(&|v| tick_label(v, z0, z1))
            .label_style(("sans-serif", px(15)))
            .axis_desc_style(("sans-serif", px(16)))
            .draw()
            .map_err(e)?;
        // Rods: their true circle, or a marker of 5 px where that would be invisible.
        let px_per_m = (width as f64 - 100.0) / (x1 - x0);
        for &(x, z, r) in rods {
            if r * px_per_m >= 5.0 {
                let circle: Vec<(f64, f64)> = (0..=64)
                    .map(|k| {
                        let a = 2.0 * std::f64::consts::PI * k as f64 / 64.0;
                        (x + r * a.cos(), z + r * a.sin())
                    })
                    .collect();
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        circle,
                        BLACK.mix(0.6).filled(),
                    )))
                    .map_err(e)?;
            } else {
                chart
                    .draw_series(std::iter::once(Circle::new((x, z), px(5), BLACK.filled())))
                    .map_err(e)?;
            }
        }
        let n = shapes.len().max(2) as f64;
        let legend = px(20) as i32;
        for (i, (t, pts)) in shapes.iter().enumerate() {
            // Dark purple (early) to yellow (late).
            let color = viridis(0.92 * i as f64 / (n - 1.0));
            let label = format!("t = {t:.3} s");
            let width = px(2);
            chart
                .draw_series(LineSeries::new(
                    pts.iter().copied(),
                    color.stroke_width(width),
                ))
                .map_err(e)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + legend, y)], color.stroke_width(width))
                });
        }
        draw_legend(&mut chart, s as f64, 14.0, SeriesLabelPosition::UpperRight).map_err(e)?;
        Ok(())
    })
}

/// Error against cost on log–log axes: one marker colour per
/// group, the Pareto front (no cheaper run is more accurate) as a black
/// line. Points with a non-positive coordinate are left out (log scale).
pub fn pareto_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    groups: &[Series],
    front: &[(f64, f64)],
) -> Result<(), String> {
    let ok = |&(x, y): &(f64, f64)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
    let all: Vec<(f64, f64)> = groups
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter(ok)
        .collect();
    if all.is_empty() {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for &(x, y) in &all {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    // Whole decades around the data (with a margin, so no marker sits on
    // an axis), at least one decade wide.
    let decade_below = |v: f64| 10f64.powf((v / 1.3).log10().floor());
    let decade_above = |v: f64| 10f64.powf((v * 1.3).log10().ceil());
    let (x0, x1) = (decade_below(x0), decade_above(x1));
    let (y0, y1) = (decade_below(y0), decade_above(y1));
    let x1 = if x1 <= x0 { x0 * 10.0 } else { x1 };
    let y1 = if y1 <= y0 { y0 * 10.0 } else { y1 };
    save_png(path, (1000, 680), |root, s| {
        let e = |err: DrawingAreaErrorKind<_>| format!("{}: {err}", path.display());
        let px = |v: u32| v * s;
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", px(24)))
            .margin(px(15))
            .x_label_area_size(px(50))
            .y_label_area_size(px(90))
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(x_label)
            .y_desc(y_label)
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", px(16)))
            .axis_desc_style(("sans-serif", px(18)))
            .draw()
            .map_err(e)?;
        let front: Vec<(f64, f64)> = front.iter().copied().filter(ok).collect();
        let (width, legend) = (px(2), px(20) as i32);
        if front.len() > 1 {
            chart
                .draw_series(LineSeries::new(front.clone(), BLACK.stroke_width(width)))
                .map_err(e)?
                .label("Pareto front")
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + legend, y)], BLACK.stroke_width(width))
                });
        }
        // Colours repeat after nine groups: the marker shape changes then.
        for (i, g) in groups.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let pts: Vec<(f64, f64)> = g.points.iter().copied().filter(ok).collect();
            let (dot, tri, shift) = (px(5), px(7), px(10) as i32);
            if i < COLORS.len() {
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, dot, color.filled())))
                    .map_err(e)?
                    .label(g.label)
                    .legend(move |(x, y)| Circle::new((x + shift, y), dot, color.filled()));
            } else {
                chart
                    .draw_series(
                        pts.iter()
                            .map(|&p| TriangleMarker::new(p, tri, color.filled())),
                    )
                    .map_err(e)?
                    .label(g.label)
                    .legend(move |(x, y)| TriangleMarker::new((x + shift, y), tri, color.filled()));
            }
        }
        chart
            .draw_series(
                front
                    .iter()
                    .map(|&p| Circle::new(p, px(8), BLACK.stroke_width(width))),
            )
            .map_err(e)?;
        // Cheap and accurate is the corner no run reaches.
        draw_legend(&mut chart, s as f64, 15.0, SeriesLabelPosition::LowerLeft).map_err(e)?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each small pixel's channel is the rounded mean of its s × s block,
    /// written out one sum at a time.
    #[test]
    fn averaging_down_is_the_rounded_block_mean() {
        let (size, s) = ((7u32, 5u32), 3u32);
        let (w, h) = (size.0 * s, size.1 * s);
        let mut x = 12345u32;
        let big: Vec<u8> = (0..w * h * 3)
            .map(|_| {
                x = x.wrapping_mul(1_103_515_245).wrapping_add(12345);
                (x >> 16) as u8
            })
            .collect();
        let small = average_down(&big, size, s);
        assert_eq!(small.len(), (size.0 * size.1 * 3) as usize);
        for y in 0..size.1 {
            for x in 0..size.0 {
                for c in 0..3 {
                    let mut sum = 0u32;
                    for dy in 0..s {
                        for dx in 0..s {
                            sum +=
                                u32::from(big[(((y * s + dy) * w + x * s + dx) * 3 + c) as usize]);
                        }
                    }
                    let mean = (sum + s * s / 2) / (s * s);
                    assert_eq!(u32::from(small[((y * size.0 + x) * 3 + c) as usize]), mean);
                }
            }
        }
        assert_eq!(average_down(&[255; 27], (1, 1), 3), vec![255, 255, 255]);
    }

    /// A plot of many series (an energy plot's six and more) keeps its
    /// height for the data: the legend goes beside them, and the highest
    /// curve runs near the top of the plot, not under a band of empty room
    /// the legend's rows once took (60 % of the height).
    #[test]
    fn many_series_leave_the_height_to_the_data() {
        let end = 1.0;
        let flat = |y: f64| vec![(0.0, y), (0.5 * end, y), (end, y)];
        let labels = ["top", "a", "b", "c", "d", "total + dissipated"];
        let series: Vec<Series> = (labels.iter().enumerate())
            .map(|(i, label)| Series {
                label,
                points: flat(if i == 0 { 1.0 } else { -(i as f64) / 10.0 }),
            })
            .collect();
        let dir = std::env::temp_dir().join(format!("ancf-plot-many-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("many.png");
        line_plot(&path, "many", "t", "y", &series).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_dir_all(&dir).unwrap();
        let (w, h) = img.dimensions();
        let blue = COLORS[0];
        let is_blue = |p: &image::Rgb<u8>| {
            (0..3).all(|k| (i32::from(p[k]) - i32::from([blue.0, blue.1, blue.2][k])).abs() < 40)
        };
        // The top curve's row: many blue pixels (the legend's sample is short).
        let row = (0..h)
            .find(|&y| (0..w).filter(|&x| is_blue(img.get_pixel(x, y))).count() > 200)
            .expect("the top curve");
        assert!(row < h / 5, "the top curve at row {row} of {h}");
    }

    /// A series denser than the pixels with sharp spikes (a raw force at
    /// every step) stays within its values: nothing of it is drawn above
    /// a line at its largest value or below one at its smallest.
    #[test]
    fn a_dense_spiky_series_stays_within_its_values() {
        let spikes: Vec<(f64, f64)> = (0..20_000)
            .map(|k| {
                let t = k as f64 * 1e-4;
                let y = if k % 97 == 0 {
                    1.0
                } else {
                    0.2 + 0.1 * (k % 7) as f64 / 7.0
                };
                (t, y)
            })
            .collect();
        let end = spikes.last().unwrap().0;
        let panel = Panel {
            title: "spikes",
            x_label: "t",
            y_label: "y",
            series: vec![
                Series {
                    label: "spiky",
                    points: spikes,
                },
                Series {
                    label: "top",
                    points: vec![(0.0, 1.0), (end, 1.0)],
                },
                Series {
                    label: "bottom",
                    points: vec![(0.0, 0.0), (end, 0.0)],
                },
            ],
            // A mark puts the legend in the upper left, away from the
            // columns read below.
            marks: vec![(0.0, 1.0, "peak".into())],
            markers: false,
        };
        let dir = std::env::temp_dir().join(format!("ancf-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("spikes.png");
        panels_plot(&path, 1, 1, (960, 480), &[panel]).unwrap();
        let img = image::open(&path).unwrap().to_rgb8();
        std::fs::remove_dir_all(&dir).unwrap();
        let (w, h) = img.dimensions();
        // The series' colours: blue for the spikes, orange and green lines.
        let is = |p: &image::Rgb<u8>, c: RGBColor| {
            (0..3).all(|k| (i32::from(p[k]) - i32::from([c.0, c.1, c.2][k])).abs() < 40)
        };
        // Columns right of the legend (upper left) and inside the plot.
        let columns = (w / 2)..(w - 30);
        let rows_of = |c: RGBColor| -> Vec<u32> {
            (0..h)
                .filter(|&y| {
                    columns
                        .clone()
                        .filter(|&x| is(img.get_pixel(x, y), c))
                        .count()
                        > 100
                })
                .collect()
        };
        let (top, bottom) = (rows_of(COLORS[1]), rows_of(COLORS[2]));
        let (top, bottom) = (*top.first().unwrap(), *bottom.last().unwrap());
        for x in columns.clone() {
            for y in 0..h {
                if is(img.get_pixel(x, y), COLORS[0]) {
                    assert!(
                        (top.saturating_sub(1)..=bottom + 1).contains(&y),
                        "a spike drawn at row {y}, outside rows {top} … {bottom}"
                    );
                }
            }
        }
    }

    /// Large forces are drawn in kN and MN, small lengths in mm and µm;
    /// other units and ranges keep their labels.
    #[test]
    fn axes_take_the_prefix_that_keeps_ticks_short() {
        assert_eq!(prefixed("force (N)", 2.5e4), ("force (kN)".into(), 1e3));
        assert_eq!(prefixed("force (N)", 3e7), ("force (MN)".into(), 1e6));
        assert_eq!(
            prefixed("moment (N m)", 1.9e4),
            ("moment (kN m)".into(), 1e3)
        );
        assert_eq!(prefixed("force (N)", 9.5e3), ("force (N)".into(), 1.0));
        assert_eq!(prefixed("z (m)", 3e-3), ("z (mm)".into(), 1e-3));
        assert_eq!(prefixed("z (m)", 1e-5 * 0.5), ("z (µm)".into(), 1e-6));
        assert_eq!(prefixed("time t (s)", 2e4), ("time t (s)".into(), 1.0));
        assert_eq!(prefixed("strain", 2e4), ("strain".into(), 1.0));
        assert_eq!(prefixed("E_xx (-)", 7e-3), ("E_xx (10⁻³)".into(), 1e-3));
        assert_eq!(prefixed("E_zz (-)", 1.2e-5), ("E_zz (10⁻⁶)".into(), 1e-6));
        assert_eq!(prefixed("E_yy (-)", 0.5), ("E_yy (-)".into(), 1.0));
        // The ticks of 25 kN read 25, not 25e3.
        let (_, scale) = prefixed("force (N)", 3e4);
        assert_eq!(tick_label(&(2.5e4 / scale), 0.0, 3e4 / scale), "25");
    }
}
