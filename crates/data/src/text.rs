//! Whole text files (model JSON and the like), with the same error type as the rest.

use crate::DataError;
use std::path::Path;

/// Reads a whole UTF-8 text file (for example a model file written by `hxai fit`).
pub fn read_text(path: &Path) -> Result<String, DataError> {
    std::fs::read_to_string(path).map_err(|e| DataError::io(path, e))
}

/// Writes a whole text file, creating missing parent folders.
pub fn write_text(path: &Path, text: &str) -> Result<(), DataError> {
    if let Some(parent) = path.parent()
        && !parent.as_os_str().is_empty()
    {
        std::fs::create_dir_all(parent).map_err(|e| DataError::io(parent, e))?;
    }
    std::fs::write(path, text).map_err(|e| DataError::io(path, e))
}
