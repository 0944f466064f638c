//! The fluid phase's particles as a structure of arrays, and the lattices that create them.

use tumble_geom::{Cylinder, DVec3};

use crate::kernel::Dimension;

/// What a particle is: a moving fluid particle or a dummy particle of a wall.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum ParticleKind {
    Fluid,
    /// A wall's dummy particle (Adami, Hu & Adams 2012): moves with its wall; its pressure is
    /// extrapolated from the fluid around it at every evaluation.
    Wall,
}

/// The particles of the fluid phase, fluid and walls together, in cell order after each step.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FluidParticles {
    /// The identity of each particle, stable across the re-sorting by cell.
    pub id: Vec<u32>,
    pub kind: Vec<ParticleKind>,
    pub position: Vec<DVec3>,
    /// A fluid particle's velocity; a wall particle's prescribed wall velocity.
    pub velocity: Vec<DVec3>,
    /// A fluid particle's density (evolved); a wall particle's last extrapolated density.
    pub density: Vec<f64>,
    pub mass: Vec<f64>,
    /// The moving wall or floating body a wall particle belongs to: k + 1 for
    /// `FluidSettings::moving_walls[k]`, then the floating bodies
    /// ([`FluidSettings::body_wall_number`](crate::FluidSettings::body_wall_number)); 0 for a
    /// fluid particle or a wall moving at its constant velocity.
    #[serde(default)]
    pub wall: Vec<u16>,
}

impl FluidParticles {
    pub fn len(&self) -> usize {
        self.position.len()
    }

    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    pub fn push(&mut self, kind: ParticleKind, position: DVec3, velocity: DVec3, density: f64, mass: f64) {
        self.id.push(self.position.len() as u32);
        self.kind.push(kind);
        self.position.push(position);
        self.velocity.push(velocity);
        self.density.push(density);
        self.mass.push(mass);
        self.wall.push(0);
    }

    /// Appends a particle with the given id (a buffer's new particle; ids stay unique).
    pub(crate) fn push_with_id(&mut self, id: u32, kind: ParticleKind, position: DVec3, velocity: DVec3, density: f64, mass: f64) {
        self.push(kind, position, velocity, density, mass);
        *self.id.last_mut().expect("just pushed") = id;
    }

    /// Removes the particles `remove` picks (called once per particle, in order), keeping the
    /// others' order and ids.
    pub(crate) fn remove_where(&mut self, mut remove: impl FnMut(usize) -> bool) {
        let kept: Vec<usize> = (0..self.len()).filter(|&i| !remove(i)).collect();
        fn pick<T: Copy>(v: &[T], kept: &[usize]) -> Vec<T> {
            kept.iter().map(|&i| v[i]).collect()
        }
        self.id = pick(&self.id, &kept);
        self.kind = pick(&self.kind, &kept);
        self.position = pick(&self.position, &kept);
        self.velocity = pick(&self.velocity, &kept);
        self.density = pick(&self.density, &kept);
        self.mass = pick(&self.mass, &kept);
        self.wall = pick(&self.wall, &kept);
    }

    /// Makes the particles from index `from` on part of moving wall `wall` (k + 1 for
    /// `FluidSettings::moving_walls[k]`).
    pub fn assign_moving_wall(&mut self, from: usize, wall: u16) {
        for w in &mut self.wall[from..] {
            *w = wall;
        }
    }

    pub fn fluid_count(&self) -> usize {
        self.kind.iter().filter(|&&k| k == ParticleKind::Fluid).count()
    }

    /// Keeps the particles `keep` accepts, in their order, numbered again from 0.
    pub fn retain(&mut self, keep: impl Fn(ParticleKind, DVec3) -> bool) {
        let kept: Vec<usize> = (0..self.len()).filter(|&i| keep(self.kind[i], self.position[i])).collect();
        self.kind = kept.iter().map(|&i| self.kind[i]).collect();
        self.position = kept.iter().map(|&i| self.position[i]).collect();
        self.velocity = kept.iter().map(|&i| self.velocity[i]).collect();
        self.density = kept.iter().map(|&i| self.density[i]).collect();
        self.mass = kept.iter().map(|&i| self.mass[i]).collect();
        self.wall = kept.iter().map(|&i| self.wall[i]).collect();
        self.id = (0..kept.len() as u32).collect();
    }
}

