//! A small SVG line-plot writer: panels of series on linear axes, with ticks and a legend.

use std::fmt::Write;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Style {
    Line,
    Markers,
    /// Markers joined by a line (a convergence or work–precision series).
    LineMarkers,
}

#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: Style,
}

#[derive(Clone, Debug, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
}

#[derive(Clone, Debug, Default)]
pub struct Figure {
    pub title: String,
    pub panels: Vec<Panel>,
}

const PANEL_W: f64 = 480.0;
const PANEL_H: f64 = 330.0;
const MARGIN: (f64, f64, f64, f64) = (62.0, 20.0, 34.0, 46.0); // left, right, top, bottom
const COLOURS: [&str; 6] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
];

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
        let (width, height) = (columns as f64 * PANEL_W, rows as f64 * PANEL_H + 30.0);
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">"#
        );
        let _ = writeln!(s, r#"<rect width="100%" height="100%" fill="white"/>"#);
        let _ = writeln!(
            s,
            r#"<text x="{}" y="20" text-anchor="middle" font-size="15">{}</text>"#,
            width / 2.0,
            escape(&self.title)
        );
        for (k, panel) in self.panels.iter().enumerate() {
            let (ox, oy) = (
                (k % columns) as f64 * PANEL_W,
                30.0 + (k / columns) as f64 * PANEL_H,
            );
            panel.draw(&mut s, ox, oy);
        }
        s.push_str("</svg>\n");
        s
    }
}

impl Panel {
    fn draw(&self, s: &mut String, ox: f64, oy: f64) {
        let (ml, mr, mt, mb) = MARGIN;
        let (x0, y0, w, h) = (ox + ml, oy + mt, PANEL_W - ml - mr, PANEL_H - mt - mb);
        let (xlo, xhi) = bounds(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.0)),
        );
        let (ylo, yhi) = bounds(
            self.series
                .iter()
                .flat_map(|s| s.points.iter().map(|p| p.1)),
        );
        let px = |x: f64| x0 + (x - xlo) / (xhi - xlo) * w;
        let py = |y: f64| y0 + h - (y - ylo) / (yhi - ylo) * h;
        let _ = writeln!(
            s,
            r##"<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="none" stroke="#444"/>"##
        );
        let _ = writeln!(
            s,
            r#"<text x="{}" y="{}" text-anchor="middle" font-size="13">{}</text>"#,
            x0 + w / 2.0,
            oy + 20.0,
            escape(&self.title)
        );
        for t in ticks(xlo, xhi) {
            let _ = writeln!(
                s,
                r##"<line x1="{0}" y1="{1}" x2="{0}" y2="{2}" stroke="#444"/><text x="{0}" y="{3}" text-anchor="middle">{4}</text>"##,
                px(t),
                y0 + h,
                y0 + h + 5.0,
                y0 + h + 18.0,
                fmt_tick(t)
            );
        }
        for t in ticks(ylo, yhi) {
            let _ = writeln!(
                s,
                r##"<line x1="{0}" y1="{1}" x2="{2}" y2="{1}" stroke="#444"/><text x="{3}" y="{4}" text-anchor="end">{5}</text>"##,
                x0 - 5.0,
                py(t),
                x0,
                x0 - 8.0,
                py(t) + 4.0,
                fmt_tick(t)
            );
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
        let mut legend = Vec::new();
        for (k, series) in self.series.iter().enumerate() {
            let colour = COLOURS[k % COLOURS.len()];
            let finite = series
                .points
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
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{:.2}" cy="{:.2}" r="2.5" fill="none" stroke="{colour}"/>"#,
                        px(x),
                        py(y)
                    );
                }
            }
            legend.push((colour, series.label.as_str()));
        }
        // the legend last, on a white box, so that it stays readable over the data
        if !legend.is_empty() {
            let _ = writeln!(
                s,
                r##"<rect x="{}" y="{}" width="190" height="{}" fill="white" fill-opacity="0.85" stroke="#bbb"/>"##,
                x0 + w - 194.0,
                y0 + 4.0,
                16.0 * legend.len() as f64 + 6.0
            );
        }
        for (k, (colour, label)) in legend.into_iter().enumerate() {
            let ly = y0 + 14.0 + 16.0 * k as f64;
            let _ = writeln!(
                s,
                r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{colour}" stroke-width="2"/><text x="{}" y="{}">{}</text>"#,
                x0 + w - 188.0,
                x0 + w - 168.0,
                x0 + w - 162.0,
                ly + 4.0,
                escape(label)
            );
        }
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
