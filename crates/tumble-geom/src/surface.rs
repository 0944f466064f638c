use crate::{Cylinder, DVec3, MeshWall, Plane, PolyContact, Polyhedron, Pose, Prism, Quad};
use glam::DQuat;

/// A sphere touching a world surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceContact {
    /// Unit normal pointing from the surface towards the sphere centre.
    pub normal: DVec3,
    /// Body overlap δ = r − distance (positive in contact).
    pub overlap: f64,
    /// Contact point halfway through the overlap (inside the wall by δ/2), as for two spheres.
    pub point: DVec3,
}

/// A static world surface a sphere can touch.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceShape {
    Plane(Plane),
    Quad(Quad),
    Cylinder(Cylinder),
    /// A convex lifter bar (boxed: six quads make it ten times the size of the others).
    Prism(Box<Prism>),
    /// A triangle mesh, which may touch a sphere at several places (one per smooth surface,
    /// ridge or corner): the wall pass asks it for all of them.
    Mesh(MeshWall),
}

impl SurfaceShape {
    /// Contact of a sphere (centre, radius) with this surface, if they overlap.
    pub fn sphere_contact(&self, centre: DVec3, radius: f64) -> Option<SurfaceContact> {
        self.sphere_proximity(centre, radius, 0.0).filter(|c| c.overlap > 0.0)
    }

    /// Like [`Self::sphere_contact`] but reports surfaces within `reach` of the
    /// sphere's surface too (overlap down to `-reach`); cohesion needs this.
    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        match self {
            SurfaceShape::Plane(p) => p.sphere_proximity(centre, radius, reach),
            SurfaceShape::Quad(q) => q.sphere_proximity(centre, radius, reach),
            SurfaceShape::Cylinder(c) => c.sphere_proximity(centre, radius, reach),
            SurfaceShape::Prism(p) => p.sphere_proximity(centre, radius, reach),
            SurfaceShape::Mesh(m) => m.sphere_proximity(centre, radius, reach),
        }
    }

    /// The shape moved rigidly: rotated by `rotation` about `pivot`, then shifted by `shift`.
    pub fn moved(&self, pivot: DVec3, rotation: DQuat, shift: DVec3) -> SurfaceShape {
        let pt = |p: DVec3| pivot + rotation * (p - pivot) + shift;
        let dir = |d: DVec3| rotation * d;
        let quad = |q: &Quad| Quad { corners: q.corners.map(pt), normal: dir(q.normal), two_sided: q.two_sided };
        match self {
            SurfaceShape::Plane(p) => SurfaceShape::Plane(Plane { point: pt(p.point), normal: dir(p.normal) }),
            SurfaceShape::Quad(q) => SurfaceShape::Quad(quad(q)),
            SurfaceShape::Cylinder(c) => SurfaceShape::Cylinder(Cylinder { point: pt(c.point), axis: dir(c.axis), ..c.clone() }),
            SurfaceShape::Prism(p) => SurfaceShape::Prism(Box::new(Prism {
                faces: p.faces.each_ref().map(quad),
                centre: pt(p.centre),
                bound: p.bound,
                axis_point: pt(p.axis_point),
                axis: dir(p.axis),
                inner: p.inner,
                hull: p.hull.clone(),
                hull_pose: Pose::new(pt(p.hull_pose.position), rotation * p.hull_pose.rotation),
            })),
            SurfaceShape::Mesh(m) => SurfaceShape::Mesh(m.moved(pivot, rotation, shift)),
        }
    }

    /// Contact of a convex polyhedron (at `pose`) with this surface: normal from the surface to
    /// the polyhedron, depth ≥ 0, up to four manifold points (see the per-shape methods).
    pub fn polyhedron_contact(&self, poly: &Polyhedron, pose: &Pose) -> Option<PolyContact> {
        match self {
            SurfaceShape::Plane(p) => p.polyhedron_contact(poly, pose),
            SurfaceShape::Quad(q) => q.polyhedron_contact(poly, pose),
            SurfaceShape::Cylinder(c) => c.polyhedron_contact(poly, pose),
            SurfaceShape::Prism(p) => p.polyhedron_contact(poly, pose),
            // A mesh meets polyhedra in the volume model only (`MeshWall::polyhedron_volumes`).
            SurfaceShape::Mesh(_) => None,
        }
    }

    /// How deep a convex polyhedron (at `pose`) reaches into this surface, if it touches: the
    /// depth model's SAT depth, or for a mesh the deepest of its patch contacts.
    pub fn polyhedron_depth(&self, poly: &Polyhedron, pose: &Pose) -> Option<f64> {
        match self {
            SurfaceShape::Mesh(m) => {
                let mut contacts = Vec::new();
                m.polyhedron_volumes(poly, pose, &mut contacts);
                contacts.iter().map(|c| c.contact.depth).reduce(f64::max)
            }
            _ => self.polyhedron_contact(poly, pose).map(|c| c.depth),
        }
    }
}

/// Builds the contact from the closest surface point and the sphere.
pub(crate) fn contact_from_closest(centre: DVec3, radius: f64, reach: f64, closest: DVec3, fallback_normal: DVec3) -> Option<SurfaceContact> {
    let d = centre - closest;
    let dist = d.length();
    let overlap = radius - dist;
    if overlap <= -reach {
        return None;
    }
    // A centre lying exactly on the surface has no direction of its own.
    let normal = if dist > 1e-12 * radius { d / dist } else { fallback_normal };
    Some(SurfaceContact { normal, overlap, point: closest - normal * (0.5 * overlap.max(0.0)) })
}
