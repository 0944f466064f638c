//! Signed distance to a placed mesh: how far a point is from the surface and on which side, for
//! filling the space behind a wall or inside a closed body with particles (the SPH fluid's dummy
//! wall particles and its regions).
//!
//! The side comes from the angle-weighted pseudo-normal of the closest feature (Bærentzen &
//! Aanæs, "Signed distance computation using the angle weighted pseudonormal", IEEE TVCG 11(3),
//! 2005): a face's own normal, the sum of the two normals at an edge, and at a corner the normals
//! of the triangles meeting there, each weighted by its angle at the corner. For a closed,
//! consistently oriented mesh the sign is then right everywhere, also at ridges, valleys and
//! corners, where the single closest triangle's normal can point the wrong way.

use crate::mesh_wall::MeshWall;
use crate::{DVec3, Region, closest_point_on_triangle};
use smallvec::SmallVec;

impl MeshWall {
    /// Distance from `x` to the mesh, positive on the side its normals point to and negative
    /// behind it; `None` when no triangle comes within `reach`.
    pub fn signed_distance(&self, x: DVec3, reach: f64) -> Option<f64> {
        let local = self.rotation.inverse() * (x - self.translation);
        let body = &self.body;
        let mesh = &body.mesh;
        let mut candidates = Vec::new();
        body.grid.candidates(local, reach, &mut candidates);
        let mut found: SmallVec<[(u32, DVec3, Region, f64); 8]> = SmallVec::new();
        let mut nearest = f64::INFINITY;
        for &t in &candidates {
            let (point, region) = closest_point_on_triangle(local, mesh.corners(t as usize));
            let d = (local - point).length();
            if d <= reach {
                nearest = nearest.min(d);
                found.push((t, point, region, d));
            }
        }
        if found.is_empty() {
            return None;
        }
        // Triangles sharing the closest point (an edge's two, a corner's fan) report it within
        // round-off of each other. A point as far from two separate places (midway between a
        // slab's faces) takes the first: either gives the side.
        let tie = 1e-9 * (nearest + reach);
        let point = found.iter().find(|f| f.3 <= nearest).expect("the nearest was found").1;
        let mut pseudo_normal = DVec3::ZERO;
        for &(t, p, region, d) in &found {
            if d > nearest + tie || (p - point).length() > tie {
                continue;
            }
            let weight = match region {
                Region::Vertex(k) => corner_angle(mesh.corners(t as usize), k as usize),
                Region::Edge(_) | Region::Face => 1.0,
            };
            pseudo_normal += mesh.normals[t as usize] * weight;
        }
        let side = (local - point).dot(pseudo_normal);
        Some(if side < 0.0 { -nearest } else { nearest })
    }

    /// Distance from `x` to the mesh, signed as [`MeshWall::signed_distance`], however far the
    /// mesh is: the search widens until it finds a triangle.
    pub fn signed_distance_anywhere(&self, x: DVec3) -> f64 {
        let (lo, hi) = self.body.grid.bounds();
        let local = self.rotation.inverse() * (x - self.translation);
        // Every triangle lies within this reach of the point.
        let farthest = (local - lo).abs().max((local - hi).abs()).length();
        let mut reach = self.body.grid.layout().1;
        loop {
            if let Some(d) = self.signed_distance(x, reach.min(farthest)) {
                return d;
            }
            if reach >= farthest {
                return f64::INFINITY;
            }
            reach *= 4.0;
        }
    }

    /// The volume the mesh encloses, positive when its normals point outward (a solid body) and
    /// negative when they point inward (a container): Σ a · (b × c) / 6 over its triangles.
    pub fn enclosed_volume(&self) -> f64 {
        let mesh = &self.body.mesh;
        (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// The world box holding the mesh.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        let mesh = &self.body.mesh;
        mesh.vertices.iter().map(|&v| self.to_world(v)).fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)))
    }
}

/// The angle of triangle `corners` at corner `k`.
fn corner_angle(corners: [DVec3; 3], k: usize) -> f64 {
    let a = corners[k];
    let (u, v) = (corners[(k + 1) % 3] - a, corners[(k + 2) % 3] - a);
    u.angle_between(v)
}

#[cfg(test)]
mod tests {
    use crate::{DQuat, DVec3, MeshWall, TriangleMesh, box_triangles, box_triangles_subdivided};

