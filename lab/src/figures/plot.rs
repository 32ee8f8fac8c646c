//! Charts as data (`Figure` of `Panel`s), drawn by plotters to SVG and PNG alike. Log axes
//! are drawn as linear axes in `log10` with decade labels, so every panel type has one
//! coordinate type.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Marker of a series.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mark {
    /// No marker.
    None,
    /// Filled circle.
    Circle,
    /// Triangle.
    Triangle,
    /// Cross.
    Cross,
    /// Open square.
    Square,
}

/// One line or scatter of a line panel.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label (empty: not in the legend).
    pub label: String,
    /// Points in data coordinates.
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Joined by a line.
    pub line: bool,
    /// Dashed line.
    pub dashed: bool,
    /// Marker.
    pub mark: Mark,
}

/// A line chart.
#[derive(Clone, Debug, Default)]
pub struct Lines {
    /// Panel title.
    pub title: String,
    /// X axis label.
    pub x_label: String,
    /// Y axis label.
    pub y_label: String,
    /// Logarithmic x.
    pub x_log: bool,
    /// Logarithmic y.
    pub y_log: bool,
    /// Fixed x range (data coordinates).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (data coordinates); values below are drawn at the bottom.
    pub y_range: Option<(f64, f64)>,
    /// The series.
    pub series: Vec<Series>,
    /// Draw the series labels inside the panel (else the figure's legend column has them).
    pub legend: bool,
}

/// A categorical map: cells `(i, j)` of an `nx x ny` grid with a colour each, with line
/// overlays in data coordinates (x log-spaced cells `xs`, y the row index).
#[derive(Clone, Debug, Default)]
pub struct Heat {
    /// Panel title.
    pub title: String,
    /// X axis label.
    pub x_label: String,
    /// Y axis label.
    pub y_label: String,
    /// Cell centres along x (log-spaced; drawn on a log axis).
    pub xs: Vec<f64>,
    /// Rows.
    pub ny: usize,
    /// `(i, j, colour)`.
    pub cells: Vec<(usize, usize, RGBColor)>,
    /// Overlays: x in data units, y in row units.
    pub overlay: Vec<Series>,
}

/// A bar chart.
#[derive(Clone, Debug, Default)]
pub struct Bars {
    /// Panel title.
    pub title: String,
    /// Y axis label.
    pub y_label: String,
    /// Logarithmic y.
    pub y_log: bool,
    /// `(name, value, colour)`.
    pub bars: Vec<(String, f64, RGBColor)>,
}

/// One panel.
#[derive(Clone, Debug)]
pub enum Panel {
    /// Line chart.
    Lines(Lines),
    /// Categorical map.
    Heat(Heat),
    /// Bar chart.
    Bars(Bars),
}

/// A legend entry of the figure's legend column.
#[derive(Clone, Debug)]
pub struct Entry {
    /// Label.
    pub label: String,
    /// Colour.
    pub color: RGBColor,
    /// Marker.
    pub mark: Mark,
    /// Draw a line sample (else a filled box).
    pub line: bool,
    /// Dashed line sample.
    pub dashed: bool,
}

/// A figure: a grid of panels, a title, and an optional legend column on the right.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Title on top.
    pub title: String,
    /// Pixel size.
    pub size: (u32, u32),
    /// Grid rows and columns.
    pub grid: (usize, usize),
    /// Panels, row by row.
    pub panels: Vec<Panel>,
    /// Legend column.
    pub legend: Vec<Entry>,
    /// Width of the legend column in pixels.
    pub legend_width: u32,
}

const FONT: &str = "sans-serif";

/// Registers a TrueType font for the charts (plotters' `ab_glyph` needs one): the
/// `RIGID3_FONT` file if set, else DejaVu Sans or Liberation Sans from the usual Debian
/// places (`fonts-dejavu-core`).
pub fn register_font() -> Result<PathBuf, String> {
    let mut candidates: Vec<PathBuf> = std::env::var_os("RIGID3_FONT")
        .map(PathBuf::from)
        .into_iter()
        .collect();
    candidates.extend(
        [
            "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/TTF/DejaVuSans.ttf",
            "/usr/share/fonts/dejavu/DejaVuSans.ttf",
            "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
            "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
            "/Library/Fonts/Arial.ttf",
            "C:\\Windows\\Fonts\\arial.ttf",
        ]
        .map(PathBuf::from),
    );
    for p in candidates {
        if let Ok(bytes) = std::fs::read(&p) {
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            if plotters::style::register_font(FONT, FontStyle::Normal, bytes).is_ok() {
                return Ok(p);
            }
        }
    }
    Err(
        "no TrueType font found for the chart labels: install fonts-dejavu-core \
         (apt-get install fonts-dejavu-core) or set RIGID3_FONT=/path/to/font.ttf"
            .into(),
    )
}

