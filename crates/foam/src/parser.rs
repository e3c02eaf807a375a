//! The FoamFile parser: header, dictionaries, value streams, lists (counted, uncounted,
//! uniform `N{v}`, typed `List<T>` in ASCII or binary), dimension sets, `#include`,
//! `#includeIfPresent`, `#includeEtc`, `#inputMode`, `#remove` and `$var` expansion (`$a`,
//! `$a.b`, `$:top.a`, `$..parent`), following OpenFOAM v1912's rules.

use crate::binary::Arch;
use crate::dict::{Dict, Entry, Item, Value};
use crate::error::{FoamError, Location, Result};
use crate::lexer::{Lexer, Tok};
use std::path::{Path, PathBuf};

/// `format` of a FoamFile.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Format {
    /// Text lists.
    #[default]
    Ascii,
    /// Contiguous lists as raw bytes (layout given by `arch`).
    Binary,
}

impl Format {
    /// The word written in the header.
    pub fn as_str(self) -> &'static str {
        match self {
            Format::Ascii => "ascii",
            Format::Binary => "binary",
        }
    }
}

/// The `FoamFile` header of a file.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Header {
    /// `format`.
    pub format: Format,
    /// Binary layout (`arch`), default `LSB;label=32;scalar=64`.
    pub arch: Arch,
    /// `class`, e.g. `volScalarField`.
    pub class: String,
    /// `object`, the file's name.
    pub object: String,
    /// `location`, e.g. `"0"` (may be empty).
    pub location: String,
    /// `note`, if any.
    pub note: Option<String>,
}

impl Header {
    /// Builds a header from a parsed `FoamFile` dictionary.
    fn from_dict(d: &Dict, lex: &Lexer, at: Location) -> Result<Header> {
        let word = |k: &str| d.item(k).ok().and_then(Item::as_word).map(str::to_string);
        let format = match word("format").as_deref() {
            None | Some("ascii") => Format::Ascii,
            Some("binary") => Format::Binary,
            Some(f) => return Err(lex.error_at(at, format!("unknown format `{f}`"))),
        };
        let arch = match word("arch") {
            Some(a) => Arch::parse(&a).map_err(|m| lex.error_at(at, m))?,
            None => Arch::default(),
        };
        Ok(Header {
            format,
            arch,
            class: word("class").unwrap_or_default(),
            object: word("object").unwrap_or_default(),
            location: word("location").unwrap_or_default(),
            note: word("note"),
        })
    }
}

/// A parsed dictionary file.
#[derive(Clone, Debug, PartialEq)]
pub struct FoamFile {
    /// The header, if the file has one.
    pub header: Option<Header>,
    /// Every entry after the header.
    pub body: Dict,
    /// Non-fatal remarks (duplicate keywords under `#inputMode warn`).
    pub warnings: Vec<String>,
}

/// Reads a whole file into memory, transparently gunzipping `name.gz` when only that exists.
pub fn read_bytes(path: &Path) -> Result<(PathBuf, Vec<u8>)> {
    match std::fs::read(path) {
        Ok(b) => Ok((path.to_path_buf(), b)),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let mut gz = path.as_os_str().to_owned();
            gz.push(".gz");
            let gz = PathBuf::from(gz);
            let raw = match std::fs::read(&gz) {
                Ok(r) => r,
                Err(_) => return Err(FoamError::io(path, e)),
            };
            let mut out = Vec::new();
            use std::io::Read;
            flate2::read::GzDecoder::new(&raw[..])
                .read_to_end(&mut out)
                .map_err(|e| FoamError::invalid(&gz, format!("not a valid gzip file: {e}")))?;
            Ok((gz, out))
        }
        Err(e) => Err(FoamError::io(path, e)),
    }
}

/// Parses a dictionary file (header optional).
pub fn parse_file(path: &Path) -> Result<FoamFile> {
    let (path, bytes) = read_bytes(path)?;
    parse_bytes(&bytes, &path)
}

/// Reads only the `FoamFile` header of a file (cheap: the body is not parsed). `None` when
/// the file has no header.
pub fn read_header(path: &Path) -> Result<Option<Header>> {
    let (path, bytes) = read_bytes(path)?;
    Parser::new(&bytes, &path, 0).parse_header()
}

