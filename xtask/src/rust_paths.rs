//! Reading Rust source without a parser, for [`crate::code_shape`]: comments, strings and
//! test modules blanked out, the paths that start with `crate`, `super` or `self`, and the
//! paths of a `use` tree. Good enough for the workspace's own code, which rustfmt keeps in
//! one shape; not a Rust lexer.

/// Every path in `code` that starts with `crate`, `super` or `self` followed by `::`, as
/// (byte offset, text of the path including any `{...}` groups).
pub fn paths(code: &str) -> Vec<(usize, String)> {
    let bytes = code.as_bytes();
    let mut out = Vec::new();
    for word in ["crate", "super", "self"] {
        let mut at = 0;
        while let Some(i) = find_word(code, word, at) {
            at = i + word.len();
            // part of a longer path (`super::super::x`) is read with its start
            let before = code[..i].trim_end();
            if before.ends_with("::") || !code[at..].starts_with("::") {
                continue;
            }
            let mut j = at;
            let mut depth = 0usize;
            while j < bytes.len() {
                let c = bytes[j] as char;
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    c if depth > 0 || c.is_alphanumeric() || c == '_' || c == ':' || c == '*' => {}
                    _ => break,
                }
                j += 1;
                if depth == 0 && j > 0 && bytes[j - 1] == b'}' {
                    break;
                }
            }
            out.push((i, code[i..j].to_string()));
        }
    }
    out.sort();
    out
}

/// The paths of a `use` tree (`a::{b, c::d as e, f::*}`), each with its alias.
pub fn use_tree(text: &str) -> Vec<(Vec<String>, Option<String>)> {
    let text: String = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut out = Vec::new();
    expand(&text, &[], &mut out);
    out
}

fn expand(text: &str, prefix: &[String], out: &mut Vec<(Vec<String>, Option<String>)>) {
    let text = text.trim();
    if let Some(open) = text.find('{') {
        let mut head: Vec<String> = prefix.to_vec();
        head.extend(segments(&text[..open]));
        let inner = text[open + 1..].trim_end().trim_end_matches('}');
        for item in split_top(inner) {
            if item.trim().is_empty() {
                continue;
            }
            expand(item, &head, out);
        }
        return;
    }
    let (path, alias) = match text.split_once(" as ") {
        Some((p, a)) => (p, Some(a.trim().to_string())),
        None => (text, None),
    };
    let mut full: Vec<String> = prefix.to_vec();
    full.extend(segments(path));
    if full.last().is_some_and(|s| s == "self") {
        full.pop();
    }
    if !full.is_empty() {
        out.push((full, alias));
    }
}

fn segments(path: &str) -> Vec<String> {
    path.split("::")
        .map(str::trim)
        .filter(|s| !s.is_empty() && *s != "*")
        .map(str::to_string)
        .collect()
}

/// `text` split at the commas outside braces.
fn split_top(text: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut depth, mut start) = (0usize, 0);
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                out.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&text[start..]);
    out
}

/// The first occurrence of `word` as a whole word in `text` from `at`.
pub fn find_word(text: &str, word: &str, mut at: usize) -> Option<usize> {
    let ident = |c: char| c.is_alphanumeric() || c == '_';
    while let Some(k) = text[at..].find(word) {
        let i = at + k;
        let before = text[..i].chars().next_back();
        let after = text[i + word.len()..].chars().next();
        if !before.is_some_and(ident) && !after.is_some_and(ident) {
            return Some(i);
        }
        at = i + word.len();
    }
    None
}

