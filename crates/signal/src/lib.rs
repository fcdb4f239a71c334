//! Digital signal processing for hxai: Butterworth filters, zero-phase filtering, integration, Welch PSD, sine fitting and the accelerometer physics model.
#![deny(missing_docs)]
