//! Property tests of the table generators: roughness and cutting force (issue 13), tool life
//! (issue 23).
#![allow(clippy::unwrap_used)]

use hxai_sim::SimError;
use hxai_sim::cases::{
    CASE_NAMES, CuttingForceConfig, RoughnessConfig, ToolLifeConfig, cutting_force,
    cutting_force::HANDBOOK_KC11, generate_case, roughness, tool_life,
};
use proptest::prelude::*;

fn col<'a>(t: &'a hxai_table::Table, name: &str) -> &'a [f64] {
    t.column(name).unwrap()
}

/// Whether every value of the column `name` lies in `[lo, hi]`.
fn within(t: &hxai_table::Table, name: &str, [lo, hi]: [f64; 2]) -> bool {
    col(t, name).iter().all(|v| (lo..=hi).contains(v))
}

fn rough(seed: u64, n: usize) -> RoughnessConfig {
    RoughnessConfig {
        seed,
        n_rows: n,
        ..RoughnessConfig::default()
    }
}

fn force(seed: u64, n: usize) -> CuttingForceConfig {
    CuttingForceConfig {
        seed,
        n_rows: n,
        ..CuttingForceConfig::default()
    }
}

fn life(seed: u64, n: usize) -> ToolLifeConfig {
    ToolLifeConfig {
        seed,
        n_rows: n,
        ..ToolLifeConfig::default()
    }
}