/// Parses dictionary text; `path` is used for messages and to resolve `#include`.
pub fn parse_bytes(bytes: &[u8], path: &Path) -> Result<FoamFile> {
    let mut p = Parser::new(bytes, path, 0);
    let header = p.parse_header()?;
    let mut scopes = vec![Dict::new()];
    p.parse_body(&mut scopes, None)?;
    Ok(FoamFile {
        header,
        body: scopes.pop().unwrap(),
        warnings: p.warnings,
    })
}

/// How a keyword defined twice in one dictionary is handled (`#inputMode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum InputMode {
    Merge,
    Overwrite,
    Protect,
    Warn,
    Error,
}

/// The element type of a typed list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Elem {
    Scalar,
    Vector,
    Label,
    Tuple(usize),
}

impl Elem {
    fn from_type(t: &str) -> Option<Elem> {
        Some(match t {
            "scalar" | "sphericalTensor" => Elem::Scalar,
            "vector" => Elem::Vector,
            "label" => Elem::Label,
            "symmTensor" => Elem::Tuple(6),
            "tensor" => Elem::Tuple(9),
            _ => return None,
        })
    }

    fn components(self) -> usize {
        match self {
            Elem::Scalar | Elem::Label => 1,
            Elem::Vector => 3,
            Elem::Tuple(n) => n,
        }
    }
}

const MAX_INCLUDE_DEPTH: usize = 32;

pub(crate) struct Parser<'a> {
    pub(crate) lex: Lexer<'a>,
    pub(crate) format: Format,
    pub(crate) arch: Arch,
    depth: usize,
    mode: InputMode,
    warnings: Vec<String>,
}

impl<'a> Parser<'a> {
    pub(crate) fn new(bytes: &'a [u8], path: &'a Path, depth: usize) -> Self {
        Parser {
            lex: Lexer::new(bytes, path),
            format: Format::Ascii,
            arch: Arch::default(),
            depth,
            mode: InputMode::Merge,
            warnings: Vec::new(),
        }
    }

    /// Parses `FoamFile { … }` if the file starts with it, and adopts its format and arch.
    pub(crate) fn parse_header(&mut self) -> Result<Option<Header>> {
        if self.lex.peek()? != &Tok::Word("FoamFile".into()) {
            return Ok(None);
        }
        let at = self.lex.here();
        self.lex.next_tok()?;
        self.lex.expect_punct(b'{', "after FoamFile")?;
        let mut scopes = Vec::new();
        let d = self.parse_sub_dict(&mut scopes, at)?;
        let h = Header::from_dict(&d, &self.lex, at)?;
        self.format = h.format;
        self.arch = h.arch;
        Ok(Some(h))
    }

    /// Parses entries into the top scope until `}` (when `open` gives where the `{` was) or the
    /// end of the file.
    pub(crate) fn parse_body(
        &mut self,
        scopes: &mut Vec<Dict>,
        open: Option<Location>,
    ) -> Result<()> {
        loop {
            let (tok, at) = self.lex.next_located()?;
            match tok {
                Tok::Eof => {
                    return match open {
                        Some(o) => Err(self
                            .lex
                            .error_at(o, "dictionary opened here is never closed (missing `}`)")),
                        None => Ok(()),
                    }
                }
                Tok::Punct(b'}') if open.is_some() => return Ok(()),
                Tok::Punct(b';') => continue,
                Tok::Word(w) if w.starts_with('#') => self.directive(&w, at, scopes)?,
                Tok::Word(w) if w.starts_with('$') => {
                    // `$dict` (`;` optional) at keyword position merges that dictionary's
                    // entries here.
                    if self.lex.peek()? == &Tok::Punct(b';') {
                        self.lex.next_tok()?;
                    }
                    match self.lookup_var(&w, scopes, at)? {
                        Value::Dict(d) => {
                            for e in d.entries().to_vec() {
                                self.insert(scopes.last_mut().unwrap(), e, at)?;
                            }
                        }
                        Value::Stream(_) => {
                            return Err(self.lex.error_at(
                                at,
                                format!("`{w}` at keyword position names a value, not a dictionary to merge"),
                            ))
                        }
                    }
                }
                Tok::Word(keyword) => self.keyword_entry(keyword, false, at, scopes)?,
                Tok::Str(keyword) => self.keyword_entry(keyword, true, at, scopes)?,
                other => {
                    return Err(self.lex.error_at(
                        at,
                        format!("expected a keyword, found {}", other.describe()),
                    ))
                }
            }
        }
    }

