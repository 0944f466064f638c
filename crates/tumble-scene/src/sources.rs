//! Particle sources and outlets as the plan holds them: compiled from `[[sources]]` and
//! `[[outlets]]`, with the candidate generator every backend draws the same sequence from.

use crate::compile::{finite3, non_negative, positive, unit};
use crate::sizes::CheckDiameter;

use crate::schema::{RateSpec, Scene, ShapeSection, SourceRegion, SourceSection, TotalSpec};
use crate::shapes::{ParticleShape, SPHERE, shape_of};
use crate::{InitialParticles, SceneError};
use glam::{DQuat, DVec3};
use std::collections::HashMap;
use tumble_geom::PeriodicBox;
pub use tumble_plan::{Body, DEFAULT_INTERVAL, InsertRegion, MAX_OUTLETS, Outlet, OutletRegion, Rate, Source, SourceKind, Total, inserted_at_most};

/// The sources and their particle kinds (polyhedra join `shapes`), and one representative
/// particle per extreme size of each kind, so Δt, the cell size and the model's features are
/// planned for the particles the sources will make.
pub(crate) fn compile_sources(
    scene: &Scene,
    material_index: &HashMap<String, u16>,
    densities: &[f64],
    shapes: &mut Vec<ParticleShape>,
    domain: &PeriodicBox,
    gravity: DVec3,
    first_group: u16,
) -> Result<(Vec<Source>, InitialParticles), SceneError> {
    let mut sources = Vec::new();
    let mut prototypes = InitialParticles::default();
    for (k, s) in scene.sources.iter().enumerate() {
        let at = |f: &str| format!("sources[{k}].{f}");
        let material = *material_index.get(&s.material).ok_or_else(|| {
            let known: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
            SceneError::field(at("material"), format!("unknown material \"{}\"; defined materials: {}", s.material, known.join(", ")))
        })?;
        let entries: Vec<(String, &ShapeSection, f64)> = match (&s.shape, &s.mixture) {
            (Some(shape), None) => vec![(at("shape"), shape, 1.0)],
            (None, Some(list)) if !list.is_empty() => {
                list.iter().enumerate().map(|(j, e)| (at(&format!("mixture[{j}].shape")), &e.shape, e.fraction)).collect()
            }
            _ => return Err(SceneError::field(at("shape"), "give one shape, or a non-empty mixture = [{ shape, fraction }, …]")),
        };
        let total_fraction: f64 = entries.iter().map(|e| e.2).sum();
        for (j, e) in entries.iter().enumerate() {
            if !(e.2.is_finite() && e.2 >= 0.0 && total_fraction > 0.0 && total_fraction.is_finite()) {
                return Err(SceneError::field(
                    at(&format!("mixture[{j}].fraction")),
                    format!("must be zero or positive and some positive, got {}", e.2),
                ));
            }
        }
        let density = densities[material as usize];
        let mut kinds = Vec::new();
        let mut mean_mass = 0.0;
        // The smallest and largest particle of each kind.
        let mut sizes = Vec::new();
        for (field, section, fraction) in &entries {
            let fraction = fraction / total_fraction;
            let kind = match shape_of(section, field)? {
                Some(poly) => {
                    let volume = poly.body.volume();
                    mean_mass += fraction * density * volume;
                    shapes.push(poly);
                    let index = (shapes.len() - 1) as u16;
                    let r = shapes[index as usize].body.bounding_radius();
                    sizes.push(Body { radius: r, volume, shape: index, orientation: DQuat::IDENTITY, effect_radius: r });
                    SourceKind { shape: index, diameter: None, effect_diameter: None, effect_ratio: None, fraction }
                }
                None => {
                    let ShapeSection::Sphere(sphere) = section else { unreachable!("shape_of gives None for spheres only") };
                    sphere.diameter.check(&format!("{field}.sphere.diameter"))?;
                    mean_mass += fraction * density * std::f64::consts::PI / 6.0 * sphere.diameter.mean_cube();
                    for d in [sphere.diameter.min(), sphere.diameter.max()] {
                        let effect = sphere.effect_diameter.or(sphere.effect_ratio.map(|k| k * d)).unwrap_or(d);
                        let volume = std::f64::consts::PI / 6.0 * d * d * d;
                        sizes.push(Body { radius: 0.5 * d, volume, shape: SPHERE, orientation: DQuat::IDENTITY, effect_radius: 0.5 * effect });
                    }
                    SourceKind {
                        shape: SPHERE,
                        diameter: Some(sphere.diameter.clone()),
                        effect_diameter: sphere.effect_diameter,
                        effect_ratio: sphere.effect_ratio,
                        fraction,
                    }
                }
            };
            kinds.push(kind);
        }
        let region = region(scene, s, &at, domain)?;
        let velocity = match s.velocity {
            Some(v) => finite3(&at("velocity"), v)?,
            None => DVec3::ZERO,
        };
        // The prototypes start at the region's highest corner with the source's velocity, so the
        // impact speed estimate covers their fall.
        let (lo, hi) = region.bounds();
        let top = DVec3::from_array([0, 1, 2].map(|a| if gravity[a] > 0.0 { lo[a] } else { hi[a] }));
        for body in &sizes {
            prototypes.push_body(top, velocity, body, material, first_group + k as u16);
        }
        let orientation = crate::particles::given_orientation(s.orientation, &at("orientation"))?;
        let rate = match s.rate {
            Some(RateSpec::ParticlesPerSecond(r)) => Some(Rate::ParticlesPerSecond(positive(&at("rate.particles_per_second"), r)?)),
            Some(RateSpec::KgPerSecond(r)) => Some(Rate::KgPerSecond(positive(&at("rate.kg_per_second"), r)?)),
            None => None,
        };
        let total = match s.total {
            Some(TotalSpec::Particles(0)) => return Err(SceneError::field(at("total.particles"), "must be at least 1")),
            Some(TotalSpec::Particles(n)) => Some(Total::Particles(n)),
            Some(TotalSpec::Kg(m)) => Some(Total::Kg(positive(&at("total.kg"), m)?)),
            None => None,
        };
        if rate.is_none() && total.is_none() {
            return Err(SceneError::field(at("rate"), "give a rate (particles_per_second or kg_per_second), a total (particles or kg), or both"));
        }
        sources.push(Source {
            name: s.name.clone().unwrap_or_else(|| format!("source{k}")),
            material,
            group: first_group + k as u16,
            kinds,
            region,
            velocity,
            orientation,
            rate,
            total,
            first_step: 0,
            every: 1,
            last_step: 0,
            mean_mass,
            seed: scene.run.seed ^ (0xA076_1D64_78BD_642F_u64.wrapping_mul(k as u64 + 1)),
        });
        non_negative(&at("start"), s.start)?;
        if let Some(stop) = s.stop
            && !(stop >= s.start)
        {
            return Err(SceneError::field(at("stop"), format!("must be at least start = {}, got {stop}", s.start)));
        }
        if let Some(i) = s.interval {
            positive(&at("interval"), i)?;
        }
    }
    Ok((sources, prototypes))
}