/// Writes `dir/stem.svg` and `dir/stem.png`.
pub fn save(fig: &Figure, dir: &Path, stem: &str) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let svg = dir.join(format!("{stem}.svg"));
    let png = dir.join(format!("{stem}.png"));
    {
        let root = SVGBackend::new(&svg, fig.size).into_drawing_area();
        draw(&root, fig).map_err(|e| format!("{}: {e}", svg.display()))?;
        root.present()
            .map_err(|e| format!("{}: {e}", svg.display()))?;
    }
    {
        let root = BitMapBackend::new(&png, fig.size).into_drawing_area();
        draw(&root, fig).map_err(|e| format!("{}: {e}", png.display()))?;
        root.present()
            .map_err(|e| format!("{}: {e}", png.display()))?;
    }
    Ok(vec![svg, png])
}

type R<DB> = Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, fig: &Figure) -> R<DB> {
    root.fill(&WHITE)?;
    let body = root.titled(&fig.title, (FONT, 26).into_font())?;
    let (w, _) = body.dim_in_pixel();
    let (grid, legend) = if fig.legend.is_empty() {
        (body.clone(), None)
    } else {
        let (g, l) = body.split_horizontally(w.saturating_sub(fig.legend_width));
        (g, Some(l))
    };
    let areas = grid.split_evenly(fig.grid);
    for (area, panel) in areas.iter().zip(&fig.panels) {
        match panel {
            Panel::Lines(p) => lines(area, p)?,
            Panel::Heat(p) => heat(area, p)?,
            Panel::Bars(p) => bars(area, p)?,
        }
    }
    if let Some(l) = legend {
        legend_column(&l, &fig.legend)?;
    }
    Ok(())
}

fn superscript(k: i64) -> String {
    let digits = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(digits[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// Tick label of a log axis (a superscript power of ten) or a linear one.
fn axis_label(log: bool, v: f64) -> String {
    if log {
        decade_label(v)
    } else {
        linear_label(v)
    }
}

fn decade_label(v: f64) -> String {
    if (v - v.round()).abs() < 1e-9 {
        superscript(v.round() as i64)
    } else {
        String::new()
    }
}

fn linear_label(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.0e}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn tf(log: bool, v: f64) -> Option<f64> {
    if log {
        (v > 0.0 && v.is_finite()).then(|| v.log10())
    } else {
        v.is_finite().then_some(v)
    }
}

/// The drawn range of one axis: the fixed range or the data's, padded; decades for log.
fn axis_range(log: bool, fixed: Option<(f64, f64)>, data: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = match fixed {
        Some((a, b)) => (tf(log, a).unwrap_or(-1.0), tf(log, b).unwrap_or(1.0)),
        None => {
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            for v in data.filter_map(|v| tf(log, v)) {
                lo = lo.min(v);
                hi = hi.max(v);
            }
            if !lo.is_finite() {
                (0.0, 1.0)
            } else if log {
                (lo.floor(), hi.ceil().max(lo.floor() + 1.0))
            } else {
                let pad = ((hi - lo) * 0.05).max(1e-12);
                (lo - pad, hi + pad)
            }
        }
    };
    (lo, if hi > lo { hi } else { lo + 1.0 })
}

fn label_count(log: bool, (lo, hi): (f64, f64)) -> usize {
    if log {
        let span = (hi - lo).round() as usize;
        if span <= 12 {
            span + 1
        } else {
            span / 2 + 1
        }
    } else {
        8
    }
}

/// Draws `mark` at `pts` (chart coordinates) and, with a label, puts it in the legend.
macro_rules! marks {
    ($chart:expr, $pts:expr, $mark:expr, $c:expr, $label:expr) => {{
        let c: RGBColor = $c;
        let label: Option<&str> = $label;
        match $mark {
            Mark::None => {}
            Mark::Circle => {
                let a = $chart.draw_series($pts.iter().map(|&p| Circle::new(p, 4, c.filled())))?;
                if let Some(l) = label {
                    a.label(l)
                        .legend(move |(x, y)| Circle::new((x + 9, y), 4, c.filled()));
                }
            }
            Mark::Triangle => {
                let a = $chart.draw_series(
                    $pts.iter()
                        .map(|&p| TriangleMarker::new(p, 5, c.stroke_width(2))),
                )?;
                if let Some(l) = label {
                    a.label(l).legend(move |(x, y)| {
                        TriangleMarker::new((x + 9, y), 5, c.stroke_width(2))
                    });
                }
            }
            Mark::Cross => {
                let a = $chart
                    .draw_series($pts.iter().map(|&p| Cross::new(p, 4, c.stroke_width(2))))?;
                if let Some(l) = label {
                    a.label(l)
                        .legend(move |(x, y)| Cross::new((x + 9, y), 4, c.stroke_width(2)));
                }
            }
            Mark::Square => {
                let a = $chart.draw_series($pts.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], c.stroke_width(2))
                }))?;
                if let Some(l) = label {
                    a.label(l).legend(move |(x, y)| {
                        Rectangle::new([(x + 5, y - 4), (x + 13, y + 4)], c.stroke_width(2))
                    });
                }
            }
        }
    }};
}

