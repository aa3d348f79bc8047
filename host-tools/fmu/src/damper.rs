//! The damper: force from displacement, velocity and coil current, by the
//! core's forward model (`Table::force`): the branch quartics, interpolation
//! between currents (linear in `tanh(I/I_s)` under a saturation term) and the
//! viscous term. The coil's time constant and the sensors' delay act in the
//! controller (the law compensates them); the damper reports them.
use fmi::fmi3::{Fmi3Error, Fmi3Res};
use fmi_export::fmi3::{Context, DefaultLoggingCategory, UserModel};
use fmi_export::FmuModel;
use mre_algorithm::Table;

/// MRE impact damper identified by mre: contact force from displacement, velocity and coil current, evaluated by the board's control core (mre_algorithm)
#[derive(FmuModel, Default, Debug)]
#[model(model_exchange = true, co_simulation = true, user_model = false)]
pub struct Damper {
    /// Damper compression from first contact (m), positive into the damper; clamped to each current's fitted stroke
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    pub displacement_m: f64,
    /// Compression velocity (m/s), positive while compressing: selects the compression or extension branch and drives the viscous term
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    pub velocity_m_s: f64,
    /// Coil current (A); clamped to the tabulated range
    #[variable(causality = Input, variability = Continuous, start = 0.0)]
    pub current_a: f64,
    /// Damper force on the impacting mass (N), positive resisting compression (computed in f32 by mre_algorithm, as on the board)
    #[variable(causality = Output, variability = Continuous, initial = Calculated)]
    pub force_n: f64,
    /// Saturation current I_s of the model file (A): currents interpolate linearly in tanh(I/I_s); 0 = linear in I
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub saturation_current_a: f64,
    /// Coil time constant L/R of the model file (s): the coil current lags its drive by it (the controller inverts it); 0 = no lag
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub coil_tau_s: f64,
    /// Sensor delay of the model file (s): how far the sampled displacement and velocity lag the motion (the controller predicts across it)
    #[variable(causality = CalculatedParameter, variability = Fixed, initial = Calculated)]
    pub sensor_delay_s: f64,
    #[variable(skip = true)]
    table: Option<Table>,
}

impl Damper {
    fn table(&mut self, context: &dyn Context<Self>) -> Result<Table, Fmi3Error> {
        if let Some(t) = self.table {
            return Ok(t);
        }
        match crate::page::load(context.resource_path()) {
            Ok((table, _)) => {
                let terms = table.terms();
                self.saturation_current_a = f64::from(terms.saturation_current_a);
                self.coil_tau_s = f64::from(terms.coil_tau_s);
                self.sensor_delay_s = f64::from(terms.sensor_delay_s);
                self.table = Some(table);
                Ok(table)
            }
            Err(message) => {
                context.log(
                    Fmi3Error::Error.into(),
                    DefaultLoggingCategory::default(),
                    format_args!("{message}"),
                );
                Err(Fmi3Error::Error)
            }
        }
    }

    /// The core's force at the inputs (x converted to mm, as the board reads it).
    pub fn force_at(table: &Table, displacement_m: f64, velocity_m_s: f64, current_a: f64) -> f32 {
        table
            .force((displacement_m * 1.0e3) as f32, velocity_m_s as f32, current_a as f32)
            .force_n
    }
}

impl UserModel for Damper {
    type LoggingCategory = DefaultLoggingCategory;

    fn configurate(&mut self, context: &dyn Context<Self>) -> Result<(), Fmi3Error> {
        self.table(context).map(|_| ())
    }

    fn calculate_values(&mut self, context: &dyn Context<Self>) -> Result<Fmi3Res, Fmi3Error> {
        let table = self.table(context)?;
        self.force_n = f64::from(Self::force_at(
            &table,
            self.displacement_m,
            self.velocity_m_s,
            self.current_a,
        ));
        Ok(Fmi3Res::OK)
    }
}
