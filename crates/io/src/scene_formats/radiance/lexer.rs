//! Radiance scene text → located records: each primitive (`modifier type identifier`, then its
//! string, integer and real argument lists, each a count followed by that many words; `alias`
//! takes one word, the name it refers to, instead) or `!command` line, every word with its
//! `file:line:column`. Comments (`#` to the end of the line) and commands are recognised where
//! a primitive may start, as Radiance's own readers do; inside an argument list `#` is an
//! ordinary word. A word in double or single quotes may hold spaces (Radiance's `fgetword`).
//!
//! Nothing is allocated from a count before the words it counts have been read, so a count of
//! 10¹² ends at the end of the file with an error, not an allocation.

use super::err;
use crate::scene_formats::{FileLocation, SceneFileError};
use std::path::Path;

/// A word of the file and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Word {
    /// The word, without its quotes.
    pub text: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column (bytes).
    pub column: u32,
}

/// A primitive as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Primitive {
    /// The modifier's name (`void` for none).
    pub modifier: Word,
    /// The type (`polygon`, `plastic`, …).
    pub kind: Word,
    /// The identifier.
    pub ident: Word,
    /// For `alias`: the name it refers to; no argument lists are read then.
    pub alias_of: Option<Word>,
    /// The string arguments.
    pub strings: Vec<Word>,
    /// The integer arguments.
    pub ints: Vec<i64>,
    /// The real arguments.
    pub reals: Vec<f64>,
}

impl Primitive {
    /// How errors name it: `type identifier`.
    pub fn describe(&self) -> String {
        format!("{} {}", self.kind.text, self.ident.text)
    }
}

/// One record of a Radiance file.
#[derive(Clone, Debug, PartialEq)]
pub enum Record {
    /// A primitive.
    Primitive(Primitive),
    /// A `!command` line (with backslash-newline continuations joined): its words, split as a
    /// shell would split plain words and quotes, and where the `!` is.
    Command {
        /// The words after the `!`.
        words: Vec<String>,
        /// The whole command as written (for messages).
        text: String,
        /// 1-based line of the `!`.
        line: u32,
        /// 1-based column of the `!`.
        column: u32,
    },
}

struct Lexer<'a> {
    text: &'a [u8],
    pos: usize,
    line: u32,
    column: u32,
    file: &'a Path,
}

impl<'a> Lexer<'a> {
    fn peek(&self) -> Option<u8> {
        self.text.get(self.pos).copied()
    }

    fn bump(&mut self) -> Option<u8> {
        let c = self.peek()?;
        self.pos += 1;
        if c == b'\n' {
            self.line += 1;
            self.column = 1;
        } else {
            self.column += 1;
        }
        Some(c)
    }

    fn skip_space(&mut self) {
        while self.peek().is_some_and(|c| c.is_ascii_whitespace()) {
            self.bump();
        }
    }

    /// The next whitespace-separated (or quoted) word; `None` at the end of the file.
    fn word(&mut self) -> Result<Option<Word>, SceneFileError> {
        self.skip_space();
        let (line, column) = (self.line, self.column);
        let Some(first) = self.peek() else { return Ok(None) };
        let mut bytes = Vec::new();
        if first == b'"' || first == b'\'' {
            self.bump();
            loop {
                match self.bump() {
                    Some(c) if c == first => break,
                    Some(c) => bytes.push(c),
                    None => return Err(self.error_at(line, column, "the file ends inside a quoted word")),
                }
            }
        } else {
            while let Some(c) = self.peek().filter(|c| !c.is_ascii_whitespace()) {
                bytes.push(c);
                self.bump();
            }
        }
        Ok(Some(Word { text: String::from_utf8_lossy(&bytes).into_owned(), line, column }))
    }

    fn error_at(&self, line: u32, column: u32, message: &str) -> SceneFileError {
        err(&FileLocation { file: self.file.to_path_buf(), line, column }, "syntax", message.to_string())
    }

