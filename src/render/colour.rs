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

/// 3 × 5 glyphs, one row of three bits per entry (bit 2 is the left column).
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
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        'e' => [7, 4, 7, 4, 7],
        ' ' => [0; 5],
        _ => return None,
    })
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

    /// A vertical colour bar at the right edge with the range's ends labelled beside it.
    pub fn colour_bar(&mut self, range: (f64, f64)) {
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