/// `text` with comments, string and character literals blanked (newlines kept, so lines
/// still count).
pub fn strip(text: &str) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    let blank = |c: char| if c == '\n' { '\n' } else { ' ' };
    while i < chars.len() {
        let c = chars[i];
        let next = chars.get(i + 1).copied();
        if c == '/' && next == Some('/') {
            while i < chars.len() && chars[i] != '\n' {
                out.push(' ');
                i += 1;
            }
        } else if c == '/' && next == Some('*') {
            let mut depth = 0usize;
            while i < chars.len() {
                if chars[i] == '/' && chars.get(i + 1) == Some(&'*') {
                    depth += 1;
                    out.push_str("  ");
                    i += 2;
                } else if chars[i] == '*' && chars.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    out.push_str("  ");
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    out.push(blank(chars[i]));
                    i += 1;
                }
            }
        } else if c == 'r' && (next == Some('"') || next == Some('#')) && !ident_before(&chars, i) {
            // a raw string r"..." or r#"..."#
            let mut j = i + 1;
            let mut hashes = 0;
            while chars.get(j) == Some(&'#') {
                hashes += 1;
                j += 1;
            }
            if chars.get(j) != Some(&'"') {
                out.push(c);
                i += 1;
                continue;
            }
            j += 1;
            loop {
                match chars.get(j) {
                    None => break,
                    Some('"') if (1..=hashes).all(|h| chars.get(j + h) == Some(&'#')) => {
                        j += 1 + hashes;
                        break;
                    }
                    _ => j += 1,
                }
            }
            out.extend(chars[i..j.min(chars.len())].iter().map(|&c| blank(c)));
            i = j;
        } else if c == '"' {
            let mut j = i + 1;
            while j < chars.len() && chars[j] != '"' {
                j += if chars[j] == '\\' { 2 } else { 1 };
            }
            j = (j + 1).min(chars.len());
            out.extend(chars[i..j].iter().map(|&c| blank(c)));
            i = j;
        } else if c == '\'' {
            // a character literal ('x', '\n', '\u{1F600}') or a lifetime ('a)
            let end = if next == Some('\\') {
                chars[i + 2..]
                    .iter()
                    .position(|&c| c == '\'')
                    .map(|p| i + 2 + p + 1)
            } else if chars.get(i + 2) == Some(&'\'') {
                Some(i + 3)
            } else {
                None
            };
            match end {
                Some(j) => {
                    out.extend(chars[i..j].iter().map(|&c| blank(c)));
                    i = j;
                }
                None => {
                    out.push(c);
                    i += 1;
                }
            }
        } else {
            out.push(c);
            i += 1;
        }
    }
    out
}

fn ident_before(chars: &[char], i: usize) -> bool {
    i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_')
}

/// `code` (already [`strip`]ped) without its `#[cfg(test)] mod name { ... }` blocks (newlines
/// kept).
pub fn without_tests(code: &str) -> String {
    let mut out = code.to_string();
    let mut at = 0;
    while let Some(k) = out[at..].find("#[cfg(test)]") {
        let i = at + k;
        at = i + 1;
        let rest = out[i + "#[cfg(test)]".len()..].trim_start();
        if !rest.starts_with("mod ") {
            continue;
        }
        let Some(open) = out[i..].find(['{', ';']).map(|o| i + o) else {
            break;
        };
        if out.as_bytes()[open] == b';' {
            continue;
        }
        let mut depth = 0usize;
        let mut end = out.len();
        for (j, c) in out[open..].char_indices() {
            match c {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + j + 1;
                        break;
                    }
                }
                _ => {}
            }
        }
        let blanked: String = out[i..end]
            .chars()
            .map(|c| if c == '\n' { '\n' } else { ' ' })
            .collect();
        out.replace_range(i..end, &blanked);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn use_trees_expand_with_aliases() {
        let got = use_tree("super::{a, b::{c as d, self}, e::*}");
        let shown: Vec<(String, Option<String>)> =
            got.into_iter().map(|(p, a)| (p.join("::"), a)).collect();
        assert_eq!(
            shown,
            [
                ("super::a".to_string(), None),
                ("super::b::c".to_string(), Some("d".to_string())),
                ("super::b".to_string(), None),
                ("super::e".to_string(), None),
            ]
        );
    }

    #[test]
    fn comments_strings_and_tests_are_blanked() {
        let text = "use super::a; // super::b\nlet s = \"super::c\"; let c = '{';\n\
                    /* super::d */ r#\"super::e\"#;\n#[cfg(test)]\nmod tests { use super::f; }\n";
        let code = without_tests(&strip(text));
        assert_eq!(code.lines().count(), text.lines().count());
        let found: Vec<String> = paths(&code).into_iter().map(|(_, p)| p).collect();
        assert_eq!(found, ["super::a"]);
    }
}
