//! VRML97 parser (ISO/IEC 14772-1 Annex A grammar): tokens → a generic node tree
//! ([`super::tree`]) with typed field values and positions.
//!
//! * Statements: nodes, `DEF name node`, `USE name`, `PROTO`, `EXTERNPROTO` and `ROUTE` (at the
//!   top, in PROTO bodies and inside node bodies, as the grammar allows). `ROUTE`s are read and
//!   dropped.
//! * Field values are read with the type the node (table in [`super::nodes`]) or the PROTO
//!   interface gives the field: all SF/MF types, single values for MF fields without brackets,
//!   hexadecimal integers, `NULL` nodes.
//! * PROTO instances are expanded as they are read ([`super::proto`]); inside a PROTO body they
//!   are kept unexpanded until the enclosing PROTO is instantiated, since their field values may
//!   be `IS` references.
//! * `EXTERNPROTO`s whose `url` names a readable local file (relative to the including file,
//!   `file://` accepted, `#Name` choosing the PROTO, else the one of the EXTERNPROTO's name) take
//!   that file's PROTO (its interface defaults and body); each library file is parsed once per
//!   file, a chain of them at most [`MAX_EXTERN_DEPTH`] deep, a cycle is a warning. Without a
//!   readable file (or without a base directory: [`parse`]) instances are skipped with a warning.
//! * `Script` nodes' interface declarations are read and dropped.
//! * An unknown node type or an unknown field is a warning (with its position); the node's body
//!   or the field's value is skipped and reading goes on. Malformed syntax is an error saying
//!   what was expected where.
//!
//! Nesting is limited to [`MAX_DEPTH`] levels, so a hostile file cannot overflow the stack.

use super::lexer::{LexError, Lexer, Pos, Token};
use super::nodes;
use super::proto::{ExpandError, Expander};
use super::tree::{Field, FieldType, FieldValue, InterfaceDecl, Node, NodeRef, ProtoDef, ProtoInstance};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::rc::Rc;

mod values;
#[cfg(test)]
use values::{parse_f32, parse_int};

/// Deepest nesting of nodes (and PROTO declarations) the parser accepts.
pub const MAX_DEPTH: usize = 200;
/// Deepest chain of EXTERNPROTO library files (a file whose PROTOs come from a file whose PROTOs
/// come from …).
pub const MAX_EXTERN_DEPTH: usize = 8;

/// A syntax error.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    /// Where.
    pub pos: Pos,
    /// What was expected, and what was found.
    pub message: String,
}

impl From<LexError> for ParseError {
    fn from(e: LexError) -> Self {
        ParseError { pos: e.pos, message: e.message }
    }
}

impl From<ExpandError> for ParseError {
    fn from(e: ExpandError) -> Self {
        ParseError { pos: e.pos, message: e.message }
    }
}

type Result<T> = std::result::Result<T, ParseError>;

/// A parsed file: its top-level nodes and the parser's warnings.
#[derive(Debug)]
pub struct Parsed {
    /// Top-level nodes, PROTO instances expanded.
    pub nodes: Vec<NodeRef>,
    /// (position, message) of each unknown node or field, skipped EXTERNPROTO instance…
    pub warnings: Vec<(Pos, String)>,
    /// The file's top-level PROTOs (and EXTERNPROTOs), by name.
    pub protos: HashMap<String, Rc<ProtoDef>>,
}

/// Checks the `#VRML V2.0 utf8` header.
fn check_header(src: &str) -> Result<()> {
    let first = src.lines().next().unwrap_or("");
    let at = Pos { line: 1, col: 1 };
    if first.starts_with("#VRML V2.0 utf8") {
        Ok(())
    } else if first.starts_with("#VRML V1.0") {
        Err(ParseError {
            pos: at,
            message: "VRML 1.0 files are not supported (expected `#VRML V2.0 utf8`)".into(),
        })
    } else {
        Err(ParseError { pos: at, message: "expected the header `#VRML V2.0 utf8` on the first line".into() })
    }
}

/// Parses a whole VRML97 file (a leading UTF-8 byte order mark is skipped: it is not a column).
/// EXTERNPROTOs are not loaded ([`parse_file`] does).
pub fn parse(src: &str) -> Result<Parsed> {
    parse_in(src, None)
}

