//! A small SVG line-plot writer: panels of series on linear or logarithmic axes, with ticks and
//! a legend below each plot area (outside the data), drawn with each series' own line and marker.
//! A panel that holds a particle map (a series coloured by a field) is drawn at equal scales
//! on both axes, with a colour bar beside it.

use std::fmt::Write;

#[derive(Clone, Debug, PartialEq)]
pub enum Style {
    Line,
    Markers,
    /// Markers joined by a line (a convergence or work–precision series).
    LineMarkers,
    /// Particles as filled dots coloured by a field, one value per point.
    Coloured(Field),
}

/// A field over a series' points (a particle map's colour).
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// The field's name and unit, shown on the colour bar.
    pub name: String,
    pub values: Vec<f64>,
}

/// The colour map's anchors, low to high (viridis at five stops: perceptually ordered and
/// readable in grey and by colour-blind readers); colours in between are blended linearly.
const COLOUR_MAP: [(f64, f64, f64); 5] = [
    (68.0, 1.0, 84.0),
    (59.0, 82.0, 139.0),
    (33.0, 145.0, 140.0),
    (94.0, 201.0, 98.0),
    (253.0, 231.0, 37.0),
];
/// Width of a particle map's colour bar and of the room for its labels.
const COLOUR_BAR_W: f64 = 12.0;
const COLOUR_BAR_ROOM: f64 = 70.0;

/// The colour of `fraction` ∈ [0, 1] of the way along the colour map.
fn colour_at(fraction: f64) -> String {
    let t = fraction.clamp(0.0, 1.0) * (COLOUR_MAP.len() - 1) as f64;
    let k = (t.floor() as usize).min(COLOUR_MAP.len() - 2);
    let (a, b, u) = (COLOUR_MAP[k], COLOUR_MAP[k + 1], t - k as f64);
    let mix = |x: f64, y: f64| (x + (y - x) * u).round() as u8;
    format!(
        "#{:02x}{:02x}{:02x}",
        mix(a.0, b.0),
        mix(a.1, b.1),
        mix(a.2, b.2)
    )
}

#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

/// How an axis maps values to positions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Scale {
    #[default]
    Linear,
    /// Decades equally spaced, labelled with their values; non-positive values are not drawn.
    Log,
}

impl Scale {
    /// A value's position along the axis, in the axis' own units.
    fn position(self, value: f64) -> f64 {
        match self {
            Scale::Linear => value,
            Scale::Log => value.log10(),
        }
    }

    /// The mantissas labelled on a log axis spanning `decades`: enough for two labels or more.
    fn labelled_mantissas(decades: f64) -> &'static [f64] {
        if decades >= 2.0 {
            &[1.0]
        } else if decades >= 0.7 {
            &[1.0, 2.0, 5.0]
        } else {
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        }
    }

    /// Tick positions m·10^k (m = 1…9) from the decade below `lo` to the one above `hi`, each
    /// with its value and whether it is labelled.
    fn log_ticks(lo: f64, hi: f64) -> impl Iterator<Item = (f64, f64, bool)> {
        let labelled = Self::labelled_mantissas(hi - lo);
        (lo.floor() as i32..=hi.ceil() as i32).flat_map(move |decade| {
            (1..10).map(move |m| {
                let value = m as f64 * 10f64.powi(decade);
                (value.log10(), value, labelled.contains(&(m as f64)))
            })
        })
    }

    /// The axis' view of data spanning positions [lo, hi]: a log axis widens to the labelled
    /// ticks on either side, so that its ends are labelled and at least two labels show. A
    /// wider view may label fewer mantissas, so the view is widened again until it holds.
    fn view(self, lo: f64, hi: f64) -> (f64, f64) {
        match self {
            Scale::Linear => (lo, hi),
            Scale::Log => {
                let mut view = (lo, hi);
                for _ in 0..3 {
                    let labelled: Vec<f64> = Self::log_ticks(view.0, view.1)
                        .filter(|&(_, _, labelled)| labelled)
                        .map(|(t, _, _)| t)
                        .collect();
                    let below = labelled.iter().rev().find(|&&t| t <= lo + 1e-9);
                    let above = labelled.iter().find(|&&t| t >= hi - 1e-9);
                    let wider = (*below.unwrap_or(&lo), *above.unwrap_or(&hi));
                    if wider == view {
                        break;
                    }
                    view = wider;
                }
                view
            }
        }
    }

    /// Ticks over positions [lo, hi]: each position with its label, or none for a minor tick.
    fn ticks(self, lo: f64, hi: f64) -> Vec<(f64, Option<String>)> {
        match self {
            Scale::Linear => ticks(lo, hi)
                .into_iter()
                .map(|t| (t, Some(fmt_tick(t))))
                .collect(),
            // within 1e-9 of the view, so that its snapped ends keep their labels
            Scale::Log => Self::log_ticks(lo, hi)
                .filter(|(t, _, _)| (lo - 1e-9..=hi + 1e-9).contains(t))
                .map(|(t, value, labelled)| (t, labelled.then(|| fmt_log_tick(value))))
                .collect(),
        }
    }
}

