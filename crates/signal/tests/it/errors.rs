//! Typed errors for every kind of bad input, and the physics chain on a known motion.
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use hxai_signal::{
    Band, Drift, Integrator, LengthUnit, PhysicsConfig, SignalError as E, WelchConfig, butter,
    displacement, fit_sine, welch,
};

#[test]
fn design_errors() {
    assert_eq!(butter(0, Band::Lowpass(10.0), 100.0), Err(E::ZeroOrder));
    assert!(matches!(
        butter(2, Band::Lowpass(10.0), 0.0),
        Err(E::InvalidSampleRate { .. })
    ));
    assert!(matches!(
        butter(2, Band::Lowpass(10.0), f64::NAN),
        Err(E::InvalidSampleRate { .. })
    ));
    assert!(matches!(
        butter(2, Band::Lowpass(50.0), 100.0),
        Err(E::InvalidCutoff { .. })
    ));
    assert!(matches!(
        butter(2, Band::Highpass(0.0), 100.0),
        Err(E::InvalidCutoff { .. })
    ));
    assert!(matches!(
        butter(2, Band::Highpass(-1.0), 100.0),
        Err(E::InvalidCutoff { .. })
    ));
    assert!(matches!(
        butter(2, Band::Bandpass(20.0, 10.0), 100.0),
        Err(E::InvalidBand { .. })
    ));
    assert!(matches!(
        butter(2, Band::Bandpass(10.0, 10.0), 100.0),
        Err(E::InvalidBand { .. })
    ));
}

#[test]
fn input_errors() {
    let sos = butter(2, Band::Lowpass(10.0), 100.0).unwrap();
    assert!(matches!(sos.filtfilt(&[]), Err(E::Empty { .. })));
    assert!(matches!(
        sos.filtfilt(&[1.0; 9]),
        Err(E::TooShort {
            len: 9,
            needed: 9,
            ..
        })
    ));
    assert!(sos.filtfilt(&[1.0; 10]).is_ok()); // one section: padlen 3 * 3 = 9
    let mut x = vec![1.0; 40];
    x[7] = f64::INFINITY;
    assert!(matches!(
        sos.filtfilt(&x),
        Err(E::NonFinite { index: 7, .. })
    ));
    assert!(matches!(
        welch(&[], 1.0, &WelchConfig::default()),
        Err(E::Empty { .. })
    ));
    assert!(matches!(
        welch(&[1.0, 2.0], -1.0, &WelchConfig::default()),
        Err(E::InvalidSampleRate { .. })
    ));
    let y: Vec<f64> = (0..100).map(|i| (i as f64).sin()).collect();
    assert!(matches!(
        fit_sine(&y, 100.0, 50.0),
        Err(E::InvalidFrequency { .. })
    ));
    assert!(matches!(
        fit_sine(&y, 100.0, 0.0),
        Err(E::InvalidFrequency { .. })
    ));
    assert!(matches!(
        fit_sine(&y[..2], 100.0, 5.0),
        Err(E::TooShort { .. })
    ));
    assert!(matches!(fit_sine(&[0.0; 100], 100.0, 5.0), Ok(f) if f.amplitude == 0.0));
    assert!(matches!(
        displacement(&y, 300.0, &PhysicsConfig::default()),
        Err(E::InvalidCutoff { cutoff, .. }) if cutoff == 200.0
    ));
    assert!(matches!(
        displacement(&y[..10], 1000.0, &PhysicsConfig::default()),
        Err(E::TooShort { .. })
    ));
}

/// A pure 20 Hz, 5 um motion: every variant of the chain recovers its amplitude. Tolerances:
/// time domain 0.5 % (the 4th-order 5 Hz edge applied twice costs under 1e-6 at 20 Hz; the linear
/// drift removal of a whole number of periods costs nothing), frequency domain 1e-6 relative
/// (the record holds whole periods, so the sine sits on one FFT bin).
#[test]
fn physics_chain_recovers_known_motion() -> Result<(), E> {
    let fs = 2000.0;
    let (f, amp_um) = (20.0, 5.0);
    let w = 2.0 * PI * f;
    let accel: Vec<f64> = (0..8000)
        .map(|i| -w * w * amp_um * 1e-6 * (w * i as f64 / fs).sin())
        .collect();
    let mid = 2000..6000;
    for (cfg, tol) in [
        (PhysicsConfig::default(), 5e-3),
        (
            PhysicsConfig {
                drift: Drift::Highpass {
                    order: 2,
                    cutoff_hz: 2.0,
                },
                ..PhysicsConfig::default()
            },
            5e-3,
        ),
        (
            PhysicsConfig {
                integrator: Integrator::Frequency,
                ..PhysicsConfig::default()
            },
            1e-6,
        ),
    ] {
        let d = displacement(&accel, fs, &cfg)?;
        let fit = fit_sine(&d[mid.clone()], fs, f)?;
        assert!(
            (fit.amplitude / amp_um - 1.0).abs() < tol,
            "{cfg:?}: amplitude {}",
            fit.amplitude
        );
        // Displacement is in phase with -accel, i.e. sin(w t) with phase 0 (relative to the
        // slice start, which is a whole number of periods in).
        assert!(fit.phase.abs() < 1e-2, "{cfg:?}: phase {}", fit.phase);
    }
    let m = displacement(
        &accel,
        fs,
        &PhysicsConfig {
            unit: LengthUnit::Metres,
            ..PhysicsConfig::default()
        },
    )?;
    let fit = fit_sine(&m[mid], fs, f)?;
    assert!((fit.amplitude / (amp_um * 1e-6) - 1.0).abs() < 5e-3);
    Ok(())
}

#[test]
fn sos_serde_round_trip_and_validation() -> Result<(), Box<dyn std::error::Error>> {
    let sos = butter(3, Band::Highpass(10.0), 1000.0)?;
    let text = serde_json::to_string(&sos)?;
    let back: hxai_signal::Sos = serde_json::from_str(&text)?;
    // serde_json's default float parser may be 1 ulp off, so compare to 1e-15 relative.
    for (a, b) in back
        .sections()
        .iter()
        .flatten()
        .zip(sos.sections().iter().flatten())
    {
        assert!((a - b).abs() <= 1e-15 * a.abs().max(b.abs()));
    }
    // a0 = 0 is refused on the way in.
    assert!(serde_json::from_str::<hxai_signal::Sos>("[[1,0,0,0,0,0]]").is_err());
    Ok(())
}
