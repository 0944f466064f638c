//! The colour map (viridis, van der Walt and Smith 2015: perceptually uniform, readable in grey
//! and by colour-blind readers) and the colour bar drawn into a finished image.

/// Viridis at t = 0, 1/8, …, 1 (matplotlib's values, 8-bit sRGB); between them linear in sRGB.
const VIRIDIS: [[u8; 3]; 9] =
    [[68, 1, 84], [71, 45, 123], [59, 82, 139], [44, 114, 142], [33, 145, 140], [40, 174, 128], [94, 201, 98], [173, 220, 48], [253, 231, 37]];

/// The colour of `t` ∈ [0, 1] (clamped; NaN is the low end), components in [0, 1] (sRGB-encoded).
pub fn viridis(t: f64) -> [f32; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    [0, 1, 2].map(|c| ((a[c] as f64 * (1.0 - f) + b[c] as f64 * f) / 255.0) as f32)
}

/// Where a value falls in the colour range `[lo, hi]` (0.5 for an empty range).
pub fn unit(value: f64, (lo, hi): (f64, f64)) -> f64 {
    if hi > lo { (value - lo) / (hi - lo) } else { 0.5 }
}

/// 3 × 5 glyphs, one row of three bits per entry (bit 2 is the left column): digits, the
/// lowercase letters, the capitals SI units use, and the signs of numbers, units and labels.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        'a' => [0, 6, 1, 5, 3],
        'b' => [4, 6, 5, 5, 6],
        'c' => [0, 3, 4, 4, 3],
        'd' => [1, 3, 5, 5, 3],
        'e' => [0, 2, 7, 4, 3],
        'f' => [1, 2, 7, 2, 2],
        'g' => [0, 3, 5, 3, 6],
        'h' => [4, 6, 5, 5, 5],
        'i' => [2, 0, 2, 2, 2],
        'j' => [1, 0, 1, 5, 2],
        'k' => [4, 5, 6, 5, 5],
        'l' => [6, 2, 2, 2, 7],
        'm' => [0, 6, 7, 5, 5],
        'n' => [0, 6, 5, 5, 5],
        'o' => [0, 2, 5, 5, 2],
        'p' => [0, 6, 5, 6, 4],
        'q' => [0, 3, 5, 3, 1],
        'r' => [0, 3, 4, 4, 4],
        's' => [0, 3, 6, 1, 6],
        't' => [2, 7, 2, 2, 1],
        'u' => [0, 5, 5, 5, 3],
        'v' => [0, 5, 5, 5, 2],
        'w' => [0, 5, 5, 7, 5],
        'x' => [0, 5, 2, 2, 5],
        'y' => [0, 5, 5, 3, 6],
        'z' => [0, 7, 1, 4, 7],
        'J' => [1, 1, 1, 5, 2],
        'N' => [5, 7, 7, 5, 5],
        'P' => [6, 5, 6, 4, 4],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        '=' => [0, 7, 0, 7, 0],
        '/' => [1, 1, 2, 4, 4],
        '_' => [0, 0, 0, 0, 7],
        '(' => [1, 2, 2, 2, 1],
        ')' => [4, 2, 2, 2, 4],
        ',' => [0, 0, 0, 2, 4],
        ':' => [0, 2, 0, 2, 0],
        ' ' => [0; 5],
        _ => return None,
    })
}

/// The unit of a snapshot field tumble writes (empty for counts, codes and unknown fields).
pub fn unit_of(field: &str) -> &'static str {
    let base = ["_x", "_y", "_z"].iter().find_map(|axis| field.strip_suffix(axis)).unwrap_or(field);
    match base {
        "speed" | "velocity" => "m/s",
        "angular_velocity" => "rad/s",
        "pressure" | "shear_stress" => "Pa",
        "density" => "kg/m3",
        "radius" | "diameter" => "m",
        "mass" => "kg",
        "force" | "normal_force" | "shear_force" => "N",
        "energy" | "kinetic_energy" => "J",
        _ => "",
    }
}

/// The colour bar's title: the field and its unit, `speed (m/s)`; letters without a glyph
/// (capitals beyond the units') are drawn in lowercase.
pub fn title(field: &str) -> String {
    let unit = unit_of(field);
    let field: String = field.chars().map(|c| if glyph(c).is_some() { c } else { c.to_ascii_lowercase() }).collect();
    if unit.is_empty() { field } else { format!("{field} ({unit})") }
}

/// A frame's time stamp, `t = 0.25 s`.
pub fn time_stamp(t: f64) -> String {
    format!("t = {} s", label(t))
}

/// A label for a colour-bar end: three significant figures, exponent form outside [0.01, 10⁴).
pub fn label(v: f64) -> String {
    if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        let decimals = if v == 0.0 { 0 } else { (2 - v.abs().log10().floor() as i32).max(0) as usize };
        let s = format!("{v:.decimals$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s }
    } else {
        format!("{v:.2e}")
    }
}

/// Pixels the colour bar and its labels take at the right edge of a `width` × `height` image.
pub fn bar_strip(width: usize, height: usize) -> usize {
    let scale = (height / 240).max(1);
    // Bar and margins, and a label of up to seven glyphs.
    (14 * scale + 2 * scale + 7 * 4 * scale + 4 * scale).min(width / 3)
}

