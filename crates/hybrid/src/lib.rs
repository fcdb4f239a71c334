//! The generic hybrid physics + symbolic-regression composer of hxai.
#![deny(missing_docs)]
