//! A meter's reading as a CSV table, the one format `opticks measure` writes and any
//! spreadsheet, pandas or Radiance's tools read. Columns: planes `i,j` (cell along u and v) and
//! `x,y,z` (cell centre, m); points `point,x,y,z,nx,ny,nz`; then per cell or point the
//! irradiance `E_R,E_G,E_B` (W/m²), the illuminance `E_v_lux`, and their standard errors
//! `SE_R,SE_G,SE_B,SE_v_lux`; under a CIE overcast sky alone (`crate::daylight`), last, the
//! daylight factor `DF_percent` (100 × E_v / E_v,h) and its standard error `SE_DF_percent`.
//!
//! Standard errors come from the dataset's independent chunks (`NaN` where a light has a single
//! chunk). The photometric column E_v is by the scene's rule (`opticks_core::scene::
//! Photometry`, computed in the meter's tally): for Radiance `.rad` scenes Radiance's,
//! 179 lm/W · (0.2651·E_R + 0.6701·E_G + 0.0648·E_B), what `rtrace -I` gives in lux; for every
//! other format 683 lm/W · (0.2126·E_R + 0.7152·E_G + 0.0722·E_B), the Rec. 709 luminance
//! weights with the 555 nm luminous efficacy. Either is an approximation, exact only if the
//! RGB channels were radiometric quantities with the spectral shapes the weights assume. The
//! summary names the rule; the columns are the same. Several meters read together
//! ([`csv_of_meters`]) have a first column `meter` naming each line's meter.

use opticks_core::sensor::meter::{MeterLayout, Reading};
use std::fmt::Write;

/// The CSV table of `reading` over `layout`: a header line, then one line per cell (row by
/// row, i fastest) or point, values in `{:e}` so they round-trip exactly. With a horizontal
/// illuminance `daylight` (E_v,h, lux), the daylight factor columns too.
pub fn csv(layout: &MeterLayout, r: &Reading, daylight: Option<f64>) -> String {
    let values = |k: usize| {
        let (v, e) = (r.value[k], r.std_error[k]);
        let mut s = format!(
            "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
            v[0], v[1], v[2], v[3], e[0], e[1], e[2], e[3]
        );
        if let Some(h) = daylight {
            let _ = write!(s, ",{:e},{:e}", 100.0 * v[3] / h, 100.0 * e[3] / h);
        }
        s
    };
    let df = if daylight.is_some() { ",DF_percent,SE_DF_percent" } else { "" };
    let mut csv = String::new();
    match layout {
        MeterLayout::Grid(m) => {
            csv += "i,j,x,y,z,E_R,E_G,E_B,E_v_lux,SE_R,SE_G,SE_B,SE_v_lux";
            csv += df;
            csv += "\n";
            for j in 0..m.ny {
                for i in 0..m.nx {
                    let c = m.cell_centre(i, j);
                    let _ =
                        writeln!(csv, "{i},{j},{},{},{},{}", c.x, c.y, c.z, values((j * m.nx + i) as usize));
                }
            }
        }
        MeterLayout::Points(points) => {
            csv += "point,x,y,z,nx,ny,nz,E_R,E_G,E_B,E_v_lux,SE_R,SE_G,SE_B,SE_v_lux";
            csv += df;
            csv += "\n";
            for (k, p) in points.iter().enumerate() {
                let (c, n) = (p.position, p.normal);
                let _ = writeln!(csv, "{k},{},{},{},{},{},{},{}", c.x, c.y, c.z, n.x, n.y, n.z, values(k));
            }
        }
    }
    csv
}

/// The CSV table of several meters, each with its name: a first column `meter` naming each
/// line's meter (quoted as CSV quotes a field when the name holds a comma, a quote or a line
/// break), then [`csv`]'s columns and lines, meter after meter. The meters are of one kind (all
/// grids or all points), so that the columns agree.
pub fn csv_of_meters(meters: &[(&str, &MeterLayout, &Reading)], daylight: Option<f64>) -> String {
    let mut out = String::new();
    for (k, (name, layout, reading)) in meters.iter().enumerate() {
        let name = csv_field(name);
        let table = csv(layout, reading, daylight);
        let mut lines = table.lines();
        let header = lines.next().unwrap_or_default();
        if k == 0 {
            let _ = writeln!(out, "meter,{header}");
        }
        for line in lines {
            let _ = writeln!(out, "{name},{line}");
        }
    }
    out
}

/// A CSV field: as it is, or quoted (quotes doubled) when it holds a comma, a quote or a line
/// break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) { format!("\"{}\"", s.replace('"', "\"\"")) } else { s.to_string() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use opticks_core::math::Vec3;
    use opticks_core::sensor::meter::MeterPoint;

    #[test]
    fn points_give_a_header_and_a_line_each() {
        let p = |x: f32| MeterPoint { position: Vec3::new(x, 0.0, 0.0), normal: Vec3::Y };
        let layout = MeterLayout::Points(vec![p(0.0), p(1.5)]);
        let reading = Reading { value: vec![[1.0, 2.0, 3.0, 4.0]; 2], std_error: vec![[0.5; 4]; 2] };
        let text = csv(&layout, &reading, None);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("point,x,y,z,nx,ny,nz,E_R") && lines[0].ends_with("SE_v_lux"));
        assert_eq!(lines[2], "1,1.5,0,0,0,1,0,1e0,2e0,3e0,4e0,5e-1,5e-1,5e-1,5e-1");
        // Under an overcast sky of E_v,h = 8 lux: DF 50 % ± 6.25 %, appended.
        let text = csv(&layout, &reading, Some(8.0));
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].ends_with(",SE_v_lux,DF_percent,SE_DF_percent"));
        assert_eq!(lines[2], "1,1.5,0,0,0,1,0,1e0,2e0,3e0,4e0,5e-1,5e-1,5e-1,5e-1,5e1,6.25e0");
    }

    #[test]
    fn several_meters_are_named_in_a_first_column() {
        let p = |x: f32| MeterPoint { position: Vec3::new(x, 0.0, 0.0), normal: Vec3::Y };
        let (a, b) = (MeterLayout::Points(vec![p(0.0)]), MeterLayout::Points(vec![p(1.0), p(2.0)]));
        let reading = |n| Reading { value: vec![[1.0, 2.0, 3.0, 4.0]; n], std_error: vec![[0.5; 4]; n] };
        let (ra, rb) = (reading(1), reading(2));
        let text = csv_of_meters(&[("floor", &a, &ra), ("wall, north", &b, &rb)], None);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4, "{text}");
        assert_eq!(lines[0], format!("meter,{}", csv(&a, &ra, None).lines().next().unwrap()));
        assert_eq!(lines[1], format!("floor,{}", csv(&a, &ra, None).lines().nth(1).unwrap()));
        assert!(lines[3].starts_with("\"wall, north\",1,2,0,0,"), "{}", lines[3]);
        assert_eq!(csv_field("a\"b"), "\"a\"\"b\"");
    }
}
