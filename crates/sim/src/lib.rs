//! Simulator of a slow-tool-servo Z axis with probe, encoder and accelerometer.
#![deny(missing_docs)]
