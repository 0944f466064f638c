//! Particle sources and outlets as the plan holds them, with the candidate generator every
//! backend draws the same sequence from.

use crate::rng::Rng;
use crate::shapes::{ParticleShape, SPHERE};
use crate::sizes::DiameterSpec;
use glam::{DQuat, DVec3};
use std::sync::Arc;
use tumble_geom::MeshWall;

/// Default simulated seconds between a volume source's insertions.
pub const DEFAULT_INTERVAL: f64 = 0.01;

/// One kind of particle a source makes: a sphere with a diameter distribution, or a polyhedron.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceKind {
    /// [`SPHERE`] or the index of the polyhedron in the plan's shape table.
    pub shape: u16,
    /// Spheres: the diameter distribution.
    pub diameter: Option<DiameterSpec>,
    /// Spheres with cohesion: the effect diameter (absolute, or as a multiple of d).
    pub effect_diameter: Option<f64>,
    pub effect_ratio: Option<f64>,
    /// Share of the source's particles by number (the kinds' shares add up to 1).
    pub fraction: f64,
}

/// Where a source's particles appear.
#[derive(Clone, Debug, PartialEq)]
pub enum InsertRegion {
    Box {
        min: DVec3,
        max: DVec3,
    },
    Cylinder {
        base: DVec3,
        axis: DVec3,
        radius: f64,
        length: f64,
    },
    /// A rectangle through `point` with normal `normal`, `width` along `u` and `height` along `v`.
    Plane {
        point: DVec3,
        normal: DVec3,
        u: DVec3,
        v: DVec3,
        width: f64,
        height: f64,
    },
    /// The inside of a closed mesh; `inside` is −1 when its normals point outward (a solid
    /// body: the inside is behind them) and +1 when they point inward (a container).
    Mesh {
        mesh: Arc<MeshWall>,
        inside: f64,
    },
}

/// Draws of a point in a mesh region's box before a sample gives up (the share of the box the
/// mesh fills, shrunk by the body's radius, is then below about 1/20 for 95 % of the samples).
pub const MESH_REGION_DRAWS: usize = 64;

impl InsertRegion {
    /// A point where a body of bounding radius `r` lies wholly inside the region (on the
    /// rectangle for a plane), uniform over those points; three draws from `rng` (a mesh: three
    /// per point of its box tried, up to [`MESH_REGION_DRAWS`], and None when none was inside).
    pub fn sample(&self, rng: &mut Rng, r: f64) -> Option<DVec3> {
        if let InsertRegion::Mesh { mesh, inside } = self {
            let (lo, hi) = mesh.bounds();
            let (lo, hi) = (lo + DVec3::splat(r), hi - DVec3::splat(r));
            return (0..MESH_REGION_DRAWS)
                .map(|_| lo + (hi - lo).max(DVec3::ZERO) * DVec3::new(rng.uniform(), rng.uniform(), rng.uniform()))
                .find(|&x| inside * mesh.signed_distance_anywhere(x) >= r);
        }
        let (a, b, c) = (rng.uniform(), rng.uniform(), rng.uniform());
        Some(match *self {
            InsertRegion::Box { min, max } => {
                let lo = min + DVec3::splat(r);
                let hi = max - DVec3::splat(r);
                lo + (hi - lo).max(DVec3::ZERO) * DVec3::new(a, b, c)
            }
            InsertRegion::Cylinder { base, axis, radius, length } => {
                let (u, v) = axis.any_orthonormal_pair();
                let rho = (radius - r).max(0.0) * a.sqrt();
                let phi = std::f64::consts::TAU * b;
                let along = r + (length - 2.0 * r).max(0.0) * c;
                base + axis * along + (u * phi.cos() + v * phi.sin()) * rho
            }
            InsertRegion::Plane { point, u, v, width, height, .. } => {
                let _ = c;
                point + u * ((width - 2.0 * r).max(0.0) * (a - 0.5)) + v * ((height - 2.0 * r).max(0.0) * (b - 0.5))
            }
            InsertRegion::Mesh { .. } => unreachable!("sampled above"),
        })
    }

    /// The region's axis-aligned bounding box.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        match *self {
            InsertRegion::Box { min, max } => (min, max),
            InsertRegion::Cylinder { base, axis, radius, length } => {
                // A disc of radius R across the axis reaches R √(1 − a_k²) along world axis k.
                let reach = (DVec3::ONE - axis * axis).max(DVec3::ZERO).powf(0.5) * radius;
                let (a, b) = (base, base + axis * length);
                (a.min(b) - reach, a.max(b) + reach)
            }
            InsertRegion::Plane { point, u, v, width, height, .. } => {
                let corners = [-0.5, 0.5].map(|a| [-0.5, 0.5].map(|b| point + u * (a * width) + v * (b * height)));
                corners.iter().flatten().fold((point, point), |(lo, hi), c| (lo.min(*c), hi.max(*c)))
            }
            InsertRegion::Mesh { ref mesh, .. } => mesh.bounds(),
        }
    }

    /// The region's volume (a plane's area times nothing: zero).
    pub fn volume(&self) -> f64 {
        match *self {
            InsertRegion::Box { min, max } => (max - min).element_product(),
            InsertRegion::Cylinder { radius, length, .. } => std::f64::consts::PI * radius * radius * length,
            InsertRegion::Plane { .. } => 0.0,
            InsertRegion::Mesh { ref mesh, .. } => mesh.enclosed_volume().abs(),
        }
    }
}

