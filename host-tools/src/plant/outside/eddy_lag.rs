//! `coil_lag` outside the model class: the field follows the coil command
//! through a second-order lag (inductance plus eddy currents in the core,
//! `Ï + 2ζω·İ + ω²·I = ω²·I_cmd`), integrated with RK4 on the fine grid. The
//! estimator searches a first-order lag.

#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct EddyLag {
    /// Natural frequency ω (rad/s).
    pub omega_rad_s: f64,
    /// Damping ratio ζ.
    pub zeta: f64,
}

impl EddyLag {
    /// The effective current for a command sampled every `dt_s`, starting in
    /// steady state at the first command.
    pub fn apply(&self, command_a: &[f64], dt_s: f64) -> Vec<f64> {
        let Some(&first) = command_a.first() else {
            return Vec::new();
        };
        let (w, z) = (self.omega_rad_s, self.zeta);
        let (mut i, mut di) = (first, 0.0);
        let mut out = Vec::with_capacity(command_a.len());
        for &u in command_a {
            out.push(i);
            let f = |i: f64, di: f64| (di, w * w * (u - i) - 2.0 * z * w * di);
            let (k1i, k1d) = f(i, di);
            let (k2i, k2d) = f(i + 0.5 * dt_s * k1i, di + 0.5 * dt_s * k1d);
            let (k3i, k3d) = f(i + 0.5 * dt_s * k2i, di + 0.5 * dt_s * k2d);
            let (k4i, k4d) = f(i + dt_s * k3i, di + dt_s * k3d);
            i += dt_s / 6.0 * (k1i + 2.0 * k2i + 2.0 * k3i + k4i);
            di += dt_s / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn critically_damped_step_follows_the_closed_form() {
        // ζ = 1: I(t) = 1 − (1 + ωt)·e^{−ωt}; at t = 1/ω, 1 − 2/e = 0.264241.
        let lag = EddyLag {
            omega_rad_s: 200.0,
            zeta: 1.0,
        };
        let dt = 1e-5;
        let mut cmd = vec![0.0];
        cmd.extend(std::iter::repeat_n(1.0, 2000));
        let out = lag.apply(&cmd, dt);
        // out[k] is the state after k − 1 steps of the unit command.
        let k = 1 + (1.0 / 200.0 / dt).round() as usize;
        assert!((out[k] - 0.264241).abs() < 1e-4, "{}", out[k]);
    }
}