/// An axis-aligned box, closed or half-open as a lattice needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: DVec3,
    pub max: DVec3,
}

impl Aabb {
    pub fn new(min: DVec3, max: DVec3) -> Self {
        Aabb { min, max }
    }

    pub fn contains(&self, x: DVec3) -> bool {
        x.cmpge(self.min).all() && x.cmplt(self.max).all()
    }
}

/// Cell centres of the lattice of spacing `dp` anchored at `anchor` that fall in `region`
/// (x, then y, then z fastest-last). In 2D the lattice is the x–z plane at y = 0.
pub fn lattice_points(region: Aabb, anchor: DVec3, dp: f64, dimension: Dimension) -> Vec<DVec3> {
    let index_range = |k: usize| {
        let lo = ((region.min[k] - anchor[k]) / dp - 0.5).ceil() as i64;
        let hi = ((region.max[k] - anchor[k]) / dp - 0.5).ceil() as i64; // exclusive
        lo..hi
    };
    let ys: Vec<f64> = match dimension {
        Dimension::Two => vec![0.0],
        Dimension::Three => index_range(1).map(|j| anchor.y + (j as f64 + 0.5) * dp).collect(),
    };
    let mut out = Vec::new();
    for k in index_range(2) {
        let z = anchor.z + (k as f64 + 0.5) * dp;
        for &y in &ys {
            for i in index_range(0) {
                let x = anchor.x + (i as f64 + 0.5) * dp;
                out.push(DVec3::new(x, y, z));
            }
        }
    }
    out
}

/// Which sides of a box are solid walls: `[axis][0]` the low side, `[axis][1]` the high side.
pub type ClosedSides = [[bool; 2]; 3];

/// Dummy particles filling `layers` lattice layers outside the closed sides of `inner` (corners
/// and edges included, so a fluid particle near a corner sees a full wall), on the lattice of
/// spacing `dp` anchored at `inner.min`. Sides left open (or periodic) get no particles, and the
/// shell does not extend past them.
pub fn wall_shell(inner: Aabb, closed: ClosedSides, layers: usize, dp: f64, dimension: Dimension) -> Vec<DVec3> {
    let thickness = layers as f64 * dp;
    let mut outer = inner;
    for k in 0..3 {
        if dimension == Dimension::Two && k == 1 {
            continue;
        }
        if closed[k][0] {
            outer.min[k] -= thickness;
        }
        if closed[k][1] {
            outer.max[k] += thickness;
        }
    }
    // Points of the outer box whose lattice centre lies outside the inner box on some axis.
    let outside = |x: DVec3| (0..3).any(|k| !(dimension == Dimension::Two && k == 1) && (x[k] < inner.min[k] || x[k] >= inner.max[k]));
    lattice_points(outer, inner.min, dp, dimension).into_iter().filter(|&x| outside(x)).collect()
}

/// A rectangle's frame for wall layers: its first corner, its two edges from it (corners 1 and 3),
/// and the unit normal e₁ × e₂ / |e₁ × e₂| the fluid lies along.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rectangle {
    pub origin: DVec3,
    pub edges: [DVec3; 2],
    pub normal: DVec3,
}

impl Rectangle {
    /// The rectangle with corners `corners` in order; `None` unless they make one (right angles
    /// to 1e-9, in one plane).
    pub fn new(corners: [DVec3; 4]) -> Option<Self> {
        let (e1, e2) = (corners[1] - corners[0], corners[3] - corners[0]);
        let (l1, l2) = (e1.length(), e2.length());
        let closes = (corners[0] + e1 + e2 - corners[2]).length() <= 1e-9 * (l1 + l2);
        if !(l1 > 0.0 && l2 > 0.0 && closes && e1.dot(e2).abs() <= 1e-9 * l1 * l2) {
            return None;
        }
        Some(Rectangle { origin: corners[0], edges: [e1, e2], normal: e1.cross(e2) / (l1 * l2) })
    }

