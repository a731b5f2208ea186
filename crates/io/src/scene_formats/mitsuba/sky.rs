//! `<emitter type="gensky">`, `<emitter type="gendaylit">` and `<emitter type="ciesky">`:
//! Opticks extensions that carry a Radiance daylight sky in Mitsuba XML, so either format can
//! hold one (Mitsuba 3 has no CIE or Perez sky), and the CIE general skies, which no Radiance
//! generator writes. The generator's arguments are those of its command line, interpreted
//! exactly as the `.rad` reader interprets a `!gensky`/`!gendaylit` line (`radiance::sky`,
//! never run):
//!
//! ```xml
//! <emitter type="gensky" id="sky">
//!     <string name="arguments" value="3 21 12 +s -a 52 -o 0 -m 0"/>
//!     <!-- Radiance's frame is x east, y north, z up; this turns it to a y-up scene. -->
//!     <transform name="to_world"><rotate x="1" angle="-90"/></transform>
//! </emitter>
//! ```
//!
//! The sky and its ground (the generator's `skyfunc` over the whole sphere, as Radiance's sky
//! and ground domes together) is one environment light named by the emitter's `id`; the sun,
//! when the generator writes one, a directional light `<id>.sun` whose irradiance is its disc's
//! radiance × the disc's solid angle. `to_world` is a rotation from Radiance's frame into the
//! scene's (identity: the scene's z is up). Values keep Radiance's units, W/(sr·m²) as its
//! generators write them.
//!
//! `ciesky` is one of the 15 CIE general skies (ISO 15469 / CIE S 011), `<integer name="type"
//! value="1…15"/>`, under the same `arguments` and `to_world` read by the same code: gensky's
//! sun position and site options, its `-b`/`-B` level (one required) and, for a sun, `-r`/`-R`
//! (`radiance::sky::ciesky`):
//!
//! ```xml
//! <emitter type="ciesky" id="sky">
//!     <integer name="type" value="12"/>
//!     <string name="arguments" value="3 21 12 -a 52 -o 0 -m 0 -B 100 -R 500"/>
//! </emitter>
//! ```

use super::Result;
use super::build::Builder;
use super::properties::Props;
use super::xml::Element;
use crate::scene_formats::radiance::CieGeneralSky;
use crate::scene_formats::radiance::sky::{self, Generator};
use glam::DVec3;
use opticks_core::math::{Mat3, Rgb};
use opticks_core::scene::{DirectionalLightDesc, EnvironmentLightDesc};
use std::f64::consts::PI;

/// `gensky`.
pub fn gensky<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    generated(b, e, ty, name, Generator::Gensky)
}

/// `gendaylit`.
pub fn gendaylit<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    generated(b, e, ty, name, Generator::Gendaylit)
}

/// `ciesky`: the type, then the arguments as gensky's element reads them.
pub fn ciesky<'d>(b: &mut Builder<'d>, e: &'d Element, ty: &str, name: String) -> Result<()> {
    let mut p = Props::of(e)?;
    super::emitter::no_objects(&p, ty)?;
    let (n, tnode) = p.int("type")?.ok_or_else(|| {
        e.err(format!(
            "a {ty} emitter needs its CIE general sky type (ISO 15469 / CIE S 011): <integer name=\"type\" value=\"1…15\"/>"
        ))
    })?;
    let model = u8::try_from(n).ok().and_then(CieGeneralSky::new).ok_or_else(|| {
        tnode.attr_err(
            "value",
            format!("CIE general sky type {n}: the types are 1 to 15 (ISO 15469 / CIE S 011)"),
        )
    })?;
    let (arguments, anode, rotation) = arguments(b, p, e, ty)?;
    let words: Vec<String> = arguments.split_whitespace().map(str::to_string).collect();
    let g =
        sky::ciesky(model, &words).map_err(|m| anode.attr_err("value", format!("{ty} {arguments}: {m}")))?;
    add(b, e, ty, name, rotation, g)
}

fn generated<'d>(
    b: &mut Builder<'d>,
    e: &'d Element,
    ty: &str,
    name: String,
    generator: Generator,
) -> Result<()> {
    let p = Props::of(e)?;
    super::emitter::no_objects(&p, ty)?;
    let (arguments, anode, rotation) = arguments(b, p, e, ty)?;
    let words: Vec<String> = arguments.split_whitespace().map(str::to_string).collect();
    let g = sky::generate(generator, &words)
        .map_err(|m| anode.attr_err("value", format!("{ty} {arguments}: {m}")))?;
    add(b, e, ty, name, rotation, g)
}

/// The `arguments` string (required) and its element, and `to_world`'s rotation; the last of
/// `p` read.
fn arguments<'d>(
    b: &mut Builder<'d>,
    mut p: Props<'d>,
    e: &'d Element,
    ty: &str,
) -> Result<(String, &'d Element, Mat3)> {
    let (arguments, anode) = p.string("arguments")?.ok_or_else(|| {
        e.err(format!(
            "a {ty} emitter needs its command line's arguments: <string name=\"arguments\" value=\"…\"/>"
        ))
    })?;
    let rotation = match p.transform("to_world")? {
        Some((t, tnode)) => super::emitter::environment_frame(&t, tnode)?,
        None => Mat3::IDENTITY,
    };
    b.finish(&p);
    Ok((arguments, anode, rotation))
}

/// The sky (with its ground) as the environment light `name`, its sun as `<name>.sun`.
fn add(
    b: &mut Builder<'_>,
    e: &Element,
    ty: &str,
    name: String,
    rotation: Mat3,
    g: sky::Generated,
) -> Result<()> {
    for w in &g.warnings {
        b.warn(e, format!("{ty}: {w}"));
    }
    b.desc.environment_lights.push(EnvironmentLightDesc {
        name: name.clone(),
        source: Builder::source(e),
        radiance: sky::sky_map(DVec3::Z, PI, Rgb::ONE, |d| g.func.brightness(d)),
        to_world: rotation * sky::MAP_TO_WORLD,
        sky: Some(g.func.model()),
    });
    if let Some(sun) = g.sun.filter(|s| s.radiance > 0.0) {
        let irradiance = Rgb::splat((sun.radiance * sky::disc_solid_angle(sun.diameter_degrees)) as f32);
        let direction = -(rotation.as_dmat3() * sun.toward);
        let light =
            DirectionalLightDesc::new(format!("{name}.sun"), Builder::source(e), direction, irradiance)
                .map_err(|m| e.err(m.to_string()))?;
        b.desc.directional_lights.push(light);
    }
    Ok(())
}
