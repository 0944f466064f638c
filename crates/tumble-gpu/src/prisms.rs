//! Lifter bars met by polyhedral particles: each bar's convex hull (`Prism::hull`, built once
//! by the plan and posed as the bar moves, as the CPU meets it) is one more shape of the device
//! shape table, and the wall table carries its pose at the time of each contact pass, so the
//! polyhedron narrow phase meets a lifter as it meets another body.

use std::sync::Arc;
use tumble_geom::{Polyhedron, Pose, Prism, SurfaceShape};
use tumble_plan::Plan;

/// One lifter bar as a table shape.
#[derive(Clone, Debug)]
pub struct PrismHull {
    /// Its index in the device shape table (after the plan's particle shapes).
    pub shape: u32,
    pub body: Arc<Polyhedron>,
}

/// The hulls of a plan's lifter bars, by wall index (empty without polyhedral particles:
/// spheres meet bars through `prism_proximity`).
#[derive(Clone, Debug, Default)]
pub struct PrismHulls(Vec<Option<PrismHull>>);

impl PrismHulls {
    pub fn new(plan: &Plan) -> Result<Self, crate::GpuError> {
        if !plan.model.polyhedra {
            return Ok(PrismHulls::default());
        }
        let mut next = plan.model.shapes.len() as u32;
        let mut hulls = Vec::with_capacity(plan.model.walls.len());
        for w in &plan.model.walls {
            let SurfaceShape::Prism(p) = &w.shape else {
                hulls.push(None);
                continue;
            };
            let body = p.hull.clone().ok_or_else(|| crate::GpuError::Feature(format!("the lifter bar \"{}\" has no volume", w.name)))?;
            hulls.push(Some(PrismHull { shape: next, body }));
            next += 1;
        }
        Ok(PrismHulls(hulls))
    }

    /// The hull shapes in table order (they follow the plan's particle shapes).
    pub fn shapes(&self) -> impl Iterator<Item = &Polyhedron> {
        self.0.iter().flatten().map(|h| &*h.body)
    }

    /// Wall `k`'s hull shape index and body pose, with the wall at `bar` (its shape at that time).
    pub fn pose(&self, k: usize, bar: &Prism) -> Option<(u32, Pose)> {
        Some((self.0.get(k)?.as_ref()?.shape, bar.hull_pose))
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
        for (k, w) in plan.model.walls.iter().enumerate() {
            for t in [0.0, 0.37, 2.9] {
                let SurfaceShape::Prism(bar) = w.shape_at(t) else { continue };
                let (shape, pose) = hulls.pose(k, &bar).unwrap();
                assert!(shape as usize >= plan.model.shapes.len());
                let hull = &hulls.0[k].as_ref().unwrap().body;
                // Every corner of the bar is a vertex of the posed hull, and the reverse.
                let world: Vec<_> = hull.vertices().iter().map(|v| pose.to_world(*v)).collect();
                for c in bar.faces[4].corners.iter().chain(&bar.faces[5].corners).copied() {
                    let nearest = world.iter().map(|v| (*v - c).length()).fold(f64::INFINITY, f64::min);
                    assert!(nearest < 1e-12, "wall {k} at t = {t}: corner {c} is {nearest} from the hull");
                }
                assert_eq!(world.len(), 8);
            }
        }
    }
}