    /// Parses a sub-dictionary whose `{` (at `open`) was consumed, as a new innermost scope.
    fn parse_sub_dict(&mut self, scopes: &mut Vec<Dict>, open: Location) -> Result<Dict> {
        scopes.push(Dict::new());
        let r = self.parse_body(scopes, Some(open));
        let d = scopes.pop().unwrap();
        r.map(|()| d)
    }

    /// Parses the value of `keyword` (a sub-dictionary or a stream) and inserts the entry.
    fn keyword_entry(
        &mut self,
        keyword: String,
        pattern: bool,
        at: Location,
        scopes: &mut Vec<Dict>,
    ) -> Result<()> {
        let value = if self.lex.peek()? == &Tok::Punct(b'{') {
            let open_at = self.lex.here();
            self.lex.next_tok()?;
            Value::Dict(self.parse_sub_dict(scopes, open_at)?)
        } else {
            let items = self.parse_stream(scopes, &keyword, at)?;
            match <[Item; 1]>::try_from(items) {
                Ok([Item::Dict(d)]) => Value::Dict(d),
                Ok([one]) => Value::Stream(vec![one]),
                Err(items) => Value::Stream(items),
            }
        };
        let e = Entry {
            keyword,
            pattern,
            value,
        };
        self.insert(scopes.last_mut().unwrap(), e, at)
    }

    fn insert(&mut self, d: &mut Dict, e: Entry, at: Location) -> Result<()> {
        let Some(i) = d.entries().iter().position(|x| x.keyword == e.keyword) else {
            d.push(e);
            return Ok(());
        };
        match self.mode {
            InputMode::Merge => {
                let old = &mut d.entries_mut()[i];
                match (&mut old.value, e.value) {
                    (Value::Dict(o), Value::Dict(n)) => {
                        for sub in n.entries().to_vec() {
                            self.insert(o, sub, at)?;
                        }
                    }
                    (slot, v) => *slot = v,
                }
            }
            InputMode::Overwrite => d.entries_mut()[i].value = e.value,
            InputMode::Protect => {}
            InputMode::Warn => self.warnings.push(format!(
                "{}: line {}: duplicate entry `{}` ignored (#inputMode warn)",
                self.lex.path().display(),
                at.line,
                e.keyword
            )),
            InputMode::Error => {
                return Err(self.lex.error_at(
                    at,
                    format!("duplicate entry `{}` (#inputMode error)", e.keyword),
                ))
            }
        }
        Ok(())
    }

    fn directive(&mut self, w: &str, at: Location, scopes: &mut Vec<Dict>) -> Result<()> {
        match w {
            "#include" | "#includeIfPresent" | "#includeEtc" | "#sinclude" => {
                let (t, tat) = self.lex.next_located()?;
                let name = match t {
                    Tok::Str(s) | Tok::Word(s) => s,
                    other => {
                        return Err(self.lex.error_at(
                            tat,
                            format!("{w} needs a file name, found {}", other.describe()),
                        ))
                    }
                };
                let optional = w != "#include" && w != "#includeEtc";
                let path = self.include_path(&name, w == "#includeEtc", tat)?;
                if optional && !path.exists() {
                    return Ok(());
                }
                self.include(&path, scopes, tat)
            }
            "#inputMode" => {
                let (t, tat) = self.lex.next_located()?;
                self.mode = match t {
                    Tok::Word(m) => match m.as_str() {
                        "merge" | "default" => InputMode::Merge,
                        "overwrite" => InputMode::Overwrite,
                        "protect" => InputMode::Protect,
                        "warn" => InputMode::Warn,
                        "error" => InputMode::Error,
                        _ => {
                            return Err(self.lex.error_at(
                                tat,
                                format!("unknown #inputMode `{m}` (merge, overwrite, protect, warn, error, default)"),
                            ))
                        }
                    },
                    other => {
                        return Err(self.lex.error_at(
                            tat,
                            format!("#inputMode needs a word, found {}", other.describe()),
                        ))
                    }
                };
                Ok(())
            }
            "#remove" => {
                let (t, tat) = self.lex.next_located()?;
                let names: Vec<String> = match t {
                    Tok::Word(n) | Tok::Str(n) => vec![n],
                    Tok::Punct(b'(') => {
                        let items = self.parse_list_items(scopes, tat, b')')?;
                        items
                            .iter()
                            .filter_map(|i| i.as_word().map(str::to_string))
                            .collect()
                    }
                    other => {
                        return Err(self.lex.error_at(
                            tat,
                            format!("#remove needs a keyword, found {}", other.describe()),
                        ))
                    }
                };
                let d = scopes.last_mut().unwrap();
                for n in names {
                    d.remove(&n);
                }
                Ok(())
            }
            "#includeFunc" | "#includeModel" => {
                // Function-object shorthand: kept as an entry holding the rest of the line,
                // so that reading controlDict works; foamgrain does not run function objects.
                let mut items = Vec::new();
                while self.lex.peek()? != &Tok::Eof && self.lex.here().line == at.line {
                    let (t, tat) = self.lex.next_located()?;
                    self.parse_item(t, tat, scopes, &mut items)?;
                }
                let e = Entry {
                    keyword: w.to_string(),
                    pattern: false,
                    value: Value::Stream(items),
                };
                scopes.last_mut().unwrap().push(e);
                Ok(())
            }
            _ => Err(self.lex.error_at(
                at,
                format!(
                    "directive `{w}` is not supported by foamgrain (supported: #include, \
                     #includeIfPresent, #includeEtc, #inputMode, #remove, #includeFunc)"
                ),
            )),
        }
    }