/// Parses the text of file `path` (which must be its real location): EXTERNPROTO URLs are
/// resolved relative to it.
pub fn parse_file(src: &str, path: &Path) -> Result<Parsed> {
    let canonical = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
    parse_in(src, Some(vec![canonical]))
}

/// `chain`: the files being parsed, outermost first (this one last); `None`: no file.
fn parse_in(src: &str, chain: Option<Vec<PathBuf>>) -> Result<Parsed> {
    let src = src.strip_prefix('\u{feff}').unwrap_or(src);
    check_header(src)?;
    let mut p = Parser {
        chain,
        libraries: HashMap::new(),
        lex: Lexer::new(src),
        peeked: None,
        protos: vec![HashMap::new()],
        defs: vec![HashMap::new()],
        interfaces: Vec::new(),
        depth: 0,
        expander: Expander::default(),
        warnings: Vec::new(),
    };
    let nodes = p.statements(false)?;
    let protos = p.protos.pop().unwrap_or_default();
    Ok(Parsed { nodes, warnings: p.warnings, protos })
}

struct Parser<'a> {
    /// The files being parsed, outermost first (`None`: text without a file).
    chain: Option<Vec<PathBuf>>,
    /// EXTERNPROTO library files already parsed: their top-level PROTOs.
    libraries: HashMap<PathBuf, Rc<HashMap<String, Rc<ProtoDef>>>>,
    lex: Lexer<'a>,
    peeked: Option<(Token<'a>, Pos)>,
    /// PROTO names in scope: the file's, then those of each enclosing PROTO body.
    protos: Vec<HashMap<String, Rc<ProtoDef>>>,
    /// DEF names: one scope for the file and one per PROTO body being read.
    defs: Vec<HashMap<String, NodeRef>>,
    /// Interfaces of the PROTOs whose bodies are being read (innermost last), for `IS`.
    interfaces: Vec<Vec<InterfaceDecl>>,
    depth: usize,
    expander: Expander,
    warnings: Vec<(Pos, String)>,
}

/// How the fields of a node body are typed.
enum BodyKind {
    Standard,
    Script,
    Proto(Rc<ProtoDef>),
}

impl<'a> Parser<'a> {
    // ----- tokens -----

