//! Light inputs shared by the scene loaders (Mitsuba, VRML97, glTF): an IES luminaire file read
//! and checked as a light's profile ([`ies_luminaire`]).
//!
//! The lights themselves, and every constraint on their parameters, are the core's
//! ([`opticks_core::light::check`],
//! [`PointLightDesc::spot`](opticks_core::scene::PointLightDesc::spot),
//! [`DirectionalLightDesc::new`](opticks_core::scene::DirectionalLightDesc::new),
//! [`opticks_core::light::axis_frame`]): the loaders call them and place the core's error at
//! the element.

use opticks_core::light::EmissionProfile;

/// An IES (LM-63) file read and checked as a light's profile: its candela grid, the flux that
/// distribution carries (W per unit colour: lumens/683) and, when the file's rated lumens
/// differ from that flux by more than 5 %, a warning saying so.
pub struct IesLuminaire {
    /// The photometric grid.
    pub profile: opticks_core::light::IesProfile,
    /// Flux of the candela distribution, W (into the front hemisphere if built so).
    pub watts: f32,
    /// The rated-lumens mismatch, if any, as a message for the loader to place.
    pub warning: Option<String>,
}

/// Why an IES file could not be a light's profile.
#[derive(Debug, thiserror::Error)]
pub enum IesLuminaireError {
    /// The file could not be read or parsed (the message names the file and line).
    #[error(transparent)]
    File(#[from] crate::ies::IesError),
    /// Its candela grid is not a valid profile.
    #[error("{}: {source}", path.display())]
    Profile {
        /// The IES file.
        path: std::path::PathBuf,
        /// What the core found wrong.
        source: opticks_core::light::ProfileError,
    },
}

/// Reads the IES file at `path` and builds it as a point light's profile, or an area light's
/// (cut at 90°) if `hemisphere`. The error message names the IES file (and its line).
pub fn ies_luminaire(path: &std::path::Path, hemisphere: bool) -> Result<IesLuminaire, IesLuminaireError> {
    let ies = crate::ies::load_ies(path)?;
    let built =
        opticks_core::light::BuiltProfile::build(&EmissionProfile::Ies(ies.profile.clone()), hemisphere)
            .map_err(|source| IesLuminaireError::Profile { path: path.to_path_buf(), source })?;
    let watts = built.integral();
    let warning = ies.rated_lumens().and_then(|rated| {
        let actual = watts * opticks_core::light::LUMENS_PER_WATT;
        let part = if hemisphere { " into the front hemisphere (an area light is one-sided)" } else { "" };
        ((actual / rated - 1.0).abs() > 0.05).then(|| {
            format!(
                "the file rates {rated} lm but its candela distribution carries {actual:.1} lm{part}; \
                 the distribution's flux is used"
            )
        })
    });
    Ok(IesLuminaire { profile: ies.profile, watts, warning })
}
