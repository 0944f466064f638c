//! A few hand-written SVG helpers for `cargo xtask charts`: a document, text,
//! lines, markers, log/linear axes with decade ticks, and a legend.
//! Plain strings, no fonts beyond the generic `sans-serif` family.

use std::fmt::Write as _;

/// Marker shapes, one per integrator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    Circle,
    Square,
    Triangle,
    Diamond,
    TriangleDown,
    Cross,
}

/// Stroke and marker style of one series.
#[derive(Clone, Copy, Debug)]
pub struct Style {
    pub colour: &'static str,
    pub shape: Shape,
    pub dashed: bool,
}

/// An SVG document under construction.
pub struct Svg {
    body: String,
    width: f64,
    height: f64,
}

/// Escapes text for XML.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Text anchor.
#[derive(Clone, Copy)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn as_str(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

impl Svg {
    pub fn new(width: f64, height: f64) -> Self {
        let mut body = String::new();
        let _ = writeln!(body, r##"<rect x="0" y="0" width="{width}" height="{height}" fill="#ffffff"/>"##);
        Svg { body, width, height }
    }

    /// A chart of `width` × `height` px with `title` centred at its top (16 px bold).
    pub fn titled(width: f64, height: f64, title: &str) -> Self {
        let mut svg = Svg::new(width, height);
        svg.bold(width / 2.0, 28.0, 16.0, Anchor::Middle, title);
        svg
    }

    /// Plain text; `size` in px.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, fill: &str, s: &str) {
        let _ = writeln!(
            self.body,
            r#"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{}" fill="{fill}">{}</text>"#,
            anchor.as_str(),
            escape(s)
        );
    }

    /// Bold text.
    pub fn bold(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, s: &str) {
        let _ = writeln!(
            self.body,
            r##"<text x="{x:.1}" y="{y:.1}" font-size="{size}" font-weight="bold" text-anchor="{}" fill="#222222">{}</text>"##,
            anchor.as_str(),
            escape(s)
        );
    }

    /// Text rotated by −90° about (x, y) (a y-axis label).
    pub fn vertical_text(&mut self, x: f64, y: f64, size: f64, s: &str) {
        let _ = writeln!(
            self.body,
            r##"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="middle" fill="#222222" transform="rotate(-90 {x:.1} {y:.1})">{}</text>"##,
            escape(s)
        );
    }

    /// A power of ten as `10` with a raised exponent.
    fn power_label(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, exponent: i32) {
        let e = if exponent < 0 { format!("\u{2212}{}", -exponent) } else { exponent.to_string() };
        let _ = writeln!(
            self.body,
            r##"<text x="{x:.1}" y="{y:.1}" font-size="{size}" text-anchor="{}" fill="#333333">10<tspan dy="-{:.1}" font-size="{:.1}">{e}</tspan></text>"##,
            anchor.as_str(),
            0.4 * size,
            0.75 * size
        );
    }

