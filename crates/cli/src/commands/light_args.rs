//! `--light NAME_OR_INDEX=SCALE` or `=R,G,B`: relighting at render time. A scalar multiplies the
//! light's power, three numbers multiply its red, green and blue power (a colour change), 0
//! switches it off. Exact, because each light's energy is split only among its own paths.

use anyhow::{Result, bail};
use opticks_core::dataset::LightScale;
use opticks_core::math::Rgb;

/// Parses one `--light` value.
pub fn parse_light_scale(s: &str) -> Result<LightScale> {
    let Some((light, value)) = s.rsplit_once('=') else {
        bail!("'{s}' must look like NAME=SCALE or NAME=R,G,B (e.g. ceiling=0.5, 0=1,0.8,0.6)");
    };
    if light.is_empty() {
        bail!("'{s}': the light name or index is empty");
    }
    let numbers: Vec<f32> = value
        .split(',')
        .map(|x| x.trim().parse::<f32>().map_err(|_| anyhow::anyhow!("'{x}' is not a number in '{s}'")))
        .collect::<Result<_>>()?;
    let factor = match numbers.as_slice() {
        [k] => Rgb::splat(*k),
        [r, g, b] => Rgb::new(*r, *g, *b),
        _ => bail!("'{s}': give one scale or three (R,G,B)"),
    };
    if !factor.is_finite() || factor.min_element() < 0.0 {
        bail!("'{s}': scales must be finite and non-negative");
    }
    Ok(LightScale { light: light.to_string(), factor })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_scalars_colours_and_refuses_nonsense() {
        assert_eq!(parse_light_scale("ceiling=0.5").unwrap().factor, Rgb::splat(0.5));
        let c = parse_light_scale("lamp=1,0.5,0").unwrap();
        assert_eq!((c.light.as_str(), c.factor), ("lamp", Rgb::new(1.0, 0.5, 0.0)));
        assert_eq!(parse_light_scale("a=b=2").unwrap().light, "a=b");
        for bad in ["ceiling", "=1", "x=", "x=1,2", "x=-1", "x=nan", "x=1,2,3,4"] {
            assert!(parse_light_scale(bad).is_err(), "{bad}");
        }
    }
}