    fn include_path(&self, name: &str, etc: bool, at: Location) -> Result<PathBuf> {
        let here = self.lex.path().parent().unwrap_or(Path::new("."));
        let expanded = expand_path_vars(name, here).map_err(|m| self.lex.error_at(at, m))?;
        let p = PathBuf::from(&expanded);
        if etc {
            // Debian's OpenFOAM keeps etc/ in /usr/share/openfoam.
            let root =
                std::env::var("WM_PROJECT_DIR").unwrap_or_else(|_| "/usr/share/openfoam".into());
            return Ok(Path::new(&root).join("etc").join(p));
        }
        Ok(if p.is_absolute() { p } else { here.join(p) })
    }

    fn include(&mut self, path: &Path, scopes: &mut Vec<Dict>, at: Location) -> Result<()> {
        if self.depth >= MAX_INCLUDE_DEPTH {
            return Err(self.lex.error_at(
                at,
                format!(
                    "#include nested deeper than {MAX_INCLUDE_DEPTH} (a file includes itself?)"
                ),
            ));
        }
        let (path, bytes) = read_bytes(path).map_err(|e| match e {
            FoamError::Io { path, source } => self.lex.error_at(
                at,
                format!("cannot read included file {}: {source}", path.display()),
            ),
            other => other,
        })?;
        let mut child = Parser::new(&bytes, &path, self.depth + 1);
        child.mode = self.mode;
        let h = child.parse_header()?;
        if h.is_none() {
            child.format = self.format;
            child.arch = self.arch;
        }
        child.parse_body(scopes, None)?;
        self.mode = child.mode;
        self.warnings.append(&mut child.warnings);
        Ok(())
    }

    fn lookup_var(&self, w: &str, scopes: &[Dict], at: Location) -> Result<Value> {
        let name = w.trim_start_matches('$');
        let name = name
            .strip_prefix('{')
            .and_then(|n| n.strip_suffix('}'))
            .unwrap_or(name);
        let found = if let Some(top) = name.strip_prefix(':') {
            scopes[0].lookup_path(top)
        } else if name.starts_with('.') {
            // `$.a` is the current scope, `$..a` its parent, and so on.
            let dots = name.bytes().take_while(|&b| b == b'.').count();
            let rest = &name[dots..];
            scopes
                .len()
                .checked_sub(dots)
                .and_then(|i| scopes[i].lookup_path(rest))
        } else {
            scopes.iter().rev().find_map(|d| d.lookup_path(name))
        };
        found
            .cloned()
            .ok_or_else(|| self.lex.error_at(at, format!("undefined variable `{w}`")))
    }