#[derive(Clone, Debug, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    pub x_scale: Scale,
    pub y_scale: Scale,
}

#[derive(Clone, Debug, Default)]
pub struct Figure {
    pub title: String,
    pub panels: Vec<Panel>,
}

const PANEL_W: f64 = 480.0;
const PANEL_H: f64 = 330.0;
const MARGIN: (f64, f64, f64, f64) = (62.0, 20.0, 34.0, 46.0); // left, right, top, bottom
/// Ten colours (matplotlib's tab10); past ten series the marker shape changes too, so that no
/// two series of a panel look alike.
const COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf",
];
/// Height of one legend row.
const LEGEND_ROW: f64 = 16.0;
/// About how wide a character of the 12 px font is.
const CHARACTER_W: f64 = 6.5;

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}

/// About five round tick values covering [lo, hi].
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let raw = (hi - lo) / 5.0;
    let magnitude = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * magnitude)
        .find(|s| raw <= *s)
        .unwrap_or(10.0 * magnitude);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - pad, hi + pad)
}

impl Figure {
    pub fn to_svg(&self) -> String {
        let columns = self.panels.len().clamp(1, 2);
        let rows = self.panels.len().div_ceil(columns).max(1);
        // each row as tall as its tallest panel (plot area plus legend)
        let row_heights: Vec<f64> = (0..rows)
            .map(|row| {
                self.panels
                    .iter()
                    .skip(row * columns)
                    .take(columns)
                    .map(Panel::height)
                    .fold(PANEL_H, f64::max)
            })
            .collect();
        let row_tops: Vec<f64> = row_heights
            .iter()
            .scan(30.0, |top, h| {
                let this = *top;
                *top += h;
                Some(this)
            })
            .collect();
        let width = columns as f64 * PANEL_W;
        let height = 30.0 + row_heights.iter().sum::<f64>();
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"#
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="20" text-anchor="middle" font-size="{:.1}">{}</text>"#,
            width / 2.0,
            fitting_font_size(&self.title, 15.0, width - 10.0),
            escape(&self.title)
        );
        for (k, panel) in self.panels.iter().enumerate() {
            let (ox, oy) = ((k % columns) as f64 * PANEL_W, row_tops[k / columns]);
            panel.draw(&mut s, ox, oy);
        }
        s.push_str("</svg>\n");
        s
    }
}

/// The font size, at most `size`, at which `text` fits in `width` (a character is about 0.55
/// of the font size wide).
fn fitting_font_size(text: &str, size: f64, width: f64) -> f64 {
    let characters = text.chars().count().max(1) as f64;
    size.min(width / (0.55 * characters))
}

/// How series `k` of a panel is drawn: its colour and marker shape.
fn look(k: usize) -> (&'static str, usize) {
    (COLOURS[k % COLOURS.len()], k / COLOURS.len() % 3)
}

