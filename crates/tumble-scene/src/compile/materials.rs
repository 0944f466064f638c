//! The material table and the name lookup every other section resolves against.

use super::positive;
use crate::SceneError;
use crate::plan::Material;
use crate::schema::Scene;
use std::collections::HashMap;

/// The scene's materials in file order, with each name's index.
pub(super) struct MaterialTable {
    pub materials: Vec<Material>,
    pub index: HashMap<String, u16>,
}

/// Densest material accepted, kg/m³: beyond it masses and energies overflow long before a
/// scene means anything (1e308 ran to exit 0).
const MAX_DENSITY: f64 = 1.0e8;

/// Validates the [[materials]] entries.
pub(super) fn materials(scene: &Scene) -> Result<MaterialTable, SceneError> {
    if scene.materials.is_empty() {
        return Err(SceneError::field("materials", "define at least one [[materials]] entry with a name and a density"));
    }
    let mut index = HashMap::new();
    let mut materials = Vec::new();
    for (k, m) in scene.materials.iter().enumerate() {
        let f = |x: &str| format!("materials[{k}].{x}");
        if index.insert(m.name.clone(), k as u16).is_some() {
            return Err(SceneError::field(f("name"), format!("material \"{}\" is defined twice", m.name)));
        }
        positive(&f("density"), m.density)?;
        if m.density > MAX_DENSITY {
            return Err(SceneError::field(
                f("density"),
                format!("must be at most {MAX_DENSITY:e} kg/m³ (densities are in kg/m³; the densest solid, osmium, is 22590), got {}", m.density),
            ));
        }
        if let Some(e) = m.youngs_modulus {
            positive(&f("youngs_modulus"), e)?;
        }
        if let Some(nu) = m.poisson_ratio
            && !(nu > -1.0 && nu < 0.5)
        {
            return Err(SceneError::field(f("poisson_ratio"), format!("must lie in (-1, 0.5), got {nu}")));
        }
        materials.push(Material { name: m.name.clone(), density: m.density, youngs_modulus: m.youngs_modulus, poisson_ratio: m.poisson_ratio });
    }
    Ok(MaterialTable { materials, index })
}

impl MaterialTable {
    /// The index of material `name`, or an error at `field` listing the defined ones.
    pub fn lookup(&self, scene: &Scene, field: String, name: &str) -> Result<u16, SceneError> {
        self.index.get(name).copied().ok_or_else(|| {
            let known: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
            SceneError::field(field, format!("unknown material \"{name}\"; defined materials: {}", known.join(", ")))
        })
    }
}
