//! The board's side of a control period: the sensor and coil traits a board
//! implements, one period over them ([`ControllerIo`]: read the sensors,
//! `Controller::step_sample`, command the coil), and the coil's open-loop
//! PWM duty.
//!
//! Moved here from the algorithm's `control` (issue 40): the algorithm does
//! no I/O; the controller it keeps takes sampled values and returns the
//! current, which the host runs as the board does.
use mre_algorithm::control::Controller;
use mre_algorithm::law::Command;
use mre_algorithm::math;

/// Displacement sensor (e.g. an ADC channel with linear scaling).
pub trait DisplacementSensor {
    /// Displacement from first contact in mm (may be NaN on a read error).
    fn read_x_mm(&mut self) -> f32;
}

/// Optional velocity sensor. Boards without one return `None` and the
/// controller uses its displacement-based estimator.
pub trait VelocitySensor {
    fn read_v_m_s(&mut self) -> Option<f32>;
}

/// The coil driver (PWM, open loop: see `open_loop_duty`).
pub trait Coil {
    fn set_current_a(&mut self, current_a: f32);
}

/// For boards without a velocity sensor.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoVelocitySensor;

impl VelocitySensor for NoVelocitySensor {
    #[inline]
    fn read_v_m_s(&mut self) -> Option<f32> {
        None
    }
}

/// One control period over a board's I/O, for the algorithm's `Controller`.
pub trait ControllerIo {
    /// One period from I/O: read the sensors, decide, command the coil.
    fn step<D, V, C>(&mut self, displacement: &mut D, velocity: &mut V, coil: &mut C) -> Command
    where
        D: DisplacementSensor + ?Sized,
        V: VelocitySensor + ?Sized,
        C: Coil + ?Sized;

    /// [`ControllerIo::step`] for a board whose one I/O object implements
    /// all three traits (it then owns the peripherals or the PIL frame state).
    fn step_io<B>(&mut self, io: &mut B) -> Command
    where
        B: DisplacementSensor + VelocitySensor + Coil + ?Sized;
}

impl ControllerIo for Controller {
    #[inline]
    fn step<D, V, C>(&mut self, displacement: &mut D, velocity: &mut V, coil: &mut C) -> Command
    where
        D: DisplacementSensor + ?Sized,
        V: VelocitySensor + ?Sized,
        C: Coil + ?Sized,
    {
        let x_mm = displacement.read_x_mm();
        let v_m_s = velocity.read_v_m_s();
        let cmd = self.step_sample(x_mm, v_m_s);
        coil.set_current_a(cmd.current_a);
        cmd
    }

    #[inline]
    fn step_io<B>(&mut self, io: &mut B) -> Command
    where
        B: DisplacementSensor + VelocitySensor + Coil + ?Sized,
    {
        let x_mm = io.read_x_mm();
        let v_m_s = io.read_v_m_s();
        let cmd = self.step_sample(x_mm, v_m_s);
        io.set_current_a(cmd.current_a);
        cmd
    }
}

/// PWM duty for a coil current without current feedback: the coil draws
/// `duty · full_scale_a` on average (duty ∈ [0, 1]).
#[inline]
pub fn open_loop_duty(current_a: f32, full_scale_a: f32) -> f32 {
    if full_scale_a.is_nan() || full_scale_a <= 0.0 {
        return 0.0;
    }
    math::clamp(current_a / full_scale_a, 0.0, 1.0)
}