    /// The next word, which must exist: `what` names it in the error at the end of the file.
    fn expect(&mut self, what: &str, of: &str) -> Result<Word, SceneFileError> {
        match self.word()? {
            Some(w) => Ok(w),
            None => Err(self.error_at(self.line, self.column, &format!("the file ends before {what}{of}"))),
        }
    }

    /// A count of arguments.
    fn count(&mut self, what: &str, of: &str) -> Result<usize, SceneFileError> {
        let w = self.expect(&format!("the number of {what} arguments"), of)?;
        w.text.parse::<usize>().map_err(|_| {
            self.error_at(
                w.line,
                w.column,
                &format!("expected the number of {what} arguments{of}, found \"{}\"", w.text),
            )
        })
    }

    /// The rest of a `!` line, continuation lines joined.
    fn command(&mut self) -> String {
        let mut text = Vec::new();
        while let Some(c) = self.bump() {
            match c {
                b'\n' => break,
                b'\\' if self.peek() == Some(b'\n') => {
                    self.bump();
                    text.push(b' ');
                }
                _ => text.push(c),
            }
        }
        String::from_utf8_lossy(&text).trim_end().to_string()
    }
}

/// Splits a command line into words: whitespace separates, quotes group.
fn split_command(text: &str) -> Vec<String> {
    let mut words = Vec::new();
    let mut chars = text.chars().peekable();
    loop {
        while chars.peek().is_some_and(|c| c.is_whitespace()) {
            chars.next();
        }
        let Some(&first) = chars.peek() else { break };
        let mut word = String::new();
        if first == '"' || first == '\'' {
            chars.next();
            for c in chars.by_ref() {
                if c == first {
                    break;
                }
                word.push(c);
            }
        } else {
            while let Some(c) = chars.peek().copied().filter(|c| !c.is_whitespace()) {
                word.push(c);
                chars.next();
            }
        }
        words.push(word);
    }
    words
}

/// Reads the records of a Radiance file's text (see the module docs).
pub fn parse(text: &[u8], file: &Path) -> Result<Vec<Record>, SceneFileError> {
    let mut lx = Lexer { text, pos: 0, line: 1, column: 1, file };
    let mut records = Vec::new();
    loop {
        lx.skip_space();
        match lx.peek() {
            None => break,
            Some(b'#') => while lx.bump().is_some_and(|c| c != b'\n') {},
            Some(b'!') => {
                let (line, column) = (lx.line, lx.column);
                lx.bump();
                let text = lx.command();
                records.push(Record::Command { words: split_command(&text), text, line, column });
            }
            Some(_) => records.push(Record::Primitive(primitive(&mut lx)?)),
        }
    }
    Ok(records)
}

fn primitive(lx: &mut Lexer) -> Result<Primitive, SceneFileError> {
    let modifier = lx.expect("a modifier", "")?;
    let kind = lx.expect("the primitive's type", &format!(" after modifier \"{}\"", modifier.text))?;
    let ident =
        lx.expect("the primitive's identifier", &format!(" after \"{} {}\"", modifier.text, kind.text))?;
    let of = format!(" of {} {}", kind.text, ident.text);
    let mut p = Primitive {
        modifier,
        kind,
        ident,
        alias_of: None,
        strings: Vec::new(),
        ints: Vec::new(),
        reals: Vec::new(),
    };
    if p.kind.text == "alias" {
        p.alias_of = Some(lx.expect("the name an alias refers to", &of)?);
        return Ok(p);
    }
    for _ in 0..lx.count("string", &of)? {
        let w = lx.expect("a string argument", &of)?;
        p.strings.push(w);
    }
    for _ in 0..lx.count("integer", &of)? {
        let w = lx.expect("an integer argument", &of)?;
        let v = w.text.parse::<i64>().map_err(|_| {
            lx.error_at(w.line, w.column, &format!("expected an integer argument{of}, found \"{}\"", w.text))
        })?;
        p.ints.push(v);
    }
    for _ in 0..lx.count("real", &of)? {
        let w = lx.expect("a real argument", &of)?;
        let v = parse_real(&w.text).ok_or_else(|| {
            lx.error_at(w.line, w.column, &format!("expected a real argument{of}, found \"{}\"", w.text))
        })?;
        p.reals.push(v);
    }
    Ok(p)
}

