//! Particle sources at run time: at each source's insertion steps, draws bodies from the
//! source's own generator, places each where it overlaps no particle and no wall, and hands
//! the accepted ones to the backend.
//!
//! The candidate sequence (kind, size, orientation, then positions) depends only on the
//! scene's seed, so every backend draws the same one; which candidates fit depends on the
//! particles already there. The feeder's books (generator states, counts, a drawn body not
//! yet placed) travel in the run's checkpoints, so a resumed run inserts what an
//! uninterrupted one would.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use tumble_scene::{Body, InitialParticles, Plan, Rate, Rng, Source, Total};
use tumble_state::{Backend, State};

/// Positions tried for one drawn body before the event ends (the region is crowded then; the
/// body is placed first at the next event, so crowding never skews the size distribution).
pub const POSITION_TRIES: usize = 100;

/// A body drawn and not yet placed, in plain numbers (for the books).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
struct PendingBody {
    radius: f64,
    volume: f64,
    shape: u16,
    /// Quaternion x, y, z, w.
    orientation: [f64; 4],
    effect_radius: f64,
}

impl From<Body> for PendingBody {
    fn from(b: Body) -> Self {
        PendingBody { radius: b.radius, volume: b.volume, shape: b.shape, orientation: b.orientation.to_array(), effect_radius: b.effect_radius }
    }
}

impl From<PendingBody> for Body {
    fn from(b: PendingBody) -> Self {
        Body { radius: b.radius, volume: b.volume, shape: b.shape, orientation: DQuat::from_array(b.orientation), effect_radius: b.effect_radius }
    }
}

/// One source's books.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SourceBooks {
    rng: u64,
    /// Insertion events done.
    events: u64,
    /// Particles inserted and their mass.
    pub inserted: u64,
    pub mass: f64,
    /// Their kinetic and potential energy at insertion (½ m v² − m g·x, as the observables
    /// count it), J: the instability monitor books it as a source.
    pub energy: f64,
    /// Bodies drawn that did not fit at their event (placed later).
    pub deferred: u64,
    pending: Option<PendingBody>,
    /// The total is reached.
    done: bool,
}

/// Every source's books and the next particle id.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FeederBooks {
    pub sources: Vec<SourceBooks>,
    next_id: u32,
}

/// Per source of `books` (none without sources): particles inserted so far and their mass.
pub fn inserted(books: Option<&FeederBooks>) -> Vec<(u64, f64)> {
    books.map_or_else(Vec::new, |b| b.sources.iter().map(|s| (s.inserted, s.mass)).collect())
}

/// Kinetic and potential energy the sources of `books` have brought in so far, J.
pub fn inserted_energy(books: Option<&FeederBooks>) -> f64 {
    books.map_or(0.0, |b| b.sources.iter().map(|s| s.energy).sum())
}

/// The sources of a plan at run time.
pub struct Feeder {
    books: FeederBooks,
}

impl Feeder {
    /// The feeder of the backend's sources, ids continuing after its particles'; None without
    /// sources (and then no state is read: a device's read-back).
    pub fn new(backend: &dyn Backend) -> Option<Feeder> {
        let plan = backend.plan();
        if plan.model.sources.is_empty() {
            return None;
        }
        let next_id = backend.state().next_id();
        let sources = plan
            .model
            .sources
            .iter()
            .map(|s| SourceBooks {
                rng: Rng::new(s.seed).state(),
                events: 0,
                inserted: 0,
                mass: 0.0,
                energy: 0.0,
                deferred: 0,
                pending: None,
                done: false,
            })
            .collect();
        Some(Feeder { books: FeederBooks { sources, next_id } })
    }

    pub fn books(&self) -> &FeederBooks {
        &self.books
    }

    /// Continues from books a checkpoint kept.
    pub fn set_books(&mut self, books: FeederBooks) {
        self.books = books;
    }

    /// The step of the next insertion event of any source, if one is left.
    pub fn next_step(&self, plan: &Plan) -> Option<u64> {
        plan.model.sources.iter().zip(&self.books.sources).filter_map(|(s, b)| event_step(s, b)).min()
    }

