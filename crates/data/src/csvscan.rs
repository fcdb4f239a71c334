//! A quick pass over a CSV file before polars reads it: the header must not repeat a
//! column name and every data row must have as many cells as the header.
//!
//! polars would rename a repeated column (`y`, `y_duplicated_0`) and carry on, which turns
//! `x,y,y` into a silently wrong table; and its message for a ragged row names neither the
//! row nor the count in the user's terms.

use crate::DataError;
use std::path::Path;

/// A CSV text's header and each data row's cell count.
struct Scan {
    header: Vec<String>,
    /// (data row from 1, fields) for each non-empty data line.
    counts: Vec<(usize, usize)>,
}

fn scan(text: &str) -> Scan {
    let mut header: Option<Vec<String>> = None;
    let mut counts = Vec::new();
    for_each_record(text, ',', |fields, has| {
        if !has {
            return;
        }
        if header.is_none() {
            header = Some(fields);
        } else {
            counts.push((counts.len() + 1, fields.len()));
        }
    });
    Scan {
        header: header.unwrap_or_default(),
        counts,
    }
}

/// Calls `each(fields, has_content)` for every record of `text`: cells split on `sep` with
/// RFC 4180 quoting (`"a,b"` is one cell, `""` inside quotes is `"`), records ended by
/// `\n`, `\r\n` or an old Mac's lone `\r`; `has_content` is false for a blank line.
fn for_each_record(text: &str, sep: char, mut each: impl FnMut(Vec<String>, bool)) {
    let mut fields: Vec<String> = Vec::new();
    let mut field = String::new();
    let mut in_quotes = false;
    let mut has = false;
    let mut chars = text.chars().peekable();
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
                has = true;
            }
            c if c == sep => {
                fields.push(std::mem::take(&mut field));
                has = true;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\r' | '\n' => {
                fields.push(std::mem::take(&mut field));
                each(std::mem::take(&mut fields), has);
                has = false;
            }
            c => {
                field.push(c);
                has = true;
            }
        }
    }
    if has {
        fields.push(field);
        each(fields, true);
    }
}

/// The refusal of a file that is not UTF-8 text, with the offset of its first bad byte.
pub(crate) fn not_utf8(path: &Path, e: &std::str::Utf8Error) -> DataError {
    DataError::Parse {
        path: path.to_path_buf(),
        message: format!(
            "the file is not UTF-8 text (invalid byte at offset {}); is it a CSV file?",
            e.valid_up_to()
        ),
    }
}

/// Checks the header for repeated names and every row for its cell count; returns the
/// header's names as RFC 4180 reads them (`"a""b"` is `a"b`, which polars would give as
/// `a""b`).
pub(crate) fn check(path: &Path, bytes: &[u8]) -> Result<Vec<String>, DataError> {
    let text = std::str::from_utf8(bytes).map_err(|e| not_utf8(path, &e))?;
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

/// How a CSV file writes its cells: the separator between cells (`None`: found from the
/// header line: `,` if it holds one, else `;`, else a tab) and the decimal mark (`.`, or `,` for a European CSV:
/// `0,05` is then 0.05).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CsvDialect {
    /// The separator between cells; `None` detects it from the header line.
    pub delimiter: Option<char>,
    /// The decimal mark of numbers.
    pub decimal: char,
}

impl Default for CsvDialect {
    fn default() -> Self {
        Self {
            delimiter: None,
            decimal: '.',
        }
    }
}

static DIALECT: std::sync::OnceLock<CsvDialect> = std::sync::OnceLock::new();

/// Sets the dialect every CSV read of this process uses (the command line's `--delimiter`
/// and `--decimal`); once per process, before the first read. Returns `false` when it was
/// already set (the first setting stays).
pub fn set_csv_dialect(d: CsvDialect) -> bool {
    DIALECT.set(d).is_ok()
}

/// The dialect of this process's CSV reads ([`set_csv_dialect`], else the default: the
/// separator found from the header line, `.` as the decimal mark).
pub fn csv_dialect() -> CsvDialect {
    DIALECT.get().copied().unwrap_or_default()
}

/// The separator of a header line: `,` if it holds one outside quotes, else `;`, else a
/// tab, else `,` (a one-column file).
pub(crate) fn separator_of(text: &str) -> char {
    let mut in_quotes = false;
    let (mut comma, mut semi, mut tab) = (false, false, false);
    for c in text.chars() {
        match c {
            '"' => in_quotes = !in_quotes,
            '\n' | '\r' if !in_quotes => break,
            ',' if !in_quotes => comma = true,
            ';' if !in_quotes => semi = true,
            '\t' if !in_quotes => tab = true,
            _ => {}
        }
    }
    if comma {
        ','
    } else if semi {
        ';'
    } else if tab {
        '\t'
    } else {
        ','
    }
}

/// A CSV text rewritten as the reader expects it, and what was changed.
pub(crate) struct Normalised {
    /// Comma-separated, `.` decimal marks, `\n` line ends; `None` when the text needed no
    /// change (the common case costs one pass and no copy).
    pub text: Option<String>,
    /// Blank lines and rows whose every cell is empty (an Excel export's trailing `,,,,`),
    /// skipped.
    pub skipped: usize,
}

