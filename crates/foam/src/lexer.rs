//! Tokenizer for OpenFOAM's FoamFile format.
//!
//! Rules (after OpenFOAM's `ISstream`): `//` and `/* */` comments; punctuation `; { } ( ) [ ]`
//! and `, : =`; quoted strings with `\"` escapes; `#{ … #}` verbatim blocks; numbers start with a
//! digit, or with `+ - .` followed by a digit; every other run of characters is a word, which may
//! contain balanced parentheses (`div(phi,U)`) and ends at white space, `"`, `;`, braces,
//! brackets or an unmatched `)`. Raw binary blocks are read on request of the parser, which knows
//! their size from the list header (`N(`).

use crate::error::{FoamError, Location, Result};
use std::path::Path;

/// One token.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A word: keyword, `List<scalar>`, `$var`, `#include`, …
    Word(String),
    /// A quoted string (quotes removed, escapes resolved).
    Str(String),
    /// An integer.
    Label(i64),
    /// A floating-point number.
    Scalar(f64),
    /// A punctuation character.
    Punct(u8),
    /// A `#{ … #}` verbatim block (content only).
    Verbatim(String),
    /// End of input.
    Eof,
}

impl Tok {
    /// A short description for error messages.
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Word(w) => format!("word `{w}`"),
            Tok::Str(s) => format!("string \"{s}\""),
            Tok::Label(l) => format!("number {l}"),
            Tok::Scalar(s) => format!("number {s}"),
            Tok::Punct(c) => format!("`{}`", *c as char),
            Tok::Verbatim(_) => "verbatim block".into(),
            Tok::Eof => "end of file".into(),
        }
    }
}

/// A tokenizer over the bytes of one file.
pub(crate) struct Lexer<'a> {
    src: &'a [u8],
    pos: usize,
    line: usize,
    path: &'a Path,
    peeked: Option<(Tok, Location)>,
}

fn is_punct(c: u8) -> bool {
    matches!(
        c,
        b';' | b'{' | b'}' | b'(' | b')' | b'[' | b']' | b',' | b':' | b'='
    )
}

fn ends_word(c: u8) -> bool {
    c.is_ascii_whitespace() || matches!(c, b'"' | b';' | b'{' | b'}' | b'[' | b']')
}

impl<'a> Lexer<'a> {
    pub(crate) fn new(src: &'a [u8], path: &'a Path) -> Self {
        Lexer {
            src,
            pos: 0,
            line: 1,
            path,
            peeked: None,
        }
    }