/// A marker of `shape` (0 circle, 1 square, 2 diamond) at (x, y).
fn marker(s: &mut String, shape: usize, x: f64, y: f64, colour: &str) {
    let _ = match shape {
        0 => writeln!(
            s,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="2.5" fill="none" stroke="{colour}"/>"#
        ),
        1 => writeln!(
            s,
            r#"<rect x="{:.2}" y="{:.2}" width="5" height="5" fill="none" stroke="{colour}"/>"#,
            x - 2.5,
            y - 2.5
        ),
        _ => writeln!(
            s,
            r#"<polygon points="{:.2},{y:.2} {x:.2},{:.2} {:.2},{y:.2} {x:.2},{:.2}" fill="none" stroke="{colour}"/>"#,
            x - 3.0,
            y - 3.0,
            x + 3.0,
            y + 3.0
        ),
    };
}

impl Panel {
    /// The panel's height: the plot area and its axes, then the legend's rows.
    fn height(&self) -> f64 {
        let rows = self.series.len().div_ceil(self.legend_columns()) as f64;
        PANEL_H
            + if rows > 0.0 {
                8.0 + LEGEND_ROW * rows
            } else {
                0.0
            }
    }

    /// Two legend columns where every label fits in half the width, else one.
    fn legend_columns(&self) -> usize {
        let half = (PANEL_W - MARGIN.0 - MARGIN.1) / 2.0 - 30.0;
        let longest = self
            .series
            .iter()
            .map(|s| s.label.chars().count())
            .max()
            .unwrap_or(0);
        if longest as f64 * CHARACTER_W <= half {
            2
        } else {
            1
        }
    }

    /// The field of the panel's particle map, if it holds one.
    fn field(&self) -> Option<&Field> {
        self.series.iter().find_map(|s| match &s.style {
            Style::Coloured(field) => Some(field),
            _ => None,
        })
    }

