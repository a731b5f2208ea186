//! Relighting: how stored samples are turned into flux when rendering against the current
//! scene. Exact, not an approximation, because a sample of light k carries Φ_k·β/N_k and β does
//! not depend on Φ_k: relighting scales or recolours Φ_k (0 switches a light off) — nothing else
//! changes. The scene file may also change a light's power directly: the scene's current power
//! is used. A light's *shape* (where and how it emits) must be unchanged, or its samples are
//! invalid.

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
    /// Per light of the table, the factor the caller's scales multiply its scene power by (1
    /// unless scaled, 0 switched off): what a quantity computed from the scene's light itself
    /// (a sky's horizontal illuminance) must be multiplied by to stay consistent.
    pub factors: Vec<Rgb>,
    /// Things the user should know (a light relit by the scene file, a light no longer in it).
    pub notes: Vec<String>,
}

/// Why a dataset cannot be lit by a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LightingError {
    /// A scale named a light that is neither in the dataset nor in the scene.
    #[error("no light '{given}': the dataset's lights are {} (give a name or an index)", names.join(", "))]
    UnknownLight {
        /// What was given.
        given: String,
        /// The dataset's light names.
        names: Vec<String>,
    },
    /// Two scales name the same light (by name or index): refused rather than multiplied.
    #[error("light '{0}' is given more than one --light scale; give it one")]
    Repeated(String),
    /// The light moved or changed shape since the trace.
    #[error("light '{0}' has moved or changed shape since the trace: its samples no longer apply")]
    ShapeChanged(String),
    /// The scene has a light the dataset never traced (and that is not switched off): its
    /// paths must be added to the dataset, or its power scaled to 0.
    #[error("light '{0}' of the scene has no paths in the dataset")]
    NotTraced(String),
}

