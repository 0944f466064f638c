//! Lifter bars met by polyhedral particles: each bar's convex hull is one more shape of the
//! device shape table (built once from its t = 0 corners), and the wall table carries its pose
//! at the time of each contact pass, so the polyhedron narrow phase meets a lifter as it meets
//! another body. The CPU hulls the bar at its current pose (`Prism::polyhedron_contact`): the
//! same solid, moved rigidly.

use glam::DQuat;
use tumble_geom::{Polyhedron, Pose, Prism, SurfaceShape};
use tumble_scene::{Plan, Wall};

/// One lifter bar as a table shape.
#[derive(Clone, Debug)]
pub struct PrismHull {
    /// Its index in the device shape table (after the plan's particle shapes).
    pub shape: u32,
    pub body: Polyhedron,
    /// The hull's body frame in the bar's frame: corners relative to the bar's centre, axes as at t = 0.
    body_in_bar: Pose,
}

/// The hulls of a plan's lifter bars, by wall index (empty without polyhedral particles:
/// spheres meet bars through `prism_proximity`).
#[derive(Clone, Debug, Default)]
pub struct PrismHulls(Vec<Option<PrismHull>>);

/// The eight corners of a bar, as `Prism::polyhedron_contact` hulls them.
fn corners(p: &Prism) -> impl Iterator<Item = glam::DVec3> + '_ {
    p.faces[4].corners.iter().chain(&p.faces[5].corners).copied()
}

impl PrismHulls {
    pub fn new(plan: &Plan) -> Result<Self, crate::GpuError> {
        if !plan.polyhedra {
            return Ok(PrismHulls::default());
        }
        let mut next = plan.shapes.len() as u32;
        let mut hulls = Vec::with_capacity(plan.walls.len());
        for w in &plan.walls {
            let SurfaceShape::Prism(p) = &w.shape else {
                hulls.push(None);
                continue;
            };
            let local: Vec<_> = corners(p).map(|c| c - p.centre).collect();
            let body =
                Polyhedron::from_points(&local).ok_or_else(|| crate::GpuError::Feature(format!("the lifter bar \"{}\" has no volume", w.name)))?;
            let body_in_bar = body.input_to_body().relative(&Pose::IDENTITY);
            hulls.push(Some(PrismHull { shape: next, body, body_in_bar }));
            next += 1;
        }
        Ok(PrismHulls(hulls))
    }

    /// The hull shapes in table order (they follow the plan's particle shapes).
    pub fn shapes(&self) -> impl Iterator<Item = &Polyhedron> {
        self.0.iter().flatten().map(|h| &h.body)
    }

    /// Wall `k`'s hull shape index and body pose, with the wall at `bar` (its shape at time `t`).
    pub fn pose(&self, k: usize, w: &Wall, bar: &Prism, t: f64) -> Option<(u32, Pose)> {
        let h = self.0.get(k)?.as_ref()?;
        // The bar moved rigidly: corners about its centre turn with the motion's rotation.
        let turn = w.motion.map_or(DQuat::IDENTITY, |m| m.pose(t).1);
        Some((h.shape, Pose::new(bar.centre, turn).compose(&h.body_in_bar)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_scene::{compile, parse_scene};

    #[test]
    fn a_hull_in_its_pose_has_the_bars_corners_at_any_time() {
        let text = include_str!("../../../scenes/drum_cubes.toml");
        let plan = compile(&parse_scene(text).unwrap()).unwrap().plan;
        let hulls = PrismHulls::new(&plan).unwrap();
        assert_eq!(hulls.shapes().count(), 8);
        for (k, w) in plan.walls.iter().enumerate() {
            for t in [0.0, 0.37, 2.9] {
                let SurfaceShape::Prism(bar) = w.shape_at(t) else { continue };
                let (shape, pose) = hulls.pose(k, w, &bar, t).unwrap();
                assert!(shape as usize >= plan.shapes.len());
                let hull = &hulls.0[k].as_ref().unwrap().body;
                // Every corner of the bar is a vertex of the posed hull, and the reverse.
                let world: Vec<_> = hull.vertices().iter().map(|v| pose.to_world(*v)).collect();
                for c in corners(&bar) {
                    let nearest = world.iter().map(|v| (*v - c).length()).fold(f64::INFINITY, f64::min);
                    assert!(nearest < 1e-12, "wall {k} at t = {t}: corner {c} is {nearest} from the hull");
                }
                assert_eq!(world.len(), 8);
            }
        }
    }
}
