//! The property-access layer every plugin builder reads its parameters through: numbers in
//! attributes, and the named properties of a plugin element (`<float name="…" value="…"/>` and
//! its siblings) with typed getters.
//!
//! Each getter checks the property's element type (`<rgb>` where a colour is wanted…), parses
//! its value (every number finite) and returns it with the element it came from, so that a
//! builder reports an impossible value at its own line; the `_or` getters return a default
//! located at the plugin element instead. [`Props::finish`] warns about the parameters nobody
//! read. New value kinds (textures) belong here, as getters, so that every plugin accepts them
//! the same way; spectra are read here, by [`Props::color`].

use super::Result;
use super::spectrum;
use super::transform::{self, Transform};
use super::xml::Element;
use glam::DVec3;
use opticks_core::math::Rgb;

/// The element types that are properties of their parent plugin (the others are nested objects).
const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

impl Element {
    /// The numbers of `s` (the value of attribute `attr`), separated by commas and/or spaces.
    pub fn numbers(&self, attr: &str, s: &str) -> Result<Vec<f64>> {
        s.split(|c: char| c == ',' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(|t| self.number(attr, t))
            .collect()
    }

    /// `t` (from attribute `attr`) as a finite number, finite also as an `f32`.
    pub fn number(&self, attr: &str, t: &str) -> Result<f64> {
        let v: f64 = t
            .trim()
            .parse()
            .map_err(|_| self.attr_err(attr, format!("attribute `{attr}`: \"{t}\" is not a number")))?;
        if !v.is_finite() || (v != 0.0 && !(v as f32).is_finite()) {
            return Err(self.attr_err(attr, format!("attribute `{attr}`: \"{t}\" is not a finite number")));
        }
        Ok(v)
    }

    /// Attribute `attr` as one number, if present.
    pub fn float_attr(&self, attr: &str) -> Result<Option<f64>> {
        match self.attr(attr)? {
            Some(s) => Ok(Some(self.number(attr, s)?)),
            None => Ok(None),
        }
    }

    /// `attr="x, y, z"` (exactly three numbers), if present.
    pub fn vec3_attr(&self, attr: &str) -> Result<Option<DVec3>> {
        let Some(s) = self.attr(attr)? else { return Ok(None) };
        let v = self.numbers(attr, s)?;
        if v.len() != 3 {
            return Err(self.attr_err(attr, format!("attribute `{attr}` needs 3 numbers, found {}", v.len())));
        }
        Ok(Some(DVec3::new(v[0], v[1], v[2])))
    }

    /// `value="x, y, z"` (or `value="s"` if `allow_single_value`) or `x`/`y`/`z` attributes
    /// (each defaulting to `default`).
    pub fn xyz(&self, default: f64, allow_single_value: bool) -> Result<DVec3> {
        if let Some(s) = self.attr("value")? {
            let v = self.numbers("value", s)?;
            return match v.len() {
                3 => Ok(DVec3::new(v[0], v[1], v[2])),
                1 if allow_single_value => Ok(DVec3::splat(v[0])),
                k => Err(self.attr_err("value", format!("attribute `value` needs 3 numbers, found {k}"))),
            };
        }
        let mut out = [default; 3];
        for (o, a) in out.iter_mut().zip(["x", "y", "z"]) {
            if let Some(v) = self.float_attr(a)? {
                *o = v;
            }
        }
        Ok(DVec3::from_array(out))
    }

    /// An error unless this element's tag is one of `tags`.
    pub fn expect_tag(&self, tags: &[&str]) -> Result<()> {
        if tags.contains(&self.tag.as_str()) {
            Ok(())
        } else {
            let list: Vec<String> = tags.iter().map(|t| format!("<{t}>")).collect();
            Err(self.err(format!("wrong property type: expected {}", list.join(" or "))))
        }
    }
}

/// The properties of one plugin element, as Mitsuba collects them, plus its nested objects.
pub struct Props<'d> {
    owner: &'d Element,
    /// Name, element, and whether a getter read it.
    entries: Vec<(&'d str, &'d Element, bool)>,
    objects: Vec<&'d Element>,
}