/// How fast a source inserts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Rate {
    ParticlesPerSecond(f64),
    KgPerSecond(f64),
}

/// When a source has inserted enough.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Total {
    Particles(u64),
    Kg(f64),
}

/// A compiled `[[sources]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct Source {
    pub name: String,
    pub material: u16,
    /// The particle group its particles belong to (after the scene's `[[particles]]` groups).
    pub group: u16,
    pub kinds: Vec<SourceKind>,
    pub region: InsertRegion,
    pub velocity: DVec3,
    /// Polyhedra: a fixed orientation, or `None` for uniformly random ones.
    pub orientation: Option<DQuat>,
    pub rate: Option<Rate>,
    pub total: Option<Total>,
    /// First insertion step, steps between insertions, and the last step an insertion may happen.
    pub first_step: u64,
    pub every: u64,
    pub last_step: u64,
    /// Mean mass of one particle (over the kinds and the distributions), kg.
    pub mean_mass: f64,
    /// Seed of the source's own generator (the run's seed and the source's index).
    pub seed: u64,
}

/// A particle a source has drawn, before it is placed: its kind, size and orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Sphere radius, or the polyhedron's bounding radius.
    pub radius: f64,
    pub volume: f64,
    /// [`SPHERE`] or the polyhedron's index in the plan's shape table.
    pub shape: u16,
    pub orientation: DQuat,
    pub effect_radius: f64,
}

impl Source {
    /// The next body of the source's sequence: its kind, size and orientation.
    pub fn draw_body(&self, rng: &mut Rng, shapes: &[ParticleShape]) -> Body {
        let mut u = rng.uniform();
        let kind = self
            .kinds
            .iter()
            .find(|k| {
                let hit = u < k.fraction;
                u -= k.fraction;
                hit
            })
            .unwrap_or(&self.kinds[self.kinds.len() - 1]);
        match kind.shape {
            SPHERE => {
                let d = kind.diameter.as_ref().map_or(0.0, |s| s.sample(rng));
                let effect = kind.effect_diameter.or(kind.effect_ratio.map(|k| k * d)).unwrap_or(d);
                Body {
                    radius: 0.5 * d,
                    volume: std::f64::consts::PI / 6.0 * d * d * d,
                    shape: SPHERE,
                    orientation: DQuat::IDENTITY,
                    effect_radius: 0.5 * effect,
                }
            }
            k => {
                let s = &shapes[k as usize];
                let user = self.orientation.unwrap_or_else(|| rng.rotation());
                let r = s.body.bounding_radius();
                Body { radius: r, volume: s.body.volume(), shape: k, orientation: (user * s.as_given).normalize(), effect_radius: r }
            }
        }
    }

    /// The largest (bounding) radius of the particles the source makes.
    pub fn largest_radius(&self, shapes: &[ParticleShape]) -> f64 {
        self.kinds
            .iter()
            .map(|k| match k.shape {
                SPHERE => 0.5 * k.diameter.as_ref().map_or(0.0, |d| d.max()),
                i => shapes[i as usize].body.bounding_radius(),
            })
            .fold(0.0, f64::max)
    }

    /// Particles the source inserts over the whole run at most (for the GPU's capacity): the
    /// total, or the rate over its active time, with a margin of 4 standard deviations for
    /// sizes drawn at random against a mass target.
    pub fn most_particles(&self, dt: f64) -> u64 {
        let active = (self.last_step.saturating_sub(self.first_step) + self.every) as f64 * dt;
        let by_rate = match self.rate {
            Some(Rate::ParticlesPerSecond(r)) => r * active,
            Some(Rate::KgPerSecond(m)) => m * active / self.mean_mass,
            None => f64::INFINITY,
        };
        let by_total = match self.total {
            Some(Total::Particles(n)) => n as f64,
            Some(Total::Kg(m)) => m / self.mean_mass,
            None => f64::INFINITY,
        };
        let n = by_rate.min(by_total);
        let mass_target = matches!(self.rate, Some(Rate::KgPerSecond(_))) || matches!(self.total, Some(Total::Kg(_)));
        let margin = if mass_target { 4.0 * n.sqrt() + 8.0 } else { 1.0 };
        (n + margin).ceil().min(u32::MAX as f64) as u64
    }
}

/// Particles `sources` may insert over the run at most, with Δt = `dt`.
pub fn inserted_at_most(sources: &[Source], dt: f64) -> u64 {
    sources.iter().map(|s| s.most_particles(dt)).sum()
}

/// A compiled `[[outlets]]` entry: particles whose centre gets inside are deleted.
#[derive(Clone, Debug, PartialEq)]
pub struct Outlet {
    pub name: String,
    pub region: OutletRegion,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum OutletRegion {
    Box {
        min: DVec3,
        max: DVec3,
    },
    /// The half-space the normal points into, beyond the plane.
    Beyond {
        point: DVec3,
        normal: DVec3,
    },
}

impl OutletRegion {
    #[inline]
    pub fn contains(&self, x: DVec3) -> bool {
        match *self {
            OutletRegion::Box { min, max } => x.cmpge(min).all() && x.cmplt(max).all(),
            OutletRegion::Beyond { point, normal } => (x - point).dot(normal) > 0.0,
        }
    }
}

/// Most outlets (the GPU backend's flag word holds an outlet's index + 1 in 8 bits).
pub const MAX_OUTLETS: usize = 255;
