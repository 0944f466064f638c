//! Collision-energy spectra of a mill run, the input of breakage models: how many ball–ball and
//! ball–liner impacts per second carry each energy. An impact is a contact that exists at a step and
//! did not at the step before; its energy is the normal kinetic energy of the approach at that
//! step, ½ m* v_n² (m* = m_a m_b / (m_a + m_b) for two balls, the ball's mass against a wall, v_n
//! relative to the wall's surface velocity). Taken from the state every step, so any backend serves.

use crate::svg::{LogAxis, Shape, Style, Svg, log_log_frame};
use std::collections::HashSet;
use std::fmt::Write as _;
use tumble::Simulation;

/// Bins: 5 per decade from 1e-7 J to 1e2 J.
const E_MIN: f64 = 1e-7;
const BINS_PER_DECADE: usize = 5;
const BINS: usize = 9 * BINS_PER_DECADE;

/// Contacts present at a step: ball pairs by id, and (ball id, wall index).
type PairSet = HashSet<(u32, u32)>;
type WallSet = HashSet<(u32, usize)>;

/// Impacts counted by energy bin over a measuring window.
#[derive(Clone, Debug)]
pub(crate) struct ImpactSpectrum {
    pub ball_ball: [u64; BINS],
    pub ball_liner: [u64; BINS],
    /// Σ ½ m* v_n² of the impacts, J.
    pub ball_ball_energy: f64,
    pub ball_liner_energy: f64,
    /// Length of the window, s.
    pub seconds: f64,
}

fn bin(e: f64) -> Option<usize> {
    (e >= E_MIN).then(|| (((e / E_MIN).log10() * BINS_PER_DECADE as f64).floor() as usize).min(BINS - 1))
}

fn lower_edge(k: usize) -> f64 {
    E_MIN * 10f64.powf(k as f64 / BINS_PER_DECADE as f64)
}

/// Runs `sim` to its end one step at a time, counting the impacts from `from` on; every wall turns
/// at `omega` (rad/s, about the z axis through the origin), as the lab mill's do.
pub(crate) fn impact_spectrum(sim: &mut Simulation, from: f64, omega: f64) -> ImpactSpectrum {
    let mut s = ImpactSpectrum { ball_ball: [0; BINS], ball_liner: [0; BINS], ball_ball_energy: 0.0, ball_liner_energy: 0.0, seconds: 0.0 };
    let (mut pairs, mut walls): (PairSet, WallSet) = Default::default();
    let t0 = from.max(sim.time());
    while sim.steps() < sim.plan().run.steps {
        sim.advance(1);
        let counting = sim.time() > t0;
        let state = sim.state();
        let world = sim.walls();
        let (mut now_pairs, mut now_walls): (PairSet, WallSet) = Default::default();
        for i in 0..state.len() {
            let (pi, ri) = (state.pos[i], state.radius[i]);
            for j in i + 1..state.len() {
                let d = state.pos[j] - pi;
                let reach = ri + state.radius[j];
                if d.length_squared() >= reach * reach {
                    continue;
                }
                let key = (state.id[i].min(state.id[j]), state.id[i].max(state.id[j]));
                if counting && !pairs.contains(&key) {
                    let vn = (state.vel[j] - state.vel[i]).dot(d.normalize_or_zero());
                    let m = state.mass[i] * state.mass[j] / (state.mass[i] + state.mass[j]);
                    let e = 0.5 * m * vn * vn;
                    s.ball_ball_energy += e;
                    if let Some(k) = bin(e) {
                        s.ball_ball[k] += 1;
                    }
                }
                now_pairs.insert(key);
            }
            for (w, wall) in world.iter().enumerate() {
                let Some(c) = wall.shape.sphere_contact(pi, ri) else { continue };
                let key = (state.id[i], w);
                if counting && !walls.contains(&key) {
                    let surface = if wall.motion.is_some() {
                        tumble_geom::DVec3::new(-omega * c.point.y, omega * c.point.x, 0.0)
                    } else {
                        tumble_geom::DVec3::ZERO
                    };
                    let vn = (state.vel[i] - surface).dot(c.normal);
                    let e = 0.5 * state.mass[i] * vn * vn;
                    s.ball_liner_energy += e;
                    if let Some(k) = bin(e) {
                        s.ball_liner[k] += 1;
                    }
                }
                now_walls.insert(key);
            }
        }
        drop(state);
        drop(world);
        (pairs, walls) = (now_pairs, now_walls);
    }
    s.seconds = sim.time() - t0;
    s
}

impl ImpactSpectrum {
    /// CSV rows: label, kind, bin edges, impacts per second in the bin and at or above its lower edge.
    pub(crate) fn csv_rows(&self, label: &str, out: &mut String) {
        for (kind, counts) in [("ball-ball", &self.ball_ball), ("ball-liner", &self.ball_liner)] {
            let mut above: u64 = counts.iter().sum();
            for (k, &n) in counts.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "{label},{kind},{:.4e},{:.4e},{:.4e},{:.4e}",
                    lower_edge(k),
                    lower_edge(k + 1),
                    n as f64 / self.seconds,
                    above as f64 / self.seconds
                );
                above -= n;
            }
        }
    }

    /// Impacts per second and impact power (W) of each kind.
    pub(crate) fn rates(&self) -> [f64; 4] {
        let n = |c: &[u64; BINS]| c.iter().sum::<u64>() as f64 / self.seconds;
        [n(&self.ball_ball), self.ball_ball_energy / self.seconds, n(&self.ball_liner), self.ball_liner_energy / self.seconds]
    }
}

/// Cumulative spectra (impacts per second at or above E against E), one curve per point and kind.
pub(crate) fn spectra_chart(spectra: &[(String, ImpactSpectrum)]) -> String {
    let mut doc = Svg::titled(1200.0, 600.0, "Laboratory mill: collision-energy spectra (impacts per second with ½ m* v_n² ≥ E)");
    let colours = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"];
    let shapes = [Shape::Circle, Shape::Square, Shape::Triangle, Shape::Diamond, Shape::TriangleDown, Shape::Cross];
    for (panel, kind) in ["ball-ball", "ball-liner"].iter().enumerate() {
        let left = 90.0 + 600.0 * panel as f64;
        let x = LogAxis::range(E_MIN, 1e2, left, left + 460.0);
        let y = LogAxis::range(1e-1, 1e5, 470.0, 60.0);
        log_log_frame(&mut doc, x, y, &format!("{kind} impact energy E, J"), "impacts per second with energy ≥ E");
        for (k, (_, s)) in spectra.iter().enumerate() {
            let counts = if panel == 0 { &s.ball_ball } else { &s.ball_liner };
            let mut above: u64 = counts.iter().sum();
            let mut pts = Vec::new();
            for (b, &n) in counts.iter().enumerate() {
                let rate = above as f64 / s.seconds;
                if rate > 0.0 && y.contains(rate) {
                    pts.push((x.px(lower_edge(b)), y.px(rate)));
                }
                above -= n;
            }
            doc.polyline(&pts, colours[k % colours.len()], 1.5, None, 1.0);
            if let Some(&(a, b)) = pts.first() {
                doc.marker(shapes[k % shapes.len()], a, b, 7.0, colours[k % colours.len()], false);
            }
        }
    }
    let entries: Vec<(Style, String)> = spectra
        .iter()
        .enumerate()
        .map(|(k, (label, _))| (Style { colour: colours[k % colours.len()], shape: shapes[k % shapes.len()], dashed: false }, label.clone()))
        .collect();
    doc.legend(100.0, 520.0, &entries, true, 11.0);
    doc.finish()
}
