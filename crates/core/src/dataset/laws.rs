//! The dataset's laws: how stored samples are turned into flux when rendering against the current
//! scene (relighting), and how datasets combine (merging). Both are exact, not approximations,
//! because a sample of light k carries Φ_k·β/N_k and β does not depend on Φ_k:
//!
//! * **Relighting** scales or recolours Φ_k (0 switches a light off) — nothing else changes.
//!   The scene file may also change a light's power directly: the scene's current power is used.
//!   A light's *shape* (where and how it emits) must be unchanged, or its samples are invalid.
//! * **Merging** independent datasets of the same scene sums N_k per light (the thesis's
//!   master/worker merge, §6.2.4): the samples of all of them then share Φ_k/(N_k¹ + N_k² + …).

use super::LightTable;
use crate::math::Rgb;
use crate::scene::Scene;

/// A render-time change of one light: its power is multiplied by `factor` (per channel).
#[derive(Clone, Debug, PartialEq)]
pub struct LightScale {
    /// The light's name, or its index in the dataset's light table.
    pub light: String,
    /// Per-channel factor (a scalar scale is the same number three times; 0 switches it off).
    pub factor: Rgb,
}

/// The flux each dataset light's samples stand for, and what was noticed on the way.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// Φ_k/N_k per light of the dataset's table (zero for lights that are off or gone).
    pub flux_per_path: Vec<Rgb>,
    /// Things the user should know (a light relit by the scene file, a light no longer in it).
    pub notes: Vec<String>,
}

/// Why a dataset cannot be lit by a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LightingError {
    /// `--light` named a light that is neither in the dataset nor in the scene.
    #[error("no light '{given}': the dataset's lights are {names:?} (give a name or an index)")]
    UnknownLight {
        /// What was given.
        given: String,
        /// The dataset's light names.
        names: Vec<String>,
    },
    /// The light moved or changed shape since the trace.
    #[error(
        "light '{0}' has moved or changed shape since the trace: its samples no longer apply (re-trace the scene)"
    )]
    ShapeChanged(String),
    /// The scene has a light the dataset never traced.
    #[error(
        "light '{0}' of the scene has no paths in the dataset: add it with `opticks add-light`, or switch it off with --light '{0}=0'"
    )]
    NotTraced(String),
}

/// Works out the flux per path of every dataset light for rendering against `scene`, after the
/// `scales`. Dataset lights are matched to scene lights by name.
pub fn lighting(table: &LightTable, scene: &Scene, scales: &[LightScale]) -> Result<Lighting, LightingError> {
    let mut notes = Vec::new();
    let mut factors = vec![Rgb::ONE; table.lights.len()];
    let mut switched_off_untraced = Vec::new();
    for s in scales {
        let by_index = s.light.parse::<usize>().ok().filter(|&i| i < table.lights.len());
        match by_index.or_else(|| table.lights.iter().position(|l| l.name == s.light)) {
            Some(k) => factors[k] *= s.factor,
            None if scene.light_index(&s.light).is_some() && s.factor == Rgb::ZERO => {
                switched_off_untraced.push(s.light.clone())
            }
            None => {
                return Err(LightingError::UnknownLight {
                    given: s.light.clone(),
                    names: table.lights.iter().map(|l| l.name.clone()).collect(),
                });
            }
        }
    }
    let mut flux_per_path = Vec::with_capacity(table.lights.len());
    for (k, record) in table.lights.iter().enumerate() {
        let power = match scene.light_index(&record.name) {
            None => {
                notes.push(format!(
                    "light '{}' is not in the scene any more: its samples are ignored",
                    record.name
                ));
                Rgb::ZERO
            }
            Some(i) if scene.light_shapes[i] != record.shape => {
                return Err(LightingError::ShapeChanged(record.name.clone()));
            }
            Some(i) => {
                let now = scene.lights[i].power();
                if (now - record.power).abs().max_element() > 1e-6 * record.power.max_element().max(1e-30) {
                    notes.push(format!(
                        "light '{}': power changed since the trace ({:?} W → {:?} W); relit exactly",
                        record.name,
                        record.power.to_array(),
                        now.to_array()
                    ));
                }
                now
            }
        };
        let phi = power * factors[k];
        flux_per_path.push(if record.paths == 0 { Rgb::ZERO } else { phi / record.paths as f32 });
        if record.paths == 0 && phi.max_element() > 0.0 {
            return Err(LightingError::NotTraced(record.name.clone()));
        }
    }
    for (i, light) in scene.lights.iter().enumerate() {
        let traced = table.lights.iter().any(|r| r.name == light.name());
        let off = switched_off_untraced.iter().any(|n| n == light.name());
        if !traced && !off && light.power().max_element() > 0.0 {
            return Err(LightingError::NotTraced(scene.lights[i].name().to_string()));
        }
    }
    Ok(Lighting { flux_per_path, notes })
}

/// Why two light tables cannot be merged.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MergeError {
    /// A light has the same name but another shape.
    #[error("light '{0}' differs in shape between the datasets: they were traced from different scenes")]
    ShapeChanged(String),
}

/// The light table of the union of two independent datasets of the same scene, and where each
/// of `b`'s lights went in it. Lights are matched by name (and must have the same shape): a
/// light in both has N_k summed; a light in only one keeps its N_k (e.g. `b` is a copy of `a`
/// that gained a light by `add-light`) — exact too, since each light's energy is split only among
/// its own paths. `a`'s lights keep their indices; `b`'s new lights follow in `b`'s order.
/// Powers are taken from `a` (samples do not depend on power; a difference is relighting).
pub fn merge_tables(a: &LightTable, b: &LightTable) -> Result<(LightTable, Vec<u32>), MergeError> {
    let mut out = a.clone();
    let mut b_index = Vec::with_capacity(b.lights.len());
    for y in &b.lights {
        match out.lights.iter().position(|x| x.name == y.name) {
            Some(k) if out.lights[k].shape != y.shape => {
                return Err(MergeError::ShapeChanged(y.name.clone()));
            }
            Some(k) => {
                out.lights[k].paths += y.paths;
                b_index.push(k as u32);
            }
            None => {
                b_index.push(out.lights.len() as u32);
                out.lights.push(y.clone());
            }
        }
    }
    Ok((out, b_index))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::LightRecord;

    fn table(lights: &[(&str, u8, u64)]) -> LightTable {
        LightTable {
            lights: lights
                .iter()
                .map(|&(name, shape, paths)| LightRecord {
                    name: name.into(),
                    shape: [shape; 16],
                    power: Rgb::ONE,
                    paths,
                })
                .collect(),
        }
    }

    #[test]
    fn merging_unites_light_tables_by_name_and_sums_their_paths() {
        let a = table(&[("sun", 1, 10), ("lamp", 2, 20)]);
        let b = table(&[("bulb", 3, 5), ("lamp", 2, 7), ("sun", 1, 1)]);
        let (m, map) = merge_tables(&a, &b).unwrap();
        assert_eq!(m, table(&[("sun", 1, 11), ("lamp", 2, 27), ("bulb", 3, 5)]));
        assert_eq!(map, [2, 1, 0]);
        let (m, map) = merge_tables(&b, &a).unwrap();
        assert_eq!(m, table(&[("bulb", 3, 5), ("lamp", 2, 27), ("sun", 1, 11)]));
        assert_eq!(map, [2, 1]);
        let moved = table(&[("lamp", 9, 1)]);
        assert_eq!(merge_tables(&a, &moved), Err(MergeError::ShapeChanged("lamp".into())));
    }
}