/// Works out the flux per path of every dataset light for rendering against `scene`, after the
/// `scales`. Dataset lights are matched to scene lights by name.
pub fn lighting(table: &LightTable, scene: &Scene, scales: &[LightScale]) -> Result<Lighting, LightingError> {
    let mut notes = Vec::new();
    let mut factors = vec![Rgb::ONE; table.lights.len()];
    let mut switched_off_untraced = Vec::new();
    let mut scaled = vec![false; table.lights.len()];
    for s in scales {
        let by_index = s.light.parse::<usize>().ok().filter(|&i| i < table.lights.len());
        match by_index.or_else(|| table.lights.iter().position(|l| l.name == s.light)) {
            Some(k) if scaled[k] => return Err(LightingError::Repeated(table.lights[k].name.clone())),
            Some(k) => {
                factors[k] *= s.factor;
                scaled[k] = true;
            }
            None if switched_off_untraced.contains(&s.light) => {
                return Err(LightingError::Repeated(s.light.clone()));
            }
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
                        "light '{}': power changed since the trace ({} W → {} W); relit exactly",
                        record.name,
                        rgb(record.power),
                        rgb(now)
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
    Ok(Lighting { flux_per_path, factors, notes })
}

/// "1.8, 1.8, 1.8": an RGB triple for messages.
fn rgb(c: Rgb) -> String {
    format!("{}, {}, {}", c.x, c.y, c.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::testing::{cornell_with_bulb, trace_into};
    use crate::scene::cornell_box;

    fn scale(light: &str, factor: Rgb) -> LightScale {
        LightScale { light: light.into(), factor }
    }

    #[test]
    fn lights_are_scaled_by_name_or_index_exactly_per_channel() {
        let scene = Scene::build(&cornell_with_bulb()).unwrap();
        let data = trace_into(&scene, 10_000, 1);
        let table = &data.header.table;
        let plain = lighting(table, &scene, &[]).unwrap();
        assert_eq!(
            plain,
            Lighting {
                flux_per_path: vec![table.flux_per_path(0), table.flux_per_path(1)],
                factors: vec![Rgb::ONE; 2],
                notes: vec![]
            }
        );
        let tint = Rgb::new(3.0, 0.5, 0.0);
        let by_name =
            lighting(table, &scene, &[scale("bulb", tint), scale("light", Rgb::splat(2.0))]).unwrap();
        let by_index = lighting(table, &scene, &[scale("1", tint), scale("0", Rgb::splat(2.0))]).unwrap();
        assert_eq!(by_name, by_index);
        assert_eq!(by_name.factors, [Rgb::splat(2.0), tint]);
        let (phi, n) = (|k: usize| table.lights[k].power, |k: usize| table.lights[k].paths as f32);
        assert_eq!(by_name.flux_per_path, [phi(0) * 2.0 / n(0), phi(1) * tint / n(1)]);
        // One scale per light: a second (by name or by index) is refused, not multiplied in.
        let twice = lighting(table, &scene, &[scale("bulb", Rgb::splat(2.0)), scale("1", Rgb::splat(0.5))]);
        assert_eq!(twice, Err(LightingError::Repeated("bulb".into())));
        let e = lighting(table, &scene, &[scale("light", Rgb::splat(2.0)), scale("light", Rgb::splat(3.0))]);
        assert_eq!(e, Err(LightingError::Repeated("light".into())));
        // 0 switches a light off.
        let off = lighting(table, &scene, &[scale("bulb", Rgb::ZERO)]).unwrap();
        assert_eq!(off.flux_per_path, [plain.flux_per_path[0], Rgb::ZERO]);
        let e = lighting(table, &scene, &[scale("sun", Rgb::ONE)]).unwrap_err();
        assert_eq!(
            e,
            LightingError::UnknownLight { given: "sun".into(), names: vec!["light".into(), "bulb".into()] }
        );
        assert!(e.to_string().contains("sun") && e.to_string().contains("bulb"), "{e}");
    }

    /// Switching the bulb off leaves exactly a trace without it: the ceiling light's chunks of a
    /// two-light trace are those of a trace of the box alone with the same N_k (each light's
    /// blocks have their own random streams), and they carry the same flux per path.
    #[test]
    fn switching_a_light_off_leaves_exactly_a_trace_without_it() {
        let two = Scene::build(&cornell_with_bulb()).unwrap();
        let one = Scene::build(&cornell_box()).unwrap();
        let both = trace_into(&two, 30_000, 1);
        let n_ceiling = both.header.table.lights[0].paths;
        let alone = trace_into(&one, n_ceiling, 1);
        let ceiling: Vec<_> = both.chunks.iter().filter(|c| c.light == 0).cloned().collect();
        assert_eq!(ceiling, alone.chunks);
        let off = lighting(&both.header.table, &two, &[scale("bulb", Rgb::ZERO)]).unwrap();
        let without = lighting(&alone.header.table, &one, &[]).unwrap();
        assert_eq!(off.flux_per_path, [without.flux_per_path[0], Rgb::ZERO]);
        // The bulb adds light.
        assert!((both.flux() - alone.flux()).min_element() > 0.0);
    }

    #[test]
    fn the_scene_may_change_a_power_but_not_a_shape_and_must_not_have_untraced_lights() {
        let two = Scene::build(&cornell_with_bulb()).unwrap();
        let data = trace_into(&two, 10_000, 2);
        let table = &data.header.table;
        // Three times the bulb's intensity in the scene file is `bulb=3`, exactly, with a note.
        let mut brighter = cornell_with_bulb();
        brighter.point_lights[0].intensity *= 3.0;
        let brighter = Scene::build(&brighter).unwrap();
        let relit = lighting(table, &brighter, &[]).unwrap();
        let scaled = lighting(table, &two, &[scale("bulb", Rgb::splat(3.0))]).unwrap();
        for (a, b) in relit.flux_per_path.iter().zip(&scaled.flux_per_path) {
            assert!((*a - *b).abs().max_element() <= 1e-6 * a.max_element(), "{a:?} vs {b:?}");
        }
        assert!(
            relit.notes.len() == 1 && relit.notes[0].contains("bulb': power changed"),
            "{:?}",
            relit.notes
        );
        // A moved light is refused; a light gone from the scene is ignored, with a note.
        let mut moved = cornell_with_bulb();
        moved.point_lights[0].position.x = 0.2;
        let moved = Scene::build(&moved).unwrap();
        assert_eq!(lighting(table, &moved, &[]), Err(LightingError::ShapeChanged("bulb".into())));
        let one = Scene::build(&cornell_box()).unwrap();
        let gone = lighting(table, &one, &[]).unwrap();
        assert_eq!(gone.flux_per_path[1], Rgb::ZERO);
        assert!(gone.notes[0].contains("'bulb' is not in the scene any more"), "{:?}", gone.notes);
        // A scene light without paths must be switched off (by name: it is in no table).
        let boxed = trace_into(&one, 10_000, 3);
        let e = lighting(&boxed.header.table, &two, &[]).unwrap_err();
        assert_eq!(e, LightingError::NotTraced("bulb".into()));
        assert!(!e.to_string().contains("opticks") && !e.to_string().contains("--"), "{e}");
        let off = lighting(&boxed.header.table, &two, &[scale("bulb", Rgb::ZERO)]).unwrap();
        assert_eq!(off.flux_per_path, [boxed.header.table.flux_per_path(0)]);
        let mut unpathed = boxed.header.table.clone();
        unpathed.lights[0].paths = 0;
        assert_eq!(lighting(&unpathed, &one, &[]), Err(LightingError::NotTraced("light".into())));
        assert_eq!(lighting(&unpathed, &one, &[scale("0", Rgb::ZERO)]).unwrap().flux_per_path, [Rgb::ZERO]);
    }
}