/// Rewrites `text` (BOM already removed) for the reader: records split on `dialect`'s
/// separator (or the header's, [`separator_of`]) with RFC 4180 quoting, any line end
/// (`\r\n`, `\n`, or an old Mac's lone `\r`), blank lines and all-empty rows skipped, and
/// with a decimal comma each number cell's `,` read as `.`.
pub(crate) fn normalise(text: &str, dialect: CsvDialect) -> Normalised {
    let sep = dialect.delimiter.unwrap_or_else(|| separator_of(text));
    if sep == ',' && dialect.decimal == '.' && !irregular(text) {
        return Normalised {
            text: None,
            skipped: 0,
        };
    }
    let mut records: Vec<Vec<String>> = Vec::new();
    let mut skipped = 0usize;
    for_each_record(text, sep, |record, has| {
        if !has || (!records.is_empty() && record.iter().all(|f| f.trim().is_empty())) {
            skipped += 1;
        } else {
            records.push(record);
        }
    });
    let mut out = String::with_capacity(text.len() + 16);
    for (r, record) in records.iter().enumerate() {
        for (i, f) in record.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            let cell = if r > 0 && dialect.decimal != '.' {
                decimal_cell(f, dialect.decimal)
            } else {
                std::borrow::Cow::Borrowed(f.as_str())
            };
            if cell.contains([',', '"', '\n', '\r']) {
                out.push('"');
                out.push_str(&cell.replace('"', "\"\""));
                out.push('"');
            } else {
                out.push_str(&cell);
            }
        }
        out.push('\n');
    }
    Normalised {
        text: Some(out),
        skipped,
    }
}

/// Whether a comma-separated `text` has a lone `\r` line end, a blank line or a data row
/// whose every cell is blank: one pass over the bytes, nothing allocated (every byte that
/// matters is ASCII; a non-ASCII character is decoded only to ask whether it is white
/// space, so the answer is that of a walk over the characters, at a fraction of its cost),
/// and once a record is known to hold a visible character, a SIMD search (`memchr`) to the
/// next quote or line end.
fn irregular(text: &str) -> bool {
    let bytes = text.as_bytes();
    let mut in_quotes = false;
    let (mut has, mut filled, mut first) = (false, false, true);
    let mut i = 0;
    while i < bytes.len() {
        // once the record has a cell and a visible character, only a quote or a line end
        // can change the answer: jump to the next one (SIMD search; most of a file)
        if has && filled {
            let next = if in_quotes {
                memchr::memchr(b'"', &bytes[i..])
            } else {
                memchr::memchr3(b'"', b'\n', b'\r', &bytes[i..])
            };
            match next {
                Some(k) => i += k,
                None => break,
            }
        }
        let b = bytes[i];
        if b >= 0x80 {
            // the lead byte of a multi-byte character (continuation bytes are skipped with it)
            let c = text[i..].chars().next().unwrap_or(' ');
            if !in_quotes {
                has = true;
            }
            filled |= !c.is_whitespace();
            i += c.len_utf8().max(1);
            continue;
        }
        i += 1;
        if in_quotes {
            if b == b'"' {
                if bytes.get(i) == Some(&b'"') {
                    i += 1;
                    filled = true;
                } else {
                    in_quotes = false;
                }
            } else {
                filled |= !b.is_ascii_whitespace() && b != 0x0b;
            }
            continue;
        }
        match b {
            b'"' => {
                in_quotes = true;
                has = true;
            }
            b'\r' if bytes.get(i) == Some(&b'\n') => {}
            b'\r' => return true,
            b'\n' => {
                if !has || (!first && !filled) {
                    return true;
                }
                (has, filled, first) = (false, false, false);
            }
            b',' => has = true,
            _ => {
                has = true;
                filled |= !b.is_ascii_whitespace() && b != 0x0b;
            }
        }
    }
    has && !first && !filled
}

/// The character walk [`irregular`] replaced, kept to check that both answer alike.
#[cfg(test)]
fn irregular_by_chars(text: &str) -> bool {
    let mut in_quotes = false;
    let (mut has, mut filled, mut first) = (false, false, true);
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        if in_quotes {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    chars.next();
                    filled = true;
                } else {
                    in_quotes = false;
                }
            } else {
                filled |= !c.is_whitespace();
            }
            continue;
        }
        match c {
            '"' => {
                in_quotes = true;
                has = true;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\r' => return true,
            '\n' => {
                if !has || (!first && !filled) {
                    return true;
                }
                (has, filled, first) = (false, false, false);
            }
            ',' => has = true,
            c => {
                has = true;
                filled |= !c.is_whitespace();
            }
        }
    }
    has && !first && !filled
}

