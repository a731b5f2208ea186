//! The daylight factor (CIE; BS EN 17037): DF = 100 % × E_v / E_v,h, the illuminance at a point
//! over the horizontal illuminance the same sky gives an unobstructed point in the open, without
//! ground reflection — defined under the CIE standard overcast sky, whose luminance
//! (1 + 2 cos θ)/3 does not depend on the sun, so that DF is a property of the building alone.
//!
//! **When.** A dataset gives a DF when the lights that are on (after `--light` relighting) are
//! CIE overcast skies and nothing else: environment lights made from Radiance's `!gensky -c`
//! (`opticks_core::scene::SkyModel::CieOvercast`) — the sky dome, and the same sky's ground
//! dome if it is on (its light reaching a point is the externally reflected component, part of
//! E_v; it gives a horizontal plane in the open nothing). A sun, a lamp, another sky model
//! (`gensky +s`, `-i`, `-u`, `gendaylit`), or only the ground dome on: no DF
//! ([`DaylightError`] says why).
//!
//! **E_v,h** is computed from the sky lights themselves, not measured: for each such light on,
//! ∫ L(ω) cos θ dω over the hemisphere above the horizon of its environment map
//! (`opticks_core::light::EnvironmentLight::pole_irradiance`, exact for the rasterised sky the
//! renderer samples, so a horizontal point in the open reads DF = 100 % up to noise), times
//! its `--light` factor, summed, in lux by the scene's photometric rule (`opticks_core::scene::
//! Photometry`: Radiance's 179 lm/W for a `.rad` scene, as the meter's E_v, so that DF is a
//! ratio of like quantities). Relighting the sky therefore leaves DF unchanged: numerator and
//! denominator scale together. The standard
//! error of DF is that of E_v over the same (exact) E_v,h.

use crate::opened::LitDataset;
use opticks_core::light::Light;
use opticks_core::math::Rgb;
use opticks_core::scene::SkyModel;

/// What a daylight factor is a percentage of.
#[derive(Clone, Debug, PartialEq)]
pub struct DaylightBasis {
    /// E_v,h: the horizontal illuminance of the sky in the open, no ground (lux; relit).
    pub horizontal_lux: f64,
    /// The CIE overcast sky lights that are on (dome and ground), by name.
    pub skies: Vec<String>,
}

impl DaylightBasis {
    /// DF (%) of an illuminance `lux`.
    pub fn percent(&self, lux: f64) -> f64 {
        100.0 * lux / self.horizontal_lux
    }
}

/// Why a dataset gives no daylight factor as lit.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum DaylightError {
    /// No CIE overcast sky is on, and no other sky model either.
    #[error(
        "no daylight factor: no CIE overcast sky is on (the daylight factor needs the environment light of a \
         Radiance `!gensky … -c` sky; lights on: {})",
        list(.0)
    )]
    NoSky(Vec<String>),
    /// The sky that is on is not the CIE overcast sky.
    #[error(
        "no daylight factor: light '{light}' is {model}; the daylight factor is defined under the CIE overcast \
         sky (`!gensky … -c`){}",
        if .others.is_empty() { String::new() } else { format!(", alone ({} on too)", lights_are(.others)) }
    )]
    NotOvercast {
        /// The light.
        light: String,
        /// Its model, in words.
        model: String,
        /// The other lights on.
        others: Vec<String>,
    },
    /// A CIE overcast sky is on, and other lights too.
    #[error(
        "no daylight factor: {} on besides the CIE overcast sky ({}), and the daylight factor is the overcast \
         sky's alone; switch {} off with --light NAME=0",
        lights_are(.others),
        .skies.join(", "),
        if .others.len() == 1 { "it" } else { "them" }
    )]
    OtherLights {
        /// The overcast sky lights on.
        skies: Vec<String>,
        /// The other lights on.
        others: Vec<String>,
    },
    /// Only the overcast sky's ground dome is on: no sky above the horizon.
    #[error(
        "no daylight factor: only the ground of the CIE overcast sky is on ({}); its sky dome, switched off, gives \
         no horizontal illuminance to divide by",
        .0.join(", ")
    )]
    GroundOnly(Vec<String>),
}

impl DaylightError {
    /// Whether the scene has a CIE overcast sky, so that a user measuring without
    /// `--daylight-factor` should hear why there is no DF column.
    pub fn worth_a_note(&self) -> bool {
        matches!(self, DaylightError::OtherLights { .. } | DaylightError::GroundOnly(_))
    }
}

fn list(names: &[String]) -> String {
    if names.is_empty() { "none".into() } else { names.join(", ") }
}

fn lights_are(names: &[String]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("'{n}'")).collect();
    match quoted.len() {
        1 => format!("light {} is", quoted[0]),
        _ => format!("lights {} are", quoted.join(", ")),
    }
}

/// The daylight factor's basis for `data` as lit (module docs), or why there is none.
pub fn daylight_basis(data: &LitDataset) -> Result<DaylightBasis, DaylightError> {
    let (mut skies, mut others, mut not_overcast) = (Vec::new(), Vec::new(), None);
    let mut horizontal = Rgb::ZERO;
    let mut dome = false;
    let flux = data.flux_per_path();
    let factors = data.light_factors();
    let lux = |e: Rgb| data.scene().photometry.lux(rgb(e));
    for (k, name) in data.light_names().into_iter().enumerate() {
        if flux[k].max_element() <= 0.0 {
            continue;
        }
        let light = data.scene().light_index(name).map(|i| &data.scene().lights[i]);
        let model = data
            .description()
            .environment_lights
            .iter()
            .find(|e| e.name == name)
            .and_then(|e| e.sky.as_ref());
        match (light, model) {
            (Some(Light::Environment(env)), Some(SkyModel::CieOvercast)) => {
                let e = env.pole_irradiance() * factors[k];
                // A dome above the horizon gives about half its ∫L dω (7/12 for the overcast
                // sky); a ground dome only the sliver its horizon texels interpolate into.
                dome |= lux(e) > 0.1 * lux(env.integral() * factors[k]);
                horizontal += e;
                skies.push(name.to_string());
            }
            (_, Some(SkyModel::Other(m))) => {
                not_overcast.get_or_insert_with(|| (name.to_string(), m.clone()));
                others.push(name.to_string());
            }
            _ => others.push(name.to_string()),
        }
    }
    if skies.is_empty() {
        return Err(match not_overcast {
            Some((light, model)) => {
                others.retain(|o| *o != light);
                DaylightError::NotOvercast { light, model, others }
            }
            None => DaylightError::NoSky(others),
        });
    }
    if !others.is_empty() {
        return Err(DaylightError::OtherLights { skies, others });
    }
    if !dome {
        return Err(DaylightError::GroundOnly(skies));
    }
    Ok(DaylightBasis { horizontal_lux: lux(horizontal), skies })
}

fn rgb(c: Rgb) -> [f64; 3] {
    [c.x as f64, c.y as f64, c.z as f64]
}
