//! What an SLA run reports after each step ([`super::run_reporting`]): the step, and with a
//! crack-length stop (`pd.stop_crack_length`, the adaptive region's run to 0.7 W) how far the
//! crack is from it, so that a progress bar's fraction and time left follow the crack instead of
//! `max_steps`, which such a run does not reach.

/// The state of an SLA run after one of its steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlaProgress {
    /// the step just taken (1-based)
    pub step: usize,
    /// `pd.sla_steps` (the scene key)
    pub max_steps: usize,
    /// the crack length after the step (mm: the scene's length unit)
    pub crack_length: f64,
    /// the crack length before the first step (the pre-crack's)
    pub initial_crack_length: f64,
    /// `pd.stop_crack_length`: the run ends when the crack reaches it
    pub stop_crack_length: Option<f64>,
}

impl SlaProgress {
    /// The fraction of the run done, in [0, 1]: the larger of the steps' fraction of `max_steps`
    /// and, with a crack-length stop, the crack's advance over the advance asked
    /// ((a - a_0) / (a_stop - a_0)); whichever stop comes first ends the run.
    pub fn fraction(&self) -> f64 {
        let by_steps = self.step as f64 / self.max_steps.max(1) as f64;
        let by_crack = self.stop_crack_length.map_or(0.0, |stop| {
            let asked = stop - self.initial_crack_length;
            if asked > 0.0 {
                (self.crack_length - self.initial_crack_length) / asked
            } else {
                1.0
            }
        });
        by_steps.max(by_crack).clamp(0.0, 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::SlaProgress;

    fn at(step: usize, a: f64, stop: Option<f64>) -> SlaProgress {
        SlaProgress {
            step,
            max_steps: 20_000,
            crack_length: a,
            initial_crack_length: 1.1,
            stop_crack_length: stop,
        }
    }

    #[test]
    fn the_fraction_follows_whichever_stop_comes_first() {
        // no crack-length stop: the steps' fraction
        assert_eq!(at(5_000, 5.0, None).fraction(), 0.25);
        // the crack halfway to its stop long before half of max_steps
        assert!((at(3_000, 4.35, Some(7.6)).fraction() - 0.5).abs() < 1e-12);
        // the steps ahead of the crack (a crack that does not grow)
        assert_eq!(at(10_000, 1.1, Some(7.6)).fraction(), 0.5);
        // the stop reached or passed, and a stop at or below the pre-crack: done
        assert_eq!(at(6_835, 7.62, Some(7.6)).fraction(), 1.0);
        assert_eq!(at(1, 1.1, Some(1.0)).fraction(), 1.0);
        // a crack length below a0 (a run's starts at the pre-crack's and only grows): 0, not < 0
        assert_eq!(at(0, 1.0, Some(7.6)).fraction(), 0.0);
    }
}
