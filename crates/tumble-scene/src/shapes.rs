//! Particle shapes: each polyhedral particle group gets one entry in the plan's shape table.

use crate::SceneError;
use crate::schema::{ParticleGroup, ShapeSection};
use glam::DVec3;
use tumble_geom::Polyhedron;
pub use tumble_plan::{ParticleShape, SPHERE, equivalent_radius};

/// The shortest and longest lengths a polyhedral shape may be given in, m.
const MIN_LENGTH: f64 = 1e-9;
const MAX_LENGTH: f64 = 1e3;

/// The most points a hull may be given (each pair test walks every edge pair).
const MAX_HULL_POINTS: usize = 1000;

/// The most sides of a prism (past that it is a cylinder for any granular purpose).
const MAX_PRISM_SIDES: u32 = 128;

/// The polyhedron of group `g`, or `None` for spheres.
pub(crate) fn group_shape(group: &ParticleGroup, g: usize) -> Result<Option<ParticleShape>, SceneError> {
    shape_of(&group.shape, &format!("particles[{g}].shape"))
}

/// The polyhedron a shape section describes, or `None` for spheres; `at` names the section.
pub(crate) fn shape_of(section: &ShapeSection, at: &str) -> Result<Option<ParticleShape>, SceneError> {
    let field = |f: &str| format!("{at}.{f}");
    // A length from 1 nm to 1 km: outside that no granular solid is meant, and the hull's
    // volume and inertia (length⁵) leave the range of f64.
    let positive = |f: &str, v: f64| {
        if (MIN_LENGTH..=MAX_LENGTH).contains(&v) {
            Ok(v)
        } else {
            Err(SceneError::field(field(f), format!("must be a length from {MIN_LENGTH:e} to {MAX_LENGTH:e} m, got {v:e}")))
        }
    };
    let (name, body) = match section {
        ShapeSection::Sphere(_) => return Ok(None),
        ShapeSection::Polyhedron(p) => {
            let points: Vec<DVec3> = p.vertices.iter().map(|v| DVec3::from(*v)).collect();
            if points.len() > MAX_HULL_POINTS {
                return Err(SceneError::field(field("polyhedron.vertices"), format!("at most {MAX_HULL_POINTS} points, got {}", points.len())));
            }
            let body = Polyhedron::from_points(&points).ok_or_else(|| {
                SceneError::field(
                    field("polyhedron.vertices"),
                    format!("the {} points span no solid (need at least four finite points not all in one plane)", points.len()),
                )
            })?;
            ("polyhedron", body)
        }
        ShapeSection::Cube(c) => ("cube", Polyhedron::cube(positive("cube.edge", c.edge)?)),
        ShapeSection::Box(b) => {
            let half =
                DVec3::new(positive("box.size[0]", b.size[0])?, positive("box.size[1]", b.size[1])?, positive("box.size[2]", b.size[2])?) * 0.5;
            let body = Polyhedron::try_cuboid(half).ok_or_else(|| {
                SceneError::field(
                    field("box.size"),
                    format!("{:?} is too flat or too thin for a solid; keep the sides within 1:100 of each other", b.size),
                )
            })?;
            ("box", body)
        }
        ShapeSection::Platonic(p) => {
            let unit: fn(f64) -> Polyhedron = match p.kind.as_str() {
                "tetrahedron" => Polyhedron::tetrahedron,
                "cube" | "hexahedron" => Polyhedron::cube,
                "octahedron" => Polyhedron::octahedron,
                "dodecahedron" => Polyhedron::dodecahedron,
                "icosahedron" => Polyhedron::icosahedron,
                other => {
                    return Err(SceneError::field(
                        field("platonic.kind"),
                        format!("unknown solid \"{other}\"; valid: tetrahedron, cube, octahedron, dodecahedron, icosahedron"),
                    ));
                }
            };
            let body = match (p.edge, p.radius) {
                (Some(edge), None) => unit(positive("platonic.edge", edge)?),
                (None, Some(r)) => {
                    let one = unit(1.0);
                    let factor = positive("platonic.radius", r)? / one.bounding_radius();
                    one.scaled(factor)
                }
                _ => return Err(SceneError::field(field("platonic"), "give exactly one of edge (edge length) or radius (circumradius)")),
            };
            ("platonic", body)
        }
        ShapeSection::Prism(p) => {
            if !(3..=MAX_PRISM_SIDES).contains(&p.sides) {
                return Err(SceneError::field(field("prism.sides"), format!("must be from 3 to {MAX_PRISM_SIDES}, got {}", p.sides)));
            }
            let (radius, height) = (positive("prism.radius", p.radius)?, positive("prism.height", p.height)?);
            let body = Polyhedron::try_prism(p.sides as usize, radius, height).ok_or_else(|| {
                SceneError::field(
                    field("prism"),
                    format!("radius {radius:e} m and height {height:e} m make a prism too flat or too thin for a solid; keep them within 1:100 of each other"),
                )
            })?;
            ("prism", body)
        }
    };
    Ok(Some(ParticleShape::new(format!("{at}.{name}"), body)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DQuat;

    #[test]
    fn boxes_and_prisms_within_one_to_a_hundred_are_solids_at_every_length() {
        // The refusal's advice: sides within 1:100 always make a hull, from 1 nm to 1 km.
        for scale in [MIN_LENGTH * 100.0, 1e-3, 1.0, MAX_LENGTH] {
            for (a, b) in [(1.0, 0.01), (0.01, 1.0)] {
                assert!(Polyhedron::try_cuboid(DVec3::new(a, b, b) * scale).is_some(), "box {a}:{b} at {scale}");
                assert!(Polyhedron::try_cuboid(DVec3::new(a, a, b) * scale).is_some(), "box {a}:{a}:{b} at {scale}");
                for sides in [3, 4, 7, 64, MAX_PRISM_SIDES as usize] {
                    assert!(Polyhedron::try_prism(sides, a * scale, b * scale).is_some(), "prism {sides} {a}:{b} at {scale}");
                }
            }
        }
        assert!(Polyhedron::try_cuboid(DVec3::new(1e-6, 0.1, 0.15)).is_none());
    }

    #[test]
    fn a_cube_as_given_keeps_its_faces_on_the_axes() {
        let s = ParticleShape::new("cube".into(), Polyhedron::cube(2.0));
        for v in s.body.vertices() {
            let w = s.as_given * *v;
            assert!((w.abs() - DVec3::ONE).length() < 1e-12, "{w}");
        }
        assert!((s.equivalent_radius - (6.0 / std::f64::consts::PI).cbrt()).abs() < 1e-12);
    }

    #[test]
    fn an_off_axis_vertex_list_is_shown_as_written() {
        // A long box turned 30° about z: its body axes are turned back, as_given undoes that.
        let turn = DQuat::from_rotation_z(0.5);
        let pts: Vec<DVec3> = [-1.0, 1.0]
            .iter()
            .flat_map(|&x| [-1.0, 1.0].map(move |y| (x, y)))
            .flat_map(|(x, y)| [-1.0, 1.0].map(move |z| turn * DVec3::new(3.0 * x, 2.0 * y, z) + DVec3::new(5.0, 0.0, 0.0)))
            .collect();
        let s = ParticleShape::new("p".into(), Polyhedron::from_points(&pts).unwrap());
        for p in &pts {
            let shown = s.as_given * (s.body.input_to_body().to_world(*p));
            assert!((shown - (*p - DVec3::new(5.0, 0.0, 0.0))).length() < 1e-9);
        }
    }
}