/// Taylor's law `(C / vc)^(1/n)` with the configuration's constants, on row `i`.
fn taylor(c: &ToolLifeConfig, t: &hxai_table::Table, i: usize) -> f64 {
    (c.taylor_c_m_min / col(t, "cutting_speed_m_min")[i]).powf(1.0 / c.taylor_n)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    // Invariant: a table is a pure function of its configuration, and another seed gives
    // other data.
    #[test]
    fn deterministic_per_seed(seed in any::<u64>(), n in 1usize..200) {
        let a = roughness(&rough(seed, n)).unwrap();
        prop_assert_eq!(&a, &roughness(&rough(seed, n)).unwrap());
        let b = roughness(&rough(seed.wrapping_add(1), n)).unwrap();
        prop_assert_ne!(col(&a, "Ra_um"), col(&b, "Ra_um"));
        let f = cutting_force(&force(seed, n)).unwrap();
        prop_assert_eq!(&f, &cutting_force(&force(seed, n)).unwrap());
        let g = cutting_force(&force(seed.wrapping_add(1), n)).unwrap();
        prop_assert_ne!(col(&f, "Fc_N"), col(&g, "Fc_N"));
    }

    // Invariant: a row does not depend on how many rows are asked for (one stream per row).
    #[test]
    fn rows_do_not_depend_on_the_row_count(seed in any::<u64>(), n in 1usize..60, extra in 1usize..60) {
        let short = roughness(&rough(seed, n)).unwrap();
        let long = roughness(&rough(seed, n + extra)).unwrap();
        for name in short.names() {
            prop_assert_eq!(col(&short, name), &col(&long, name)[..n]);
        }
        let short = cutting_force(&force(seed, n)).unwrap();
        let long = cutting_force(&force(seed, n + extra)).unwrap();
        for name in short.names() {
            prop_assert_eq!(col(&short, name), &col(&long, name)[..n]);
        }
    }

    // Invariant: every input column stays inside its configured range, the targets are
    // positive, and the measured roughness never falls below the kinematic law by more than
    // the scatter allows (every effect adds roughness; scatter is log-normal with sd 0.06,
    // so 5 sd is a factor exp(-0.3)).
    #[test]
    fn columns_stay_in_their_ranges(seed in any::<u64>()) {
        let (rc, fc) = (rough(seed, 300), force(seed, 300));
        let (rt, ft) = (roughness(&rc).unwrap(), cutting_force(&fc).unwrap());
        for (case, t, name, range) in [
            ("roughness", &rt, "feed_mm", rc.feed_mm),
            ("roughness", &rt, "cutting_speed_m_min", rc.cutting_speed_m_min),
            ("roughness", &rt, "cutting_time_min", rc.cutting_time_min),
            ("roughness", &rt, "depth_of_cut_mm", rc.depth_of_cut_mm),
            ("cutting_force", &ft, "chip_thickness_mm", fc.chip_thickness_mm),
            ("cutting_force", &ft, "width_of_cut_mm", fc.width_of_cut_mm),
            ("cutting_force", &ft, "rake_angle_deg", fc.rake_angle_deg),
            ("cutting_force", &ft, "cutting_speed_m_min", fc.cutting_speed_m_min),
            ("cutting_force", &ft, "cutting_time_min", fc.cutting_time_min),
        ] {
            prop_assert!(within(t, name, range), "{} {}", case, name);
        }

        prop_assert!(col(&rt, "nose_radius_mm").iter().all(|r| rc.nose_radii_mm.contains(r)));
        prop_assert!(col(&rt, "tool").iter().all(|k| *k >= 1.0 && *k <= rc.n_tools as f64 && k.fract() == 0.0));
        for (i, ra) in col(&rt, "Ra_um").iter().enumerate() {
            let f = col(&rt, "feed_mm")[i];
            let r = col(&rt, "nose_radius_mm")[i];
            let kin = 1000.0 * f * f / (32.0 * r);
            prop_assert!(*ra > 0.0 && *ra < 50.0, "Ra {} um out of range", ra);
            prop_assert!(*ra >= kin * (-5.0 * rc.noise_rel).exp(), "Ra {} below kinematic {}", ra, kin);
        }

        // Every insert has one rake angle.
        let tools = col(&ft, "tool");
        let rake = col(&ft, "rake_angle_deg");
        for i in 0..ft.n_rows() {
            for j in 0..i {
                if tools[i] == tools[j] {
                    prop_assert_eq!(rake[i], rake[j]);
                }
            }
        }
        // Bounds: the handbook's kc1.1 times the largest factors (rake 1.18, speed 1.03,
        // wear 1 + 0.49, scatter exp(5 * 0.03)) over the largest chip section.
        let fmax = HANDBOOK_KC11 * 4.0 * 0.5_f64.powf(0.78) * 1.18 * 1.03 * 1.49 * 1.17;
        prop_assert!(col(&ft, "Fc_N").iter().all(|f| *f > 0.0 && *f < fmax));
    }

    // Invariant: with every effect off and no scatter, the target column is the engineer's
    // law exactly (relative 1e-12).
    #[test]
    fn physics_only_reproduces_the_law(seed in any::<u64>(), n in 1usize..100) {
        let c = RoughnessConfig { seed, n_rows: n, ..RoughnessConfig::physics_only() };
        let t = roughness(&c).unwrap();
        for i in 0..n {
            let f = col(&t, "feed_mm")[i];
            let r = col(&t, "nose_radius_mm")[i];
            let law = 1000.0 * f.powi(2) / (32.0 * r);
            let ra = col(&t, "Ra_um")[i];
            prop_assert!((ra - law).abs() <= 1e-12 * law, "row {}: {} vs {}", i, ra, law);
        }
        let c = CuttingForceConfig { seed, n_rows: n, ..CuttingForceConfig::physics_only() };
        let t = cutting_force(&c).unwrap();
        for i in 0..n {
            let h = col(&t, "chip_thickness_mm")[i];
            let b = col(&t, "width_of_cut_mm")[i];
            let law = c.kc11_n_mm2 * b * h.powf(1.0 - c.mc);
            let fc = col(&t, "Fc_N")[i];
            prop_assert!((fc - law).abs() <= 1e-12 * law, "row {}: {} vs {}", i, fc, law);
        }
    }
}