    /// Parses a value stream up to `;`.
    fn parse_stream(
        &mut self,
        scopes: &mut Vec<Dict>,
        key: &str,
        key_at: Location,
    ) -> Result<Vec<Item>> {
        let mut items = Vec::new();
        loop {
            let (tok, at) = self.lex.next_located()?;
            match tok {
                Tok::Punct(b';') => return Ok(items),
                Tok::Eof => {
                    return Err(self.lex.error_at(
                        key_at,
                        format!("entry `{key}` is not ended by `;` before the end of the file"),
                    ))
                }
                Tok::Punct(b'}') => {
                    return Err(self
                        .lex
                        .error_at(at, format!("entry `{key}` is not ended by `;` before `}}`")))
                }
                t => self.parse_item(t, at, scopes, &mut items)?,
            }
        }
    }

    /// Parses one item starting with `tok` and appends it (a `$var` may append several).
    pub(crate) fn parse_item(
        &mut self,
        tok: Tok,
        at: Location,
        scopes: &mut Vec<Dict>,
        out: &mut Vec<Item>,
    ) -> Result<()> {
        match tok {
            Tok::Word(w) if w.starts_with('$') && w.len() > 1 => {
                match self.lookup_var(&w, scopes, at)? {
                    Value::Stream(s) => out.extend(s),
                    Value::Dict(d) => out.push(Item::Dict(d)),
                }
            }
            Tok::Word(w) if w.starts_with('#') => {
                return Err(self.lex.error_at(
                    at,
                    format!("directive `{w}` is not supported inside a value"),
                ))
            }
            Tok::Word(w) => {
                let elem = w
                    .strip_prefix("List<")
                    .and_then(|t| t.strip_suffix('>'))
                    .and_then(Elem::from_type);
                let next_is_list = matches!(self.lex.peek()?, Tok::Label(_) | Tok::Punct(b'('));
                if let (Some(elem), true) = (elem, next_is_list) {
                    out.push(Item::Word(w.clone()));
                    let type_name = &w[5..w.len() - 1];
                    out.push(self.parse_typed_list(elem, type_name)?);
                } else if self.lex.peek()? == &Tok::Punct(b'{') {
                    let open = self.lex.here();
                    self.lex.next_tok()?;
                    let d = self.parse_sub_dict(scopes, open)?;
                    out.push(Item::Named(w, d));
                } else {
                    out.push(Item::Word(w));
                }
            }
            Tok::Str(s) => out.push(Item::Str(s)),
            Tok::Scalar(v) => out.push(Item::Scalar(v)),
            Tok::Label(n) => match self.lex.peek()? {
                Tok::Punct(b'{') => {
                    let count = self.count(n, at)?;
                    self.lex.next_tok()?;
                    let mut one = Vec::new();
                    let (t, tat) = self.lex.next_located()?;
                    self.parse_item(t, tat, scopes, &mut one)?;
                    self.lex
                        .expect_punct(b'}', "to close a uniform list `N{value}`")?;
                    let [v] = <[Item; 1]>::try_from(one).map_err(|_| {
                        self.lex
                            .error_at(at, "a uniform list `N{value}` needs exactly one value")
                    })?;
                    out.push(Item::List(vec![v; count]));
                }
                _ => out.push(Item::Label(n)),
            },
            Tok::Punct(b'(') => out.push(Item::List(self.parse_list_items(scopes, at, b')')?)),
            Tok::Punct(b'[') => out.push(Item::Dims(self.parse_list_items(scopes, at, b']')?)),
            Tok::Punct(b'{') => {
                let d = self.parse_sub_dict(scopes, at)?;
                out.push(Item::Dict(d));
            }
            Tok::Punct(c @ (b',' | b':' | b'=')) => out.push(Item::Punct(c as char)),
            Tok::Verbatim(v) => out.push(Item::Verbatim(v)),
            other => {
                return Err(self
                    .lex
                    .error_at(at, format!("unexpected {}", other.describe())))
            }
        }
        Ok(())
    }

    /// Checks a declared list length: not negative and not more than the bytes left could hold.
    pub(crate) fn count(&self, n: i64, at: Location) -> Result<usize> {
        if n < 0 || n as u64 > self.lex.remaining() as u64 {
            return Err(self.lex.error_at(
                at,
                format!(
                    "list length {n} is impossible ({} bytes left in the file)",
                    self.lex.remaining()
                ),
            ));
        }
        Ok(n as usize)
    }

