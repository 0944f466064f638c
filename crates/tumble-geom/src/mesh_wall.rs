//! A triangle mesh as a wall: the mesh and its triangle grid are built once and shared by every
//! pose, and a moving mesh moves by composing its pose, never by moving its vertices.

use crate::mesh::TriangleMesh;
use crate::mesh_grid::TriangleGrid;
use crate::surface::SurfaceContact;
use crate::{DQuat, DVec3, MeshContact, MeshPatches, PatchContact, Polyhedron, Pose, Region};
use smallvec::SmallVec;
use std::cell::RefCell;
use std::sync::{Arc, OnceLock};

/// A mesh with its triangle grid, in the mesh's own frame (its pose at t = 0 is the identity).
#[derive(Debug)]
pub struct MeshBody {
    pub mesh: TriangleMesh,
    pub grid: TriangleGrid,
    /// Its flat patches, which polyhedra meet one contact each: built at the first polyhedron's
    /// query, so scenes of spheres never pay for them.
    patches: OnceLock<MeshPatches>,
    /// The first of this mesh's spring keys: triangle t of the mesh is `first_key + t`, so the
    /// springs of every mesh of a scene have distinct keys.
    pub first_key: u32,
}

impl MeshBody {
    /// The mesh's flat patches (built once, on first use).
    pub fn patches(&self) -> &MeshPatches {
        self.patches.get_or_init(|| MeshPatches::new(&self.mesh))
    }
}

/// A placed mesh: world = rotation · local + translation.
#[derive(Clone, Debug)]
pub struct MeshWall {
    pub body: Arc<MeshBody>,
    pub rotation: DQuat,
    pub translation: DVec3,
}

impl PartialEq for MeshWall {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.body, &other.body) && self.rotation == other.rotation && self.translation == other.translation
    }
}

/// One contact of a sphere with a placed mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshWallContact {
    /// The triangle whose closest point this is (the mesh's index).
    pub triangle: u32,
    pub region: Region,
    /// Normal, overlap and contact point as for any other surface.
    pub contact: SurfaceContact,
}

thread_local! {
    /// Candidate triangles of the current query (one buffer per thread, so queries allocate nothing).
    static CANDIDATES: RefCell<Vec<u32>> = const { RefCell::new(Vec::new()) };
}

impl MeshWall {
    /// The mesh at its own frame's pose, binned on cells of about `cell`.
    pub fn new(mesh: TriangleMesh, cell: f64, first_key: u32) -> MeshWall {
        let grid = TriangleGrid::new(&mesh, cell);
        MeshWall { body: Arc::new(MeshBody { mesh, grid, patches: OnceLock::new(), first_key }), rotation: DQuat::IDENTITY, translation: DVec3::ZERO }
    }

    fn is_identity(&self) -> bool {
        self.rotation == DQuat::IDENTITY && self.translation == DVec3::ZERO
    }

    /// The contacts of a sphere by the mesh's ownership rule (at most one per smooth surface,
    /// ridge or corner), and in `groups` each triangle within reach with the index of its
    /// group's contact in the result ([`crate::NO_CONTACT`] when its group gave none).
    pub fn sphere_contacts(&self, centre: DVec3, radius: f64, reach: f64, groups: &mut SmallVec<[(u32, u8); 8]>) -> SmallVec<[MeshWallContact; 4]> {
        // A static mesh is queried in world coordinates as given, so its contacts are exact.
        let identity = self.is_identity();
        let local = if identity { centre } else { self.rotation.inverse() * (centre - self.translation) };
        let body = &self.body;
        let found = CANDIDATES.with_borrow_mut(|candidates| {
            body.grid.candidates(local, radius + reach, candidates);
            body.mesh.sphere_contacts_grouped(local, radius, reach, candidates.iter().copied(), groups)
        });
        found
            .iter()
            .map(|c: &MeshContact| {
                let (closest, normal) =
                    if identity { (c.point, c.normal) } else { (self.rotation * c.point + self.translation, self.rotation * c.normal) };
                // Halfway through the overlap, as for every other surface.
                let point = closest - normal * (0.5 * c.overlap.max(0.0));
                MeshWallContact { triangle: c.triangle, region: c.region, contact: SurfaceContact { normal, overlap: c.overlap, point } }
            })
            .collect()
    }