    fn draw(&self, s: &mut String, ox: f64, oy: f64) {
        let (ml, mr, mt, mb) = MARGIN;
        let field = self.field();
        let bar_room = if field.is_some() {
            COLOUR_BAR_ROOM
        } else {
            0.0
        };
        let (x0, y0, w, h) = (
            ox + ml,
            oy + mt,
            PANEL_W - ml - mr - bar_room,
            PANEL_H - mt - mb,
        );
        // every point in axis positions (a log axis' non-positive values become non-finite)
        let positions: Vec<Vec<(f64, f64)>> = self
            .series
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .map(|&(x, y)| (self.x_scale.position(x), self.y_scale.position(y)))
                    .collect()
            })
            .collect();
        let (xlo, xhi) = bounds(positions.iter().flatten().map(|p| p.0));
        let (ylo, yhi) = bounds(positions.iter().flatten().map(|p| p.1));
        let (mut xlo, mut xhi) = self.x_scale.view(xlo, xhi);
        let (mut ylo, mut yhi) = self.y_scale.view(ylo, yhi);
        if field.is_some() {
            // equal scales: the shorter range widens about its middle to the common scale
            let scale = ((xhi - xlo) / w).max((yhi - ylo) / h);
            let (xm, ym) = (0.5 * (xlo + xhi), 0.5 * (ylo + yhi));
            (xlo, xhi) = (xm - 0.5 * scale * w, xm + 0.5 * scale * w);
            (ylo, yhi) = (ym - 0.5 * scale * h, ym + 0.5 * scale * h);
        }
        let range = field.map(|f| {
            let (lo, hi) = f
                .values
                .iter()
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                });
            if lo.is_finite() && hi > lo {
                (lo, hi)
            } else {
                (lo.min(0.0), lo.max(0.0) + 1.0)
            }
        });
        let fraction = |v: f64| range.map_or(0.5, |(lo, hi)| (v - lo) / (hi - lo));
        let px = |x: f64| x0 + (x - xlo) / (xhi - xlo) * w;
        let py = |y: f64| y0 + h - (y - ylo) / (yhi - ylo) * h;
        let _ = writeln!(
            s,
            r##"<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="none" stroke="#444"/>"##
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle" font-size="{:.1}">{}</text>"#,
            x0 + w / 2.0,
            oy + 20.0,
            fitting_font_size(&self.title, 13.0, PANEL_W - 10.0),
            escape(&self.title)
        );
        // a labelled tick is 5 px long, a minor one 3 px
        for (t, label) in self.x_scale.ticks(xlo, xhi) {
            let length = if label.is_some() { 5.0 } else { 3.0 };
            let _ = writeln!(
                s,
                r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#444"/>"##,
                px(t),
                y0 + h,
                y0 + h + length,
            );
            if let Some(label) = label {
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{}" text-anchor="middle">{label}</text>"#,
                    px(t),
                    y0 + h + 18.0,
                );
            }
        }
        for (t, label) in self.y_scale.ticks(ylo, yhi) {
            let length = if label.is_some() { 5.0 } else { 3.0 };
            let _ = writeln!(
                s,
                r##"<line x1="{}" y1="{1}" x2="{x0}" y2="{1}" stroke="#444"/>"##,
                x0 - length,
                py(t),
            );
            if let Some(label) = label {
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{}" text-anchor="end">{label}</text>"#,
                    x0 - 8.0,
                    py(t) + 4.0,
                );
            }
        }
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
            x0 + w / 2.0,
            y0 + h + 36.0,
            escape(&self.x_label)
        );
        let _ = writeln!(
            s,
            r#"<text transform="translate({},{}) rotate(-90)" text-anchor="middle">{}</text>"#,
            ox + 14.0,
            y0 + h / 2.0,
            escape(&self.y_label)
        );
        for (k, (series, points)) in self.series.iter().zip(&positions).enumerate() {
            let (colour, shape) = look(k);
            if let Style::Coloured(field) = &series.style {
                for (&(x, y), &v) in points.iter().zip(&field.values) {
                    if x.is_finite() && y.is_finite() && v.is_finite() {
                        let _ = writeln!(
                            s,
                            r#"<circle cx="{:.2}" cy="{:.2}" r="2.5" fill="{}"/>"#,
                            px(x),
                            py(y),
                            colour_at(fraction(v))
                        );
                    }
                }
                continue;
            }
            let finite = points
                .iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite());
            if matches!(series.style, Style::Line | Style::LineMarkers) {
                let path: Vec<String> = finite
                    .clone()
                    .map(|&(x, y)| format!("{:.2},{:.2}", px(x), py(y)))
                    .collect();
                let _ = writeln!(
                    s,
                    r#"<polyline fill="none" stroke="{colour}" stroke-width="1.5" points="{}"/>"#,
                    path.join(" ")
                );
            }
            if matches!(series.style, Style::Markers | Style::LineMarkers) {
                for &(x, y) in finite {
                    marker(s, shape, px(x), py(y), colour);
                }
            }
        }
        if let (Some(field), Some((lo, hi))) = (field, range) {
            let bx = x0 + w + 12.0;
            let stops: Vec<String> = (0..COLOUR_MAP.len())
                .map(|k| {
                    let f = k as f64 / (COLOUR_MAP.len() - 1) as f64;
                    format!(
                        r#"<stop offset="{f}" stop-color="{}"/>"#,
                        colour_at(1.0 - f)
                    )
                })
                .collect();
            let id = format!("bar{}{}", ox as i64, oy as i64);
            let _ = writeln!(
                s,
                r##"<defs><linearGradient id="{id}" x1="0" y1="0" x2="0" y2="1">{}</linearGradient></defs><rect x="{bx}" y="{y0}" width="{COLOUR_BAR_W}" height="{h}" fill="url(#{id})" stroke="#444"/>"##,
                stops.join("")
            );
            for (value, y) in [(hi, y0 + 4.0), (lo, y0 + h)] {
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{y}">{}</text>"#,
                    bx + COLOUR_BAR_W + 3.0,
                    fmt_tick(value)
                );
            }
            let _ = writeln!(
                s,
                r#"<text transform="translate({},{}) rotate(-90)" text-anchor="middle" font-size="{:.1}">{}</text>"#,
                bx + COLOUR_BAR_W + 30.0,
                y0 + h / 2.0,
                fitting_font_size(&field.name, 12.0, h),
                escape(&field.name)
            );
        }
        // the legend below the axis label, outside the data: each entry drawn as its series is
        let columns = self.legend_columns();
        let column_width = (PANEL_W - ml - mr) / columns as f64;
        for (k, series) in self.series.iter().enumerate() {
            let (colour, shape) = look(k);
            let lx = x0 + (k % columns) as f64 * column_width;
            let ly = oy + PANEL_H + 6.0 + LEGEND_ROW * (k / columns) as f64;
            if matches!(series.style, Style::Line | Style::LineMarkers) {
                let _ = writeln!(
                    s,
                    r#"<line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{colour}" stroke-width="2"/>"#,
                    lx + 20.0
                );
            }
            if matches!(series.style, Style::Markers | Style::LineMarkers) {
                marker(s, shape, lx + 10.0, ly, colour);
            }
            if matches!(series.style, Style::Coloured(_)) {
                let _ = writeln!(
                    s,
                    r#"<circle cx="{:.2}" cy="{ly:.2}" r="2.5" fill="{}"/>"#,
                    lx + 10.0,
                    colour_at(0.5)
                );
            }
            // cut labels that would leave the column
            let room = ((column_width - 30.0) / CHARACTER_W) as usize;
            let label: String = if series.label.chars().count() > room {
                let kept: String = series.label.chars().take(room.saturating_sub(1)).collect();
                format!("{kept}…")
            } else {
                series.label.clone()
            };
            let _ = writeln!(
                s,
                r#"<text x="{}" y="{}">{}</text>"#,
                lx + 26.0,
                ly + 4.0,
                escape(&label)
            );
        }
    }
}

