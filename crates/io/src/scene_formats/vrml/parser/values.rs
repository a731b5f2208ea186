//! Field values of the VRML97 parser: the typed value of a field (`SFVec3f`, `MFInt32`, …),
//! lists in brackets, numbers (with VRML's hexadecimal integers and a fast path for short
//! decimal floats), booleans, strings and images. A child of `parser.rs` (an `impl` of its
//! [`Parser`]) so that the statement grammar and the value grammar each stay a file of their own.

use super::super::tree::{FieldType, FieldValue};
use super::{ParseError, Parser, Result};
use crate::scene_formats::vrml::lexer::{Pos, Token};

impl<'a> Parser<'a> {
    pub(super) fn value(&mut self, t: FieldType) -> Result<FieldValue> {
        use FieldType::*;
        Ok(match t {
            SFBool => FieldValue::Bool(self.bool()?),
            SFFloat => FieldValue::Float(self.f32()?),
            SFInt32 => FieldValue::Int(self.i32()?),
            SFTime => FieldValue::Time(self.f64()?),
            SFString => FieldValue::Str(self.string()?),
            SFVec2f => FieldValue::Vec2([self.f32()?, self.f32()?]),
            SFVec3f | SFColor => FieldValue::Vec3(self.vec3()?),
            SFRotation => FieldValue::Rotation([self.f32()?, self.f32()?, self.f32()?, self.f32()?]),
            SFImage => FieldValue::Image(self.image()?),
            SFNode => FieldValue::Node(self.node_statement("a node, USE or NULL")?),
            MFFloat => FieldValue::Floats(self.scalars(parse_f32, "a finite number")?),
            MFInt32 => FieldValue::Ints(self.scalars(parse_int, "a 32-bit integer")?),
            MFTime => FieldValue::Times(self.many(|p| p.f64())?),
            MFString => FieldValue::Strs(self.many(|p| p.string())?),
            MFVec2f => FieldValue::Vec2s(self.many(|p| Ok([p.f32()?, p.f32()?]))?),
            MFVec3f | MFColor => {
                if matches!(self.peek()?, Token::LBracket) {
                    let pos = self.lex.pos();
                    let flat = self.scalars(parse_f32, "a finite number")?;
                    if flat.len() % 3 != 0 {
                        return Err(ParseError {
                            pos,
                            message: format!("{} numbers is not a whole number of 3-vectors", flat.len()),
                        });
                    }
                    FieldValue::Vec3s(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
                } else {
                    FieldValue::Vec3s(vec![self.vec3()?])
                }
            }
            MFRotation => FieldValue::Rotations(self.many(|p| Ok([p.f32()?, p.f32()?, p.f32()?, p.f32()?]))?),
            MFNode => {
                if matches!(self.peek()?, Token::LBracket) {
                    self.next()?;
                    let mut v = Vec::new();
                    while !matches!(self.peek()?, Token::RBracket) {
                        if let Some(n) = self.node_statement("a node, USE or `]`")? {
                            v.push(n);
                        }
                    }
                    self.next()?;
                    FieldValue::Nodes(v)
                } else {
                    FieldValue::Nodes(self.node_statement("a node, USE, NULL or `[`")?.into_iter().collect())
                }
            }
        })
    }

    /// An MF value: `[ v v … ]` or a single `v`.
    pub(super) fn many<T>(&mut self, mut one: impl FnMut(&mut Self) -> Result<T>) -> Result<Vec<T>> {
        if !matches!(self.peek()?, Token::LBracket) {
            return Ok(vec![one(self)?]);
        }
        self.next()?;
        let mut v = Vec::new();
        while !matches!(self.peek()?, Token::RBracket) {
            v.push(one(self)?);
        }
        self.next()?;
        Ok(v)
    }

    /// An MF value of numbers: `[ n n … ]` or a single `n`, read on the lexer's fast path.
    pub(super) fn scalars<T>(&mut self, parse: fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>> {
        if !matches!(self.peek()?, Token::LBracket) {
            let (s, pos) = self.number(what)?;
            return match parse(s) {
                Some(v) => Ok(vec![v]),
                None => Self::expected(what, &Token::Number(s), pos),
            };
        }
        self.next()?;
        let mut v = Vec::new();
        loop {
            if self.peeked.is_none() {
                match self.lex.number_or_close() {
                    Some(Some((s, pos))) => match parse(s) {
                        Some(x) => {
                            v.push(x);
                            continue;
                        }
                        None => return Self::expected(what, &Token::Number(s), pos),
                    },
                    Some(None) => return Ok(v),
                    None => {}
                }
            }
            match self.next()? {
                (Token::Number(s), pos) => match parse(s) {
                    Some(x) => v.push(x),
                    None => return Self::expected(what, &Token::Number(s), pos),
                },
                (Token::RBracket, _) => return Ok(v),
                (t, pos) => return Self::expected(&format!("{what} or `]`"), &t, pos),
            }
        }
    }

    pub(super) fn number(&mut self, what: &str) -> Result<(&'a str, Pos)> {
        match self.next()? {
            (Token::Number(s), pos) => Ok((s, pos)),
            (t, pos) => Self::expected(what, &t, pos),
        }
    }

    pub(super) fn f32(&mut self) -> Result<f32> {
        let (s, pos) = self.number("a number")?;
        match s.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(ParseError { pos, message: format!("{s} is not a finite 32-bit number") }),
            Err(_) => match parse_int(s) {
                Some(i) => Ok(i as f32),
                None => Self::expected("a number", &Token::Number(s), pos),
            },
        }
    }

    pub(super) fn f64(&mut self) -> Result<f64> {
        let (s, pos) = self.number("a number")?;
        match s.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Self::expected("a finite number", &Token::Number(s), pos),
        }
    }