/// Each effect, switched on alone, changes the target where the literature says it should.
#[test]
fn each_effect_acts_where_expected() {
    let base = RoughnessConfig::physics_only();
    let law = |t: &hxai_table::Table, i: usize| {
        let f = col(t, "feed_mm")[i];
        1000.0 * f * f / (32.0 * col(t, "nose_radius_mm")[i])
    };
    // Ploughing: the relative excess grows as the feed falls.
    let t = roughness(&RoughnessConfig {
        h_min_mm: 0.002,
        h_min_tool_sd: 0.0,
        ..base.clone()
    })
    .unwrap();
    let feed = col(&t, "feed_mm");
    let (lo, hi) = (0..t.n_rows()).fold((0.0_f64, f64::INFINITY), |(lo, hi), i| {
        let excess = col(&t, "Ra_um")[i] / law(&t, i) - 1.0;
        assert!(excess > 0.0);
        if feed[i] < 0.06 {
            (lo.max(excess), hi)
        } else if feed[i] > 0.25 {
            (lo, hi.min(excess))
        } else {
            (lo, hi)
        }
    });
    assert!(
        lo > hi,
        "ploughing excess at low feed {lo} vs high feed {hi}"
    );
    // Built-up edge: only at low cutting speed (above 200 m/min it is < 1e-4 um).
    let t = roughness(&RoughnessConfig {
        bue_um: 0.8,
        ..base.clone()
    })
    .unwrap();
    for i in 0..t.n_rows() {
        let excess = col(&t, "Ra_um")[i] - law(&t, i);
        let vc = col(&t, "cutting_speed_m_min")[i];
        if vc > 200.0 {
            assert!(excess.abs() < 1e-4, "BUE {excess} at {vc} m/min");
        }
        if vc < 60.0 {
            assert!(excess > 0.6, "BUE only {excess} at {vc} m/min");
        }
    }
    // Wear: zero excess at zero cutting time, more with time.
    let t = roughness(&RoughnessConfig {
        wear_ra_per_mm: 2.0,
        cutting_time_min: [0.0, 0.0],
        ..base.clone()
    })
    .unwrap();
    for i in 0..t.n_rows() {
        assert_eq!(col(&t, "Ra_um")[i], law(&t, i));
    }
    // Force: a larger rake angle gives less force than Kienzle at the reference rake.
    let c = CuttingForceConfig {
        rake_per_deg: 0.015,
        ..CuttingForceConfig::physics_only()
    };
    let t = cutting_force(&c).unwrap();
    for i in 0..t.n_rows() {
        let k = c.kc11_n_mm2
            * col(&t, "width_of_cut_mm")[i]
            * col(&t, "chip_thickness_mm")[i].powf(1.0 - c.mc);
        let ratio = col(&t, "Fc_N")[i] / k;
        let gamma = col(&t, "rake_angle_deg")[i];
        assert!((ratio - (1.0 - 0.015 * (gamma - 6.0))).abs() < 1e-12);
    }
}

#[test]
fn bad_settings_are_refused_by_name() {
    let e = roughness(&RoughnessConfig {
        feed_mm: [0.3, 0.1],
        ..RoughnessConfig::default()
    })
    .unwrap_err();
    assert!(matches!(
        e,
        SimError::InvalidParameter {
            name: "feed_mm",
            ..
        }
    ));
    let e = roughness(&RoughnessConfig {
        n_rows: 0,
        ..RoughnessConfig::default()
    })
    .unwrap_err();
    assert!(matches!(
        e,
        SimError::InvalidParameter { name: "n_rows", .. }
    ));
    let e = cutting_force(&CuttingForceConfig {
        mc: 1.0,
        ..CuttingForceConfig::default()
    })
    .unwrap_err();
    assert!(matches!(e, SimError::InvalidParameter { name: "mc", .. }));
    let e = cutting_force(&CuttingForceConfig {
        rake_per_deg: 0.2,
        ..CuttingForceConfig::default()
    })
    .unwrap_err();
    assert!(matches!(
        e,
        SimError::InvalidParameter {
            name: "rake_per_deg",
            ..
        }
    ));
    let e = generate_case("milling", None, None).unwrap_err();
    assert!(e.to_string().contains("milling") && e.to_string().contains("roughness"));
}

