//! Reading and writing hxai data folders (manifest + CSV/Parquet records).
#![deny(missing_docs)]