    pub(super) fn i32(&mut self) -> Result<i32> {
        let (s, pos) = self.number("an integer")?;
        match parse_int(s) {
            Some(v) => Ok(v),
            None => Self::expected("a 32-bit integer", &Token::Number(s), pos),
        }
    }

    pub(super) fn vec3(&mut self) -> Result<[f32; 3]> {
        Ok([self.f32()?, self.f32()?, self.f32()?])
    }

    pub(super) fn bool(&mut self) -> Result<bool> {
        match self.next()? {
            (Token::Id("TRUE"), _) => Ok(true),
            (Token::Id("FALSE"), _) => Ok(false),
            (t, pos) => Self::expected("TRUE or FALSE", &t, pos),
        }
    }

    pub(super) fn string(&mut self) -> Result<String> {
        match self.next()? {
            (Token::Str(s), _) => Ok(s),
            (t, pos) => Self::expected("a quoted string", &t, pos),
        }
    }

    pub(super) fn image(&mut self) -> Result<Vec<i32>> {
        let (w, h, c) = (self.i32()?, self.i32()?, self.i32()?);
        let mut v = vec![w, h, c];
        let n = i64::from(w.max(0)) * i64::from(h.max(0));
        for _ in 0..n {
            v.push(self.i32()?);
        }
        Ok(v)
    }
}

/// A finite 32-bit float (integers in hexadecimal too).
pub(super) fn parse_f32(s: &str) -> Option<f32> {
    if let Some(v) = parse_f32_short(s) {
        return Some(v);
    }
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() => Some(v),
        Ok(_) => None,
        Err(_) => parse_int(s).map(|i| i as f32),
    }
}

/// Clinger's fast path for f32: `[-]digits[.digits]` with at most 7 significant digits and at
/// most 10 decimals is m / 10^k with m < 2^24 and 10^k exact in f32, so one f32 division is
/// correctly rounded — the same result as `str::parse`, several times faster.
pub(super) fn parse_f32_short(s: &str) -> Option<f32> {
    const POW10: [f32; 11] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10];
    let b = s.as_bytes();
    let (neg, b) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        _ => (false, b),
    };
    let (mut m, mut digits, mut decimals, mut dot) = (0u32, 0u32, 0usize, false);
    for &c in b {
        match c {
            b'0'..=b'9' => {
                if m > 0 || c != b'0' {
                    digits += 1;
                }
                m = m.wrapping_mul(10).wrapping_add(u32::from(c - b'0'));
                decimals += usize::from(dot);
            }
            b'.' if !dot => dot = true,
            _ => return None,
        }
    }
    if digits > 7 || decimals > 10 || b.is_empty() || b == b"." {
        return None;
    }
    let v = m as f32 / POW10[decimals];
    Some(if neg { -v } else { v })
}

/// A decimal or `0x` hexadecimal 32-bit integer (hex values are bit patterns, as in SFImage).
pub(super) fn parse_int(s: &str) -> Option<i32> {
    // Fast path: short plain decimals.
    let b = s.as_bytes();
    let (neg, digits) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        _ => (false, b),
    };
    if !digits.is_empty() && digits.len() <= 9 && digits.iter().all(u8::is_ascii_digit) {
        let v = digits.iter().fold(0i32, |acc, d| acc * 10 + i32::from(d - b'0'));
        return Some(if neg { -v } else { v });
    }
    parse_int_slow(s)
}

pub(super) fn parse_int_slow(s: &str) -> Option<i32> {
    let (neg, digits) = match s.as_bytes().first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    let v: i64 = if let Some(hex) = digits.strip_prefix("0x").or_else(|| digits.strip_prefix("0X")) {
        let v = u32::from_str_radix(hex, 16).ok()?;
        i64::from(v as i32)
    } else {
        if !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
        digits.parse::<i64>().ok()?
    };
    let v = if neg { -v } else { v };
    i32::try_from(v).ok()
}