impl<'d> Props<'d> {
    /// The properties of `owner`: each needs a `name`, given once.
    pub fn of(owner: &'d Element) -> Result<Self> {
        let mut p = Props { owner, entries: Vec::new(), objects: Vec::new() };
        for c in &owner.children {
            if PROPERTY_TAGS.contains(&c.tag.as_str()) {
                let name = c.required("name")?;
                if let Some((_, prev, _)) = p.entries.iter().find(|(k, _, _)| *k == name) {
                    return Err(c.err(format!("parameter `{name}` is given twice (first at {})", prev.at)));
                }
                p.entries.push((name, c, false));
            } else {
                p.objects.push(c);
            }
        }
        Ok(p)
    }

    /// The plugin element these are the properties of.
    pub fn owner(&self) -> &'d Element {
        self.owner
    }

    /// The nested objects (`<bsdf>`, `<ref>`, `<film>`, …), in file order.
    pub fn objects(&self) -> &[&'d Element] {
        &self.objects
    }

    /// The nested `<texture>` or `<ref>` named `name` (its `name` attribute), removed from
    /// [`Self::objects`].
    pub fn take_object(&mut self, name: &str) -> Option<&'d Element> {
        let i = self
            .objects
            .iter()
            .position(|o| matches!(o.tag.as_str(), "texture" | "ref") && o.raw("name") == Some(name))?;
        Some(self.objects.remove(i))
    }

    /// The nested object `o` (one of [`Self::objects`], by identity), removed from them.
    pub fn remove_object(&mut self, o: &'d Element) -> &'d Element {
        self.objects.retain(|x| !std::ptr::eq(*x, o));
        o
    }

    /// The property `name`, marked as read.
    pub fn take(&mut self, name: &str) -> Option<&'d Element> {
        self.entries.iter_mut().find(|(n, _, _)| *n == name).map(|e| {
            e.2 = true;
            e.1
        })
    }

    /// The property `name`, marked as read, which must be one of `tags`.
    pub fn take_as(&mut self, name: &str, tags: &[&str]) -> Result<Option<&'d Element>> {
        let Some(e) = self.take(name) else { return Ok(None) };
        e.expect_tag(tags)?;
        Ok(Some(e))
    }

    /// Marks parameters that are accepted but have no effect in Opticks as read.
    pub fn ignore(&mut self, names: &[&str]) {
        for n in names {
            self.take(n);
        }
    }

    /// Warns (into `warnings`) about parameters nobody read.
    pub fn finish(&self, warnings: &mut Vec<String>) {
        for (name, e, used) in &self.entries {
            if !used {
                warnings.push(
                    e.warning(format!("parameter `{name}` is not supported by Opticks and is ignored")),
                );
            }
        }
    }

    /// A `<float>` or `<integer>`.
    pub fn float(&mut self, name: &str) -> Result<Option<(f64, &'d Element)>> {
        let Some(e) = self.take_as(name, &["float", "integer"])? else { return Ok(None) };
        let v = e.required("value")?;
        Ok(Some((e.number("value", v)?, e)))
    }

    /// [`Self::float`], or `default` (located at the plugin element).
    pub fn float_or(&mut self, name: &str, default: f64) -> Result<(f64, &'d Element)> {
        Ok(self.float(name)?.unwrap_or((default, self.owner)))
    }

    /// An `<integer>`.
    pub fn int(&mut self, name: &str) -> Result<Option<(i64, &'d Element)>> {
        let Some(e) = self.take_as(name, &["integer"])? else { return Ok(None) };
        let v = e.required("value")?;
        let i = v
            .trim()
            .parse::<i64>()
            .map_err(|_| e.attr_err("value", format!("attribute `value`: \"{v}\" is not an integer")))?;
        Ok(Some((i, e)))
    }

    /// A `<boolean>` (`true` or `false`, any case).
    pub fn bool(&mut self, name: &str) -> Result<Option<bool>> {
        let Some(e) = self.take_as(name, &["boolean"])? else { return Ok(None) };
        let v = e.required("value")?;
        match v.trim().to_ascii_lowercase().as_str() {
            "true" => Ok(Some(true)),
            "false" => Ok(Some(false)),
            _ => Err(e.attr_err("value", format!("attribute `value`: \"{v}\" is not true or false"))),
        }
    }

    /// A `<string>`.
    pub fn string(&mut self, name: &str) -> Result<Option<(String, &'d Element)>> {
        let Some(e) = self.take_as(name, &["string"])? else { return Ok(None) };
        Ok(Some((e.required("value")?.to_string(), e)))
    }

    /// [`Self::string`], or `default` (located at the plugin element).
    pub fn string_or(&mut self, name: &str, default: &str) -> Result<(String, &'d Element)> {
        Ok(self.string(name)?.unwrap_or((default.to_string(), self.owner)))
    }

    /// A colour: `<rgb value="r, g, b">` (one number: grey), a `<spectrum>` (a constant, wavelength:value
    /// pairs or an `.spd` `filename`, converted as Mitsuba's RGB variants do, with emitter
    /// semantics when the plugin is an `<emitter>` and without clamping for the indices `eta`
    /// and `k`: [`super::spectrum`]) or a `<float>`.
    pub fn color(&mut self, name: &str) -> Result<Option<(Rgb, &'d Element)>> {
        let Some(e) = self.take_as(name, &["rgb", "spectrum", "float"])? else { return Ok(None) };
        if e.tag == "spectrum" {
            let emitter = self.owner.tag == "emitter";
            return Ok(Some((spectrum_colour(e, emitter, matches!(name, "eta" | "k"))?.as_vec3(), e)));
        }
        let s = e.required("value")?;
        let v = e.numbers("value", s)?;
        let c = match (e.tag.as_str(), v.len()) {
            (_, 1) => DVec3::splat(v[0]),
            ("rgb", 3) => DVec3::new(v[0], v[1], v[2]),
            ("rgb", k) => {
                return Err(e.attr_err("value", format!("an RGB value needs 1 or 3 numbers, found {k}")));
            }
            (_, k) => return Err(e.attr_err("value", format!("expected a single number, found {k}"))),
        };
        Ok(Some((c.as_vec3(), e)))
    }

    /// [`Self::color`], or `default` (located at the plugin element).
    pub fn color_or(&mut self, name: &str, default: Rgb) -> Result<(Rgb, &'d Element)> {
        Ok(self.color(name)?.unwrap_or((default, self.owner)))
    }

    /// A `<point>` or `<vector>`: `x`/`y`/`z` (default 0) or `value="x, y, z"`.
    pub fn point(&mut self, name: &str) -> Result<Option<(DVec3, &'d Element)>> {
        let Some(e) = self.take_as(name, &["point", "vector"])? else { return Ok(None) };
        Ok(Some((e.xyz(0.0, false)?, e)))
    }

    /// A `<transform>` ([`transform::read`]).
    pub fn transform(&mut self, name: &str) -> Result<Option<(Transform, &'d Element)>> {
        let Some(e) = self.take_as(name, &["transform"])? else { return Ok(None) };
        Ok(Some((transform::read(e)?, e)))
    }
}