    /// Items up to the closing `close` (the opening bracket is consumed already).
    fn parse_list_items(
        &mut self,
        scopes: &mut Vec<Dict>,
        open: Location,
        close: u8,
    ) -> Result<Vec<Item>> {
        let mut items = Vec::new();
        loop {
            let (tok, at) = self.lex.next_located()?;
            match tok {
                Tok::Punct(c) if c == close => break,
                Tok::Eof => {
                    return Err(self.lex.error_at(
                        open,
                        format!("list opened here is never closed by `{}`", close as char),
                    ))
                }
                Tok::Punct(b';') => {
                    return Err(self.lex.error_at(
                        at,
                        format!("`;` inside a list opened at line {}", open.line),
                    ))
                }
                t => self.parse_item(t, at, scopes, &mut items)?,
            }
        }
        Ok(items)
    }

    /// Reads a typed list after `List<T>`: `N(…)`, `N{v}` or `(…)`, ASCII or binary.
    pub(crate) fn parse_typed_list(&mut self, elem: Elem, type_name: &str) -> Result<Item> {
        let mut labels = Vec::new();
        let mut values = Vec::new();
        self.read_typed(elem, &mut labels, &mut values)?;
        Ok(match elem {
            Elem::Label => Item::Labels(labels),
            Elem::Scalar => Item::Scalars(values),
            Elem::Vector => {
                Item::Vectors(values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
            }
            Elem::Tuple(n) => Item::Tuples {
                type_name: type_name.to_string(),
                components: n,
                values,
            },
        })
    }

    /// Reads one list of `elem` into `labels` (for labels) or `values` (flattened components).
    pub(crate) fn read_typed(
        &mut self,
        elem: Elem,
        labels: &mut Vec<i64>,
        values: &mut Vec<f64>,
    ) -> Result<()> {
        let (tok, at) = self.lex.next_located()?;
        let count = match tok {
            Tok::Label(n) => Some(self.count(n, at)?),
            Tok::Punct(b'(') => None,
            other => {
                return Err(self.lex.error_at(
                    at,
                    format!("expected a list (`N(` or `(`), found {}", other.describe()),
                ))
            }
        };
        let comps = elem.components();
        if let Some(n) = count {
            let (t, oat) = self.lex.next_located()?;
            match t {
                Tok::Punct(b'(') => {}
                Tok::Punct(b'{') => {
                    // Uniform list N{v}.
                    let one = self.read_elements(elem, Some(1), oat, b'}', labels, values)?;
                    debug_assert_eq!(one, 1);
                    if elem == Elem::Label {
                        let v = labels[labels.len() - 1];
                        labels.resize(labels.len() - 1 + n, v);
                    } else {
                        let v: Vec<f64> = values[values.len() - comps..].to_vec();
                        values.truncate(values.len() - comps);
                        for _ in 0..n {
                            values.extend_from_slice(&v);
                        }
                    }
                    return Ok(());
                }
                other => {
                    return Err(self.lex.error_at(
                        oat,
                        format!(
                            "expected `(` after list length {n}, found {}",
                            other.describe()
                        ),
                    ))
                }
            }
            if self.format == Format::Binary {
                let size = if elem == Elem::Label {
                    self.arch.label_bytes
                } else {
                    self.arch.scalar_bytes * comps
                };
                let raw_at = self.lex.here();
                let bytes = n
                    .checked_mul(size)
                    .ok_or_else(|| self.lex.error_at(at, format!("list length {n} overflows")))?;
                let raw = self.lex.read_raw(bytes)?;
                if elem == Elem::Label {
                    self.arch.decode_labels(raw, labels);
                } else {
                    self.arch.decode_scalars(raw, values);
                }
                let (t, cat) = self.lex.next_located()?;
                if t != Tok::Punct(b')') {
                    return Err(self.lex.error_at(
                        cat,
                        format!(
                            "binary list of {n} {}s starting at byte {} is not closed by `)` \
                             (found {}): wrong length or arch?",
                            type_label(elem),
                            raw_at.byte,
                            t.describe()
                        ),
                    ));
                }
                return Ok(());
            }
            self.read_elements(elem, Some(n), oat, b')', labels, values)?;
        } else {
            self.read_elements(elem, None, at, b')', labels, values)?;
        }
        Ok(())
    }

    /// ASCII elements up to `close`; returns how many were read.
    fn read_elements(
        &mut self,
        elem: Elem,
        count: Option<usize>,
        open: Location,
        close: u8,
        labels: &mut Vec<i64>,
        values: &mut Vec<f64>,
    ) -> Result<usize> {
        let comps = elem.components();
        if let Some(n) = count {
            if elem == Elem::Label {
                labels.reserve(n);
            } else {
                values.reserve(n * comps);
            }
        }
        let mut k = 0usize;
        loop {
            let (t, at) = self.lex.next_located()?;
            match t {
                Tok::Punct(c) if c == close => break,
                Tok::Label(l) if comps == 1 => {
                    if elem == Elem::Label {
                        labels.push(l);
                    } else {
                        values.push(l as f64);
                    }
                }
                Tok::Scalar(s) if elem == Elem::Scalar => values.push(s),
                Tok::Punct(b'(') if comps > 1 => {
                    for c in 0..comps {
                        let (t, cat) = self.lex.next_located()?;
                        match t {
                            Tok::Label(l) => values.push(l as f64),
                            Tok::Scalar(s) => values.push(s),
                            other => {
                                return Err(self.lex.error_at(
                                    cat,
                                    format!(
                                        "{} {k}: component {c} should be a number, found {}",
                                        type_label(elem),
                                        other.describe()
                                    ),
                                ))
                            }
                        }
                    }
                    self.lex.expect_punct(
                        b')',
                        &format!("after the {comps} components of {} {k}", type_label(elem)),
                    )?;
                }
                Tok::Eof => {
                    return Err(self.lex.error_at(
                        open,
                        format!(
                            "list opened here ends with the file after {k} {}s",
                            type_label(elem)
                        ),
                    ))
                }
                other => {
                    return Err(self.lex.error_at(
                        at,
                        format!(
                            "{} {k}: expected a {}, found {}",
                            type_label(elem),
                            type_label(elem),
                            other.describe()
                        ),
                    ))
                }
            }
            k += 1;
        }
        if let Some(n) = count {
            if k != n {
                return Err(self.lex.error_at(
                    open,
                    format!("list declares {n} {}s but holds {k}", type_label(elem)),
                ));
            }
        }
        Ok(k)
    }
}

fn type_label(e: Elem) -> &'static str {
    match e {
        Elem::Scalar => "scalar",
        Elem::Vector => "vector",
        Elem::Label => "label",
        Elem::Tuple(_) => "tensor",
    }
}

