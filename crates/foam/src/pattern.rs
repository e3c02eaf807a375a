//! Keyword patterns: a quoted keyword in a dictionary (`"(inlet|outlet)"`, `".*Wall"`) is a
//! regular expression that must match a whole name, as in OpenFOAM's `wordRe`.

/// True when `pattern`, read as a regular expression, matches all of `name`. A pattern that is
/// not a valid regular expression matches only itself literally.
pub fn matches_whole(pattern: &str, name: &str) -> bool {
    match regex::Regex::new(&format!("^(?:{pattern})$")) {
        Ok(re) => re.is_match(name),
        Err(_) => pattern == name,
    }
}

#[cfg(test)]
mod tests {
    use super::matches_whole;

    #[test]
    fn whole_name_matching() {
        assert!(matches_whole("(inlet|outlet)", "inlet"));
        assert!(!matches_whole("(inlet|outlet)", "inlet2"));
        assert!(matches_whole(".*Wall", "leftWall"));
        assert!(!matches_whole("wall", "walls"));
        assert!(matches_whole("a(b", "a(b"));
    }
}
