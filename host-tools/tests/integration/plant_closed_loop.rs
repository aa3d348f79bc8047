//! `mre sim`: the core's impact law in the loop with the plant.
use mre_host::plant::closed_loop::{run_comparison, RunSpec, SimSetup};
use mre_host::plant::{ImpactConfig, Plant, PlantStepper};

#[test]
fn controlled_impact_stays_in_stroke_with_a_lower_peak_than_passive() {
    let setup = SimSetup::default();
    let specs = [RunSpec::Passive(0.0), RunSpec::Passive(2.0), RunSpec::Controlled];
    let cmp = run_comparison(&setup, &specs).unwrap();
    for r in &cmp.runs {
        eprintln!(
            "{:>14}: peak {:7.0} N, decel {:6.1} g, stroke {:5.2}/{} mm, rebound {:?} m/s",
            r.label,
            r.summary.peak_force_n,
            r.summary.peak_deceleration_m_s2 / 9.81,
            r.summary.max_stroke_mm,
            r.usable_stroke_mm,
            r.summary.rebound_velocity_m_s
        );
    }
    let [soft, stiff, controlled] = &cmp.runs[..] else {
        panic!()
    };
    // The usable stroke is what makes the problem: soft bottoms out, stiff does not.
    assert!(!soft.within_stroke && stiff.within_stroke);
    assert!(
        controlled.within_stroke,
        "controlled stroke {}",
        controlled.summary.max_stroke_mm
    );
    assert!(controlled.summary.peak_force_n < stiff.summary.peak_force_n);
    let (reference, reduction) = cmp.controlled_vs_passive.clone().unwrap();
    assert_eq!(reference, "passive 2 A");
    eprintln!("controlled peak is {reduction:.1} % below {reference}");
    // The ideal constant force over the usable stroke is a floor no controller beats.
    let ideal = setup.impact.mass_kg * setup.impact.impact_velocity_m_s.powi(2)
        / (2.0 * setup.usable_stroke_mm() * 1e-3)
        + setup.impact.mass_kg * setup.impact.gravity_m_s2;
    assert!(controlled.summary.peak_force_n > ideal);
}

#[test]
fn stepper_in_lockstep_reproduces_the_callback_run() {
    // The PIL path drives the stepper one period at a time; with the same
    // commands it must give the same samples as the callback API.
    let plant = Plant::nominal();
    let cfg = ImpactConfig::default();
    let command = |x_mm: f32, _v: f32| if x_mm < 2.0 { 2.0f32 } else { 0.5 };
    let via_callback = mre_host::plant::simulate(
        &plant,
        &cfg,
        mre_host::plant::CurrentSource::Controller(Box::new(command)),
    )
    .unwrap();
    let mut stepper = PlantStepper::new(&plant, &cfg).unwrap();
    let mut sample = stepper.last_sample();
    while !stepper.is_finished() {
        sample = stepper.step_period(command(sample.x_mm as f32, sample.v_m_s as f32));
    }
    let via_stepper = stepper.into_trajectory();
    assert_eq!(via_callback, via_stepper);
    // Zero-order hold: the command only changes on control-period boundaries.
    let per_period = (cfg.control_period_s / plant.measurement.sample_period_s).round() as usize;
    for (i, w) in via_stepper.samples.windows(2).enumerate() {
        if (i + 1) % per_period != 1 {
            assert_eq!(w[0].command_a, w[1].command_a, "sample {}", i + 1);
        }
    }
}

#[test]
fn sim_report_writes_csv_summary_and_plots() {
    use mre_host::plant::closed_loop::{run_sim, SimRequest};
    let dir = tempfile::tempdir().unwrap();
    let request = SimRequest {
        runs: vec![RunSpec::Passive(2.0), RunSpec::Passive(0.5)],
        ..SimRequest::default()
    };
    let cmp = run_sim(&request, dir.path()).unwrap();
    assert_eq!(cmp.runs.len(), 2);
    assert!(cmp.controlled_vs_passive.is_none(), "no controlled run, no comparison");
    for name in [
        "passive-2a.csv",
        "passive-0.5a.csv",
        "summary.json",
        "summary.md",
        "force_time.png",
        "force_displacement.png",
    ] {
        assert!(dir.path().join(name).metadata().unwrap().len() > 100, "{name}");
    }
    let mut reader = csv::Reader::from_path(dir.path().join("passive-2a.csv")).unwrap();
    let headers: Vec<String> = reader.headers().unwrap().iter().map(str::to_owned).collect();
    assert_eq!(
        headers,
        [
            "time_s",
            "displacement_mm",
            "velocity_m_s",
            "force_n",
            "command_a",
            "current_a"
        ]
    );
    let png = std::fs::read(dir.path().join("force_time.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    assert!(RunSpec::parse("passive:3").is_err() && RunSpec::parse("active").is_err());
    assert_eq!(RunSpec::parse("passive:0").unwrap(), RunSpec::Passive(0.0));
}
