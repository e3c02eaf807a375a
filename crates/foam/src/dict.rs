//! The dictionary data model: a FoamFile is a [`Dict`] of [`Entry`]s; an entry is either a
//! sub-dictionary or a stream of [`Item`]s ended by `;`.

use std::fmt;

/// One item of an entry's value stream (what stands between the keyword and the `;`).
#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    /// A bare word (`uniform`, `fixedValue`, `List<scalar>`, `div(phi,U)`).
    Word(String),
    /// A quoted string (without the quotes).
    Str(String),
    /// An integer token.
    Label(i64),
    /// A floating-point token.
    Scalar(f64),
    /// A parenthesised list of items, e.g. a vector `(0 0 1)` or a word list `(wall)`.
    List(Vec<Item>),
    /// A contiguous list of scalars (`List<scalar>`), ASCII or binary in the file.
    Scalars(Vec<f64>),
    /// A contiguous list of vectors (`List<vector>`), ASCII or binary in the file.
    Vectors(Vec<[f64; 3]>),
    /// A contiguous list of labels (`List<label>`), ASCII or binary in the file.
    Labels(Vec<i64>),
    /// A contiguous list of fixed-size tuples other than vectors (`List<tensor>` has 9
    /// components, `List<symmTensor>` 6): `values.len()` is a multiple of `components`.
    Tuples {
        /// Type name as written, e.g. `tensor`.
        type_name: String,
        /// Components per element.
        components: usize,
        /// All components, element after element.
        values: Vec<f64>,
    },
    /// A dimension set `[0 1 -1 0 0 0 0]` (or with unit names).
    Dims(Vec<Item>),
    /// A dictionary inside a list (`name { … }` in the `boundary` file gives `Named`).
    Dict(Dict),
    /// A named dictionary inside a list: `inlet { type patch; … }`.
    Named(String, Dict),
    /// Punctuation kept in a stream, such as `,` `:` `=`.
    Punct(char),
    /// A `#{ … #}` verbatim block.
    Verbatim(String),
}

impl Item {
    /// The number, if this item is a label or a scalar.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            Item::Label(l) => Some(l as f64),
            Item::Scalar(s) => Some(s),
            _ => None,
        }
    }

    /// The integer, if this item is a label.
    pub fn as_label(&self) -> Option<i64> {
        match *self {
            Item::Label(l) => Some(l),
            _ => None,
        }
    }

    /// The text, if this item is a word or a string.
    pub fn as_word(&self) -> Option<&str> {
        match self {
            Item::Word(w) | Item::Str(w) => Some(w),
            _ => None,
        }
    }

    /// The vector, if this item is a list of exactly three numbers.
    pub fn as_vector(&self) -> Option<[f64; 3]> {
        match self {
            Item::List(v) if v.len() == 3 => Some([v[0].as_f64()?, v[1].as_f64()?, v[2].as_f64()?]),
            Item::Scalars(v) if v.len() == 3 => Some([v[0], v[1], v[2]]),
            _ => None,
        }
    }

    /// The numbers of a list item (a generic list of numbers or a typed scalar list).
    pub fn as_f64_list(&self) -> Option<Vec<f64>> {
        match self {
            Item::List(v) => v.iter().map(Item::as_f64).collect(),
            Item::Scalars(v) => Some(v.clone()),
            Item::Labels(v) => Some(v.iter().map(|&l| l as f64).collect()),
            _ => None,
        }
    }

    /// A short description for error messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Item::Word(_) => "word",
            Item::Str(_) => "string",
            Item::Label(_) => "integer",
            Item::Scalar(_) => "number",
            Item::List(_) => "list",
            Item::Scalars(_) => "scalar list",
            Item::Vectors(_) => "vector list",
            Item::Labels(_) => "label list",
            Item::Tuples { .. } => "tuple list",
            Item::Dims(_) => "dimension set",
            Item::Dict(_) | Item::Named(..) => "dictionary",
            Item::Punct(_) => "punctuation",
            Item::Verbatim(_) => "verbatim block",
        }
    }
}

