//! VRML97 lexer (ISO/IEC 14772-1 §5, Annex A): turns the text into tokens with their 1-based
//! line and column, and nothing else.
//!
//! Whitespace is spaces, tabs, line breaks **and commas**; `#` starts a comment to the end of the
//! line (the `#VRML V2.0 utf8` header is checked by the parser before lexing starts). Tokens are
//! identifiers (any run of characters except controls, space and `"#'+,-.[\]{}`, not starting
//! with a digit, `+` or `-`), numbers (decimal, exponent, or hexadecimal integers), quoted
//! strings with `\"` and `\\` escapes, the brackets `{ } [ ]` and the period of `ROUTE a.b TO
//! c.d`.
//!
//! The lexer never allocates except for strings with escapes, and numbers are handed to the
//! parser as sub-slices that it converts with the standard library's allocation-free parsers:
//! that is what lets a 40 MB `IndexedFaceSet` parse at ~300 MB/s (docs/performance.md has the measurement).

use std::fmt;

/// A 1-based position in the text (column in bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Pos {
    /// Line, from 1.
    pub line: u32,
    /// Column (byte offset in the line), from 1.
    pub col: u32,
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.col)
    }
}

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub enum Token<'a> {
    /// An identifier or keyword (`Transform`, `DEF`, `TRUE`, a field name…).
    Id(&'a str),
    /// A number, as written (validated by the parser for the type it expects).
    Number(&'a str),
    /// A quoted string, escapes resolved.
    Str(String),
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `.` (only meaningful in `ROUTE`)
    Period,
    /// End of the text.
    Eof,
}

impl fmt::Display for Token<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Token::Id(s) => write!(f, "`{s}`"),
            Token::Number(s) => write!(f, "number {s}"),
            Token::Str(s) => {
                let short: String = s.chars().take(30).collect();
                write!(f, "string \"{short}{}\"", if short.len() < s.len() { "…" } else { "" })
            }
            Token::LBrace => f.write_str("`{`"),
            Token::RBrace => f.write_str("`}`"),
            Token::LBracket => f.write_str("`[`"),
            Token::RBracket => f.write_str("`]`"),
            Token::Period => f.write_str("`.`"),
            Token::Eof => f.write_str("end of file"),
        }
    }
}

/// A lexical error: where and what.
#[derive(Clone, Debug, PartialEq)]
pub struct LexError {
    /// Where.
    pub pos: Pos,
    /// What is wrong.
    pub message: String,
}

/// The lexer: a cursor over the text. Cheap to copy, so the parser peeks by copying it.
#[derive(Clone, Copy, Debug)]
pub struct Lexer<'a> {
    src: &'a str,
    at: usize,
    line: u32,
    line_start: usize,
}

fn is_id_rest(b: u8) -> bool {
    !(b <= 0x20
        || b == 0x7f
        || matches!(b, b'"' | b'#' | b'\'' | b',' | b'.' | b'[' | b'\\' | b']' | b'{' | b'}'))
}

