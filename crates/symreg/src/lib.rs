//! Symbolic regression for hxai: QLattice-style path sampling and genetic search with Levenberg-Marquardt constants.
#![deny(missing_docs)]
