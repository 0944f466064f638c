//! Progress reporting for `tumble run`: a redrawn bar on a terminal, plain periodic lines otherwise.

use std::io::Write;
use std::time::Instant;

/// Reports simulated time, steps/s, particle-steps/s and the time remaining.
pub struct Progress {
    terminal: bool,
    start: Instant,
    last: Option<Instant>,
    total_steps: u64,
    duration: f64,
}

impl Progress {
    pub fn new(terminal: bool, total_steps: u64, duration: f64) -> Self {
        Progress { terminal, start: Instant::now(), last: None, total_steps, duration }
    }

    /// Reports if enough wall time has passed since the last report (0.1 s on a terminal, 2 s otherwise).
    pub fn update(&mut self, steps: u64, time: f64, particle_steps: u128) {
        let interval = if self.terminal { 0.1 } else { 2.0 };
        if self.last.is_some_and(|l| l.elapsed().as_secs_f64() < interval) {
            return;
        }
        self.draw(steps, time, particle_steps);
    }

    fn draw(&mut self, steps: u64, time: f64, particle_steps: u128) {
        self.last = Some(Instant::now());
        let wall = self.start.elapsed().as_secs_f64().max(1e-9);
        let fraction = steps as f64 / self.total_steps.max(1) as f64;
        let remaining = if steps > 0 { wall * (1.0 - fraction) / fraction } else { f64::NAN };
        let stats = format!(
            "t = {:.4e} / {:.4e} s, {:.0} steps/s, {:.3e} particle-steps/s, {} left",
            time,
            self.duration,
            steps as f64 / wall,
            particle_steps as f64 / wall,
            clock(remaining)
        );
        let mut err = std::io::stderr().lock();
        if self.terminal {
            let width = 30;
            let filled = ((fraction * width as f64).round() as usize).min(width);
            let _ = write!(err, "\r[{}{}] {:>3.0} % {stats}\x1b[K", "#".repeat(filled), "-".repeat(width - filled), 100.0 * fraction);
        } else {
            let _ = writeln!(err, "progress {:>3.0} %: {stats}", 100.0 * fraction);
        }
        let _ = err.flush();
    }

    /// Draws the final state and ends the bar's line on a terminal.
    pub fn finish(&mut self, steps: u64, time: f64, particle_steps: u128) {
        if self.terminal {
            self.draw(steps, time, particle_steps);
            eprintln!();
        }
    }
}

/// Seconds as `1h02m`, `3m05s` or `42s`.
fn clock(seconds: f64) -> String {
    if !seconds.is_finite() {
        return "--".into();
    }
    let s = seconds.round() as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, (s % 3600) / 60),
    }
}