/// The value of an entry.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// `keyword { … }`
    Dict(Dict),
    /// `keyword item item … ;`
    Stream(Vec<Item>),
}

/// One keyword and its value.
#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    /// The keyword. A quoted keyword (`"(inlet|outlet)"`) is a regular-expression pattern.
    pub keyword: String,
    /// True when the keyword was quoted, i.e. is a pattern.
    pub pattern: bool,
    /// The value.
    pub value: Value,
}

/// A dictionary: entries in file order, keywords unique (later definitions merged or replaced
/// according to `#inputMode` while parsing).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Dict {
    entries: Vec<Entry>,
}

/// Why a typed lookup failed; the caller adds the file name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LookupError(pub String);

impl fmt::Display for LookupError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for LookupError {}

impl Dict {
    /// An empty dictionary.
    pub fn new() -> Self {
        Self::default()
    }

    /// The entries in order.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// Mutable access to the entries.
    pub fn entries_mut(&mut self) -> &mut Vec<Entry> {
        &mut self.entries
    }

    /// The keywords in order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.entries.iter().map(|e| e.keyword.as_str())
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The entry with this exact keyword.
    pub fn entry(&self, key: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.keyword == key)
    }

    /// The value with this exact keyword.
    pub fn get(&self, key: &str) -> Option<&Value> {
        self.entry(key).map(|e| &e.value)
    }

    /// Mutable value with this exact keyword.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Value> {
        self.entries
            .iter_mut()
            .find(|e| e.keyword == key)
            .map(|e| &mut e.value)
    }

    /// True when the keyword exists.
    pub fn contains(&self, key: &str) -> bool {
        self.entry(key).is_some()
    }

    /// Sets (replaces or appends) an entry.
    pub fn set(&mut self, key: &str, value: Value) {
        match self.get_mut(key) {
            Some(v) => *v = value,
            None => self.entries.push(Entry {
                keyword: key.to_string(),
                pattern: false,
                value,
            }),
        }
    }

    /// Sets a stream entry of one item.
    pub fn set_item(&mut self, key: &str, item: Item) {
        self.set(key, Value::Stream(vec![item]));
    }

    /// Removes an entry; returns it if it existed.
    pub fn remove(&mut self, key: &str) -> Option<Entry> {
        let i = self.entries.iter().position(|e| e.keyword == key)?;
        Some(self.entries.remove(i))
    }

    /// Appends an entry without checking for duplicates (the parser handles `#inputMode`).
    pub(crate) fn push(&mut self, e: Entry) {
        self.entries.push(e);
    }

    /// The sub-dictionary `key`.
    pub fn dict(&self, key: &str) -> Result<&Dict, LookupError> {
        match self.get(key) {
            Some(Value::Dict(d)) => Ok(d),
            Some(Value::Stream(_)) => {
                Err(LookupError(format!("entry `{key}` is not a dictionary")))
            }
            None => Err(LookupError(format!("missing dictionary `{key}`"))),
        }
    }

    /// The sub-dictionary `key`, if present.
    pub fn opt_dict(&self, key: &str) -> Option<&Dict> {
        match self.get(key) {
            Some(Value::Dict(d)) => Some(d),
            _ => None,
        }
    }

    /// The items of stream entry `key`.
    pub fn stream(&self, key: &str) -> Result<&[Item], LookupError> {
        match self.get(key) {
            Some(Value::Stream(s)) => Ok(s),
            Some(Value::Dict(_)) => Err(LookupError(format!(
                "entry `{key}` is a dictionary, expected a value"
            ))),
            None => Err(LookupError(format!("missing entry `{key}`"))),
        }
    }

    /// The single item of entry `key` (an entry of several items is an error).
    pub fn item(&self, key: &str) -> Result<&Item, LookupError> {
        match self.stream(key)? {
            [one] => Ok(one),
            s => Err(LookupError(format!(
                "entry `{key}` should hold one value but holds {}",
                s.len()
            ))),
        }
    }

    /// Entry `key` as a number.
    pub fn f64(&self, key: &str) -> Result<f64, LookupError> {
        let it = self.item(key)?;
        it.as_f64().ok_or_else(|| {
            LookupError(format!(
                "entry `{key}` should be a number, found a {}",
                it.kind()
            ))
        })
    }

    /// Entry `key` as a number, or `default` when absent.
    pub fn f64_or(&self, key: &str, default: f64) -> Result<f64, LookupError> {
        if self.contains(key) {
            self.f64(key)
        } else {
            Ok(default)
        }
    }

    /// Entry `key` as an integer.
    pub fn label(&self, key: &str) -> Result<i64, LookupError> {
        let it = self.item(key)?;
        it.as_label().ok_or_else(|| {
            LookupError(format!(
                "entry `{key}` should be an integer, found a {}",
                it.kind()
            ))
        })
    }

    /// Entry `key` as a word or string.
    pub fn word(&self, key: &str) -> Result<&str, LookupError> {
        let it = self.item(key)?;
        it.as_word().ok_or_else(|| {
            LookupError(format!(
                "entry `{key}` should be a word, found a {}",
                it.kind()
            ))
        })
    }

    /// Entry `key` as a vector `(x y z)`.
    pub fn vector(&self, key: &str) -> Result<[f64; 3], LookupError> {
        let it = self.item(key)?;
        it.as_vector().ok_or_else(|| {
            LookupError(format!(
                "entry `{key}` should be a vector (x y z), found a {}",
                it.kind()
            ))
        })
    }

    /// Entry `key` as a switch (`yes/no`, `on/off`, `true/false`, `y/n`, `1/0`).
    pub fn switch(&self, key: &str) -> Result<bool, LookupError> {
        let it = self.item(key)?;
        let v = match it {
            Item::Word(w) => match w.as_str() {
                "yes" | "on" | "true" | "y" | "t" => Some(true),
                "no" | "off" | "false" | "n" | "f" | "none" => Some(false),
                _ => None,
            },
            Item::Label(1) => Some(true),
            Item::Label(0) => Some(false),
            _ => None,
        };
        v.ok_or_else(|| {
            LookupError(format!(
                "entry `{key}` should be a switch (yes/no, on/off, true/false)"
            ))
        })
    }

    /// Looks up a possibly scoped name as OpenFOAM's `$var` does, relative to this dictionary:
    /// `a.b` descends into sub-dictionary `a`; each part matches an exact keyword first, then a
    /// pattern keyword (the last defined first), as OpenFOAM v1912's scoped search does.
    /// Returns `None` when not found here.
    pub fn lookup_path(&self, path: &str) -> Option<&Value> {
        let mut d = self;
        let mut parts = path.split('.').peekable();
        while let Some(p) = parts.next() {
            let v = match d.get(p) {
                Some(v) => v,
                None => {
                    &d.entries
                        .iter()
                        .rev()
                        .find(|e| e.pattern && crate::pattern::matches_whole(&e.keyword, p))?
                        .value
                }
            };
            if parts.peek().is_none() {
                return Some(v);
            }
            match v {
                Value::Dict(sub) => d = sub,
                Value::Stream(_) => return None,
            }
        }
        None
    }

    /// The entry that applies to `name` the way OpenFOAM resolves boundaryField entries: an
    /// exact keyword first, then any of `groups` (patch groups, `inGroups`), then patterns
    /// (quoted keywords, regular expressions matching the whole name), the last one defined
    /// winning.
    pub fn resolve(&self, name: &str, groups: &[String]) -> Option<&Entry> {
        if let Some(e) = self
            .entries
            .iter()
            .find(|e| !e.pattern && e.keyword == name)
        {
            return Some(e);
        }
        for g in groups {
            if let Some(e) = self.entries.iter().find(|e| !e.pattern && &e.keyword == g) {
                return Some(e);
            }
        }
        self.entries
            .iter()
            .rev()
            .filter(|e| e.pattern)
            .find(|e| crate::pattern::matches_whole(&e.keyword, name))
    }
}
