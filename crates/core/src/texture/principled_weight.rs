//! [`PrincipledWeight`]: which float parameter of Mitsuba's `principled` BSDF a texture sets
//! ([`super::ColourSlot::Principled`]). Its own file because the principled BSDF has ten such
//! weights, each with its Mitsuba name and its field, which would crowd the texture module.

use crate::bsdf::Principled;

/// The float parameters of Mitsuba's `principled` that a texture can give, each in [0, 1].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PrincipledWeight {
    /// `roughness`.
    Roughness,
    /// `anisotropic`.
    Anisotropic,
    /// `metallic`.
    Metallic,
    /// `spec_tint`.
    SpecTint,
    /// `sheen`.
    Sheen,
    /// `sheen_tint`.
    SheenTint,
    /// `clearcoat`.
    Clearcoat,
    /// `clearcoat_gloss`.
    ClearcoatGloss,
    /// `flatness`.
    Flatness,
    /// `spec_trans` (its texture also makes the BSDF transmit, [`Principled::has_spec_trans`]).
    SpecTrans,
}

impl PrincipledWeight {
    /// Every weight, in Mitsuba's documentation's order.
    pub const ALL: [PrincipledWeight; 10] = [
        PrincipledWeight::Roughness,
        PrincipledWeight::Anisotropic,
        PrincipledWeight::Metallic,
        PrincipledWeight::SpecTint,
        PrincipledWeight::Sheen,
        PrincipledWeight::SheenTint,
        PrincipledWeight::Clearcoat,
        PrincipledWeight::ClearcoatGloss,
        PrincipledWeight::Flatness,
        PrincipledWeight::SpecTrans,
    ];

    /// Mitsuba's name of the parameter.
    pub fn name(self) -> &'static str {
        match self {
            PrincipledWeight::Roughness => "roughness",
            PrincipledWeight::Anisotropic => "anisotropic",
            PrincipledWeight::Metallic => "metallic",
            PrincipledWeight::SpecTint => "spec_tint",
            PrincipledWeight::Sheen => "sheen",
            PrincipledWeight::SheenTint => "sheen_tint",
            PrincipledWeight::Clearcoat => "clearcoat",
            PrincipledWeight::ClearcoatGloss => "clearcoat_gloss",
            PrincipledWeight::Flatness => "flatness",
            PrincipledWeight::SpecTrans => "spec_trans",
        }
    }

    /// The field of `p` it sets.
    pub fn field(self, p: &mut Principled) -> &mut f32 {
        match self {
            PrincipledWeight::Roughness => &mut p.roughness,
            PrincipledWeight::Anisotropic => &mut p.anisotropic,
            PrincipledWeight::Metallic => &mut p.metallic,
            PrincipledWeight::SpecTint => &mut p.spec_tint,
            PrincipledWeight::Sheen => &mut p.sheen,
            PrincipledWeight::SheenTint => &mut p.sheen_tint,
            PrincipledWeight::Clearcoat => &mut p.clearcoat,
            PrincipledWeight::ClearcoatGloss => &mut p.clearcoat_gloss,
            PrincipledWeight::Flatness => &mut p.flatness,
            PrincipledWeight::SpecTrans => &mut p.spec_trans,
        }
    }
}