    /// Whether `x` lies within the rectangle's outline (seen along its normal) and less than
    /// `depth` in front of it, or anywhere behind it.
    pub fn covers(&self, x: DVec3, depth: f64) -> bool {
        let d = x - self.origin;
        let within = self.edges.iter().all(|e| (0.0..=e.length_squared()).contains(&d.dot(*e)));
        within && d.dot(self.normal) < depth
    }
}

/// Dummy particles in `layers` lattice layers Δp apart behind a rectangle (against its normal),
/// Δp apart along each edge (rounded to a whole number of particles). In 2D one edge must lie
/// along y: the layers are lines in the x–z plane at y = 0.
pub fn rectangle_layers(r: &Rectangle, layers: usize, dp: f64, dimension: Dimension) -> Vec<DVec3> {
    let count = |e: DVec3| (e.length() / dp).round().max(1.0) as usize;
    let (origin, along): (DVec3, Vec<(DVec3, usize)>) = match dimension {
        Dimension::Three => (r.origin, r.edges.iter().map(|&e| (e, count(e))).collect()),
        Dimension::Two => {
            // The edge that lies in the plane; the other (along y) does not enter.
            let e = if r.edges[0].y.abs() < r.edges[1].y.abs() { r.edges[0] } else { r.edges[1] };
            (DVec3::new(r.origin.x, 0.0, r.origin.z), vec![(DVec3::new(e.x, 0.0, e.z), count(e))])
        }
    };
    let mut out = Vec::new();
    for k in 0..layers {
        let back = origin - (k as f64 + 0.5) * dp * r.normal;
        match along.as_slice() {
            [(e, n)] => out.extend((0..*n).map(|i| back + (i as f64 + 0.5) / *n as f64 * *e)),
            [(e1, n1), (e2, n2)] => {
                for j in 0..*n2 {
                    out.extend((0..*n1).map(|i| back + (i as f64 + 0.5) / *n1 as f64 * *e1 + (j as f64 + 0.5) / *n2 as f64 * *e2));
                }
            }
            _ => unreachable!(),
        }
    }
    out
}

/// Dummy particles in `layers` rings behind a cylinder's surface (outside it for a drum, inside
/// for a pipe), the rings Δp apart radially and along the axis, each ring's particles Δp apart
/// (rounded to a whole number around it). In 2D the axis must be y: the rings are circles in
/// the x–z plane through y = 0, and the length does not enter.
pub fn cylinder_shell(c: &Cylinder, layers: usize, dp: f64, dimension: Dimension) -> Vec<DVec3> {
    let axis = c.axis.normalize();
    let (e1, e2, centre, stations) = match dimension {
        Dimension::Two => (DVec3::X, DVec3::Z, DVec3::new(c.point.x, 0.0, c.point.z), vec![0.0]),
        Dimension::Three => {
            let (e1, e2) = axis.any_orthonormal_pair();
            let n = (c.length / dp).round().max(1.0) as usize;
            (e1, e2, c.point, (0..n).map(|m| (m as f64 + 0.5) * c.length / n as f64).collect())
        }
    };
    let mut out = Vec::new();
    for k in 0..layers {
        let offset = (k as f64 + 0.5) * dp;
        let r = if c.inside { c.radius + offset } else { c.radius - offset };
        if r <= 0.0 {
            break;
        }
        let n = (std::f64::consts::TAU * r / dp).round().max(3.0) as usize;
        for &s in &stations {
            for j in 0..n {
                let (sin, cos) = (std::f64::consts::TAU * j as f64 / n as f64).sin_cos();
                out.push(centre + s * axis + r * (cos * e1 + sin * e2));
            }
        }
    }
    out
}

