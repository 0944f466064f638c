//! `tumble render DIR`: pictures of a run's snapshots (docs/cli.md, "Pictures"). The snapshots
//! (`particles.pvd`, `bodies.pvd`, `walls.vtp` or `walls.pvd`) are read back ([`vtp`]), framed
//! by one orthographic camera for the whole series ([`camera`]), coloured by a field through
//! viridis ([`colour`]), drawn on the GPU ([`gpu`]) and written as PNG frames and one APNG
//! animation ([`frames`]).

pub mod camera;
pub mod colour;
mod frames;
pub mod gpu;
mod series;
pub mod vtp;

pub use camera::{Camera, View};
pub use frames::write_png;
pub use gpu::{Line, Picture, Renderer, Sphere, Triangle};
pub use series::{Series, Snapshot};

use glam::DVec3;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `tumble render` draws and how.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    pub view: View,
    /// The world axis drawn vertical: 0, 1, 2 for x, y, z.
    pub up_axis: usize,
    /// The point array the particles are coloured by (`speed`: |velocity|; vectors by their magnitude).
    pub field: String,
    pub width: u32,
    pub height: u32,
    /// Every this many snapshots (1: all).
    pub every: usize,
    /// The colour range; None: the field's range over the frames drawn.
    pub range: Option<(f64, f64)>,
    pub legend: bool,
    /// Frames per second of the animation; 0: no animation.
    pub fps: u16,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { view: View::Front, up_axis: 2, field: "speed".into(), width: 640, height: 480, every: 1, range: None, legend: true, fps: 10 }
    }
}

/// What a render wrote and how long it took.
#[derive(Clone, Debug)]
pub struct RenderReport {
    pub frames: Vec<PathBuf>,
    pub animation: Option<PathBuf>,
    pub range: (f64, f64),
    /// Seconds drawing and reading back, per frame (without reading files and encoding PNG).
    pub draw_seconds_per_frame: f64,
    pub total_seconds: f64,
}

/// Renders the run in `dir` into `dir/render/`.
pub fn render_run(dir: &Path, options: &RenderOptions) -> Result<RenderReport, String> {
    let start = Instant::now();
    if options.every == 0 {
        return Err("--every must be at least 1".into());
    }
    let series = Series::open(dir)?;
    let drawn: Vec<usize> = (0..series.len()).step_by(options.every).collect();
    // First pass, one snapshot in memory at a time: the field's range and the framed box.
    let (mut field, mut lo, mut hi) = ((f64::INFINITY, f64::NEG_INFINITY), DVec3::INFINITY, DVec3::NEG_INFINITY);
    let mut wall_boxes = Vec::new();
    for &k in &drawn {
        let s = series.load(k)?;
        s.check_field(&options.field)?;
        let (a, b) = s.field_range(&options.field);
        field = (field.0.min(a), field.1.max(b));
        let (a, b) = s.particle_bounds();
        (lo, hi) = (lo.min(a), hi.max(b));
        if k == 0 || series.walls_move() {
            wall_boxes.extend(s.wall_boxes());
        }
    }
    let range = options.range.unwrap_or(if field.0.is_finite() { field } else { (0.0, 1.0) });
    let scale = if lo.is_finite() { (hi - lo).length() } else { f64::INFINITY };
    for &(a, b) in wall_boxes.iter().filter(|&&w| series::bounded(w, scale)) {
        (lo, hi) = (lo.min(a), hi.max(b));
    }
    if !lo.is_finite() {
        return Err(format!("{}: the snapshots hold no particles and no walls", dir.display()));
    }
    // The colour bar keeps a strip at the right edge: the scene is framed in what is left.
    let strip = if options.legend { colour::bar_strip(options.width as usize, options.height as usize) as f64 } else { 0.0 };
    let drawn_width = (options.width as f64 - strip).max(1.0);
    let mut camera = Camera::framing(options.view, options.up_axis, lo, hi, drawn_width / options.height as f64);
    let widened = camera.half_width * options.width as f64 / drawn_width;
    camera.centre += camera.right * (widened - camera.half_width);
    camera.half_width = widened;
    let renderer = Renderer::new(options.width, options.height)?;
    let out = dir.join("render");
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut writer = frames::FrameWriter::new(&out, options.width, options.height, if options.fps > 0 { drawn.len() } else { 0 }, options.fps)?;
    let mut draw_seconds = 0.0;
    for &k in &drawn {
        let s = series.load(k)?;
        let picture = s.picture(&options.field, range, scale);
        let t = Instant::now();
        let mut rgba = renderer.draw(&picture, &camera);
        draw_seconds += t.elapsed().as_secs_f64();
        if options.legend {
            let mut image = colour::Image { rgba: &mut rgba, width: options.width as usize, height: options.height as usize };
            image.colour_bar(range, &colour::title(&options.field));
            image.corner_text(&colour::time_stamp(s.time));
        }
        writer.frame(s.index, &rgba)?;
    }
    let (frames, animation) = writer.finish()?;
    Ok(RenderReport {
        frames,
        animation,
        range,
        draw_seconds_per_frame: draw_seconds / drawn.len().max(1) as f64,
        total_seconds: start.elapsed().as_secs_f64(),
    })
}

impl RenderReport {
    /// The line `tumble render` prints.
    pub fn describe(&self, out: &Path) -> String {
        format!(
            "{} frames in {:.2} s ({:.1} ms drawing each), colour range {} to {}; images in {}{}\n",
            self.frames.len(),
            self.total_seconds,
            1e3 * self.draw_seconds_per_frame,
            colour::label(self.range.0),
            colour::label(self.range.1),
            out.display(),
            if self.animation.is_some() { ", animation.png" } else { "" }
        )
    }
}

/// The options of `tumble render`'s arguments; errors name the argument and what is valid.
#[allow(clippy::too_many_arguments)]
pub fn options_from_args(
    view: &str,
    up: &str,
    field: String,
    range: Option<&str>,
    size: &str,
    every: usize,
    fps: u16,
    legend: bool,
) -> Result<RenderOptions, String> {
    let (width, height) = size
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)))
        .filter(|&(w, h)| w > 0 && h > 0)
        .ok_or_else(|| format!("--size {size}: expected WxH in pixels, e.g. 640x480"))?;
    let range = match range {
        None => None,
        Some(r) => Some(
            r.split_once(',')
                .and_then(|(lo, hi)| Some((lo.trim().parse::<f64>().ok()?, hi.trim().parse::<f64>().ok()?)))
                .filter(|(lo, hi)| lo.is_finite() && hi.is_finite() && hi > lo)
                .ok_or_else(|| format!("--range {r}: expected LO,HI with LO < HI, e.g. 0,0.5"))?,
        ),
    };
    if every == 0 {
        return Err("--every 0: draw every K-th snapshot, K at least 1".into());
    }
    Ok(RenderOptions { view: View::parse(view)?, up_axis: camera::parse_axis(up)?, field, width, height, every, range, legend, fps })
}