fn is_number_char(b: u8) -> bool {
    b.is_ascii_alphanumeric() || matches!(b, b'.' | b'+' | b'-')
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `src`.
    pub fn new(src: &'a str) -> Self {
        Lexer { src, at: 0, line: 1, line_start: 0 }
    }

    /// The position of the next character.
    pub fn pos(&self) -> Pos {
        Pos { line: self.line, col: (self.at - self.line_start + 1).min(u32::MAX as usize) as u32 }
    }

    /// Skips whitespace, commas and comments.
    fn skip_blank(&mut self) {
        let b = self.src.as_bytes();
        while let Some(&c) = b.get(self.at) {
            match c {
                b' ' | b'\t' | b',' => self.at += 1,
                b'\n' => {
                    self.at += 1;
                    self.line += 1;
                    self.line_start = self.at;
                }
                b'\r' => {
                    self.at += 1;
                    if b.get(self.at) != Some(&b'\n') {
                        self.line += 1;
                        self.line_start = self.at;
                    }
                }
                b'#' => {
                    while let Some(&c) = b.get(self.at) {
                        if c == b'\n' || c == b'\r' {
                            break;
                        }
                        self.at += 1;
                    }
                }
                _ => return,
            }
        }
    }

    /// Fast path for number lists: after blanks, `Some(Some(number))` if a number follows,
    /// `Some(None)` if a `]` follows (consumed), `None` (nothing consumed) for anything else.
    #[inline]
    pub fn number_or_close(&mut self) -> Option<Option<(&'a str, Pos)>> {
        self.skip_blank();
        let b = self.src.as_bytes();
        let start = self.at;
        match b.get(start) {
            Some(b']') => {
                self.at += 1;
                Some(None)
            }
            Some(b'0'..=b'9' | b'+' | b'-') => {
                let pos = self.pos();
                let mut i = start + 1;
                while let Some(&d) = b.get(i) {
                    if d.is_ascii_alphanumeric()
                        || d == b'.'
                        || ((d == b'+' || d == b'-') && matches!(b[i - 1], b'e' | b'E'))
                    {
                        i += 1;
                    } else {
                        break;
                    }
                }
                self.at = i;
                Some(Some((&self.src[start..i], pos)))
            }
            _ => None,
        }
    }

    /// The next token and where it starts.
    pub fn next_token(&mut self) -> Result<(Token<'a>, Pos), LexError> {
        self.skip_blank();
        let pos = self.pos();
        let b = self.src.as_bytes();
        let Some(&c) = b.get(self.at) else { return Ok((Token::Eof, pos)) };
        let start = self.at;
        let tok = match c {
            b'{' | b'}' | b'[' | b']' => {
                self.at += 1;
                match c {
                    b'{' => Token::LBrace,
                    b'}' => Token::RBrace,
                    b'[' => Token::LBracket,
                    _ => Token::RBracket,
                }
            }
            b'.' if !b.get(self.at + 1).is_some_and(|d| d.is_ascii_digit()) => {
                self.at += 1;
                Token::Period
            }
            b'0'..=b'9' | b'+' | b'-' | b'.' => {
                while b.get(self.at).is_some_and(|&d| is_number_char(d)) {
                    // A sign only starts the number or follows an exponent letter.
                    let d = b[self.at];
                    if (d == b'+' || d == b'-') && self.at > start && !matches!(b[self.at - 1], b'e' | b'E') {
                        break;
                    }
                    self.at += 1;
                }
                Token::Number(&self.src[start..self.at])
            }
            b'"' => self.string(pos)?,
            b'\'' | b'\\' => {
                return Err(LexError { pos, message: format!("unexpected character `{}`", c as char) });
            }
            _ if c < 0x20 || c == 0x7f => {
                return Err(LexError { pos, message: format!("unexpected control character 0x{c:02x}") });
            }
            _ => {
                while b.get(self.at).is_some_and(|&d| is_id_rest(d)) {
                    self.at += 1;
                }
                // Identifiers end at ASCII bytes, so the slice is on character boundaries.
                Token::Id(&self.src[start..self.at])
            }
        };
        Ok((tok, pos))
    }

    fn string(&mut self, pos: Pos) -> Result<Token<'a>, LexError> {
        let b = self.src.as_bytes();
        self.at += 1;
        let mut out = String::new();
        let mut run = self.at;
        loop {
            match b.get(self.at) {
                None => {
                    return Err(LexError {
                        pos,
                        message: "string not closed before the end of the file".into(),
                    });
                }
                Some(b'"') => {
                    out.push_str(&self.src[run..self.at]);
                    self.at += 1;
                    return Ok(Token::Str(out));
                }
                Some(b'\\') => {
                    out.push_str(&self.src[run..self.at]);
                    self.at += 1;
                    // The escaped character (any; `\"` and `\\` are the ones that matter).
                    match self.src[self.at..].chars().next() {
                        Some(ch) => {
                            out.push(ch);
                            if ch == '\n' {
                                self.line += 1;
                                self.line_start = self.at + 1;
                            }
                            self.at += ch.len_utf8();
                        }
                        None => {
                            return Err(LexError {
                                pos,
                                message: "string not closed before the end of the file".into(),
                            });
                        }
                    }
                    run = self.at;
                }
                Some(b'\n') => {
                    self.at += 1;
                    self.line += 1;
                    self.line_start = self.at;
                }
                Some(_) => self.at += 1,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(src: &str) -> Vec<Token<'_>> {
        let mut l = Lexer::new(src);
        let mut v = Vec::new();
        loop {
            let (t, _) = l.next_token().unwrap();
            if t == Token::Eof {
                return v;
            }
            v.push(t);
        }
    }

    #[test]
    fn tokens_commas_and_comments() {
        use Token::*;
        assert_eq!(
            all("DEF a_1 Transform { # c\n translation 1,-2.5e-1 +.5 } [0x1F] \"a\\\"b\" A.b"),
            vec![
                Id("DEF"),
                Id("a_1"),
                Id("Transform"),
                LBrace,
                Id("translation"),
                Number("1"),
                Number("-2.5e-1"),
                Number("+.5"),
                RBrace,
                LBracket,
                Number("0x1F"),
                RBracket,
                Str("a\"b".into()),
                Id("A"),
                Period,
                Id("b"),
            ]
        );
    }

    #[test]
    fn numbers_split_at_a_sign_and_positions_count_lines() {
        assert_eq!(all("1-2"), vec![Token::Number("1"), Token::Number("-2")]);
        let mut l = Lexer::new("a\r\n  b\rc \"x\ny\" d");
        let p: Vec<Pos> = (0..4).map(|_| l.next_token().unwrap().1).collect();
        assert_eq!(
            p,
            [
                Pos { line: 1, col: 1 },
                Pos { line: 2, col: 3 },
                Pos { line: 3, col: 1 },
                Pos { line: 3, col: 3 }
            ]
        );
        assert_eq!(l.next_token().unwrap().1, Pos { line: 4, col: 4 });
    }

    #[test]
    fn bad_input_is_an_error_with_a_position() {
        let e = Lexer::new("  \"abc").next_token().unwrap_err();
        assert_eq!(e.pos, Pos { line: 1, col: 3 });
        assert!(Lexer::new("'").next_token().is_err());
        assert!(Lexer::new("\u{1}").next_token().is_err());
    }
}
