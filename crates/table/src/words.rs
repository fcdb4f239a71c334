//! A JSON reader's complaint in a user's words: serde names Rust types (`expected u16`,
//! `expected struct SineFit`, `unknown variant`), which mean nothing to someone who edited a
//! model or configuration file by hand. [`plain_json_error`] says the same with JSON's
//! words (a whole number, a number, text, a list, an object, a key, a value).

/// Rust's integer type names and their ranges, for "a whole number from A to B".
const INTEGERS: [(&str, &str); 10] = [
    ("u8", "a whole number from 0 to 255"),
    ("u16", "a whole number from 0 to 65535"),
    ("u32", "a whole number from 0 to 4294967295"),
    ("u64", "a whole number of 0 or more"),
    ("usize", "a whole number of 0 or more"),
    ("i8", "a whole number from -128 to 127"),
    ("i16", "a whole number from -32768 to 32767"),
    ("i32", "a whole number from -2147483648 to 2147483647"),
    ("i64", "a whole number"),
    ("isize", "a whole number"),
];

/// The JSON words for what serde expected (`u16`, `f64`, `a sequence`, `struct X`, ...).
fn expected_words(what: &str) -> String {
    let what = what.trim();
    if let Some((_, words)) = INTEGERS.iter().find(|(t, _)| *t == what) {
        return (*words).to_string();
    }
    match what {
        "f64" | "f32" => "a number".into(),
        "a string" | "string" => "text".into(),
        "a boolean" => "true or false".into(),
        "a sequence" => "a list [..]".into(),
        "a map" => "an object {..}".into(),
        "string or map" => "text or an object {..}".into(),
        w if w.starts_with("struct ") || w.starts_with("enum ") => "an object {..}".into(),
        w if w.starts_with("a tuple of size ") || w.starts_with("an array of length ") => {
            format!("a list of {}", w.rsplit(' ').next().unwrap_or("several")) + " values"
        }
        w => w.to_string(),
    }
}

/// What serde found (`integer `-1``, `string "x"`, `floating point `1.5``, ...) in JSON's
/// words.
fn found_words(found: &str) -> String {
    let found = found.trim();
    let strip = |p: &str| {
        found
            .strip_prefix(p)
            .map(|r| r.trim_matches('`').to_string())
    };
    if let Some(v) = strip("integer ") {
        return format!("the whole number {v}");
    }
    if let Some(v) = strip("floating point ") {
        return format!("the number {v}");
    }
    if let Some(v) = strip("string ") {
        return format!("the text {v}");
    }
    if let Some(v) = strip("boolean ") {
        return format!("the value {v}");
    }
    match found {
        "sequence" => "a list".into(),
        "map" => "an object".into(),
        "null" => "null".into(),
        f => f.to_string(),
    }
}

/// serde_json's error message in JSON's words (the position, `at line L column C`, is
/// kept). Messages it does not recognise come back unchanged.
///
/// ```
/// use hxai_table::plain_json_error as p;
/// assert_eq!(
///     p("invalid value: integer `99999`, expected u16 at line 3 column 14"),
///     "value out of range: the whole number 99999, expected a whole number from 0 to 65535 at line 3 column 14"
/// );
/// assert_eq!(
///     p("invalid type: string \"1.0\", expected f64 at line 1 column 9"),
///     "wrong type: the text \"1.0\", expected a number at line 1 column 9"
/// );
/// assert_eq!(
///     p("unknown variant `cubic`, expected `additive` or `multiplicative` at line 2 column 5"),
///     "unknown value `cubic`, expected `additive` or `multiplicative` at line 2 column 5"
/// );
/// assert_eq!(p("missing field `fs_hz`"), "the key `fs_hz` is missing");
/// assert_eq!(p("invalid type: integer `2`, expected a sequence"), "wrong type: the whole number 2, expected a list [..]");
/// assert_eq!(p("EOF while parsing a value at line 1 column 0"), "EOF while parsing a value at line 1 column 0");
/// ```
pub fn plain_json_error(message: &str) -> String {
    // Split off serde_json's position, kept as it is.
    let (body, position) = match message.rfind(" at line ") {
        Some(i) => (&message[..i], &message[i..]),
        None => (message, ""),
    };
    let typed = |rest: &str, head: &str| -> Option<String> {
        let (found, expected) = rest.split_once(", expected ")?;
        Some(format!(
            "{head}: {}, expected {}",
            found_words(found),
            expected_words(expected)
        ))
    };
    let plain = if let Some(rest) = body.strip_prefix("invalid type: ") {
        typed(rest, "wrong type")
    } else if let Some(rest) = body.strip_prefix("invalid value: ") {
        typed(rest, "value out of range")
    } else if let Some(rest) = body.strip_prefix("unknown variant ") {
        Some(format!("unknown value {rest}"))
    } else if let Some(rest) = body.strip_prefix("unknown field ") {
        Some(format!("unknown key {rest}"))
    } else if let Some(rest) = body.strip_prefix("missing field ") {
        Some(format!("the key {rest} is missing"))
    } else if let Some(rest) = body.strip_prefix("invalid length ") {
        let (n, expected) = rest.split_once(", expected ").unwrap_or((rest, ""));
        Some(format!(
            "a list of {n} values, expected {}",
            expected_words(expected)
        ))
    } else {
        None
    };
    format!("{}{position}", plain.unwrap_or_else(|| body.to_string()))
}
