//! Whole text files (model JSON and the like), with the same error type as the rest.

use crate::DataError;
use std::path::Path;

/// Reads a whole UTF-8 text file (for example a model file written by `hxai fit`).
pub fn read_text(path: &Path) -> Result<String, DataError> {
    let bytes = std::fs::read(path).map_err(|e| DataError::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| DataError::Parse {
        path: path.to_path_buf(),
        message: format!(
            "the file is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ),
    })
}

/// Writes a whole text file atomically (temporary file, then rename; see
/// [`crate::write_atomic`]), creating missing parent folders.
pub fn write_text(path: &Path, text: &str) -> Result<(), DataError> {
    crate::atomic::write_bytes(path, text.as_bytes())
}

/// [`write_text`] staged, not committed (see [`crate::stage`]).
pub fn stage_text(path: &Path, text: &str) -> Result<crate::AtomicFile, DataError> {
    use std::io::Write;
    crate::atomic::stage(path, |f| {
        f.write_all(text.as_bytes())
            .map_err(|e| DataError::io(path, e))
    })
}