/// An RGBA image, rows top to bottom.
pub struct Image<'a> {
    pub rgba: &'a mut [u8],
    pub width: usize,
    pub height: usize,
}

impl Image<'_> {
    fn put(&mut self, x: usize, y: usize, c: [u8; 3]) {
        if x < self.width && y < self.height {
            let at = 4 * (y * self.width + x);
            self.rgba[at..at + 3].copy_from_slice(&c);
            self.rgba[at + 3] = 255;
        }
    }

    /// `text` with its right end at `right`, its top at `top`, each glyph pixel `scale` wide.
    fn text(&mut self, text: &str, right: usize, top: usize, scale: usize, c: [u8; 3]) {
        let advance = 4 * scale;
        let left = right.saturating_sub(advance * text.chars().count());
        for (k, ch) in text.chars().enumerate() {
            let Some(rows) = glyph(ch) else { continue };
            for (r, bits) in rows.iter().enumerate() {
                for col in 0..3 {
                    if bits & (4 >> col) != 0 {
                        for dy in 0..scale {
                            for dx in 0..scale {
                                self.put(left + k * advance + col * scale + dx, top + r * scale + dy, c);
                            }
                        }
                    }
                }
            }
        }
    }

    /// A vertical colour bar at the right edge with the range's ends labelled beside it and its
    /// `title` (the field and its unit) above it.
    pub fn colour_bar(&mut self, range: (f64, f64), title: &str) {
        let scale = (self.height / 240).max(1);
        let (bar_w, margin) = (6 * scale, 8 * scale);
        let (top, bottom) = (self.height / 5, self.height - self.height / 5);
        let right = self.width.saturating_sub(margin);
        let left = right.saturating_sub(bar_w);
        let ink = [40, 40, 40];
        for y in top.saturating_sub(1)..=bottom {
            for x in left.saturating_sub(1)..=right {
                self.put(x, y, ink);
            }
        }
        for y in top..bottom {
            let t = (bottom - 1 - y) as f64 / (bottom - top - 1).max(1) as f64;
            let c = viridis(t).map(|v| (v * 255.0).round() as u8);
            for x in left..right {
                self.put(x, y, c);
            }
        }
        let text_right = left.saturating_sub(2 * scale);
        self.text(&label(range.1), text_right, top, scale, ink);
        self.text(&label(range.0), text_right, bottom.saturating_sub(5 * scale), scale, ink);
        // The title ends at the bar's right edge, above it (it may reach into the picture).
        self.text(title, right, top.saturating_sub(9 * scale), scale, ink);
    }

    /// `text` at the top left corner (a frame's time stamp).
    pub fn corner_text(&mut self, text: &str) {
        let scale = (self.height / 240).max(1);
        let right = 4 * scale + 4 * scale * text.chars().count();
        self.text(text, right, 4 * scale, scale, [40, 40, 40]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_runs_from_dark_purple_to_yellow_through_its_table() {
        assert_eq!(viridis(0.0), [68.0 / 255.0, 1.0 / 255.0, 84.0 / 255.0]);
        assert_eq!(viridis(1.0), [253.0 / 255.0, 231.0 / 255.0, 37.0 / 255.0]);
        assert_eq!(viridis(0.5), [33.0 / 255.0, 145.0 / 255.0, 140.0 / 255.0]);
        assert_eq!(viridis(-3.0), viridis(0.0));
        // Halfway between the first two entries.
        let mid = viridis(1.0 / 16.0);
        assert!((mid[1] * 255.0 - 23.0).abs() < 1e-4, "{mid:?}");
        // Lightness (here the green channel) rises monotonically.
        let g: Vec<f32> = (0..=64).map(|k| viridis(k as f64 / 64.0)[1]).collect();
        assert!(g.windows(2).all(|w| w[1] > w[0]));
    }

    /// Every field tumble's snapshots hold gets its unit, and every character of its title and
    /// of a time stamp has a glyph (none is silently skipped).
    #[test]
    fn titles_name_the_field_and_its_unit_in_drawable_characters() {
        assert_eq!(title("speed"), "speed (m/s)");
        assert_eq!(title("pressure"), "pressure (Pa)");
        assert_eq!(title("velocity_z"), "velocity_z (m/s)");
        assert_eq!(title("angular_velocity"), "angular_velocity (rad/s)");
        assert_eq!(title("density"), "density (kg/m3)");
        assert_eq!(title("kind"), "kind");
        assert_eq!(time_stamp(0.25), "t = 0.25 s");
        for field in ["speed", "pressure", "density", "radius", "mass", "angular_velocity", "material", "group", "id", "kind", "Shear_Force"] {
            let t = title(field);
            assert!(t.chars().all(|c| glyph(c).is_some()), "{t}");
        }
        assert!(time_stamp(1.5e-4).chars().all(|c| glyph(c).is_some()));
    }

    #[test]
    fn labels_have_three_significant_figures() {
        assert_eq!(label(0.0), "0");
        assert_eq!(label(1.23456), "1.23");
        assert_eq!(label(0.5), "0.5");
        assert_eq!(label(250.0), "250");
        assert_eq!(label(-0.0123), "-0.0123");
        assert_eq!(label(1.5e-4), "1.50e-4");
        assert!(label(123456.0).chars().all(|c| glyph(c).is_some()));
    }
}
