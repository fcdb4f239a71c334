//! The twelve acceleration-signal features of the hxai case study.
#![deny(missing_docs)]