/// A finite real as Radiance writes them (`1`, `-.5`, `2e-3`, `+4.`); not `inf` or `nan`.
pub fn parse_real(s: &str) -> Option<f64> {
    let plain = s.bytes().all(|c| c.is_ascii_digit() || matches!(c, b'.' | b'-' | b'+' | b'e' | b'E'));
    s.parse::<f64>().ok().filter(|v| plain && v.is_finite())
}

/// Why an option of a command (`xform -t`, a view's `-vp`) lacks its number.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NumberError {
    /// The words end before the number.
    #[error("{option} needs a number")]
    Missing {
        /// The option.
        option: String,
    },
    /// The word is not a finite real ([`parse_real`]).
    #[error("{option}: \"{word}\" is not a number")]
    NotANumber {
        /// The option.
        option: String,
        /// The word found.
        word: String,
    },
}

/// Word `i` of `words` as the number `option` takes ([`parse_real`]).
pub fn option_number(words: &[impl AsRef<str>], i: usize, option: &str) -> Result<f64, NumberError> {
    let Some(word) = words.get(i).map(AsRef::as_ref) else {
        return Err(NumberError::Missing { option: option.to_string() });
    };
    parse_real(word)
        .ok_or_else(|| NumberError::NotANumber { option: option.to_string(), word: word.to_string() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_words_and_positions() {
        let text = b"# a comment\nvoid plastic red\n0\n0\n5 .5 0 0 0 0\n  !xform -t 1 0 0 \\\n  b.rad\nred polygon \"my floor\" 0 0 9 0 0 0 1 0 0 1 1 0\nvoid alias r2 red\n";
        let r = parse(text, Path::new("a.rad")).unwrap();
        assert_eq!(r.len(), 4);
        let Record::Primitive(p) = &r[0] else { panic!() };
        assert_eq!((p.kind.text.as_str(), p.ident.line, p.ident.column), ("plastic", 2, 14));
        assert_eq!(p.reals, [0.5, 0.0, 0.0, 0.0, 0.0]);
        let Record::Command { words, line, column, .. } = &r[1] else { panic!() };
        assert_eq!((words.join(" ").as_str(), *line, *column), ("xform -t 1 0 0 b.rad", 6, 3));
        let Record::Primitive(p) = &r[2] else { panic!() };
        assert_eq!((p.ident.text.as_str(), p.reals.len(), p.ident.line), ("my floor", 9, 8));
        let Record::Primitive(p) = &r[3] else { panic!() };
        assert_eq!(p.alias_of.as_ref().unwrap().text, "red");
    }

    #[test]
    fn errors_are_located() {
        let e = parse(b"void plastic red\n0\n0\n5 .5 x 0 0 0\n", Path::new("a.rad")).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("a.rad:4:6: syntax: expected a real argument of plastic red, found \"x\""),
            "{e}"
        );
        let e = parse(b"void plastic red\n0\n0\n5 .5 nan 0 0 0\n", Path::new("a.rad")).unwrap_err();
        assert!(e.to_string().contains("found \"nan\""), "{e}");
        let e = parse(b"void plastic red 0 0 99999999999 1", Path::new("a.rad")).unwrap_err();
        assert!(e.to_string().contains("the file ends before a real argument of plastic red"), "{e}");
        let e = parse(b"void plastic", Path::new("a.rad")).unwrap_err();
        assert!(e.to_string().contains("the file ends before the primitive's identifier"), "{e}");
        let e = parse(b"void plastic red x", Path::new("a.rad")).unwrap_err();
        assert!(
            e.to_string().starts_with("a.rad:1:18: syntax: expected the number of string arguments"),
            "{e}"
        );
    }
}