/// Points filling the inside of a cylinder in rings Δp apart, the outermost Δp/2 inside its
/// surface, each ring's points Δp apart (rounded to a whole number around it), and along the axis
/// at Δp (3D; in 2D the axis must be y and the rings are circles in the x–z plane at y = 0);
/// each point with the volume (in 2D, area) it stands for: its share of its ring's annulus, the
/// innermost ring's reaching to the axis. A remainder narrower than Δp/2 at the axis is one point there. The fill follows a drum's wall,
/// so water filled this way meets the drum's rings without the gaps a lattice cut to the circle leaves.
pub fn cylinder_fill(c: &Cylinder, dp: f64, dimension: Dimension) -> Vec<(DVec3, f64)> {
    let axis = c.axis.normalize();
    let (e1, e2, centre, stations, slice) = match dimension {
        Dimension::Two => (DVec3::X, DVec3::Z, DVec3::new(c.point.x, 0.0, c.point.z), vec![0.0], 1.0),
        Dimension::Three => {
            let (e1, e2) = axis.any_orthonormal_pair();
            let n = (c.length / dp).round().max(1.0) as usize;
            (e1, e2, c.point, (0..n).map(|m| (m as f64 + 0.5) * c.length / n as f64).collect(), c.length / n as f64)
        }
    };
    let mut out = Vec::new();
    let mut r = c.radius - 0.5 * dp;
    while r > 0.0 {
        // The innermost ring (or point) also stands for what lies between it and the axis.
        let disc = std::f64::consts::PI * (r + 0.5 * dp).powi(2);
        let (around, volume) = if r < 0.5 * dp {
            (1, disc * slice)
        } else {
            let n = (std::f64::consts::TAU * r / dp).round().max(3.0) as usize;
            let area = if r - dp <= 0.0 { disc } else { std::f64::consts::TAU * r * dp };
            (n, area / n as f64 * slice)
        };
        for &s in &stations {
            for j in 0..around {
                let offset = if around == 1 {
                    DVec3::ZERO
                } else {
                    let (sin, cos) = (std::f64::consts::TAU * j as f64 / around as f64).sin_cos();
                    r * (cos * e1 + sin * e2)
                };
                out.push((centre + s * axis + offset, volume));
            }
        }
        r -= dp;
    }
    out
}

