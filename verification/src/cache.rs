//! Results kept under a hash of what decides them: their inputs and the running program's own
//! bytes, so that a rebuilt program never reuses a result of another build. A kept result is
//! written atomically, after the work it records has finished: an interrupted run leaves no
//! result that looks complete.

use crate::report::write_atomic;
use crate::VerifyError;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::Path;

/// The SHA-256 of `inputs`, in order, and of the running program's bytes, in hex.
pub fn inputs_hash(inputs: &[&[u8]]) -> Result<String, VerifyError> {
    let mut hasher = Sha256::new();
    for input in inputs {
        // each input's length first, so that no two lists of inputs hash alike
        hasher.update((input.len() as u64).to_le_bytes());
        hasher.update(input);
    }
    let exe = std::env::current_exe().map_err(|source| VerifyError::Io {
        path: "the running program".into(),
        source,
    })?;
    let program = std::fs::read(&exe).map_err(|source| VerifyError::Io {
        path: exe.display().to_string(),
        source,
    })?;
    hasher.update(&program);
    Ok(hasher
        .finalize()
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect())
}

#[derive(Serialize, Deserialize)]
struct Kept<T> {
    inputs_hash: String,
    result: T,
}

/// The result kept at `path` under `hash`; none where there is no file, it does not parse, or
/// it was kept under another hash.
pub fn kept<T: DeserializeOwned>(path: &Path, hash: &str) -> Option<T> {
    let text = std::fs::read_to_string(path).ok()?;
    let kept: Kept<T> = serde_json::from_str(&text).ok()?;
    (kept.inputs_hash == hash).then_some(kept.result)
}

/// Keeps `result` at `path` under `hash`.
pub fn keep<T: Serialize>(path: &Path, hash: &str, result: &T) -> Result<(), VerifyError> {
    let kept = Kept {
        inputs_hash: hash.to_string(),
        result,
    };
    let text = serde_json::to_string_pretty(&kept).expect("a kept result serialises");
    write_atomic(path, text.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A result comes back under its own hash only; the hash separates its inputs.
    #[test]
    fn a_result_comes_back_under_its_own_hash() {
        let path = std::env::temp_dir().join(format!("blastsph-kept-{}.json", std::process::id()));
        let hash = inputs_hash(&[b"ab", b"c"]).unwrap();
        assert_ne!(hash, inputs_hash(&[b"a", b"bc"]).unwrap());
        assert_eq!(hash, inputs_hash(&[b"ab", b"c"]).unwrap());
        keep(&path, &hash, &vec![1.5, 2.5]).unwrap();
        assert_eq!(kept::<Vec<f64>>(&path, &hash), Some(vec![1.5, 2.5]));
        assert_eq!(kept::<Vec<f64>>(&path, "another"), None);
        assert_eq!(kept::<String>(&path, &hash), None);
        std::fs::remove_file(&path).unwrap();
        assert_eq!(kept::<Vec<f64>>(&path, &hash), None);
    }
}
