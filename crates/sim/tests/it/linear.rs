//! With friction, noise and quantisation switched off the machine is linear, so each channel's
//! steady-state amplitude and phase are known in closed form. This checks the hand-written
//! RK4 integration, the steady-state start and the channel wiring against those formulas.

use hxai_signal::fit_sine;
use hxai_sim::{SimConfig, simulate};
use std::f64::consts::PI;

type TestResult = Result<(), Box<dyn std::error::Error>>;

#[derive(Clone, Copy, Debug)]
struct C(f64, f64);
impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn div(self, o: C) -> C {
        let d = o.0 * o.0 + o.1 * o.1;
        C(
            (self.0 * o.0 + self.1 * o.1) / d,
            (self.1 * o.0 - self.0 * o.1) / d,
        )
    }
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn abs(self) -> f64 {
        self.0.hypot(self.1)
    }
    fn arg(self) -> f64 {
        self.1.atan2(self.0)
    }
}

fn wrap(p: f64) -> f64 {
    (p + PI).rem_euclid(2.0 * PI) - PI
}

#[test]
fn frictionless_noiseless_machine_matches_transfer_functions() -> TestResult {
    let mut cfg = SimConfig {
        amplitudes_um: vec![4.0, 11.0],
        frequencies_hz: vec![10.0, 25.0, 40.0],
        repeats: 1,
        duration_s: 1.0,
        ..SimConfig::default()
    };
    cfg.servo.coulomb_ms2 = 0.0;
    cfg.servo.static_ms2 = 0.0;
    cfg.probe.noise_nm = 0.0;
    cfg.probe.resolution_nm = 0.0;
    cfg.probe.bandwidth_hz = 1.0e7;
    cfg.encoder.resolution_nm = 0.0;
    cfg.encoder.delay_s = 0.0;
    let a = &mut cfg.accel;
    a.sensitivity_error = 0.0;
    a.highpass_hz = 0.0;
    a.noise_density = 0.0;
    a.mains_ms2 = 0.0;
    a.harmonics.clear();
    a.adc_bits = 32;
    let kappa = a.mode_shape_ratio;
    let records = simulate(&cfg)?;
    for r in &records {
        let (amp, f) = (r.amplitude_um, r.frequency_hz);
        let w = 2.0 * PI * f;
        let wn = 2.0 * PI * cfg.servo.natural_hz;
        let wt = 2.0 * PI * cfg.tool.natural_hz;
        let wb = 2.0 * PI * cfg.base.natural_hz;
        let hs = C(wn * wn, 0.0).div(C(wn * wn - w * w, 2.0 * cfg.servo.damping * wn * w));
        let hz = C(w * w, 0.0).div(C(wt * wt - w * w, 2.0 * cfg.tool.damping * wt * w));
        let hb = C(cfg.base.mass_ratio * w * w, 0.0)
            .div(C(wb * wb - w * w, 2.0 * cfg.base.damping * wb * w));
        let slide = hs.mul(C(amp, 0.0));
        let tip = slide.add(slide.mul(hz));
        // Acceleration = -w^2 * (frame + slide + kappa * tool deflection), in m/s^2.
        let accel_pos = slide
            .mul(hb)
            .add(slide)
            .add(slide.mul(hz).mul(C(kappa, 0.0)));
        let accel = C(-w * w * 1e-6, 0.0).mul(accel_pos);

        let fc = fit_sine(&r.command_um, r.fs_hz, f)?;
        let fe = fit_sine(&r.encoder_um, r.fs_hz, f)?;
        let fp = fit_sine(&r.probe_um, r.fs_hz, f)?;
        let fa = fit_sine(&r.accel_ms2, r.fs_hz, f)?;
        // Tolerance: 1e-4 relative in amplitude and 1e-4 rad in phase (RK4 at 40 kHz is far
        // more accurate; the steady-state start leaves no transient to speak of).
        let check = |name: &str, got: hxai_signal::SineFit, want: C| {
            let rel = (got.amplitude - want.abs()).abs() / want.abs();
            let dphi = wrap(got.phase - fc.phase - want.arg()).abs();
            assert!(
                rel < 1e-4 && dphi < 1e-4,
                "{} {name}: amplitude {} vs {} (rel {rel:e}), phase error {dphi:e} rad",
                r.id,
                got.amplitude,
                want.abs()
            );
        };
        check("encoder", fe, slide.div(C(amp, 0.0)).mul(C(amp, 0.0)));
        check("probe", fp, tip);
        check("accel", fa, accel);
    }
    Ok(())
}