    fn next(&mut self) -> Result<(Token<'a>, Pos)> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => Ok(self.lex.next_token()?),
        }
    }

    fn peek(&mut self) -> Result<&Token<'a>> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lex.next_token()?);
        }
        match &self.peeked {
            Some((t, _)) => Ok(t),
            None => Ok(&Token::Eof),
        }
    }

    fn expected<T>(what: &str, found: &Token, pos: Pos) -> Result<T> {
        Err(ParseError { pos, message: format!("expected {what}, found {found}") })
    }

    fn expect(&mut self, want: Token<'static>, what: &str) -> Result<Pos> {
        let (t, pos) = self.next()?;
        if t == want { Ok(pos) } else { Self::expected(what, &t, pos) }
    }

    fn id(&mut self, what: &str) -> Result<(&'a str, Pos)> {
        match self.next()? {
            (Token::Id(s), pos) if !is_keyword(s) => Ok((s, pos)),
            (t, pos) => Self::expected(what, &t, pos),
        }
    }

    fn enter(&mut self, pos: Pos) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ParseError {
                pos,
                message: format!("nodes nested more than {MAX_DEPTH} levels deep"),
            });
        }
        Ok(())
    }

    // ----- statements -----

    /// Statements up to the end of the file, or up to a `}` (a PROTO body; the `}` is consumed).
    fn statements(&mut self, in_body: bool) -> Result<Vec<NodeRef>> {
        let mut nodes = Vec::new();
        loop {
            match self.peek()? {
                Token::Eof if !in_body => return Ok(nodes),
                Token::RBrace if in_body => {
                    self.next()?;
                    return Ok(nodes);
                }
                Token::Id("PROTO") => self.proto()?,
                Token::Id("EXTERNPROTO") => self.externproto()?,
                Token::Id("ROUTE") => self.route()?,
                _ => {
                    let what = if in_body { "a node, PROTO, ROUTE or `}`" } else { "a node, PROTO or ROUTE" };
                    match self.node_statement(what)? {
                        Some(n) => nodes.push(n),
                        None => {
                            let pos = self.lex.pos();
                            return Self::expected(what, &Token::Id("NULL"), pos);
                        }
                    }
                }
            }
        }
    }

    /// `NULL` (→ `None`), `USE name`, `DEF name Type { … }` or `Type { … }`.
    fn node_statement(&mut self, what: &str) -> Result<Option<NodeRef>> {
        let (t, pos) = self.next()?;
        match t {
            Token::Id("NULL") => Ok(None),
            Token::Id("USE") => {
                let (name, at) = self.id("a DEF name after USE")?;
                match self.defs.last().and_then(|d| d.get(name)) {
                    Some(n) => Ok(Some(n.clone())),
                    None => Err(ParseError {
                        pos: at,
                        message: format!("USE of `{name}`, which no DEF defines before"),
                    }),
                }
            }
            Token::Id("DEF") => {
                let (name, _) = self.id("a name after DEF")?;
                let (t, pos) = self.next()?;
                match t {
                    Token::Id(ty) if !is_keyword(ty) => {
                        let n = self.node(ty, pos, Some(name.to_string()))?;
                        if let Some(d) = self.defs.last_mut() {
                            d.insert(name.to_string(), n.clone());
                        }
                        Ok(Some(n))
                    }
                    t => Self::expected("a node type after the DEF name", &t, pos),
                }
            }
            Token::Id(ty) if !is_keyword(ty) => Ok(Some(self.node(ty, pos, None)?)),
            t => Self::expected(what, &t, pos),
        }
    }

    /// A node after its type name: `{ body }`.
    fn node(&mut self, ty: &'a str, pos: Pos, def_name: Option<String>) -> Result<NodeRef> {
        self.enter(pos)?;
        self.expect(Token::LBrace, &format!("`{{` after the node type `{ty}`"))?;
        let proto = self.protos.iter().rev().find_map(|s| s.get(ty)).cloned();
        let node = if let Some(proto) = proto {
            let fields = self.body(ty, &BodyKind::Proto(proto.clone()))?;
            self.instance(proto, ty, pos, def_name, fields)?
        } else if nodes::is_standard(ty) {
            let kind = if ty == "Script" { BodyKind::Script } else { BodyKind::Standard };
            let fields = self.body(ty, &kind)?;
            Rc::new(Node {
                type_name: ty.to_string(),
                pos,
                def_name,
                fields,
                proto: None,
                unexpanded: false,
                unknown: false,
            })
        } else {
            self.warnings.push((pos, format!("unknown node type `{ty}`: skipped")));
            self.skip_body()?;
            unknown_node(ty, pos, def_name)
        };
        self.depth -= 1;
        Ok(node)
    }

    /// A PROTO instance: expanded now, or kept for later inside a PROTO body.
    fn instance(
        &mut self,
        proto: Rc<ProtoDef>,
        ty: &str,
        pos: Pos,
        def_name: Option<String>,
        fields: Vec<Field>,
    ) -> Result<NodeRef> {
        if proto.body.is_none() {
            let urls = proto.urls.join(", ");
            self.warnings.push((
                pos,
                format!(
                    "`{ty}` is an EXTERNPROTO (url {urls}); external PROTOs are not loaded: instance skipped"
                ),
            ));
            return Ok(unknown_node(ty, pos, def_name));
        }
        let given: Vec<(String, FieldValue)> = fields.into_iter().map(|f| (f.name, f.value)).collect();
        if !self.interfaces.is_empty() {
            return Ok(Rc::new(Node {
                type_name: ty.to_string(),
                pos,
                def_name,
                fields: Vec::new(),
                proto: Some(Rc::new(ProtoInstance { proto, fields: given })),
                unexpanded: true,
                unknown: false,
            }));
        }
        Ok(self.expander.instantiate(&proto, given, pos, def_name, self.depth)?)
    }

    /// Fields of a node body up to and including its `}`.
    fn body(&mut self, ty: &str, kind: &BodyKind) -> Result<Vec<Field>> {
        let mut fields = Vec::new();
        loop {
            let (t, pos) = self.next()?;
            let name = match t {
                Token::RBrace => return Ok(fields),
                Token::Id("PROTO") => {
                    self.peeked = Some((t, pos));
                    self.proto()?;
                    continue;
                }
                Token::Id("EXTERNPROTO") => {
                    self.peeked = Some((t, pos));
                    self.externproto()?;
                    continue;
                }
                Token::Id("ROUTE") => {
                    self.peeked = Some((t, pos));
                    self.route()?;
                    continue;
                }
                Token::Id(kw @ ("eventIn" | "eventOut" | "field" | "exposedField"))
                    if matches!(kind, BodyKind::Script) =>
                {
                    self.script_decl(kw)?;
                    continue;
                }
                Token::Id(name) => name,
                t => return Self::expected(&format!("a field name or `}}` in `{ty}`"), &t, pos),
            };
            let field_type = match kind {
                BodyKind::Standard | BodyKind::Script => nodes::field_type(ty, name),
                BodyKind::Proto(p) => p
                    .interface
                    .iter()
                    .find(|d| d.name == name && matches!(d.kind, "field" | "exposedField"))
                    .map(|d| d.ty),
            };
            if matches!(self.peek()?, Token::Id("IS")) {
                self.next()?;
                let (target, at) = self.id("a PROTO interface name after IS")?;
                self.check_is(name, field_type, target, at)?;
                if let Some(_t) = field_type {
                    fields.push(Field {
                        name: name.to_string(),
                        pos,
                        value: FieldValue::Is(target.to_string()),
                    });
                }
                continue;
            }
            match field_type {
                Some(t) => {
                    let value = self.value(t)?;
                    fields.push(Field { name: name.to_string(), pos, value });
                }
                None => {
                    self.warnings.push((pos, format!("`{ty}` has no field `{name}`: skipped")));
                    self.skip_value()?;
                }
            }
        }
    }

    /// Checks `field IS target` against the interface of the PROTO being declared.
    fn check_is(&self, field: &str, ty: Option<FieldType>, target: &str, at: Pos) -> Result<()> {
        let Some(interface) = self.interfaces.last() else {
            return Err(ParseError { pos: at, message: "IS is only allowed inside a PROTO body".into() });
        };
        let Some(decl) = interface.iter().find(|d| d.name == target) else {
            return Err(ParseError {
                pos: at,
                message: format!("IS `{target}`: the PROTO declares no `{target}`"),
            });
        };
        match ty {
            Some(t) if t != decl.ty => Err(ParseError {
                pos: at,
                message: format!("`{field} IS {target}`: the field is {t:?} but `{target}` is {:?}", decl.ty),
            }),
            _ => Ok(()),
        }
    }

    /// `eventIn T name [IS x]`, `eventOut T name [IS x]`, `field T name value|IS x` in a Script.
    fn script_decl(&mut self, kind: &str) -> Result<()> {
        let (ty, _) = self.field_type()?;
        let (name, _) = self.id("a name")?;
        if matches!(self.peek()?, Token::Id("IS")) {
            self.next()?;
            let (target, at) = self.id("a PROTO interface name after IS")?;
            return self.check_is(name, Some(ty), target, at);
        }
        if matches!(kind, "field" | "exposedField") {
            self.value(ty)?;
        }
        Ok(())
    }

    fn field_type(&mut self) -> Result<(FieldType, Pos)> {
        let (t, pos) = self.next()?;
        match t {
            Token::Id(s) => match FieldType::from_name(s) {
                Some(ft) => Ok((ft, pos)),
                None => Self::expected("a field type (SFBool, MFVec3f, …)", &t, pos),
            },
            t => Self::expected("a field type (SFBool, MFVec3f, …)", &t, pos),
        }
    }

    /// `PROTO name [ interface ] { body }`.
    fn proto(&mut self) -> Result<()> {
        let (_, pos) = self.next()?;
        self.enter(pos)?;
        let (name, _) = self.id("a PROTO name")?;
        let interface = self.interface(true)?;
        self.expect(Token::LBrace, "`{` to open the PROTO body")?;
        self.protos.push(HashMap::new());
        self.defs.push(HashMap::new());
        self.interfaces.push(interface);
        let body = self.statements(true);
        self.protos.pop();
        self.defs.pop();
        let interface = self.interfaces.pop().unwrap_or_default();
        let body = body?;
        if body.is_empty() {
            return Err(ParseError { pos, message: format!("PROTO `{name}` has no node in its body") });
        }
        let def = ProtoDef { name: name.to_string(), pos, interface, body: Some(body), urls: Vec::new() };
        if let Some(scope) = self.protos.last_mut() {
            scope.insert(name.to_string(), Rc::new(def));
        }
        self.depth -= 1;
        Ok(())
    }

    /// `EXTERNPROTO name [ interface without values ] urls`.
    fn externproto(&mut self) -> Result<()> {
        let (_, pos) = self.next()?;
        let (name, _) = self.id("an EXTERNPROTO name")?;
        let interface = self.interface(false)?;
        let urls = match self.value(FieldType::MFString)? {
            FieldValue::Strs(v) => v,
            _ => Vec::new(),
        };
        let def = match self.library_proto(name, &urls, pos)? {
            // The library's interface carries the defaults the EXTERNPROTO's lacks.
            Some(lib) => ProtoDef {
                name: name.to_string(),
                pos,
                interface: lib.interface.clone(),
                body: lib.body.clone(),
                urls: Vec::new(),
            },
            None => ProtoDef { name: name.to_string(), pos, interface, body: None, urls },
        };
        if let Some(scope) = self.protos.last_mut() {
            scope.insert(name.to_string(), Rc::new(def));
        }
        Ok(())
    }

    /// The PROTO an EXTERNPROTO's `urls` name in a readable local file, if any (module docs).
    fn library_proto(&mut self, name: &str, urls: &[String], pos: Pos) -> Result<Option<Rc<ProtoDef>>> {
        let Some(chain) = &self.chain else { return Ok(None) };
        let dir = chain.last().and_then(|f| f.parent()).map(Path::to_path_buf).unwrap_or_default();
        for (path, fragment) in urls.iter().filter_map(|u| super::local_url(&dir, u)) {
            let canonical = path.canonicalize().unwrap_or_else(|_| path.clone());
            let protos = match self.libraries.get(&canonical) {
                Some(p) => p.clone(),
                None => {
                    if chain.contains(&canonical) {
                        self.warnings.push((
                            pos,
                            format!("EXTERNPROTO {name}: {} includes itself: not loaded", path.display()),
                        ));
                        return Ok(None);
                    }
                    if chain.len() >= MAX_EXTERN_DEPTH {
                        return Err(ParseError {
                            pos,
                            message: format!(
                                "EXTERNPROTO libraries nested more than {MAX_EXTERN_DEPTH} deep"
                            ),
                        });
                    }
                    let text = super::read_source(&path)
                        .map_err(|e| ParseError { pos, message: format!("EXTERNPROTO {name}: {e}") })?;
                    let mut inner = chain.clone();
                    inner.push(canonical.clone());
                    let parsed = parse_in(&text, Some(inner)).map_err(|e| ParseError {
                        pos,
                        message: format!(
                            "EXTERNPROTO {name}: {}:{}:{}: {}",
                            path.display(),
                            e.pos.line,
                            e.pos.col,
                            e.message
                        ),
                    })?;
                    for (at, m) in parsed.warnings {
                        self.warnings
                            .push((pos, format!("in {}:{}:{}: {m}", path.display(), at.line, at.col)));
                    }
                    let protos = Rc::new(parsed.protos);
                    self.libraries.insert(canonical, protos.clone());
                    protos
                }
            };
            let want = if fragment.is_empty() { name } else { fragment };
            match protos.get(want) {
                Some(p) if p.body.is_some() => return Ok(Some(p.clone())),
                _ => self
                    .warnings
                    .push((pos, format!("EXTERNPROTO {name}: {} has no PROTO {want}", path.display()))),
            }
        }
        Ok(None)
    }

    fn interface(&mut self, with_values: bool) -> Result<Vec<InterfaceDecl>> {
        self.expect(Token::LBracket, "`[` to open the interface")?;
        let mut decls = Vec::new();
        loop {
            let (t, pos) = self.next()?;
            let kind = match t {
                Token::RBracket => return Ok(decls),
                Token::Id("eventIn") => "eventIn",
                Token::Id("eventOut") => "eventOut",
                Token::Id("field") => "field",
                Token::Id("exposedField") => "exposedField",
                t => return Self::expected("eventIn, eventOut, field, exposedField or `]`", &t, pos),
            };
            let (ty, _) = self.field_type()?;
            let (name, _) = self.id("an interface name")?;
            let default = if with_values && matches!(kind, "field" | "exposedField") {
                Some(self.value(ty)?)
            } else {
                None
            };
            decls.push(InterfaceDecl { kind, ty, name: name.to_string(), default });
        }
    }

    /// `ROUTE a.b TO c.d`: read and ignored.
    fn route(&mut self) -> Result<()> {
        self.next()?;
        self.id("a node name after ROUTE")?;
        self.expect(Token::Period, "`.` in ROUTE")?;
        self.id("an event name")?;
        match self.next()? {
            (Token::Id("TO"), _) => {}
            (t, pos) => return Self::expected("TO", &t, pos),
        }
        self.id("a node name after TO")?;
        self.expect(Token::Period, "`.` in ROUTE")?;
        self.id("an event name")?;
        Ok(())
    }

    // ----- skipping what is not understood -----

    /// Skips a node body after its `{`, up to the matching `}`. DEF names inside are remembered
    /// (as unknown nodes) so that later USEs still resolve.
    fn skip_body(&mut self) -> Result<()> {
        let mut depth = 1usize;
        while depth > 0 {
            let (t, pos) = self.next()?;
            match t {
                Token::LBrace | Token::LBracket => depth += 1,
                Token::RBrace | Token::RBracket => depth -= 1,
                Token::Id("DEF") => {
                    if let (Token::Id(name), _) = self.next()? {
                        let ty = match self.peek()? {
                            Token::Id(ty) => ty.to_string(),
                            _ => String::new(),
                        };
                        let n = unknown_node(&ty, pos, Some(name.to_string()));
                        if let Some(d) = self.defs.last_mut() {
                            d.insert(name.to_string(), n);
                        }
                    }
                }
                Token::Eof => return Self::expected("`}` to close the node", &t, pos),
                _ => {}
            }
        }
        Ok(())
    }

    /// Skips the value of an unknown field, whatever its type.
    fn skip_value(&mut self) -> Result<()> {
        let (t, pos) = self.next()?;
        match t {
            Token::LBracket => {
                let mut depth = 1usize;
                while depth > 0 {
                    let (t, pos) = self.next()?;
                    match t {
                        Token::LBrace | Token::LBracket => depth += 1,
                        Token::RBrace | Token::RBracket => depth -= 1,
                        Token::Eof => return Self::expected("`]`", &t, pos),
                        _ => {}
                    }
                }
            }
            Token::Number(_) => {
                while matches!(self.peek()?, Token::Number(_)) {
                    self.next()?;
                }
            }
            Token::Str(_) | Token::Id("TRUE" | "FALSE" | "NULL") => {}
            Token::Id("USE") => {
                self.id("a DEF name after USE")?;
            }
            Token::Id("IS") => {
                self.id("a PROTO interface name after IS")?;
            }
            Token::Id(_) => {
                self.peeked = Some((t, pos));
                self.node_statement("a field value")?;
            }
            t => return Self::expected("a field value", &t, pos),
        }
        Ok(())
    }
}