/// Sets each source's steps once Δt is known: the first at `start`, then every `interval`
/// (at least one step) until `stop` or the end of the run.
pub(crate) fn schedule_sources(scene: &Scene, sources: &mut [Source], dt: f64, steps: u64, gravity: DVec3, shapes: &[ParticleShape]) {
    for (s, section) in sources.iter_mut().zip(&scene.sources) {
        let interval = section.interval.unwrap_or_else(|| default_interval(s, gravity, shapes));
        s.first_step = (section.start / dt).round() as u64;
        s.every = ((interval / dt).round() as u64).max(1);
        s.last_step = section.stop.map_or(steps, |t| ((t / dt).round() as u64).min(steps));
    }
}

/// A plane source inserts again once its particles have moved one largest diameter off the
/// plane (at their speed, or falling from rest); a volume source every [`DEFAULT_INTERVAL`].
fn default_interval(s: &Source, gravity: DVec3, shapes: &[ParticleShape]) -> f64 {
    let InsertRegion::Plane { normal, .. } = &s.region else { return DEFAULT_INTERVAL };
    let d = 2.0 * s.largest_radius(shapes);
    let v = s.velocity.dot(*normal).abs();
    let g = gravity.dot(*normal).abs();
    // d = v t + g t² / 2, solved for t.
    let t = if g > 0.0 {
        (-v + (v * v + 2.0 * g * d).sqrt()) / g
    } else if v > 0.0 {
        d / v
    } else {
        DEFAULT_INTERVAL
    };
    t.min(DEFAULT_INTERVAL)
}