    /// Runs every insertion event due at the backend's current step.
    pub fn feed(&mut self, backend: &mut dyn Backend) -> Result<(), String> {
        let new = {
            let plan = backend.plan();
            let step = backend.steps();
            let due: Vec<usize> =
                (0..plan.model.sources.len()).filter(|&k| event_step(&plan.model.sources[k], &self.books.sources[k]) == Some(step)).collect();
            if due.is_empty() {
                return Ok(());
            }
            let mut space = Space::new(plan, &backend.state(), backend.time());
            let mut new = InitialParticles::default();
            for k in due {
                let source = &plan.model.sources[k];
                let books = &mut self.books.sources[k];
                place(plan, source, books, &mut space, &mut new);
                books.events += 1;
            }
            if new.is_empty() {
                return Ok(());
            }
            State::from_particles(plan, &new, self.books.next_id)
        };
        self.books.next_id += new.len() as u32;
        backend.insert(new)
    }
}

/// The step of `source`'s next event, if it has one.
fn event_step(source: &Source, books: &SourceBooks) -> Option<u64> {
    let step = source.first_step + books.events * source.every;
    (!books.done && step <= source.last_step).then_some(step)
}

/// How many particles, or how much mass, the source should have inserted once this event is done.
fn target(source: &Source, books: &SourceBooks, dt: f64) -> (u64, f64) {
    let covered = (books.events + 1) as f64 * source.every as f64 * dt;
    let (mut count, mut mass) = (u64::MAX, f64::INFINITY);
    match source.rate {
        Some(Rate::ParticlesPerSecond(r)) => count = (r * covered + 1e-9).floor() as u64,
        Some(Rate::KgPerSecond(r)) => mass = r * covered,
        None => {}
    }
    match source.total {
        Some(Total::Particles(n)) => count = count.min(n),
        Some(Total::Kg(m)) => mass = mass.min(m),
        None => {}
    }
    (count, mass)
}

/// One event of one source: bodies placed until the target is met or the region is crowded.
fn place(plan: &Plan, source: &Source, books: &mut SourceBooks, space: &mut Space, new: &mut InitialParticles) {
    let (count, mass) = target(source, books, plan.model.dt);
    let density = plan.model.materials[source.material as usize].density;
    let mut rng = Rng::from_state(books.rng);
    while books.inserted < count && books.mass < mass {
        let body: Body = match books.pending.take() {
            Some(p) => p.into(),
            None => source.draw_body(&mut rng, &plan.model.shapes),
        };
        let spot = (0..POSITION_TRIES).filter_map(|_| source.region.sample(&mut rng, body.radius)).find(|&x| space.fits(x, body.radius));
        let Some(x) = spot else {
            books.pending = Some(body.into());
            books.deferred += 1;
            break;
        };
        space.add(x, body.radius);
        new.push_body(x, source.velocity, &body, source.material, source.group);
        let m = density * body.volume;
        books.inserted += 1;
        books.mass += m;
        books.energy += 0.5 * m * source.velocity.length_squared() - m * plan.model.gravity.dot(x);
    }
    let total_met = match source.total {
        Some(Total::Particles(n)) => books.inserted >= n,
        Some(Total::Kg(m)) => books.mass >= m,
        None => false,
    };
    books.done = total_met;
    books.rng = rng.state();
}

/// The particles and walls a candidate must clear, on a hash grid of bounding spheres.
struct Space {
    walls: Vec<tumble_geom::SurfaceShape>,
    domain: tumble_geom::PeriodicBox,
    cell: f64,
    /// Cells per periodic axis (0 on other axes: unbounded).
    wrap: [i64; 3],
    grid: HashMap<[i64; 3], Vec<(DVec3, f64)>>,
    /// Clearance beyond contact: f32 rounding of positions on a device (relative to the
    /// domain's centre) must not turn a near miss into an overlap.
    clearance: f64,
}