/// Whether `x` lies on a cylinder's fluid side, at least `dp / 2` from its surface: inside a
/// drum, outside a pipe, or beyond its ends (in 2D, where it has none, on its side only).
pub fn on_fluid_side(c: &Cylinder, x: DVec3, dp: f64, dimension: Dimension) -> bool {
    let axis = c.axis.normalize();
    let d = x - c.point;
    let s = d.dot(axis);
    let two_d = dimension == Dimension::Two;
    if !two_d && !(0.0..=c.length).contains(&s) {
        return true;
    }
    let radial = if two_d { DVec3::new(d.x, 0.0, d.z) } else { d - s * axis };
    let r = radial.length();
    let slack = 1e-9 * dp;
    if c.inside { r <= c.radius - 0.5 * dp + slack } else { r >= c.radius + 0.5 * dp - slack }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lattice_counts_and_shell_thickness() {
        let dp = 0.1;
        let inner = Aabb::new(DVec3::ZERO, DVec3::new(1.0, 0.0, 2.0));
        let fluid = lattice_points(inner, DVec3::ZERO, dp, Dimension::Two);
        assert_eq!(fluid.len(), 10 * 20);
        assert!((fluid[0] - DVec3::new(0.05, 0.0, 0.05)).length() < 1e-12);
        // A tank open at the top: three layers under and beside, corners filled.
        let closed = [[true, true], [false, false], [true, false]];
        let walls = wall_shell(inner, closed, 3, dp, Dimension::Two);
        assert_eq!(walls.len(), 16 * 23 - 10 * 20);
        assert!(walls.iter().all(|x| x.x < 0.0 || x.x > 1.0 || x.z < 0.0));
        let lowest = walls.iter().map(|x| x.z).fold(f64::INFINITY, f64::min);
        assert!((lowest + 0.25).abs() < 1e-12);
    }

    /// A drum's rings lie Δp/2, 3Δp/2, … outside its radius with neighbours about Δp apart
    /// around each; a pipe's inside it; the fluid's side keeps Δp/2 clear of the surface.
    #[test]
    fn cylinder_rings_and_the_fluid_side() {
        let (dp, r) = (0.01, 0.1);
        let drum = Cylinder::new(DVec3::new(0.0, 0.0, 0.0), DVec3::Y, r, 0.05, true);
        let rings = cylinder_shell(&drum, 3, dp, Dimension::Two);
        let radius = |x: &DVec3| x.x.hypot(x.z);
        for k in 0..3 {
            let ring: Vec<&DVec3> = rings.iter().filter(|x| (radius(x) - (r + (k as f64 + 0.5) * dp)).abs() < 1e-12).collect();
            let n = (std::f64::consts::TAU * (r + (k as f64 + 0.5) * dp) / dp).round() as usize;
            assert_eq!(ring.len(), n, "ring {k}");
            assert!(ring.iter().all(|x| x.y == 0.0));
        }
        assert_eq!(rings.len(), [0.5, 1.5, 2.5].iter().map(|k| (std::f64::consts::TAU * (r + k * dp) / dp).round() as usize).sum::<usize>());
        // 3D: five stations along the 0.05 m axis, each with the same rings.
        assert_eq!(cylinder_shell(&drum, 3, dp, Dimension::Three).len(), 5 * rings.len());
        let pipe = Cylinder { inside: false, ..drum };
        assert!(cylinder_shell(&pipe, 3, dp, Dimension::Two).iter().all(|x| radius(x) < r));
        for (x, inside_drum) in [(0.093, true), (0.0951, false), (0.2, false)] {
            assert_eq!(on_fluid_side(&drum, DVec3::new(x, 0.0, 0.0), dp, Dimension::Two), inside_drum, "drum at {x}");
            assert_eq!(on_fluid_side(&pipe, DVec3::new(x + 0.011, 0.0, 0.0), dp, Dimension::Two), x + 0.011 >= 0.105, "pipe at {x}");
        }
        // Beyond a 3D cylinder's ends every point is on the fluid's side.
        assert!(on_fluid_side(&drum, DVec3::new(0.2, 0.06, 0.0), dp, Dimension::Three));
        assert!(!on_fluid_side(&drum, DVec3::new(0.2, 0.04, 0.0), dp, Dimension::Three));
    }

    /// The rings that fill a cylinder stand for its whole area (2D) or volume (3D), whether or
    /// not its radius is a whole number of spacings, and no two points are closer than 0.8 Δp.
    #[test]
    fn a_cylinder_fill_covers_the_cylinder_once() {
        let dp = 0.005;
        for radius in [0.1, 0.1013, 0.0987] {
            let disc = Cylinder::new(DVec3::new(0.3, 0.0, 0.2), DVec3::Y, radius, 1.0, true);
            let points = cylinder_fill(&disc, dp, Dimension::Two);
            let area: f64 = points.iter().map(|p| p.1).sum();
            let exact = std::f64::consts::PI * radius * radius;
            assert!((area / exact - 1.0).abs() < 1e-12, "R = {radius}: the fill stands for {area}, the disc is {exact}");
            for (i, a) in points.iter().enumerate() {
                assert!((a.0 - disc.point).length() < radius, "a point outside the drum");
                for b in &points[i + 1..] {
                    assert!((a.0 - b.0).length() > 0.8 * dp, "R = {radius}: points {} and {} are {} apart", a.0, b.0, (a.0 - b.0).length());
                }
            }
        }
        let can = Cylinder::new(DVec3::ZERO, DVec3::new(1.0, 1.0, 0.0), 0.03, 0.04, true);
        let volume: f64 = cylinder_fill(&can, dp, Dimension::Three).iter().map(|p| p.1).sum();
        let exact = std::f64::consts::PI * 0.03 * 0.03 * 0.04;
        assert!((volume / exact - 1.0).abs() < 1e-12, "3D: {volume} against {exact}");
    }
}