/// A log axis' label: its whole mantissa, as a plain number between 0.001 and 10⁴, else as
/// `me-k`.
fn fmt_log_tick(value: f64) -> String {
    if (1e-3..1e4).contains(&value) {
        fmt_tick(value)
    } else {
        format!("{value:.0e}")
    }
}

fn fmt_tick(t: f64) -> String {
    if t == 0.0 {
        "0".into()
    } else if t.abs() >= 1e4 || t.abs() < 1e-3 {
        format!("{t:.1e}")
    } else {
        let s = format!("{t:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_inside() {
        let t = ticks(0.03, 0.97);
        let expected = [0.2, 0.4, 0.6, 0.8];
        assert_eq!(t.len(), expected.len());
        assert!(t.iter().zip(expected).all(|(a, b)| (a - b).abs() < 1e-12));
    }

    /// Twelve series in two panels: every series looks different from the others of its
    /// panel, and every text element (the legend included) lies inside the canvas.
    #[test]
    fn series_never_look_alike_and_text_stays_on_the_canvas() {
        let looks: Vec<_> = (0..30).map(look).collect();
        for (k, a) in looks.iter().enumerate() {
            assert!(looks[..k].iter().all(|b| b != a), "series {k} repeats");
        }
        let panel = |n: usize| Panel {
            title: "p".into(),
            series: (0..n)
                .map(|k| Series {
                    label: format!("a series with a rather long label number {k}"),
                    points: vec![(0.0, k as f64), (1.0, 2.0 * k as f64)],
                    style: Style::LineMarkers,
                })
                .collect(),
            ..Panel::default()
        };
        let svg = Figure {
            title: "t".into(),
            panels: vec![panel(12), panel(3), panel(1)],
        }
        .to_svg();
        let attribute = |tag: &str, name: &str| -> f64 {
            let start = tag.find(&format!(" {name}=\"")).expect("attribute") + name.len() + 3;
            let end = start + tag[start..].find('"').unwrap();
            tag[start..end].parse().unwrap()
        };
        let root = &svg[..svg.find('>').unwrap()];
        let (width, height) = (attribute(root, "width"), attribute(root, "height"));
        for tag in svg.split("<text").skip(1) {
            let tag = &tag[..tag.find('>').unwrap()];
            if tag.contains(" y=\"") {
                let (x, y) = (attribute(tag, "x"), attribute(tag, "y"));
                assert!(
                    (0.0..=width).contains(&x) && (0.0..=height).contains(&y),
                    "{tag}"
                );
            }
        }
    }

    /// A particle map: one data unit is as many pixels along x as along y, and the lowest and
    /// highest values take the colour map's two ends.
    #[test]
    fn particle_maps_have_equal_scales_and_span_the_colour_map() {
        let panel = Panel {
            series: vec![Series {
                label: "particles".into(),
                points: vec![(0.0, 0.0), (1.0, 0.0), (0.0, 4.0)],
                style: Style::Coloured(Field {
                    name: "strain".into(),
                    values: vec![0.0, 1.0, 2.0],
                }),
            }],
            ..Panel::default()
        };
        let svg = Figure {
            title: "map".into(),
            panels: vec![panel],
        }
        .to_svg();
        let circles: Vec<(f64, f64, String)> = svg
            .split("<circle")
            .skip(1)
            .map(|tag| &tag[..tag.find('>').unwrap()])
            .filter(|tag| !tag.contains("stroke"))
            .map(|tag| {
                let value = |name: &str| {
                    let start = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
                    tag[start..start + tag[start..].find('"').unwrap()].to_string()
                };
                (
                    value("cx").parse().unwrap(),
                    value("cy").parse().unwrap(),
                    value("fill"),
                )
            })
            .collect();
        // three particles and the legend's sample
        assert_eq!(circles.len(), 4, "{svg}");
        let x_unit = circles[1].0 - circles[0].0;
        let y_unit = (circles[0].1 - circles[2].1) / 4.0;
        assert!(
            x_unit > 0.0 && (x_unit - y_unit).abs() < 0.02,
            "{x_unit} {y_unit}"
        );
        assert_eq!(circles[0].2, "#440154");
        assert_eq!(circles[2].2, "#fde725");
    }

    /// A log–log panel labels whole decades, equally spaced, each with its value; a view
    /// narrower than a decade still shows two labels or more.
    #[test]
    fn log_axes_label_equally_spaced_decades() {
        let panel = |points: Vec<(f64, f64)>| Panel {
            series: vec![Series {
                label: "s".into(),
                points,
                style: Style::LineMarkers,
            }],
            x_scale: Scale::Log,
            y_scale: Scale::Log,
            ..Panel::default()
        };
        // x labels: text elements centred under the axis
        let x_labels = |svg: &str| -> Vec<(f64, String)> {
            svg.split("<text x=\"")
                .skip(1)
                .filter(|t| t.contains("text-anchor=\"middle\">") && !t.contains("font-size"))
                .filter_map(|t| {
                    let x: f64 = t[..t.find('"').unwrap()].parse().ok()?;
                    let label = &t[t.find('>').unwrap() + 1..t.find("</text>").unwrap()];
                    Some((x, label.to_string()))
                })
                .filter(|(_, label)| label.parse::<f64>().is_ok())
                .collect()
        };
        let svg = Figure {
            title: "wide".into(),
            panels: vec![panel(vec![(0.02, 1e-4), (300.0, 1e-1)])],
        }
        .to_svg();
        let labels = x_labels(&svg);
        let values: Vec<&str> = labels.iter().map(|(_, l)| l.as_str()).collect();
        assert_eq!(values, ["0.01", "0.1", "1", "10", "100", "1000"], "{svg}");
        let gaps: Vec<f64> = labels.windows(2).map(|w| w[1].0 - w[0].0).collect();
        assert!(gaps.iter().all(|g| (g - gaps[0]).abs() < 1e-9), "{gaps:?}");
        // non-positive values cannot be placed on a log axis and are left out
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        let narrow = Figure {
            title: "narrow".into(),
            panels: vec![panel(vec![(0.105, 1.0), (0.13, 2.0), (-1.0, 3.0)])],
        }
        .to_svg();
        let values: Vec<String> = x_labels(&narrow).into_iter().map(|(_, l)| l).collect();
        assert!(values.len() >= 2, "{values:?}");
        assert!(values.contains(&"0.1".to_string()), "{values:?}");
    }

    #[test]
    fn svg_is_well_formed_enough_to_have_one_root() {
        let fig = Figure {
            title: "a < b".into(),
            panels: vec![Panel {
                series: vec![Series {
                    label: "s".into(),
                    points: vec![(0.0, 1.0), (1.0, f64::NAN), (2.0, 3.0)],
                    style: Style::Line,
                }],
                ..Panel::default()
            }],
        };
        let svg = fig.to_svg();
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("a &lt; b") && !svg.contains("NaN"));
    }
}