fn region(scene: &Scene, s: &SourceSection, at: &impl Fn(&str) -> String, domain: &PeriodicBox) -> Result<InsertRegion, SceneError> {
    let inside = |field: String, lo: DVec3, hi: DVec3| {
        let slack = 1e-9 * domain.extent().max_element();
        if lo.cmpge(domain.min - slack).all() && hi.cmple(domain.max + slack).all() {
            Ok(())
        } else {
            Err(SceneError::field(field, format!("reaches outside the domain [{} .. {}]", domain.min, domain.max)))
        }
    };
    Ok(match &s.region {
        SourceRegion::Box(b) => {
            let (min, max) = (finite3(&at("region.box.min"), b.min)?, finite3(&at("region.box.max"), b.max)?);
            if !min.cmplt(max).all() {
                return Err(SceneError::field(at("region.box"), "min must be below max on every axis"));
            }
            inside(at("region.box"), min, max)?;
            InsertRegion::Box { min, max }
        }
        SourceRegion::Cylinder(c) => {
            let base = finite3(&at("region.cylinder.base"), c.base)?;
            let axis = unit(&at("region.cylinder.axis"), c.axis)?;
            let radius = positive(&at("region.cylinder.radius"), c.radius)?;
            let length = positive(&at("region.cylinder.length"), c.length)?;
            let r = InsertRegion::Cylinder { base, axis, radius, length };
            let (lo, hi) = r.bounds();
            inside(at("region.cylinder"), lo, hi)?;
            r
        }
        SourceRegion::Plane(p) => {
            let point = finite3(&at("region.plane.point"), p.point)?;
            let normal = unit(&at("region.plane.normal"), p.normal)?;
            let width = positive(&at("region.plane.width"), p.width)?;
            let height = positive(&at("region.plane.height"), p.height)?;
            let u = if normal.cross(DVec3::Z).length() > 1e-6 { normal.cross(DVec3::Z).normalize() } else { normal.cross(DVec3::X).normalize() };
            let v = normal.cross(u);
            let r = InsertRegion::Plane { point, normal, u, v, width, height };
            let (lo, hi) = r.bounds();
            inside(at("region.plane"), lo, hi)?;
            r
        }
        SourceRegion::Mesh(m) => {
            let field = at("region.mesh");
            // The binning only speeds up the distance search: 16 cells along the domain.
            let mesh = crate::mesh_walls::closed_mesh(scene, &field, m, domain.extent().max_element() / 16.0, "a source")?;
            let (lo, hi) = mesh.bounds();
            inside(field, lo, hi)?;
            let inside = if mesh.enclosed_volume() > 0.0 { -1.0 } else { 1.0 };
            InsertRegion::Mesh { mesh: std::sync::Arc::new(mesh), inside }
        }
    })
}