/// Expands `$VAR`, `${VAR}` (environment), `$FOAM_CASE` / `<case>`, `<constant>`, `<system>`
/// (the case holding `dir`: the nearest ancestor with `system/controlDict`) in an include path.
fn expand_path_vars(name: &str, dir: &Path) -> Result<String, String> {
    let case_root = || -> Result<PathBuf, String> {
        dir.ancestors()
            .find(|d| d.join("system").join("controlDict").exists())
            .map(Path::to_path_buf)
            .ok_or_else(|| format!("cannot resolve the case directory for `{name}`"))
    };
    let mut s = name.to_string();
    for (tag, sub) in [
        ("<case>", ""),
        ("<constant>", "constant"),
        ("<system>", "system"),
    ] {
        if s.contains(tag) {
            let root = case_root()?;
            s = s.replace(tag, &root.join(sub).to_string_lossy());
        }
    }
    let mut out = String::new();
    let mut rest = s.as_str();
    while let Some(i) = rest.find('$') {
        out.push_str(&rest[..i]);
        let after = &rest[i + 1..];
        let (var, tail) = if let Some(b) = after.strip_prefix('{') {
            let end = b
                .find('}')
                .ok_or_else(|| format!("unclosed `${{` in `{name}`"))?;
            (&b[..end], &b[end + 1..])
        } else {
            let end = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            (&after[..end], &after[end..])
        };
        let value = if var == "FOAM_CASE" {
            case_root()?.to_string_lossy().into_owned()
        } else {
            std::env::var(var)
                .map_err(|_| format!("environment variable `{var}` in `{name}` is not set"))?
        };
        out.push_str(&value);
        rest = tail;
    }
    out.push_str(rest);
    Ok(out)
}
