//! Logical lines of a deck: `&` at the end of a line continues it, `#` starts a comment outside
//! quotes, and words are split on blanks with `"…"`/`'…'` quoting (as LAMMPS's input parser).

/// One logical line: its first physical line (1-based) and its text without comment.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LogicalLine {
    /// 1-based number of the first physical line.
    pub line: usize,
    /// The joined text.
    pub text: String,
}

/// Joins continued lines; comments are removed afterwards by [`strip_comment`].
pub fn logical_lines(src: &str) -> Vec<LogicalLine> {
    let mut out = Vec::new();
    let mut cur: Option<LogicalLine> = None;
    for (k, raw) in src.lines().enumerate() {
        let trimmed = raw.trim_end();
        // as LAMMPS: a trailing `&` continues the line even inside a comment
        let (body, cont) = match trimmed.strip_suffix('&') {
            Some(b) => (b, true),
            None => (trimmed, false),
        };
        match cur.as_mut() {
            Some(l) => {
                l.text.push(' ');
                l.text.push_str(body);
            }
            None => {
                cur = Some(LogicalLine {
                    line: k + 1,
                    text: body.to_string(),
                })
            }
        }
        if !cont {
            out.extend(cur.take());
        }
    }
    out.extend(cur);
    out
}

/// The text before an unquoted `#`.
pub fn strip_comment(s: &str) -> &str {
    let mut quote: Option<char> = None;
    for (i, c) in s.char_indices() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => {}
            None if c == '"' || c == '\'' => quote = Some(c),
            None if c == '#' => return &s[..i],
            None => {}
        }
    }
    s
}

/// Splits on blanks, keeping quoted words together (quotes removed).
pub fn split_words(s: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut cur = String::new();
    let mut in_word = false;
    let mut quote: Option<char> = None;
    for c in s.chars() {
        match quote {
            Some(q) if c == q => quote = None,
            Some(_) => cur.push(c),
            None if c == '"' || c == '\'' => {
                quote = Some(c);
                in_word = true;
            }
            None if c.is_whitespace() => {
                if in_word {
                    words.push(std::mem::take(&mut cur));
                    in_word = false;
                }
            }
            None => {
                cur.push(c);
                in_word = true;
            }
        }
    }
    if quote.is_some() {
        return Err("unterminated quote".into());
    }
    if in_word {
        words.push(cur);
    }
    Ok(words)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuation_comments_quotes() {
        let l = logical_lines("a b &\n  c # x\n\nd \"e f\" # g\nh");
        assert_eq!(l[0].line, 1);
        assert_eq!(strip_comment(&l[0].text).trim(), "a b    c");
        assert_eq!(l[2].line, 4);
        assert_eq!(
            split_words(strip_comment(&l[2].text)).unwrap(),
            ["d", "e f"]
        );
        assert_eq!(l[3].text, "h");
        assert_eq!(split_words("x '#y' z").unwrap(), ["x", "#y", "z"]);
        assert!(split_words("x \"y").is_err());
    }
}