/// Compiles `[[outlets]]`.
pub(crate) fn compile_outlets(scene: &Scene) -> Result<Vec<Outlet>, SceneError> {
    let most = MAX_OUTLETS;
    if scene.outlets.len() > most {
        return Err(SceneError::field("outlets", format!("at most {most} outlets, got {}", scene.outlets.len())));
    }
    let mut out = Vec::new();
    for (k, o) in scene.outlets.iter().enumerate() {
        let at = |f: &str| format!("outlets[{k}].{f}");
        if o.name.trim().is_empty() {
            return Err(SceneError::field(at("name"), "must not be empty"));
        }
        if scene.outlets[..k].iter().any(|p| p.name == o.name) {
            return Err(SceneError::field(at("name"), format!("\"{}\" names two outlets", o.name)));
        }
        let region = match (&o.box_, &o.plane) {
            (Some(b), None) => {
                let (min, max) = (finite3(&at("box.min"), b.min)?, finite3(&at("box.max"), b.max)?);
                if !min.cmplt(max).all() {
                    return Err(SceneError::field(at("box"), "min must be below max on every axis"));
                }
                OutletRegion::Box { min, max }
            }
            (None, Some(p)) => OutletRegion::Beyond { point: finite3(&at("plane.point"), p.point)?, normal: unit(&at("plane.normal"), p.normal)? },
            _ => return Err(SceneError::field(at("box"), "give exactly one of box = { min, max } or plane = { point, normal }")),
        };
        out.push(Outlet { name: o.name.clone(), region });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::rng::Rng;
    use crate::{SPHERE, compile, parse_scene};

    fn source(body: &str) -> crate::CompiledScene {
        let text = format!(
            r#"
name = "s"
[run]
duration = 0.1
[domain]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[[materials]]
name = "m"
density = 1000.0
[contact]
normal = {{ model = "linear", stiffness = 1000.0 }}
restitution = 0.5
[[sources]]
material = "m"
{body}
"#
        );
        compile(&parse_scene(&text).unwrap()).unwrap()
    }

    #[test]
    fn a_mixture_draws_each_kind_at_its_share_by_number() {
        let c = source(
            "mixture = [{ fraction = 1.0, shape = { cube = { edge = 0.05 } } }, { fraction = 3.0, shape = { sphere = { diameter = 0.05 } } }]\nregion = { box = { min = [-0.5, -0.5, -0.5], max = [0.5, 0.5, 0.5] } }\ntotal = { particles = 10 }",
        );
        let s = &c.plan.model.sources[0];
        let mut rng = Rng::new(1);
        let n = 200_000;
        let cubes = (0..n).filter(|_| s.draw_body(&mut rng, &c.plan.model.shapes).shape != SPHERE).count();
        // Binomial standard error 0.001.
        assert!((cubes as f64 / n as f64 - 0.25).abs() < 0.004, "{cubes} cubes in {n}");
    }

    #[test]
    fn region_samples_keep_the_body_inside_and_cover_the_region() {
        for region in [
            "{ box = { min = [-0.5, -0.2, 0.0], max = [0.5, 0.2, 0.3] } }",
            "{ cylinder = { base = [0.1, 0.0, -0.4], axis = [1.0, 1.0, 0.0], radius = 0.2, length = 0.5 } }",
            "{ plane = { point = [0.0, 0.0, 0.5], normal = [0.0, 1.0, 1.0], width = 0.6, height = 0.3 } }",
        ] {
            let c = source(&format!("shape = {{ sphere = {{ diameter = 0.1 }} }}\nregion = {region}\ntotal = {{ particles = 10 }}"));
            let r = 0.05;
            let reg = c.plan.model.sources[0].region.clone();
            let mut rng = Rng::new(2);
            let points: Vec<glam::DVec3> = (0..20_000).map(|_| reg.sample(&mut rng, r).unwrap()).collect();
            let mean = points.iter().sum::<glam::DVec3>() / points.len() as f64;
            for x in &points {
                let inside = match reg.clone() {
                    super::InsertRegion::Box { min, max } => (*x - r).cmpge(min - 1e-12).all() && (*x + r).cmple(max + 1e-12).all(),
                    super::InsertRegion::Cylinder { base, axis, radius, length } => {
                        let along = (*x - base).dot(axis);
                        let across = (*x - base - axis * along).length();
                        along >= r - 1e-12 && along <= length - r + 1e-12 && across <= radius - r + 1e-12
                    }
                    super::InsertRegion::Plane { point, normal, u, v, width, height } => {
                        let d = *x - point;
                        d.dot(normal).abs() < 1e-12 && d.dot(u).abs() <= 0.5 * width - r + 1e-12 && d.dot(v).abs() <= 0.5 * height - r + 1e-12
                    }
                    super::InsertRegion::Mesh { .. } => unreachable!("no mesh here"),
                };
                assert!(inside, "{region}: {x} leaves the body outside the region");
            }
            // Uniform sampling puts the mean at the region's centre (standard error ~ 0.002 here).
            let centre = match reg {
                super::InsertRegion::Box { min, max } => 0.5 * (min + max),
                super::InsertRegion::Cylinder { base, axis, length, .. } => base + axis * (0.5 * length),
                super::InsertRegion::Plane { point, .. } => point,
                super::InsertRegion::Mesh { .. } => unreachable!("no mesh here"),
            };
            assert!((mean - centre).length() < 0.01, "{region}: mean {mean}, centre {centre}");
        }
    }

    /// An octahedron |x − c|₁ ≤ a as an OBJ file, its faces wound outward or (`inward`) inward.
    fn octahedron(name: &str, centre: glam::DVec3, a: f64, inward: bool) -> std::path::PathBuf {
        let mut text = String::new();
        for v in [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]] {
            let p = centre + glam::DVec3::from_array(v) * a;
            text += &format!("v {} {} {}\n", p.x, p.y, p.z);
        }
        // Vertices 1..6 are +x, −x, +y, −y, +z, −z; each face is one choice of sign per axis.
        for (x, y, z) in [(1, 3, 5), (3, 2, 5), (2, 4, 5), (4, 1, 5), (3, 1, 6), (2, 3, 6), (4, 2, 6), (1, 4, 6)] {
            text += &if inward { format!("f {x} {z} {y}\n") } else { format!("f {x} {y} {z}\n") };
        }
        let path = std::env::temp_dir().join(format!("tumble-source-{name}-{}.obj", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    /// A source in a closed mesh places every body wholly inside it, uniformly (the mean at the
    /// centre, the share in the inner half of the octahedron's size 1/8 of the usable volume),
    /// whichever way the faces are wound; the region's volume is the mesh's.
    #[test]
    fn a_mesh_region_keeps_the_body_inside_the_closed_mesh() {
        let (centre, a, r) = (glam::DVec3::new(0.1, -0.2, 0.05), 0.6, 0.05);
        for inward in [false, true] {
            let file = octahedron(if inward { "in" } else { "out" }, centre, a, inward);
            let c = source(&format!(
                "shape = {{ sphere = {{ diameter = 0.1 }} }}\nregion = {{ mesh = {{ file = \"{}\" }} }}\ntotal = {{ particles = 10 }}",
                file.display()
            ));
            let reg = &c.plan.model.sources[0].region;
            assert!((reg.volume() / (4.0 * a * a * a / 3.0) - 1.0).abs() < 1e-12, "volume {}", reg.volume());
            let mut rng = Rng::new(3);
            // The usable inside fills 13.5 % of the box the draws come from: 64 draws miss it
            // with probability 1e-4.
            let points: Vec<glam::DVec3> = (0..20_000).filter_map(|_| reg.sample(&mut rng, r)).collect();
            assert!(points.len() >= 19_990, "inward {inward}: {} of 20000 samples found no place", 20_000 - points.len());
            // The body's centre lies at least r from every face: |x − c|₁ ≤ a − r √3.
            let reach = a - r * 3f64.sqrt();
            let norm = |x: glam::DVec3| (x - centre).abs().element_sum();
            assert!(points.iter().all(|&x| norm(x) <= reach + 1e-12), "inward {inward}: a body leaves the mesh");
            let mean = points.iter().sum::<glam::DVec3>() / points.len() as f64;
            assert!((mean - centre).length() < 0.01, "inward {inward}: mean {mean}");
            let inner = points.iter().filter(|&&x| norm(x) <= 0.5 * reach).count() as f64 / points.len() as f64;
            assert!((inner - 0.125).abs() < 0.01, "inward {inward}: {inner} of the places in the inner half");
            std::fs::remove_file(file).unwrap();
        }
    }
}
