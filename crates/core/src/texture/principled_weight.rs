//! [`PrincipledWeight`]: which float parameter of Mitsuba's `principled` or `principledthin`
//! BSDF a texture sets ([`super::ColourSlot::Principled`]). Its own file because the principled
//! BSDFs have a dozen such weights, each with its Mitsuba name and its field, which would crowd
//! the texture module.

use crate::bsdf::{Principled, PrincipledThin};

/// The float parameters of Mitsuba's `principled` and `principledthin` that a texture can
/// give, each in [0, 1] but `diff_trans` (in [0, 2], [`PrincipledWeight::max`]).
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
    /// `diff_trans` of `principledthin`, in [0, 2].
    DiffTrans,
}

impl PrincipledWeight {
    /// The weights of `principledthin`, in Mitsuba's documentation's order.
    pub const THIN: [PrincipledWeight; 8] = [
        PrincipledWeight::Roughness,
        PrincipledWeight::Anisotropic,
        PrincipledWeight::SpecTrans,
        PrincipledWeight::SpecTint,
        PrincipledWeight::Sheen,
        PrincipledWeight::SheenTint,
        PrincipledWeight::Flatness,
        PrincipledWeight::DiffTrans,
    ];

    /// Every weight of `principled`, in Mitsuba's documentation's order.
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
            PrincipledWeight::DiffTrans => "diff_trans",
        }
    }

    /// The largest value the weight takes (the least is 0): 2 for `diff_trans`, else 1.
    pub fn max(self) -> f32 {
        if self == PrincipledWeight::DiffTrans { 2.0 } else { 1.0 }
    }

    /// The field of `p` it sets; `None` for a weight `principled` does not have.
    pub fn field(self, p: &mut Principled) -> Option<&mut f32> {
        Some(match self {
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
            PrincipledWeight::DiffTrans => return None,
        })
    }

    /// The field of `p` it sets; `None` for a weight `principledthin` does not have.
    pub fn thin_field(self, p: &mut PrincipledThin) -> Option<&mut f32> {
        Some(match self {
            PrincipledWeight::Roughness => &mut p.roughness,
            PrincipledWeight::Anisotropic => &mut p.anisotropic,
            PrincipledWeight::SpecTint => &mut p.spec_tint,
            PrincipledWeight::Sheen => &mut p.sheen,
            PrincipledWeight::SheenTint => &mut p.sheen_tint,
            PrincipledWeight::Flatness => &mut p.flatness,
            PrincipledWeight::SpecTrans => &mut p.spec_trans,
            PrincipledWeight::DiffTrans => &mut p.diff_trans,
            PrincipledWeight::Metallic | PrincipledWeight::Clearcoat | PrincipledWeight::ClearcoatGloss => {
                return None;
            }
        })
    }
}