/// A cell with `mark` as its decimal mark, as `.`: only where the result is a number (a
/// word with a comma stays as it is).
fn decimal_cell(f: &str, mark: char) -> std::borrow::Cow<'_, str> {
    if !f.contains(mark) {
        return std::borrow::Cow::Borrowed(f);
    }
    let t = f.trim().replacen(mark, ".", 1);
    if t.parse::<f64>().is_ok() {
        std::borrow::Cow::Owned(t)
    } else {
        std::borrow::Cow::Borrowed(f)
    }
}

#[cfg(test)]
mod dialect_tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn norm(text: &str, d: CsvDialect) -> (String, usize) {
        let n = normalise(text, d);
        (n.text.unwrap_or_else(|| text.to_string()), n.skipped)
    }

    #[test]
    fn separators_line_ends_and_blank_rows() {
        let d = CsvDialect::default();
        // an ordinary file is handed on untouched
        assert!(normalise("a,b\n1,2\n", d).text.is_none());
        assert_eq!(norm("a;b\n1;2\n", d), ("a,b\n1,2\n".into(), 0));
        assert_eq!(norm("a\tb\n1\t2\n", d), ("a,b\n1,2\n".into(), 0));
        assert_eq!(norm("a,b\r1,2\r3,4\r", d), ("a,b\n1,2\n3,4\n".into(), 0));
        assert_eq!(norm("a,b\r\n1,2\r\n", d).1, 0);
        // blank lines inside and at the end, Excel's trailing ,, rows
        assert_eq!(
            norm("a,b\n1,2\n\n3,4\n,\n , \n\n", d),
            ("a,b\n1,2\n3,4\n".into(), 4)
        );
        // a cell holding the separator keeps its quotes
        assert_eq!(norm("a;b\n\"x,y\";2\n", d), ("a,b\n\"x,y\",2\n".into(), 0));
    }

    #[test]
    fn a_decimal_comma_is_read_in_number_cells_only() {
        let d = CsvDialect {
            delimiter: Some(';'),
            decimal: ',',
        };
        assert_eq!(
            norm("v [m/min];f,mm;name\n120,5;0,05;a,b\n-1,5e3;2;x\n", d).0,
            "v [m/min],\"f,mm\",name\n120.5,0.05,\"a,b\"\n-1.5e3,2,x\n"
        );
    }
}

#[cfg(test)]
mod fuzz {
    //! Bounded fuzzing of the reader's first pass (issue 52 item 7): any text, in any
    //! dialect, is normalised without a panic; a table of plain cells written in a dialect
    //! reads back as the same cells.
    use super::*;
    use proptest::prelude::*;

    /// Cases of each property: 512 in every test run, `HXAI_FUZZ_CASES` for a long run
    /// (docs/bad-input.md).
    fn cases() -> u32 {
        std::env::var("HXAI_FUZZ_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(512)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: cases(), ..ProptestConfig::default() })]

        #[test]
        fn any_text_is_normalised_without_a_panic(
            text in "[a-c0-9,;\t\"\r\n .-]{0,80}",
            sep in prop::sample::select(vec![None, Some(','), Some(';'), Some('\t')]),
            decimal in prop::sample::select(vec!['.', ',']),
        ) {
            let n = normalise(&text, CsvDialect { delimiter: sep, decimal });
            if let Some(t) = n.text {
                // one line per record kept, each ended by `\n`
                prop_assert!(t.is_empty() || t.ends_with('\n'), "{t:?}");
                prop_assert!(!t.contains('\r') || t.contains('"'), "{t:?}");
            }
            let _ = separator_of(&text);
        }

        /// The byte walk of `irregular` answers as the character walk it replaced, on
        /// texts with quotes, every line end, ASCII and Unicode white space (a vertical
        /// tab, a no-break space, an ideographic space) and other non-ASCII characters.
        #[test]
        fn the_byte_walk_answers_as_the_character_walk(
            text in "[a1,\"\r\n \t\u{b}\u{a0}\u{3000}é€]{0,60}",
        ) {
            prop_assert_eq!(irregular(&text), irregular_by_chars(&text), "{:?}", text);
        }

        #[test]
        fn a_table_in_a_dialect_reads_back_as_its_cells(
            rows in prop::collection::vec(prop::collection::vec(-1e6f64..1e6, 3), 1..6),
            semi in any::<bool>(),
        ) {
            let (sep, mark) = if semi { (';', ',') } else { (',', '.') };
            let mut text = String::from("a;b;c\n").replace(';', &sep.to_string());
            for r in &rows {
                let cells: Vec<String> = r
                    .iter()
                    .map(|v| format!("{v}").replace('.', &mark.to_string()))
                    .collect();
                text.push_str(&cells.join(&sep.to_string()));
                text.push('\n');
            }
            let n = normalise(&text, CsvDialect { delimiter: Some(sep), decimal: mark });
            let plain = n.text.unwrap_or(text);
            let mut lines = plain.lines();
            prop_assert_eq!(lines.next(), Some("a,b,c"));
            for r in &rows {
                let got: Vec<f64> = lines
                    .next()
                    .unwrap_or_default()
                    .split(',')
                    .map(|c| c.parse::<f64>().unwrap_or(f64::NAN))
                    .collect();
                prop_assert_eq!(&got, r);
            }
        }
    }
}