#[test]
fn named_cases_use_the_defaults() {
    for name in CASE_NAMES {
        let t = generate_case(name, Some(7), Some(3)).unwrap();
        assert_eq!(t.n_rows(), 7);
    }
    assert_eq!(
        generate_case("roughness", Some(5), Some(9)).unwrap(),
        roughness(&RoughnessConfig {
            n_rows: 5,
            seed: 9,
            ..RoughnessConfig::default()
        })
        .unwrap()
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    // Invariant: the tool-life table is a pure function of its configuration, another seed
    // gives other data, and a row does not depend on how many rows are asked for.
    #[test]
    fn tool_life_is_deterministic_per_row(seed in any::<u64>(), n in 1usize..60, extra in 1usize..60) {
        let a = tool_life(&life(seed, n)).unwrap();
        prop_assert_eq!(&a, &tool_life(&life(seed, n)).unwrap());
        let b = tool_life(&life(seed.wrapping_add(1), n)).unwrap();
        prop_assert_ne!(col(&a, "tool_life_min"), col(&b, "tool_life_min"));
        let long = tool_life(&life(seed, n + extra)).unwrap();
        for name in a.names() {
            prop_assert_eq!(col(&a, name), &col(&long, name)[..n]);
        }
    }

    // Invariant: with the feed effect and the scatter off, the target is Taylor's law
    // exactly (relative 1e-12).
    #[test]
    fn tool_life_physics_only_is_taylors_law(seed in any::<u64>(), n in 1usize..100) {
        let c = ToolLifeConfig { seed, n_rows: n, ..ToolLifeConfig::physics_only() };
        let t = tool_life(&c).unwrap();
        for i in 0..n {
            let law = taylor(&c, &t, i);
            let got = col(&t, "tool_life_min")[i];
            prop_assert!((got - law).abs() <= 1e-12 * law, "row {}: {} vs {}", i, got, law);
        }
    }

    // Invariant (the documented hidden truth): with no scatter, measured over Taylor's law is
    // `(f / 0.25)^(-0.6 / 0.25)` = `(f / 0.25)^-2.4`, a function of the feed alone, to 1e-12
    // relative; inputs stay in their ranges.
    #[test]
    fn tool_life_truth_is_the_feed_power_law(seed in any::<u64>(), n in 1usize..200) {
        let c = ToolLifeConfig { seed, n_rows: n, noise_rel: 0.0, ..ToolLifeConfig::default() };
        prop_assert_eq!(c.feed_life_exponent(), 0.6 / 0.25);
        let t = tool_life(&c).unwrap();
        prop_assert!(within(&t, "cutting_speed_m_min", [150.0, 350.0]));
        prop_assert!(within(&t, "feed_mm", [0.1, 0.4]));
        prop_assert!(within(&t, "coolant_temp_C", [18.0, 28.0]));
        prop_assert!(within(&t, "workpiece_diameter_mm", [30.0, 120.0]));
        for i in 0..n {
            let f = col(&t, "feed_mm")[i];
            let ratio = col(&t, "tool_life_min")[i] / taylor(&c, &t, i);
            let truth = (f / 0.25).powf(-2.4);
            prop_assert!((ratio - truth).abs() <= 1e-12 * truth, "row {}: {} vs {}", i, ratio, truth);
            prop_assert_eq!(col(&t, "tool")[i], (i % 10 + 1) as f64);
        }
    }
}

/// With the default scatter the measured/true ratio is log-normal with sd `noise_rel`: on
/// 4000 rows the sample sd of its log is within 5 % of 0.3 and its mean near 0.
#[test]
fn tool_life_scatter_has_the_documented_size() {
    let c = ToolLifeConfig {
        n_rows: 4000,
        ..ToolLifeConfig::default()
    };
    let t = tool_life(&c).unwrap();
    let logs: Vec<f64> = (0..t.n_rows())
        .map(|i| {
            let f = col(&t, "feed_mm")[i];
            (col(&t, "tool_life_min")[i] / (taylor(&c, &t, i) * c.feed_factor(f))).ln()
        })
        .collect();
    let n = logs.len() as f64;
    let mean = logs.iter().sum::<f64>() / n;
    let sd = (logs.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!(mean.abs() < 0.03, "mean log ratio {mean}");
    assert!((sd / 0.3 - 1.0).abs() < 0.05, "sd of log ratio {sd}");
}

#[test]
fn tool_life_bad_settings_are_refused_by_name() {
    let cases: [(&str, ToolLifeConfig); 8] = [
        (
            "n_rows",
            ToolLifeConfig {
                n_rows: 0,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "n_tools",
            ToolLifeConfig {
                n_tools: 0,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "taylor_c_m_min",
            ToolLifeConfig {
                taylor_c_m_min: -1.0,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "taylor_n",
            ToolLifeConfig {
                taylor_n: 0.0,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "feed_ref_mm",
            ToolLifeConfig {
                feed_ref_mm: f64::NAN,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "feed_exponent",
            ToolLifeConfig {
                feed_exponent: -0.1,
                ..ToolLifeConfig::default()
            },
        ),
        (
            "feed_mm",
            ToolLifeConfig {
                feed_mm: [0.4, 0.1],
                ..ToolLifeConfig::default()
            },
        ),
        (
            "noise_rel",
            ToolLifeConfig {
                noise_rel: 1.5,
                ..ToolLifeConfig::default()
            },
        ),
    ];
    for (want, c) in cases {
        match tool_life(&c).unwrap_err() {
            SimError::InvalidParameter { name, .. } => assert_eq!(name, want),
            other => panic!("{want}: {other}"),
        }
    }
    let e = tool_life(&ToolLifeConfig {
        cutting_speed_m_min: [0.0, 300.0],
        ..ToolLifeConfig::default()
    })
    .unwrap_err();
    assert!(e.to_string().contains("cutting_speed_m_min"), "{e}");
    assert_eq!(
        generate_case("tool_life", Some(5), Some(9)).unwrap(),
        tool_life(&life(9, 5)).unwrap()
    );
}