fn mark_at<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    mark: Mark,
    (x, y): (i32, i32),
    c: RGBColor,
) -> R<DB> {
    match mark {
        Mark::None => Ok(()),
        Mark::Circle => area.draw(&Circle::new((x, y), 4, c.filled())),
        Mark::Triangle => area.draw(&TriangleMarker::new((x, y), 5, c.stroke_width(2))),
        Mark::Cross => area.draw(&Cross::new((x, y), 4, c.stroke_width(2))),
        Mark::Square => area.draw(&Rectangle::new(
            [(x - 4, y - 4), (x + 4, y + 4)],
            c.stroke_width(2),
        )),
    }
}

fn lines<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Lines) -> R<DB> {
    let xs = p.series.iter().flat_map(|s| s.points.iter().map(|q| q.0));
    let ys = p.series.iter().flat_map(|s| s.points.iter().map(|q| q.1));
    let xr = axis_range(p.x_log, p.x_range, xs);
    let yr = axis_range(p.y_log, p.y_range, ys);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, (FONT, 20).into_font())
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    let xf = |v: &f64| axis_label(p.x_log, *v);
    let yf = |v: &f64| axis_label(p.y_log, *v);
    chart
        .configure_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .x_labels(label_count(p.x_log, xr))
        .y_labels(label_count(p.y_log, yr))
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style((FONT, 15).into_font())
        .axis_desc_style((FONT, 17).into_font())
        .light_line_style(RGBColor(236, 236, 236))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;
    for s in &p.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter_map(|&(x, y)| Some((tf(p.x_log, x)?, tf(p.y_log, y)?.max(yr.0))))
            .collect();
        let style = s.color.stroke_width(2);
        if s.line && pts.len() > 1 {
            let a = if s.dashed {
                chart.draw_series(DashedLineSeries::new(pts.clone(), 6, 4, style))?
            } else {
                chart.draw_series(LineSeries::new(pts.clone(), style))?
            };
            if p.legend && !s.label.is_empty() {
                let c = s.color;
                a.label(&s.label).legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 18, y)], c.stroke_width(2))
                });
            }
        }
        let label = (p.legend && !s.label.is_empty() && !(s.line && pts.len() > 1))
            .then_some(s.label.as_str());
        marks!(chart, pts, s.mark, s.color, label);
    }
    if p.legend {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 14).into_font())
            .draw()?;
    }
    Ok(())
}

fn heat<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Heat) -> R<DB> {
    let lx: Vec<f64> = p.xs.iter().map(|x| x.log10()).collect();
    let d = if lx.len() > 1 {
        (lx[lx.len() - 1] - lx[0]) / (lx.len() - 1) as f64
    } else {
        1.0
    };
    let (x0, x1) = (lx[0] - d / 2.0, lx[lx.len() - 1] + d / 2.0);
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, (FONT, 17).into_font())
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(x0..x1, 0.0..p.ny as f64)?;
    let xf = |v: &f64| decade_label(*v);
    let yf = |v: &f64| format!("{v:.0}");
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc(&p.x_label)
        .y_desc(&p.y_label)
        .x_labels(label_count(true, (x0, x1)))
        .y_labels(5)
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style((FONT, 13).into_font())
        .axis_desc_style((FONT, 14).into_font())
        .draw()?;
    chart.draw_series(p.cells.iter().map(|&(i, j, c)| {
        Rectangle::new(
            [
                (lx[i] - d / 2.0, j as f64),
                (lx[i] + d / 2.0, j as f64 + 1.0),
            ],
            c.filled(),
        )
    }))?;
    for s in &p.overlay {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter_map(|&(x, y)| Some((tf(true, x)?, y)))
            .filter(|&(x, _)| x >= x0 && x <= x1)
            .collect();
        let style = s.color.stroke_width(3);
        if s.dashed {
            chart.draw_series(DashedLineSeries::new(pts, 6, 4, style))?;
        } else {
            chart.draw_series(LineSeries::new(pts, style))?;
        }
    }
    Ok(())
}