/// Words that cannot be node type or DEF names (the writer avoids them as DEF names too).
pub(super) fn is_keyword(s: &str) -> bool {
    matches!(
        s,
        "DEF"
            | "USE"
            | "PROTO"
            | "EXTERNPROTO"
            | "ROUTE"
            | "TO"
            | "IS"
            | "NULL"
            | "TRUE"
            | "FALSE"
            | "eventIn"
            | "eventOut"
            | "field"
            | "exposedField"
    )
}

fn unknown_node(ty: &str, pos: Pos, def_name: Option<String>) -> NodeRef {
    Rc::new(Node {
        type_name: ty.to_string(),
        pos,
        def_name,
        fields: Vec::new(),
        proto: None,
        unexpanded: false,
        unknown: true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(body: &str) -> Parsed {
        parse(&format!("#VRML V2.0 utf8\n{body}")).unwrap()
    }

    fn parse_err(body: &str) -> ParseError {
        parse(&format!("#VRML V2.0 utf8\n{body}")).unwrap_err()
    }

    #[test]
    fn use_needs_an_earlier_def() {
        let e = parse_err("Transform { children [ Shape { geometry Box {} } USE T2 ] }");
        assert_eq!(e.pos, Pos { line: 2, col: 54 });
        assert!(e.message.contains("USE of `T2`"), "{}", e.message);
        assert!(parse_err("DEF A Group { children USE A }").message.contains("USE of `A`"));
    }

    #[test]
    fn values_of_every_kind() {
        let p = parse_ok(
            "DEF B Box { size 1 2 3 }\n\
             Transform { children [ USE B Shape { geometry USE B } ] scale 2,2,2 }\n\
             IndexedFaceSet { coordIndex [ 0 1 2 -1 ] coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } solid FALSE }\n\
             PixelTexture { image 2 1 1 0xFF 0x00 }\n\
             WorldInfo { info [\"a\" \"b\\\"c\"] title \"t\" }\n\
             Switch { whichChoice -1 choice Group {} }\n\
             ROUTE A.b TO C.d",
        );
        assert_eq!(p.nodes.len(), 6);
        let t = &p.nodes[1];
        match t.get("children") {
            Some(FieldValue::Nodes(c)) => assert!(Rc::ptr_eq(&c[0], &p.nodes[0])),
            v => panic!("{v:?}"),
        }
        assert_eq!(t.get("scale"), Some(&FieldValue::Vec3([2.0, 2.0, 2.0])));
        assert_eq!(p.nodes[2].get("coordIndex"), Some(&FieldValue::Ints(vec![0, 1, 2, -1])));
        assert_eq!(p.nodes[3].get("image"), Some(&FieldValue::Image(vec![2, 1, 1, 255, 0])));
        assert_eq!(p.nodes[4].get("info"), Some(&FieldValue::Strs(vec!["a".into(), "b\"c".into()])));
        assert!(matches!(p.nodes[5].get("choice"), Some(FieldValue::Nodes(v)) if v.len() == 1));
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    }

    #[test]
    fn unknown_nodes_and_fields_warn_and_are_skipped() {
        let p = parse_ok(
            "Foo { bar [ 1 2 { } ] DEF X Baz { } }\nBox { size 1 1 1 colour 1 0 0 }\nGroup { children USE X }",
        );
        assert_eq!(p.nodes.len(), 3);
        assert!(p.nodes[0].unknown);
        assert_eq!(p.nodes[1].get("size"), Some(&FieldValue::Vec3([1.0; 3])));
        assert_eq!(p.warnings.len(), 2, "{:?}", p.warnings);
        assert_eq!(p.warnings[0].0, Pos { line: 2, col: 1 });
        assert_eq!(p.warnings[1].0, Pos { line: 3, col: 18 });
    }

    #[test]
    fn malformed_input_says_what_was_expected_where() {
        let e = parse_err("Transform { translation 1 2 }");
        assert_eq!(e.pos, Pos { line: 2, col: 29 });
        assert!(e.message.contains("expected a number, found `}`"), "{}", e.message);
        assert!(parse_err("Group {").message.contains("end of file"));
        assert!(parse_err("Box { size 1 2 3e99 }").message.contains("finite"));
        assert!(parse_err("Switch { whichChoice 1.5 }").message.contains("integer"));
        assert!(parse("Group {}").unwrap_err().message.contains("#VRML V2.0 utf8"));
        assert!(parse("#VRML V1.0 ascii\n").unwrap_err().message.contains("1.0"));
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let deep = "Group { children ".repeat(100_000);
        let e = parse_err(&deep);
        assert!(e.message.contains("nested more than"), "{}", e.message);
        let brackets = format!("Foo {{ {} }}", "[".repeat(1_000_000));
        assert!(parse_err(&brackets).message.contains("end of file"));
    }

    #[test]
    fn the_float_fast_path_agrees_with_the_standard_library() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let digits = (x % 8) as usize;
            let m = (x >> 8) % 10u64.pow(digits as u32 + 1);
            let s = format!("{m}");
            let k = ((x >> 40) % (s.len() as u64 + 1)) as usize;
            let text = format!(
                "{}{}.{}",
                if x & 1 << 60 != 0 { "-" } else { "" },
                &s[..s.len() - k],
                &s[s.len() - k..]
            );
            assert_eq!(parse_f32(&text), text.parse::<f32>().ok(), "{text}");
        }
        for t in ["0.885809", "18.387", "-0.000001", "1.", ".5", "0", "-0", "12345678.9", "0.0000000001"] {
            assert_eq!(parse_f32(t), t.parse::<f32>().ok(), "{t}");
        }
    }

    #[test]
    fn integers() {
        assert_eq!(parse_int("0xFFFFFFFF"), Some(-1));
        assert_eq!(parse_int("-12"), Some(-12));
        assert_eq!(parse_int("3000000000"), None);
        assert_eq!(parse_int("1.0"), None);
    }
}
