//! The damper: force from displacement, velocity and coil current, by the
//! core's forward model (`Table::force`): the branch quartics, interpolation
//! between currents (linear in `tanh(I/I_s)` under a saturation term) and the
//! viscous term. The coil's time constant and the sensors' delay act in the
//! controller (the law compensates them); the damper reports them.
//!
//! The branch (compression or extension) follows the velocity's sign, and
//! the force jumps between the branches' quartics at v = 0 (hundreds of N).
//! For variable-step solvers, Model Exchange declares that switch as a state
//! event: the event indicator is the velocity (`branch_indicator_m_s`), and
//! in Continuous-Time Mode the branch stays the one chosen at the last event
//! (Event Mode, initialisation), so the right-hand side the solver sees is
//! smooth between events and the switch happens where the solver located
//! the zero crossing. Co-Simulation, Event Mode and Initialization Mode pick
//! the branch from the velocity at every evaluation, as the core's
//! `Table::force` does.
use fmi::fmi3::{Fmi3Error, Fmi3Res};
use fmi::EventFlags;
use fmi_export::fmi3::{Context, DefaultLoggingCategory, UserModel};
use fmi_export::FmuModel;
use mre_algorithm::model::Branch;
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
    /// Branch event indicator (m/s): the compression velocity, whose zero crossing switches the force between the extension and compression branches (Model Exchange state event)
    #[variable(causality = Local, variability = Continuous, event_indicator = true)]
    pub branch_indicator_m_s: f64,
    #[variable(skip = true)]
    table: Option<Table>,
    /// The branch chosen at the last event (held in Continuous-Time Mode).
    #[variable(skip = true)]
    branch: Option<Branch>,
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

    /// The core's force on `branch` (x converted to mm, as the board reads it).
    pub fn force_on(table: &Table, displacement_m: f64, velocity_m_s: f64, branch: Branch, current_a: f64) -> f32 {
        table
            .force_on_branch_v(
                (displacement_m * 1.0e3) as f32,
                velocity_m_s as f32,
                branch,
                current_a as f32,
            )
            .force_n
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
        let from_v = Branch::from_velocity(self.velocity_m_s as f32);
        let branch = match self.branch {
            Some(held) if crate::export::in_continuous_time(context) => held,
            _ => {
                self.branch = Some(from_v);
                from_v
            }
        };
        self.force_n = f64::from(Self::force_on(
            &table,
            self.displacement_m,
            self.velocity_m_s,
            branch,
            self.current_a,
        ));
        self.branch_indicator_m_s = self.velocity_m_s;
        Ok(Fmi3Res::OK)
    }

    fn get_event_indicators(
        &mut self,
        _context: &dyn Context<Self>,
        indicators: &mut [f64],
    ) -> Result<bool, Fmi3Error> {
        // The velocity: its sign selects the branch (Branch::from_velocity).
        match indicators {
            [z] => {
                *z = self.velocity_m_s;
                Ok(true)
            }
            _ => Err(Fmi3Error::Error),
        }
    }

    fn event_update(&mut self, _context: &dyn Context<Self>, flags: &mut EventFlags) -> Result<Fmi3Res, Fmi3Error> {
        // The switch: the branch of the velocity at the event.
        flags.reset();
        self.branch = Some(Branch::from_velocity(self.velocity_m_s as f32));
        Ok(Fmi3Res::OK)
    }
}