    /// The overlap-volume contacts of a polyhedron at `pose` with the mesh's flat patches, one
    /// per patch it overlaps, in patch order.
    pub fn polyhedron_volumes(&self, poly: &Polyhedron, pose: &Pose, out: &mut Vec<PatchContact>) {
        out.clear();
        let identity = self.is_identity();
        let local = if identity {
            *pose
        } else {
            Pose::new(self.rotation.inverse() * (pose.position - self.translation), self.rotation.inverse() * pose.rotation)
        };
        let body = &self.body;
        CANDIDATES.with_borrow_mut(|candidates| {
            body.grid.candidates(local.position, 2.0 * poly.bounding_radius(), candidates);
            body.patches().polyhedron_volumes(&body.mesh, poly, &local, candidates, out);
        });
        if !identity {
            for c in out.iter_mut() {
                c.contact.move_rigidly(self.rotation, self.translation);
            }
        }
    }

    /// The deepest of the sphere's contacts within `reach` (start checks, placement, candidates).
    pub fn sphere_proximity(&self, centre: DVec3, radius: f64, reach: f64) -> Option<SurfaceContact> {
        let contacts = self.sphere_contacts(centre, radius, reach, &mut SmallVec::new());
        contacts.iter().map(|c| c.contact).reduce(|a, b| if b.overlap > a.overlap { b } else { a })
    }

    /// The mesh moved rigidly: rotated by `rotation` about `pivot`, then shifted by `shift`.
    pub fn moved(&self, pivot: DVec3, rotation: DQuat, shift: DVec3) -> MeshWall {
        MeshWall {
            body: self.body.clone(),
            rotation: (rotation * self.rotation).normalize(),
            translation: pivot + rotation * (self.translation - pivot) + shift,
        }
    }

    /// A mesh point in the world.
    pub fn to_world(&self, local: DVec3) -> DVec3 {
        if self.is_identity() { local } else { self.rotation * local + self.translation }
    }

    /// Triangle `t`'s corners in the world.
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.body.mesh.corners(t).map(|c| self.to_world(c))
    }

    /// True when triangles `a` and `b` share a corner.
    pub fn share_a_corner(&self, a: u32, b: u32) -> bool {
        let tri = &self.body.mesh.triangles;
        tri[a as usize].iter().any(|v| tri[b as usize].contains(v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{DEFAULT_CURVATURE, box_triangles_subdivided};

    #[test]
    fn a_moved_mesh_meets_a_sphere_as_the_mesh_with_moved_vertices_does() {
        let (v, t) = box_triangles_subdivided(DVec3::new(-0.2, -0.1, 0.0), DVec3::new(0.3, 0.2, 0.4), 3);
        let mesh = TriangleMesh::new(&v, &t, DEFAULT_CURVATURE).unwrap().0;
        let wall = MeshWall::new(mesh.clone(), 0.05, 0);
        let (pivot, rotation, shift) =
            (DVec3::new(0.1, 0.0, 0.2), DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 2.0).normalize(), 0.7), DVec3::new(0.0, 0.3, -0.1));
        // Twice: composing two moves is one move.
        let moved = wall.moved(pivot, rotation, shift).moved(DVec3::ZERO, rotation.inverse(), DVec3::X);
        let map = |x: DVec3| rotation.inverse() * (pivot + rotation * (x - pivot) + shift) + DVec3::X;
        let direct = MeshWall::new(mesh.transformed(map, false), 0.05, 0);
        let mut s = 5u64;
        let mut u = move || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut touching = 0;
        for _ in 0..400 {
            let local = DVec3::new(u() * 0.8 - 0.35, u() * 0.6 - 0.25, u() * 0.7 - 0.15);
            let x = map(local);
            let (a, b) = (moved.sphere_contacts(x, 0.06, 0.0, &mut SmallVec::new()), direct.sphere_contacts(x, 0.06, 0.0, &mut SmallVec::new()));
            assert_eq!(a.len(), b.len(), "at {x}");
            for (p, q) in a.iter().zip(&b) {
                assert_eq!(p.triangle, q.triangle);
                assert!((p.contact.normal - q.contact.normal).length() < 1e-12);
                assert!((p.contact.point - q.contact.point).length() < 1e-12);
                assert!((p.contact.overlap - q.contact.overlap).abs() < 1e-12);
            }
            touching += !a.is_empty() as usize;
        }
        assert!(touching > 50, "{touching}");
    }
}
