//! The model files' JSON shape does not change under the code: a model file written by an
//! earlier commit (testdata/models/, made at 5ec3fe8, before `ModelForms` took over the
//! correction's readable forms) is loaded and written again, and the two JSON documents are
//! equal, key for key and number for number (issue 26: the types behind the files may be
//! reorganised, the files may not). Older files that use a legacy spelling (`engine` for
//! `strategy`) load and are written in today's spelling, so they are not fixtures here.
#![allow(clippy::unwrap_used)]
use hxai_hybrid::records::RecordModel;
use hxai_hybrid::tables::TableModel;
use serde_json::Value;

fn fixture(path: &str) -> String {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../");
    std::fs::read_to_string(format!("{root}{path}")).unwrap()
}

/// The paths (`/correction/equation`, `/split/train[3]`) where two documents differ.
fn differences(a: &Value, b: &Value, path: &str, out: &mut Vec<String>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            for k in x.keys().chain(y.keys().filter(|k| !x.contains_key(*k))) {
                let p = format!("{path}/{k}");
                match (x.get(k), y.get(k)) {
                    (Some(u), Some(v)) => differences(u, v, &p, out),
                    (Some(_), None) => out.push(format!("{p} dropped")),
                    (None, _) => out.push(format!("{p} added")),
                }
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (u, v)) in x.iter().zip(y).enumerate() {
                differences(u, v, &format!("{path}[{i}]"), out);
            }
        }
        _ if a != b => out.push(format!("{path}: {a} -> {b}")),
        _ => {}
    }
}

fn same(before: &str, after: &str, what: &str) {
    let a: Value = serde_json::from_str(before).unwrap();
    let b: Value = serde_json::from_str(after).unwrap();
    let mut d = Vec::new();
    differences(&a, &b, "", &mut d);
    d.truncate(10);
    assert!(
        d.is_empty(),
        "{what}: written again, the JSON differs: {d:?}"
    );
}

#[test]
fn a_table_hybrid_model_file_is_written_back_unchanged() {
    let text = fixture("testdata/models/process_model.json");
    let m = TableModel::from_json(&text).unwrap();
    same(&text, &m.to_json(), "process_model.json");
}

#[test]
fn a_tool_model_file_is_written_back_unchanged() {
    let path = "testdata/models/tool_model.json";
    let text = fixture(path);
    let m = RecordModel::from_json(&text).unwrap();
    same(&text, &m.to_json().unwrap(), path);
}

/// Issue 52: a model file that is not a table hybrid at all says what it holds instead of
/// "schema_version none": `null`, a list, `{}`, a number, a text `schema_version`, a
/// fractional one, and `hxai sr --json`'s output (named as such).
#[test]
fn files_that_are_not_table_models_say_what_they_hold() {
    use hxai_hybrid::tables::TableModel;
    let cases = [
        ("null", "JSON `null`"),
        ("[]", "a JSON list of 0 item(s)"),
        ("{}", "an empty JSON object"),
        ("3", "the number 3"),
        (
            "{\"schema_version\": \"1\"}",
            "a text where a whole number is expected",
        ),
        ("{\"schema_version\": 1.5}", "1.5, not a whole number"),
        ("{\"best\": {}, \"pareto\": []}", "`hxai sr --json`"),
    ];
    for (text, says) in cases {
        let e = TableModel::from_json(text).expect_err(text).to_string();
        assert!(e.contains(says), "{text}: {e}");
        assert!(!e.contains("schema_version none"), "{text}: {e}");
    }
    // a whole number of another version keeps its own message
    let e = TableModel::from_json("{\"schema_version\": 7}")
        .expect_err("version 7")
        .to_string();
    assert!(e.contains("schema_version 7"), "{e}");
}
