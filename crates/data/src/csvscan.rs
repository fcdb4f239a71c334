//! A quick pass over a CSV file before polars reads it: the header must not repeat a
//! column name and every data row must have as many cells as the header.
//!
//! polars would rename a repeated column (`y`, `y_duplicated_0`) and carry on, which turns
//! `x,y,y` into a silently wrong table; and its message for a ragged row names neither the
//! row nor the count in the user's terms.

use crate::DataError;
use std::path::Path;

/// Splits CSV text into records of fields (RFC 4180 quoting, `\n` or `\r\n` line ends).
/// Returns each record's field count and, for the first record, its fields.
struct Scan {
    header: Vec<String>,
    /// (data row from 1, fields) for each non-empty data line.
    counts: Vec<(usize, usize)>,
}

fn scan(text: &str) -> Scan {
    let mut header: Option<Vec<String>> = None;
    let mut counts = Vec::new();
    let mut fields: Vec<String> = Vec::new();
    let mut field = String::new();
    let mut in_quotes = false;
    let mut line_has_content = false;
    let mut chars = text.chars().peekable();
    let mut row = 0usize;
    let mut end_record = |fields: &mut Vec<String>,
                          field: &mut String,
                          has: &mut bool,
                          header: &mut Option<Vec<String>>| {
        if *has {
            fields.push(std::mem::take(field));
            if header.is_none() {
                *header = Some(std::mem::take(fields));
            } else {
                row += 1;
                counts.push((row, fields.len()));
                fields.clear();
            }
        }
        field.clear();
        fields.clear();
        *has = false;
    };
    while let Some(c) = chars.next() {
        if in_quotes {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    chars.next();
                    field.push('"');
                } else {
                    in_quotes = false;
                }
            } else {
                field.push(c);
            }
            continue;
        }
        match c {
            '"' => {
                in_quotes = true;
                line_has_content = true;
            }
            ',' => {
                fields.push(std::mem::take(&mut field));
                line_has_content = true;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => end_record(&mut fields, &mut field, &mut line_has_content, &mut header),
            c => {
                field.push(c);
                line_has_content = true;
            }
        }
    }
    end_record(&mut fields, &mut field, &mut line_has_content, &mut header);
    Scan {
        header: header.unwrap_or_default(),
        counts,
    }
}

/// Checks the header for repeated names and every row for its cell count; returns the
/// header's names as RFC 4180 reads them (`"a""b"` is `a"b`, which polars would give as
/// `a""b`).
pub(crate) fn check(path: &Path, bytes: &[u8]) -> Result<Vec<String>, DataError> {
    let text = match std::str::from_utf8(bytes) {
        Ok(t) => t,
        Err(e) => {
            return Err(DataError::Parse {
                path: path.to_path_buf(),
                message: format!(
                    "the file is not UTF-8 text (invalid byte at offset {}); is it a CSV file?",
                    e.valid_up_to()
                ),
            });
        }
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let s = scan(text);
    for (i, name) in s.header.iter().enumerate() {
        if !name.is_empty() && s.header[..i].contains(name) {
            return Err(DataError::DuplicateColumn {
                path: path.to_path_buf(),
                column: name.clone(),
            });
        }
    }
    let expected = s.header.len();
    for &(row, found) in &s.counts {
        if found != expected {
            return Err(DataError::RaggedRow {
                path: path.to_path_buf(),
                row,
                found,
                expected,
            });
        }
    }
    Ok(s.header)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn quotes_and_line_ends() {
        let s = scan("a,\"b,c\",d\r\n1,\"x\"\"y\",3\n\n4,5,6\n");
        assert_eq!(s.header, vec!["a", "b,c", "d"]);
        // a doubled quote inside a quoted name is one quote (RFC 4180)
        let q = scan("\"a\"\"b\",c\n1,2\n");
        assert_eq!(q.header, vec!["a\"b", "c"]);
        assert_eq!(s.counts, vec![(1, 3), (2, 3)]);
    }

    #[test]
    fn duplicate_and_ragged_are_named() {
        let p = Path::new("t.csv");
        let e = check(p, b"x,y,y\n1,2,3\n").unwrap_err();
        assert!(matches!(e, DataError::DuplicateColumn { ref column, .. } if column == "y"));
        let e = check(p, b"x,y\n1,2\n3\n").unwrap_err();
        assert!(
            matches!(
                e,
                DataError::RaggedRow {
                    row: 2,
                    found: 1,
                    expected: 2,
                    ..
                }
            ),
            "{e}"
        );
        assert!(check(p, b"\xef\xbb\xbfx,y\n1,2\n").is_ok());
    }
}