    pub fn line(&mut self, (x1, y1): (f64, f64), (x2, y2): (f64, f64), stroke: &str, width: f64, dash: Option<&str>) {
        let dash = dash.map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
        let _ = writeln!(self.body, r#"<line x1="{x1:.1}" y1="{y1:.1}" x2="{x2:.1}" y2="{y2:.1}" stroke="{stroke}" stroke-width="{width}"{dash}/>"#);
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: &str) {
        let _ = writeln!(self.body, r#"<rect x="{x:.1}" y="{y:.1}" width="{w:.1}" height="{h:.1}" fill="{fill}" stroke="{stroke}"/>"#);
    }

    pub fn polyline(&mut self, points: &[(f64, f64)], stroke: &str, width: f64, dash: Option<&str>, opacity: f64) {
        if points.len() < 2 {
            return;
        }
        let mut p = String::new();
        for (x, y) in points {
            let _ = write!(p, "{x:.1},{y:.1} ");
        }
        let dash = dash.map(|d| format!(r#" stroke-dasharray="{d}""#)).unwrap_or_default();
        let _ = writeln!(
            self.body,
            r#"<polyline points="{}" fill="none" stroke="{stroke}" stroke-width="{width}" stroke-opacity="{opacity}" stroke-linejoin="round"{dash}/>"#,
            p.trim_end()
        );
    }

    /// A marker of `size` px (about its width) centred on (x, y); hollow draws the outline only.
    pub fn marker(&mut self, shape: Shape, x: f64, y: f64, size: f64, colour: &str, hollow: bool) {
        let r = 0.5 * size;
        let fill = if hollow { "none".to_string() } else { colour.to_string() };
        let paint = format!(r#"fill="{fill}" stroke="{colour}" stroke-width="1.3""#);
        let poly = |pts: &[(f64, f64)]| pts.iter().map(|(a, b)| format!("{:.1},{:.1}", x + a, y + b)).collect::<Vec<_>>().join(" ");
        let s = match shape {
            Shape::Circle => format!(r#"<circle cx="{x:.1}" cy="{y:.1}" r="{r:.1}" {paint}/>"#),
            Shape::Square => {
                format!(r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}" {paint}/>"#, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r)
            }
            Shape::Triangle => format!(r#"<polygon points="{}" {paint}/>"#, poly(&[(0.0, -1.15 * r), (1.05 * r, 0.8 * r), (-1.05 * r, 0.8 * r)])),
            Shape::TriangleDown => {
                format!(r#"<polygon points="{}" {paint}/>"#, poly(&[(0.0, 1.15 * r), (1.05 * r, -0.8 * r), (-1.05 * r, -0.8 * r)]))
            }
            Shape::Diamond => format!(r#"<polygon points="{}" {paint}/>"#, poly(&[(0.0, -1.2 * r), (1.2 * r, 0.0), (0.0, 1.2 * r), (-1.2 * r, 0.0)])),
            Shape::Cross => format!(
                r#"<path d="M{:.1},{:.1} L{:.1},{:.1} M{:.1},{:.1} L{:.1},{:.1}" stroke="{colour}" stroke-width="2.2" fill="none"/>"#,
                x - r,
                y - r,
                x + r,
                y + r,
                x - r,
                y + r,
                x + r,
                y - r
            ),
        };
        let _ = writeln!(self.body, "{s}");
    }

    /// A legend box at (x, y): one row per entry with a line sample (if `lines`) and marker.
    pub fn legend(&mut self, x: f64, y: f64, entries: &[(Style, String)], lines: bool, size: f64) {
        let row = size + 6.0;
        let width = 34.0 + entries.iter().map(|(_, s)| s.chars().count()).max().unwrap_or(0) as f64 * 0.56 * size;
        self.rect(x, y, width, row * entries.len() as f64 + 6.0, "#ffffff", "#bbbbbb");
        for (k, (style, label)) in entries.iter().enumerate() {
            let cy = y + 3.0 + row * (k as f64 + 0.5);
            if lines {
                self.line((x + 5.0, cy), (x + 27.0, cy), style.colour, 2.0, style.dashed.then_some("5,3"));
            }
            self.marker(style.shape, x + 16.0, cy, 7.0, style.colour, false);
            self.text(x + 32.0, cy + 0.35 * size, size, Anchor::Start, "#222222", label);
        }
    }

    pub fn finish(self) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"sans-serif\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        )
    }
}

/// A logarithmic axis from 10^lo to 10^hi mapped onto pixels p0 → p1.
#[derive(Clone, Copy, Debug)]
pub struct LogAxis {
    pub lo: f64,
    pub hi: f64,
    pub p0: f64,
    pub p1: f64,
}

impl LogAxis {
    /// Whole decades covering the positive values (at least one decade wide).
    pub fn covering(values: impl Iterator<Item = f64>, p0: f64, p1: f64) -> Self {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values.filter(|v| *v > 0.0 && v.is_finite()) {
            lo = lo.min(v.log10());
            hi = hi.max(v.log10());
        }
        if !lo.is_finite() {
            (lo, hi) = (0.0, 1.0);
        }
        let (mut lo, mut hi) = ((lo + 1e-9).floor(), (hi - 1e-9).ceil());
        if hi <= lo {
            hi = lo + 1.0;
        }
        if hi - lo > 17.0 {
            lo = hi - 17.0;
        }
        LogAxis { lo, hi, p0, p1 }
    }

    /// An explicit range [a, b] (not rounded to decades).
    pub fn range(a: f64, b: f64, p0: f64, p1: f64) -> Self {
        LogAxis { lo: a.log10(), hi: b.log10(), p0, p1 }
    }

    pub fn px(&self, v: f64) -> f64 {
        self.p0 + (v.log10() - self.lo) / (self.hi - self.lo) * (self.p1 - self.p0)
    }

    pub fn contains(&self, v: f64) -> bool {
        v > 0.0 && v.log10() >= self.lo - 1e-9 && v.log10() <= self.hi + 1e-9
    }

    /// Tick values: (value, is_decade, labelled).
    fn ticks(&self) -> Vec<(f64, bool, bool)> {
        let span = self.hi - self.lo;
        let step = if span > 9.0 { 2 } else { 1 };
        let mut out = Vec::new();
        for d in (self.lo.floor() as i32)..=(self.hi.ceil() as i32) {
            for m in 1..10 {
                let v = m as f64 * 10f64.powi(d);
                if !self.contains(v) {
                    continue;
                }
                let decade = m == 1;
                let labelled = if decade { d.rem_euclid(step) == 0 } else { span <= 2.5 && (m == 2 || m == 5) };
                if decade || span <= 8.0 {
                    out.push((v, decade, labelled));
                }
            }
        }
        out
    }
}

/// Formats a tick value that is not a power of ten (2, 5, 0.2, 0.05, …).
fn plain(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    s.to_string()
}

fn tick_label(svg: &mut Svg, (x, y): (f64, f64), size: f64, anchor: Anchor, v: f64, decade: bool, span: f64) {
    let e = v.log10().round() as i32;
    // Short ranges read better as plain numbers (0.05, 0.1, 1).
    if !decade || (span <= 2.5 && (-2..=2).contains(&e)) {
        svg.text(x, y, size, anchor, "#333333", &plain(v));
    } else {
        svg.power_label(x, y, size, anchor, e);
    }
}

/// A plot frame with log axes on both sides: grid, ticks, tick labels and axis labels.
pub fn log_log_frame(svg: &mut Svg, x: LogAxis, y: LogAxis, xlabel: &str, ylabel: &str) {
    let (left, right, top, bottom) = (x.p0, x.p1, y.p1, y.p0);
    svg.rect(left, top, right - left, bottom - top, "#fbfbfb", "none");
    for (v, decade, labelled) in x.ticks() {
        let px = x.px(v);
        if decade {
            svg.line((px, top), (px, bottom), "#dddddd", 1.0, None);
        }
        svg.line((px, bottom), (px, bottom + if decade { 6.0 } else { 3.0 }), "#555555", 1.0, None);
        if labelled {
            tick_label(svg, (px, bottom + 19.0), 11.0, Anchor::Middle, v, decade, x.hi - x.lo);
        }
    }
    for (v, decade, labelled) in y.ticks() {
        let py = y.px(v);
        if decade {
            svg.line((left, py), (right, py), "#dddddd", 1.0, None);
        }
        svg.line((left - if decade { 6.0 } else { 3.0 }, py), (left, py), "#555555", 1.0, None);
        if labelled {
            tick_label(svg, (left - 8.0, py + 4.0), 11.0, Anchor::End, v, decade, y.hi - y.lo);
        }
    }
    svg.rect(left, top, right - left, bottom - top, "none", "#555555");
    svg.text(0.5 * (left + right), bottom + 36.0, 12.0, Anchor::Middle, "#222222", xlabel);
    svg.vertical_text(left - 44.0, 0.5 * (top + bottom), 12.0, ylabel);
}

/// The x axis alone (log) under a band from `top` to `bottom`, with vertical grid lines.
pub fn log_x_axis(svg: &mut Svg, x: LogAxis, top: f64, bottom: f64, xlabel: &str) {
    for (v, decade, labelled) in x.ticks() {
        let px = x.px(v);
        svg.line((px, top), (px, bottom), if decade { "#cccccc" } else { "#eeeeee" }, 1.0, None);
        svg.line((px, bottom), (px, bottom + if decade { 6.0 } else { 3.0 }), "#555555", 1.0, None);
        if labelled {
            tick_label(svg, (px, bottom + 19.0), 11.0, Anchor::Middle, v, decade, x.hi - x.lo);
        }
    }
    svg.line((x.p0, bottom), (x.p1, bottom), "#555555", 1.0, None);
    svg.text(0.5 * (x.p0 + x.p1), bottom + 38.0, 13.0, Anchor::Middle, "#222222", xlabel);
}

/// A linear axis from `lo` to `hi` mapped onto pixels p0 → p1, ticked every `step`.
#[derive(Clone, Copy, Debug)]
pub struct LinearAxis {
    pub lo: f64,
    pub hi: f64,
    pub step: f64,
    pub p0: f64,
    pub p1: f64,
}

impl LinearAxis {
    pub fn px(&self, v: f64) -> f64 {
        self.p0 + (v - self.lo) / (self.hi - self.lo) * (self.p1 - self.p0)
    }

    fn ticks(&self) -> Vec<f64> {
        let first = (self.lo / self.step - 1e-9).ceil() as i64;
        let last = (self.hi / self.step + 1e-9).floor() as i64;
        (first..=last).map(|k| k as f64 * self.step).collect()
    }
}

/// The y axis of a frame with a linear x axis.
#[derive(Clone, Copy, Debug)]
pub enum YAxis {
    Linear(LinearAxis),
    Log(LogAxis),
}

impl YAxis {
    fn pixels(&self) -> (f64, f64) {
        match self {
            YAxis::Linear(a) => (a.p0, a.p1),
            YAxis::Log(a) => (a.p0, a.p1),
        }
    }
}

/// A plot frame with a linear x axis and a linear or log y axis.
pub fn linear_frame(svg: &mut Svg, x: LinearAxis, y: YAxis, xlabel: &str, ylabel: &str) {
    let (bottom, top) = y.pixels();
    let (left, right) = (x.p0, x.p1);
    svg.rect(left, top, right - left, bottom - top, "#fbfbfb", "none");
    for v in x.ticks() {
        let px = x.px(v);
        svg.line((px, top), (px, bottom), "#dddddd", 1.0, None);
        svg.line((px, bottom), (px, bottom + 6.0), "#555555", 1.0, None);
        svg.text(px, bottom + 19.0, 11.0, Anchor::Middle, "#333333", &plain(v));
    }
    match y {
        YAxis::Linear(a) => {
            for v in a.ticks() {
                let py = a.px(v);
                svg.line((left, py), (right, py), if v == 0.0 { "#999999" } else { "#dddddd" }, 1.0, None);
                svg.line((left - 6.0, py), (left, py), "#555555", 1.0, None);
                svg.text(left - 8.0, py + 4.0, 11.0, Anchor::End, "#333333", &plain(v));
            }
        }
        YAxis::Log(a) => {
            for (v, decade, labelled) in a.ticks() {
                let py = a.px(v);
                if decade {
                    svg.line((left, py), (right, py), "#dddddd", 1.0, None);
                }
                svg.line((left - if decade { 6.0 } else { 3.0 }, py), (left, py), "#555555", 1.0, None);
                if labelled {
                    tick_label(svg, (left - 8.0, py + 4.0), 11.0, Anchor::End, v, decade, a.hi - a.lo);
                }
            }
        }
    }
    svg.rect(left, top, right - left, bottom - top, "none", "#555555");
    svg.text(0.5 * (left + right), bottom + 36.0, 12.0, Anchor::Middle, "#222222", xlabel);
    svg.vertical_text(left - 48.0, 0.5 * (top + bottom), 12.0, ylabel);
}

/// A colour on a perceptual sequential scale (viridis stops, linear in between), `t` in [0, 1].
pub fn viridis(t: f64) -> String {
    const STOPS: [(f64, f64, f64); 5] = [(68.0, 1.0, 84.0), (59.0, 82.0, 139.0), (33.0, 145.0, 140.0), (94.0, 201.0, 98.0), (253.0, 231.0, 37.0)];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 } * (STOPS.len() - 1) as f64;
    let k = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |x: f64, y: f64| (x + (y - x) * f).round() as u8;
    format!("#{:02x}{:02x}{:02x}", mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A labelled heat map: `values[row][col]` over categorical axes, each cell coloured on the viridis
/// scale between the smallest and largest value and labelled with `label(row, col)` (one or two lines).
#[allow(clippy::too_many_arguments)]
pub fn heat_map(
    title: &str,
    subtitle: &str,
    x_label: &str,
    x_ticks: &[String],
    y_label: &str,
    y_ticks: &[String],
    values: &[Vec<f64>],
    label: impl Fn(usize, usize) -> Vec<String>,
    scale_label: &str,
) -> String {
    let (cols, rows) = (x_ticks.len(), y_ticks.len());
    let (cell_w, cell_h) = (170.0, 90.0);
    let (left, top) = (140.0, 90.0);
    let width = (left + cols as f64 * cell_w + 190.0).max(960.0);
    let height = top + rows as f64 * cell_h + 80.0;
    let mut svg = Svg::new(width, height);
    svg.bold(width / 2.0, 30.0, 18.0, Anchor::Middle, title);
    svg.text(width / 2.0, 52.0, 12.0, Anchor::Middle, "#444444", subtitle);
    let finite = values.iter().flatten().copied().filter(|v| v.is_finite());
    let lo = finite.clone().fold(f64::INFINITY, f64::min);
    let hi = finite.fold(f64::NEG_INFINITY, f64::max);
    let span = if hi > lo { hi - lo } else { 1.0 };
    for (r, row) in values.iter().enumerate() {
        // Row 0 at the bottom, like a y axis.
        let y = top + (rows - 1 - r) as f64 * cell_h;
        for (c, &v) in row.iter().enumerate() {
            let x = left + c as f64 * cell_w;
            let t = (v - lo) / span;
            svg.rect(x, y, cell_w, cell_h, &if v.is_finite() { viridis(t) } else { "#dddddd".into() }, "#ffffff");
            let ink = if t > 0.6 { "#111111" } else { "#ffffff" };
            let lines = label(r, c);
            for (k, s) in lines.iter().enumerate() {
                let (size, dy) = if k == 0 { (18.0, 0.0) } else { (11.0, 20.0 * k as f64) };
                svg.text(x + cell_w / 2.0, y + cell_h / 2.0 + 6.0 - 8.0 * (lines.len() - 1) as f64 + dy, size, Anchor::Middle, ink, s);
            }
        }
        svg.text(left - 10.0, y + cell_h / 2.0 + 5.0, 14.0, Anchor::End, "#222222", &y_ticks[r]);
    }
    for (c, t) in x_ticks.iter().enumerate() {
        svg.text(left + (c as f64 + 0.5) * cell_w, top + rows as f64 * cell_h + 22.0, 14.0, Anchor::Middle, "#222222", t);
    }
    svg.text(left + cols as f64 * cell_w / 2.0, top + rows as f64 * cell_h + 50.0, 15.0, Anchor::Middle, "#222222", x_label);
    svg.vertical_text(left - 95.0, top + rows as f64 * cell_h / 2.0, 15.0, y_label);
    // Colour bar.
    let (bx, bh) = (left + cols as f64 * cell_w + 30.0, rows as f64 * cell_h);
    for k in 0..50 {
        let t = k as f64 / 49.0;
        svg.rect(bx, top + bh * (1.0 - (k + 1) as f64 / 50.0), 22.0, bh / 50.0 + 0.5, &viridis(t), "none");
    }
    svg.text(bx + 28.0, top + 10.0, 12.0, Anchor::Start, "#222222", &format!("{hi:.3}"));
    svg.text(bx + 28.0, top + bh, 12.0, Anchor::Start, "#222222", &format!("{lo:.3}"));
    svg.vertical_text(bx + 100.0, top + bh / 2.0, 12.0, scale_label);
    svg.finish()
}