    /// The path being read (for error messages).
    pub(crate) fn path(&self) -> &'a Path {
        self.path
    }

    /// The current location (of the next unread byte, or of the peeked token).
    pub(crate) fn here(&self) -> Location {
        match &self.peeked {
            Some((_, at)) => *at,
            None => Location {
                line: self.line,
                byte: self.pos,
            },
        }
    }

    /// A parse error at `at`.
    pub(crate) fn error_at(&self, at: Location, msg: impl Into<String>) -> FoamError {
        FoamError::Parse {
            path: self.path.to_path_buf(),
            at,
            msg: msg.into(),
        }
    }

    /// A parse error at the current location.
    pub(crate) fn error(&self, msg: impl Into<String>) -> FoamError {
        self.error_at(self.here(), msg)
    }

    fn skip_space_and_comments(&mut self) -> Result<()> {
        loop {
            while self.pos < self.src.len() && self.src[self.pos].is_ascii_whitespace() {
                if self.src[self.pos] == b'\n' {
                    self.line += 1;
                }
                self.pos += 1;
            }
            if self.src[self.pos..].starts_with(b"//") {
                while self.pos < self.src.len() && self.src[self.pos] != b'\n' {
                    self.pos += 1;
                }
            } else if self.src[self.pos..].starts_with(b"/*") {
                let start = self.here();
                self.pos += 2;
                loop {
                    if self.pos + 1 >= self.src.len() {
                        return Err(self.error_at(start, "comment `/*` is never closed"));
                    }
                    if self.src[self.pos] == b'*' && self.src[self.pos + 1] == b'/' {
                        self.pos += 2;
                        break;
                    }
                    if self.src[self.pos] == b'\n' {
                        self.line += 1;
                    }
                    self.pos += 1;
                }
            } else {
                return Ok(());
            }
        }
    }

    /// Looks at the next token without consuming it.
    pub(crate) fn peek(&mut self) -> Result<&Tok> {
        if self.peeked.is_none() {
            let t = self.scan()?;
            self.peeked = Some(t);
        }
        Ok(&self.peeked.as_ref().unwrap().0)
    }

    /// The next token and where it starts.
    pub(crate) fn next_located(&mut self) -> Result<(Tok, Location)> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => self.scan(),
        }
    }

    /// The next token.
    pub(crate) fn next_tok(&mut self) -> Result<Tok> {
        Ok(self.next_located()?.0)
    }

    /// Consumes the punctuation `c` or fails naming what was found instead.
    pub(crate) fn expect_punct(&mut self, c: u8, context: &str) -> Result<()> {
        let (t, at) = self.next_located()?;
        if t == Tok::Punct(c) {
            Ok(())
        } else {
            Err(self.error_at(
                at,
                format!("expected `{}` {context}, found {}", c as char, t.describe()),
            ))
        }
    }

    /// Reads `n` raw bytes right after a `(` (binary list content). Must not be called with a
    /// token peeked.
    pub(crate) fn read_raw(&mut self, n: usize) -> Result<&'a [u8]> {
        debug_assert!(self.peeked.is_none());
        let left = self.src.len() - self.pos;
        if n > left {
            return Err(self.error(format!(
                "binary list cut short: needs {n} bytes, only {left} left in the file"
            )));
        }
        let s = &self.src[self.pos..self.pos + n];
        self.pos += n;
        Ok(s)
    }

    /// Bytes left after the current position (to bound allocation from declared counts).
    pub(crate) fn remaining(&self) -> usize {
        self.src.len() - self.pos
    }

    fn scan(&mut self) -> Result<(Tok, Location)> {
        self.skip_space_and_comments()?;
        let at = Location {
            line: self.line,
            byte: self.pos,
        };
        let Some(&c) = self.src.get(self.pos) else {
            return Ok((Tok::Eof, at));
        };
        let next = self.src.get(self.pos + 1).copied();
        let tok = if c == b'"' {
            self.scan_string(at)?
        } else if c == b'#' && next == Some(b'{') {
            self.scan_verbatim(at)?
        } else if is_punct(c) {
            self.pos += 1;
            Tok::Punct(c)
        } else if c.is_ascii_digit()
            || (matches!(c, b'+' | b'-' | b'.')
                && next.is_some_and(|n| n.is_ascii_digit() || (n == b'.' && c != b'.')))
        {
            self.scan_number(at)?
        } else {
            self.scan_word()
        };
        Ok((tok, at))
    }

    fn scan_string(&mut self, at: Location) -> Result<Tok> {
        self.pos += 1;
        let mut s = Vec::new();
        loop {
            let Some(&c) = self.src.get(self.pos) else {
                return Err(self.error_at(at, "string is never closed"));
            };
            self.pos += 1;
            match c {
                b'"' => break,
                b'\\' if self.src.get(self.pos) == Some(&b'"') => {
                    s.push(b'"');
                    self.pos += 1;
                }
                b'\n' => {
                    self.line += 1;
                    s.push(c);
                }
                _ => s.push(c),
            }
        }
        String::from_utf8(s)
            .map(Tok::Str)
            .map_err(|_| self.error_at(at, "string is not valid UTF-8"))
    }

    fn scan_verbatim(&mut self, at: Location) -> Result<Tok> {
        self.pos += 2;
        let start = self.pos;
        loop {
            if self.pos + 1 >= self.src.len() {
                return Err(self.error_at(at, "verbatim block `#{` is never closed by `#}`"));
            }
            if self.src[self.pos] == b'#' && self.src[self.pos + 1] == b'}' {
                break;
            }
            if self.src[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        let body = String::from_utf8_lossy(&self.src[start..self.pos]).into_owned();
        self.pos += 2;
        Ok(Tok::Verbatim(body))
    }

    fn scan_number(&mut self, at: Location) -> Result<Tok> {
        let start = self.pos;
        while self.pos < self.src.len()
            && matches!(
                self.src[self.pos],
                b'0'..=b'9' | b'.' | b'e' | b'E' | b'+' | b'-'
            )
        {
            self.pos += 1;
        }
        // A number glued to word characters ("1abc", "2D") is a word, as in OpenFOAM.
        if self.pos < self.src.len()
            && !ends_word(self.src[self.pos])
            && !is_punct(self.src[self.pos])
            && !self.src[self.pos..].starts_with(b"//")
            && !self.src[self.pos..].starts_with(b"/*")
        {
            self.pos = start;
            return Ok(self.scan_word());
        }
        let text = std::str::from_utf8(&self.src[start..self.pos]).unwrap();
        let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
        if digits.bytes().all(|b| b.is_ascii_digit()) {
            if let Ok(v) = text.parse::<i64>() {
                return Ok(Tok::Label(v));
            }
        }
        text.parse::<f64>()
            .map(Tok::Scalar)
            .map_err(|_| self.error_at(at, format!("malformed number `{text}`")))
    }

    fn scan_word(&mut self) -> Tok {
        let start = self.pos;
        if self.src[start..].starts_with(b"${") {
            // `${name}`: a variable written with braces.
            if let Some(end) = self.src[start..]
                .iter()
                .position(|&c| c == b'}' || c == b'\n')
            {
                if self.src[start + end] == b'}' {
                    self.pos = start + end + 1;
                    return Tok::Word(
                        String::from_utf8_lossy(&self.src[start..self.pos]).into_owned(),
                    );
                }
            }
        }
        let mut depth = 0usize;
        while let Some(&c) = self.src.get(self.pos) {
            if ends_word(c) {
                break;
            }
            if c == b'/' && matches!(self.src.get(self.pos + 1), Some(b'/' | b'*')) {
                break;
            }
            if c == b'(' {
                depth += 1;
            } else if c == b')' {
                if depth == 0 {
                    break;
                }
                depth -= 1;
            }
            self.pos += 1;
        }
        if self.pos == start {
            // A lone character that starts nothing else: take it as a one-byte word so the
            // parser can report it.
            self.pos += 1;
        }
        Tok::Word(String::from_utf8_lossy(&self.src[start..self.pos]).into_owned())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn toks(s: &str) -> Vec<Tok> {
        let p = Path::new("t");
        let mut l = Lexer::new(s.as_bytes(), p);
        let mut v = Vec::new();
        loop {
            let t = l.next_tok().unwrap();
            if t == Tok::Eof {
                return v;
            }
            v.push(t);
        }
    }

    #[test]
    fn words_numbers_punctuation_and_comments() {
        use Tok::*;
        let t =
            toks("div(phi,U) Gauss linear; // c\n /* x \n y */ a 1e-05 -3 .5 [0 1 -1] \"q\\\"s\"");
        assert_eq!(
            t,
            vec![
                Word("div(phi,U)".into()),
                Word("Gauss".into()),
                Word("linear".into()),
                Punct(b';'),
                Word("a".into()),
                Scalar(1e-5),
                Label(-3),
                Scalar(0.5),
                Punct(b'['),
                Label(0),
                Label(1),
                Label(-1),
                Punct(b']'),
                Str("q\"s".into()),
            ]
        );
    }

    #[test]
    fn counted_lists_and_uniform_lists() {
        use Tok::*;
        assert_eq!(
            toks("3(1 2 3) 2{0} List<scalar>"),
            vec![
                Label(3),
                Punct(b'('),
                Label(1),
                Label(2),
                Label(3),
                Punct(b')'),
                Label(2),
                Punct(b'{'),
                Label(0),
                Punct(b'}'),
                Word("List<scalar>".into()),
            ]
        );
    }

    #[test]
    fn unclosed_comment_names_its_line() {
        let p = Path::new("f");
        let mut l = Lexer::new(b"a\n/* open", p);
        l.next_tok().unwrap();
        let e = l.next_tok().unwrap_err().to_string();
        assert!(e.contains("f: line 2"), "{e}");
    }

    #[test]
    fn words_glued_to_digits_and_inf_are_words() {
        use Tok::*;
        assert_eq!(
            toks("2D inf nan -x"),
            vec![
                Word("2D".into()),
                Word("inf".into()),
                Word("nan".into()),
                Word("-x".into())
            ]
        );
    }

    #[test]
    fn raw_read_reports_short_block() {
        let p = Path::new("f");
        let mut l = Lexer::new(b"2(abc", p);
        assert_eq!(l.next_tok().unwrap(), Tok::Label(2));
        assert_eq!(l.next_tok().unwrap(), Tok::Punct(b'('));
        let e = l.read_raw(16).unwrap_err().to_string();
        assert!(e.contains("cut short"), "{e}");
    }
}
