//! Writes a problem's outputs: `<problem>.json`, `<problem>.csv`, `<problem>.svg`. Each file is
//! written under a temporary name and renamed into place, so a file with the final name is
//! always complete.

use crate::record::{ProblemOutput, Table};
use crate::VerifyError;
use std::path::{Path, PathBuf};

/// Writes `bytes` to `path` atomically (temporary file in the same folder, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), VerifyError> {
    let io = |source| VerifyError::Io {
        path: path.display().to_string(),
        source,
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let temporary = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&temporary, bytes).map_err(io)?;
    std::fs::rename(&temporary, path).map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        io(e)
    })
}

pub fn table_to_csv(table: &Table) -> Vec<u8> {
    let mut writer = csv::Writer::from_writer(Vec::new());
    writer
        .write_record(&table.columns)
        .expect("writing to memory");
    for row in &table.rows {
        writer
            .write_record(row.iter().map(|v| format!("{v:e}")))
            .expect("writing to memory");
    }
    writer.into_inner().expect("writing to memory")
}

/// Writes JSON, CSV and SVG of one problem into `dir` (created if missing); returns the paths.
pub fn write_outputs(dir: &Path, output: &ProblemOutput) -> Result<Vec<PathBuf>, VerifyError> {
    std::fs::create_dir_all(dir).map_err(|source| VerifyError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let stem = &output.record.problem;
    let json = serde_json::to_vec_pretty(&output.record).expect("records serialise");
    let files = [
        (format!("{stem}.csv"), table_to_csv(&output.profile)),
        (format!("{stem}.svg"), output.figure.to_svg().into_bytes()),
        // the JSON last: its presence says the others are there too
        (format!("{stem}.json"), json),
    ];
    let mut paths = Vec::new();
    for (name, bytes) in files {
        let path = dir.join(name);
        write_atomic(&path, &bytes)?;
        paths.push(path);
    }
    Ok(paths)
}
