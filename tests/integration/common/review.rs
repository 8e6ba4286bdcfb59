//! What a snapshot keeps of a result: its numbers to three significant digits.

use serde_json::Value;

/// `value` with every number rounded to three significant digits and the keys in `dropped`
/// removed wherever they occur: what a snapshot keeps of a record, so that a reviewer sees the
/// numbers that moved and nothing that depends on the machine's speed.
pub fn reviewable(value: Value, dropped: &[&str]) -> Value {
    match value {
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => round_to_3_digits(x),
            _ => Value::Number(n),
        },
        Value::Array(items) => {
            Value::Array(items.into_iter().map(|v| reviewable(v, dropped)).collect())
        }
        Value::Object(map) => Value::Object(
            map.into_iter()
                .filter(|(k, _)| !dropped.contains(&k.as_str()))
                .map(|(k, v)| (k, reviewable(v, dropped)))
                .collect(),
        ),
        other => other,
    }
}

fn round_to_3_digits(x: f64) -> Value {
    if x == 0.0 || !x.is_finite() {
        return serde_json::json!(x);
    }
    let text = format!("{x:.2e}");
    serde_json::json!(text.parse::<f64>().expect("a formatted number parses"))
}