impl Space {
    fn new(plan: &Plan, state: &State, t: f64) -> Space {
        let largest_source = plan.model.sources.iter().map(|s| s.largest_radius(&plan.model.shapes));
        let largest = state.radius.iter().copied().chain(largest_source).fold(0.0, f64::max);
        let domain = plan.model.domain;
        let cell = (2.0 * largest).max(1e-12);
        let extent = domain.extent();
        let wrap = [0, 1, 2].map(|k| if domain.periodic[k] { ((extent[k] / cell).floor() as i64).max(1) } else { 0 });
        let mut space = Space {
            walls: plan.model.walls.iter().map(|w| w.shape_at(t)).collect(),
            domain,
            cell,
            wrap,
            grid: HashMap::new(),
            clearance: 4.0 * f32::EPSILON as f64 * 0.5 * extent.max_element(),
        };
        for i in 0..state.len() {
            space.add(state.pos[i], state.radius[i]);
        }
        space
    }

    fn key(&self, x: DVec3) -> [i64; 3] {
        let k = ((x - self.domain.min) / self.cell).floor();
        [0, 1, 2].map(|a| if self.wrap[a] > 0 { (k[a] as i64).rem_euclid(self.wrap[a]) } else { k[a] as i64 })
    }

    fn add(&mut self, x: DVec3, r: f64) {
        let key = self.key(x);
        self.grid.entry(key).or_default().push((x, r));
    }

    /// True when a sphere of radius `r` at `x` (a polyhedron's bounding sphere) clears every
    /// particle and wall by the clearance, inside the domain.
    fn fits(&self, x: DVec3, r: f64) -> bool {
        if !self.domain.contains(x) {
            return false;
        }
        if self.walls.iter().any(|w| w.sphere_contact(x, r + self.clearance).is_some()) {
            return false;
        }
        let c = self.key(x);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    // Saturating: a domain of 1e300 m puts every key at the i64 limit.
                    let mut key = [c[0].saturating_add(dx), c[1].saturating_add(dy), c[2].saturating_add(dz)];
                    for a in 0..3 {
                        if self.wrap[a] > 0 {
                            key[a] = key[a].rem_euclid(self.wrap[a]);
                        }
                    }
                    let Some(list) = self.grid.get(&key) else { continue };
                    for &(y, ry) in list {
                        let d = self.domain.minimum_image(x - y).length();
                        if d < r + ry + self.clearance {
                            return false;
                        }
                    }
                }
            }
        }
        true
    }
}

/// The first source that tried to insert and never found room, in words.
pub fn idle_source(sim: &crate::Simulation) -> Option<String> {
    let books = sim.feeder_books()?;
    sim.plan().model.sources.iter().zip(&books.sources).find(|(_, b)| b.inserted == 0 && b.deferred > 0).map(|(s, b)| {
        format!(
            "source \"{}\" inserted no particle: at each of its {} insertions none of {POSITION_TRIES} places drawn in its region was clear of the walls, the other particles and the domain's sides",
            s.name, b.deferred
        )
    })
}

/// A warning per source that inserted nothing, or ended behind its schedule: a drawn particle
/// still found no free place.
pub fn shortfall_warnings(sim: &crate::Simulation) -> Vec<String> {
    let Some(books) = sim.feeder_books() else { return Vec::new() };
    let plan = sim.plan();
    let mut warnings = Vec::new();
    for (s, b) in plan.model.sources.iter().zip(&books.sources) {
        if b.inserted == 0 && b.deferred > 0 {
            // Not one place of the region was free: a region behind a wall or outside the domain,
            // not a rate too high for its size.
            warnings.push(format!(
                "source \"{}\" inserted no particle: at each of its {} insertions none of {POSITION_TRIES} places drawn in its region was clear of the walls, the other particles and the domain's sides; check that its region lies inside the walls and the domain",
                s.name, b.deferred
            ));
        } else if b.inserted == 0 {
            warnings.push(format!(
                "source \"{}\" inserted no particle: its first insertion, at t = {:.6e} s, was not reached before the run ended",
                s.name,
                s.first_step as f64 * plan.model.dt
            ));
        } else if b.pending.is_some() {
            warnings.push(format!(
                "source \"{}\" fell behind its rate: {} times a drawn particle found no free place in the region and waited for the next insertion ({} particles, {:.6e} kg inserted); a larger region or a lower rate inserts on time",
                s.name, b.deferred, b.inserted, b.mass
            ));
        }
    }
    warnings
}