fn bars<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Bars) -> R<DB> {
    let n = p.bars.len();
    let yr = axis_range(p.y_log, None, p.bars.iter().map(|b| b.1));
    let y0 = if p.y_log { yr.0 } else { 0.0 };
    let mut chart = ChartBuilder::on(area)
        .caption(&p.title, (FONT, 20).into_font())
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(-0.5..n as f64 - 0.5, y0..yr.1)?;
    let names: Vec<String> = p.bars.iter().map(|b| b.0.clone()).collect();
    let xf = |v: &f64| {
        let i = v.round();
        if (v - i).abs() < 1e-9 && i >= 0.0 && (i as usize) < names.len() {
            names[i as usize].clone()
        } else {
            String::new()
        }
    };
    let yf = |v: &f64| axis_label(p.y_log, *v);
    chart
        .configure_mesh()
        .disable_x_mesh()
        .y_desc(&p.y_label)
        .x_labels(n)
        .y_labels(label_count(p.y_log, (y0, yr.1)))
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style((FONT, 13).into_font())
        .axis_desc_style((FONT, 17).into_font())
        .draw()?;
    for (i, (_, v, c)) in p.bars.iter().enumerate() {
        let top = tf(p.y_log, *v).unwrap_or(y0);
        let x = i as f64;
        chart.draw_series(std::iter::once(Rectangle::new(
            [(x - 0.35, y0), (x + 0.35, top)],
            c.filled(),
        )))?;
        chart.draw_series(std::iter::once(Text::new(
            format!("{v:.0}"),
            (x - 0.2, top + (yr.1 - y0) * 0.02),
            (FONT, 14).into_font(),
        )))?;
    }
    Ok(())
}

fn legend_column<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> R<DB> {
    let font = (FONT, 16).into_font();
    for (k, e) in entries.iter().enumerate() {
        let y = 60 + 26 * k as i32;
        if e.line {
            if e.dashed {
                for s in 0..3 {
                    area.draw(&PathElement::new(
                        [(10 + 10 * s, y), (16 + 10 * s, y)],
                        e.color.stroke_width(2),
                    ))?;
                }
            } else {
                area.draw(&PathElement::new(
                    [(10, y), (38, y)],
                    e.color.stroke_width(2),
                ))?;
            }
        } else if e.mark == Mark::None {
            area.draw(&Rectangle::new(
                [(12, y - 8), (36, y + 8)],
                e.color.filled(),
            ))?;
        }
        mark_at(area, e.mark, (24, y), e.color)?;
        area.draw(&Text::new(e.label.clone(), (46, y - 9), font.clone()))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_axes_label_decades_only() {
        assert_eq!(decade_label(-3.0), "10⁻³");
        assert_eq!(decade_label(12.0), "10¹²");
        assert_eq!(decade_label(0.5), "");
        assert_eq!(axis_range(true, None, [3e-5, 0.2].into_iter()), (-5.0, 0.0));
        assert_eq!(tf(true, 0.0), None);
    }

    #[test]
    fn a_small_figure_renders_to_svg_and_png() {
        if register_font().is_err() {
            eprintln!("no font on this machine: rendering not tested");
            return;
        }
        let fig = Figure {
            title: "t".into(),
            size: (320, 240),
            grid: (1, 2),
            panels: vec![
                Panel::Lines(Lines {
                    x_log: true,
                    y_log: true,
                    series: vec![Series {
                        label: "a".into(),
                        points: vec![(0.1, 1e-3), (1.0, 1e-1)],
                        color: RGBColor(0, 0, 255),
                        line: true,
                        dashed: false,
                        mark: Mark::Circle,
                    }],
                    legend: true,
                    ..Lines::default()
                }),
                Panel::Bars(Bars {
                    bars: vec![("x".into(), 10.0, RGBColor(1, 2, 3))],
                    y_log: true,
                    ..Bars::default()
                }),
            ],
            legend: vec![],
            legend_width: 0,
        };
        let dir = std::env::temp_dir().join(format!("rigid3-plot-{}", std::process::id()));
        let files = save(&fig, &dir, "tiny").unwrap();
        for f in &files {
            assert!(std::fs::metadata(f).unwrap().len() > 100, "{}", f.display());
        }
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(
            svg.contains("10⁻³") || svg.contains("10⁻"),
            "decade labels in the SVG"
        );
        let _ = std::fs::remove_dir_all(dir);
    }
}