    fn box_wall(n: usize, inward: bool) -> MeshWall {
        let (v, mut t) = if n == 1 {
            box_triangles(DVec3::ZERO, DVec3::new(2.0, 1.0, 0.5))
        } else {
            box_triangles_subdivided(DVec3::ZERO, DVec3::new(2.0, 1.0, 0.5), n)
        };
        if inward {
            for tri in &mut t {
                tri.swap(1, 2);
            }
        }
        MeshWall::new(TriangleMesh::new(&v, &t, 0.25f64.to_radians()).unwrap().0, 0.3, 0)
    }

    /// The exact signed distance to the box [0, 2] × [0, 1] × [0, 0.5], positive outside.
    fn box_distance(x: DVec3) -> f64 {
        let (lo, hi) = (DVec3::ZERO, DVec3::new(2.0, 1.0, 0.5));
        let outside = (lo - x).max(x - hi).max(DVec3::ZERO);
        if outside != DVec3::ZERO { outside.length() } else { -((x - lo).min(hi - x).min_element()) }
    }

    /// A small deterministic sequence in [0, 1).
    fn halton(i: u32, base: u32) -> f64 {
        let (mut f, mut r, mut i) = (1.0, 0.0, i);
        while i > 0 {
            f /= base as f64;
            r += f * (i % base) as f64;
            i /= base;
        }
        r
    }

    #[test]
    fn a_boxs_signed_distance_is_the_analytic_one_at_faces_edges_and_corners() {
        for n in [1, 4] {
            for inward in [false, true] {
                let wall = box_wall(n, inward);
                let sign = if inward { -1.0 } else { 1.0 };
                let mut sides = [0; 2];
                for i in 1..3000u32 {
                    let x = DVec3::new(halton(i, 2), halton(i, 3), halton(i, 5)) * DVec3::new(3.0, 2.0, 1.5) - DVec3::new(0.5, 0.5, 0.5);
                    let expected = sign * box_distance(x);
                    let d = wall.signed_distance(x, 0.6).map_or(f64::NAN, |d| d);
                    if expected.abs() <= 0.55 {
                        assert!((d - expected).abs() < 1e-12, "n = {n}, inward = {inward}, x = {x}: {d} against {expected}");
                        sides[(d > 0.0) as usize] += 1;
                    }
                    let anywhere = wall.signed_distance_anywhere(x);
                    assert!((anywhere - expected).abs() < 1e-12, "n = {n}, inward = {inward}, x = {x}: {anywhere} against {expected}");
                }
                assert!(sides[0] > 100 && sides[1] > 100, "{sides:?}");
            }
        }
    }

    #[test]
    fn points_near_a_boxs_edges_and_corners_get_the_side_of_the_box() {
        // On the diagonals out of a corner and an edge, where one triangle's normal alone is
        // wrong for about half of the triangles sharing the closest point.
        let wall = box_wall(1, false);
        for s in [-0.2, -1e-3, 1e-3, 0.2] {
            for x in [DVec3::splat(s), DVec3::new(2.0 - s, 1.0 - s, 0.5 - s), DVec3::new(1.0, -s, -s), DVec3::new(2.0 - s, 0.3, 0.5 - s)] {
                let expected = box_distance(x);
                let d = wall.signed_distance(x, 1.0).unwrap();
                assert!((d - expected).abs() < 1e-12, "x = {x}: {d} against {expected}");
            }
        }
    }

    #[test]
    fn a_point_midway_between_two_faces_is_inside() {
        // The box is 0.5 thick in z: z = 0.25 is as far from the floor as from the lid.
        for n in [1, 4] {
            let wall = box_wall(n, false);
            for x in [DVec3::new(1.0, 0.5, 0.25), DVec3::new(0.7, 0.4, 0.25), DVec3::new(1.0, 0.5, 0.25 + 1e-17)] {
                assert!((wall.signed_distance_anywhere(x) + 0.25).abs() < 1e-12, "n = {n}, x = {x}: {}", wall.signed_distance_anywhere(x));
            }
        }
    }

    #[test]
    fn a_placed_mesh_is_measured_where_it_stands() {
        let wall = box_wall(1, false).moved(DVec3::ZERO, DQuat::from_rotation_z(0.5), DVec3::new(3.0, -1.0, 2.0));
        let x = DVec3::new(0.4, 0.2, -0.1);
        let moved = DQuat::from_rotation_z(0.5) * x + DVec3::new(3.0, -1.0, 2.0);
        assert!((wall.signed_distance(moved, 1.0).unwrap() - box_distance(x)).abs() < 1e-12);
    }

    #[test]
    fn the_enclosed_volume_is_signed_by_the_normals() {
        assert!((box_wall(4, false).enclosed_volume() - 1.0).abs() < 1e-12);
        assert!((box_wall(1, true).enclosed_volume() + 1.0).abs() < 1e-12);
    }
}
