//! `[integrator]`, `[end]` and `[output]`: the scheme, the plan and the output times.
use super::*;

/// `auto`'s first step where the scene gives no `dt`, in units of `end.t_end`: a proposal the
/// adaptive schemes it picks grow by their controller's factor per accepted step (or cut on
/// rejection), so a few steps reach the particle's own scale from any start this small; the
/// fates do not depend on it beyond the tolerance.
pub const AUTO_FIRST_STEP: f64 = 1e-6;

impl Builder<'_> {
    /// `[integrator]`: the scheme by name through the registry of integrators, the first step
    /// `dt` and the largest step `dt_max` (the plan's). `auto` may leave `dt` out
    /// ([`AUTO_FIRST_STEP`]); every other integrator needs it.
    pub(super) fn integrator(
        &self,
        spec: &IntegratorSpec,
    ) -> Result<(SceneIntegrator, Option<Num>, Option<Num>), SceneError> {
        let keys = self.model_keys(spec, "integrator", "type", &["dt", "dt_max"])?;
        let integrator =
            crate::integrator::registry::by_name(&keys.name, &keys.values).map_err(|e| self.model_error(&keys, e))?;
        let dt = self.table_number(spec, "integrator", "dt")?;
        if dt.is_none() && integrator.name() != "auto" {
            return Err(self.err(
                spec.span(),
                "integrator.dt",
                format!(
                    "`{}` needs `dt` (only `auto` chooses its own first step)",
                    integrator.name()
                ),
            ));
        }
        let dt_max = self.table_number(spec, "integrator", "dt_max")?;
        Ok((integrator, dt, dt_max))
    }

    pub(super) fn plan(
        &self,
        dt: Option<&Num>,
        dt_max: Option<&Num>,
        end: &EndSpec,
        output: &OutputSpec,
        particles: u64,
    ) -> Result<(Plan, Vec<f64>), SceneError> {
        let t_end = self.positive(&end.t_end, "end.t_end")?;
        let dt = match dt {
            Some(dt) => self.positive(dt, "integrator.dt")?,
            None => AUTO_FIRST_STEP * t_end,
        };
        let outputs = match &output.every {
            None => vec![t_end],
            Some(every) => {
                let e = self.positive(every, "output.every")?;
                let n = (t_end / e).floor();
                // t_end and every are finite and > 0, so n is a number (∞ when every underflows).
                if n >= MAX_OUTPUTS as f64 {
                    return Err(self.err(
                        every.span(),
                        "output.every",
                        format!("t_end / every = {:e} output times; at most {MAX_OUTPUTS}", t_end / e),
                    ));
                }
                let mut times: Vec<f64> = (1..=n as u64)
                    .map(|k| k as f64 * e)
                    // An output within round-off of t_end would be a second frame at the same time.
                    .filter(|&t| t < t_end * (1.0 - 1e-9))
                    .collect();
                times.push(t_end);
                times
            }
        };
        // One state per particle at the start, every output time and the event.
        let samples = particles.saturating_mul(outputs.len() as u64 + 2);
        if samples > MAX_SAMPLES {
            let span = output.every.as_ref().map_or(end.t_end.span(), |e| e.span());
            return Err(self.err(
                span,
                "output.every",
                format!(
                    "{particles} particles × {} output times = {samples} states to keep; at most {MAX_SAMPLES} (write fewer outputs or split the run)",
                    outputs.len()
                ),
            ));
        }
        let mut plan = Plan::new(t_end, dt)
            .and_then(|p| p.with_outputs(&outputs))
            .map_err(|e| self.param(end.t_end.span(), "end.t_end, integrator.dt, output.every", e))?;
        if let Some(m) = dt_max {
            let v = self.positive(m, "integrator.dt_max")?;
            plan = plan
                .with_dt_max(v)
                .map_err(|e| self.param(m.span(), "integrator.dt_max", e))?;
        }
        let max_steps = match &end.max_steps {
            Some(m) if *m.get_ref() == 0 => return Err(self.err(m.span(), "end.max_steps", "must be at least 1")),
            Some(m) => *m.get_ref(),
            None => DEFAULT_MAX_STEPS,
        };
        // No wall-time limit: it would make a particle's fate depend on the machine's load.
        let plan = plan.with_budget(Budget {
            max_steps,
            wall_time: None,
        });
        Ok((plan, outputs))
    }
}