/// The RGB colour of the `<spectrum>` element `e` (module [`super::spectrum`]'s rules).
fn spectrum_colour(e: &Element, emitter: bool, unbounded: bool) -> Result<DVec3> {
    let (w, v) = match (e.attr("value")?, e.attr("filename")?) {
        (Some(_), Some(_)) | (None, None) => {
            return Err(e.err("a <spectrum> needs either `value` or `filename` (not both)"));
        }
        (Some(s), None) if !s.contains(':') => {
            let v = e.numbers("value", s)?;
            if v.len() != 1 {
                return Err(e.attr_err(
                    "value",
                    format!("expected one number or wavelength:value pairs, found {}", v.len()),
                ));
            }
            return Ok(if emitter { spectrum::uniform_emission(v[0]) } else { DVec3::splat(v[0]) });
        }
        (Some(s), None) => spectrum::parse_pairs(s).map_err(|m| e.attr_err("value", m.to_string()))?,
        (None, Some(file)) => {
            let path = e.resolve(file);
            // Through `input_file`: a device (`/dev/zero`) or a FIFO is refused before it is read.
            let text = crate::input_file::read_to_string(&path).map_err(|err| {
                e.attr_err("filename", format!("cannot read spectrum file {}: {err}", path.display()))
            })?;
            spectrum::parse_spd(&text)
                .map_err(|m| e.attr_err("filename", format!("{}:{}: {m}", path.display(), m.line)))?
        }
    };
    spectrum::check(&w).map_err(|m| e.err(m.to_string()))?;
    Ok(spectrum::to_srgb(&w, &v, !(emitter || unbounded), !emitter))
}
