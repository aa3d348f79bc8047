//! Drift: the default image (what `cargo fw` boots: `ControlConfig::at_rate`,
//! the generated table, the board's limits) and the default simulation (what
//! `mre sim`, `mre pil` and `mre bench-control` run: `SimRequest::default()`)
//! must share one installation, value for value.
use mre_algorithm::control::{ControlConfig, DEFAULT_RATE_HZ, V_SENSOR_FULL_SCALE_M_S};
use mre_algorithm::generated_table::GENERATED_TABLE;
use mre_algorithm::installation::DEFAULT_INSTALLATION as I;
use mre_algorithm::limits::{BOARD, X_SENSOR_MAX_MM};
use mre_algorithm::table::Table;
use mre_host::plant::closed_loop::{law_config, setup_for, RunSpec, SimRequest, SimSetup};

#[test]
fn the_default_image_and_the_default_simulation_share_one_installation() {
    let image = ControlConfig::at_rate(DEFAULT_RATE_HZ).unwrap();
    let sim = setup_for(&SimRequest::default()).unwrap();
    let sim_law = law_config(&sim);

    // Mass and usable stroke: what the law plans with, on both sides.
    assert_eq!(image.law.mass_kg, sim_law.mass_kg, "mass: image vs simulation");
    assert_eq!(
        f64::from(image.law.mass_kg),
        sim.impact.mass_kg,
        "mass: image vs the simulated drop"
    );
    assert_eq!(
        image.law.stroke_max_mm, sim_law.stroke_max_mm,
        "stroke: image vs simulation"
    );
    assert_eq!(f64::from(image.law.stroke_max_mm), sim.usable_stroke_mm());
    assert_eq!(SimSetup::default().usable_stroke_mm(), sim.usable_stroke_mm());
    assert_eq!(
        (image.law.mass_kg, image.law.stroke_max_mm),
        (I.mass_kg, I.usable_stroke_mm)
    );

    // The coil drive: the image's drive range is the simulated driver's V/R.
    let driver = sim.impact.driver;
    assert_eq!(
        f64::from(image.law.drive_max_a),
        driver.supply_v / driver.resistance_ohm
    );
    assert_eq!(
        (driver.supply_v, driver.resistance_ohm),
        (f64::from(I.supply_v), f64::from(I.coil_resistance_ohm))
    );
    assert_eq!(image.law.drive_max_a, I.drive_max_a());

    // The coil rating: the image's output clamp and limit, the simulation's
    // largest passive current.
    assert_eq!(image.law.current_max_a, I.coil_rating_a);
    assert_eq!(BOARD.current_a.max, I.coil_rating_a);
    assert!(RunSpec::parse(&format!("passive:{}", I.coil_rating_a)).is_ok());
    assert!(RunSpec::parse(&format!("passive:{}", I.coil_rating_a + 0.1)).is_err());

    // The sensors.
    assert_eq!(V_SENSOR_FULL_SCALE_M_S, I.v_sensor_full_scale_m_s);
    assert_eq!(X_SENSOR_MAX_MM, I.x_sensor_range_mm);
    assert_eq!(BOARD.stroke_mm.max, I.x_sensor_range_mm);

    // The flown table covers the usable stroke in every entry.
    let table = Table::from_image(&GENERATED_TABLE).unwrap();
    // The image derives its configuration from the table's installation:
    // the same configuration, value for value.
    assert_eq!(
        mre_protocol::upload::installed_config(&table, DEFAULT_RATE_HZ).unwrap(),
        image
    );
    for e in table.entries() {
        assert!(
            e.x_max_mm >= I.usable_stroke_mm,
            "{} A entry ends at {} mm",
            e.current_a,
            e.x_max_mm
        );
    }
}
