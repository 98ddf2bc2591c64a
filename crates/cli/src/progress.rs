//! Live progress of `stride predict`: one line per initial guess with the mesh being
//! solved, its iteration, objective and infeasibilities, the time spent on that mesh and an
//! estimate of the time left there.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use stride_ocp::guess::GuessKind;
use stride_ocp::predict::{MeshStage, ProgressSource};
use stride_solve::solver::IterationRecord;

/// Least time between two redraws on a terminal.
const REDRAW: Duration = Duration::from_millis(500);
/// Least time between two plain lines of one guess when stderr is not a terminal.
const PLAIN_EVERY: Duration = Duration::from_secs(10);

/// The progress lines of the guesses of one prediction, written to stderr: redrawn in place
/// on a terminal, else a plain line per guess at each new mesh and every 10 s.
pub struct ProgressBoard {
    guesses: Vec<GuessKind>,
    /// Barrier parameter μ where a solve ends (the solver's floor): the time estimate
    /// measures progress as the fraction of the way from the first μ to it, in log scale.
    mu_end: f64,
    tty: bool,
    state: Mutex<BoardState>,
}

struct BoardState {
    lines: Vec<String>,
    stage: Vec<Option<MeshStage>>,
    mu_start: Vec<f64>,
    last_plain: Vec<Option<Instant>>,
    last_draw: Option<Instant>,
    drawn: bool,
}

impl ProgressBoard {
    /// A board for `guesses`, whose solves end at the barrier parameter `mu_end`.
    pub fn new(guesses: &[GuessKind], mu_end: f64) -> Self {
        let n = guesses.len();
        Self {
            guesses: guesses.to_vec(),
            mu_end,
            tty: std::io::stderr().is_terminal(),
            state: Mutex::new(BoardState {
                lines: guesses
                    .iter()
                    .map(|g| format!("{g:<22} starting"))
                    .collect(),
                stage: vec![None; n],
                mu_start: vec![f64::NAN; n],
                last_plain: vec![None; n],
                last_draw: None,
                drawn: false,
            }),
        }
    }

    /// Record one solver iteration of `src`.
    pub fn update(&self, src: ProgressSource, r: &IterationRecord) {
        let Some(i) = self.guesses.iter().position(|&g| g == src.guess) else {
            return;
        };
        let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
        let new_stage = st.stage[i] != Some(src.stage);
        if new_stage {
            st.stage[i] = Some(src.stage);
            st.mu_start[i] = r.mu;
        }
        st.lines[i] = self.line(src, r, st.mu_start[i]);
        if self.tty {
            let due = st.last_draw.is_none_or(|t| t.elapsed() >= REDRAW);
            if due || new_stage {
                st.last_draw = Some(Instant::now());
                self.draw(&mut st);
            }
        } else if new_stage || st.last_plain[i].is_none_or(|t| t.elapsed() >= PLAIN_EVERY) {
            st.last_plain[i] = Some(Instant::now());
            eprintln!("{}", st.lines[i]);
        }
    }

    /// Draw the final state of every line (on a terminal).
    pub fn finish(&self) {
        if self.tty {
            let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
            self.draw(&mut st);
        }
    }

    fn draw(&self, st: &mut BoardState) {
        let mut err = std::io::stderr().lock();
        if st.drawn {
            let _ = write!(err, "\x1b[{}A", st.lines.len());
        }
        for l in &st.lines {
            let _ = writeln!(err, "\r\x1b[2K{l}");
        }
        let _ = err.flush();
        st.drawn = true;
    }

    fn line(&self, src: ProgressSource, r: &IterationRecord, mu_start: f64) -> String {
        let stage = match src.stage {
            MeshStage::Coarse(n) => format!("coarse mesh ({n} intervals)"),
            MeshStage::Final(n) => format!("final mesh ({n} intervals)"),
        };
        let t = r.elapsed.as_secs_f64();
        format!(
            "{:<22} {stage:<28} iteration {:>4}  objective {:>11.4e}  constraint violation {:>8.1e}  optimality {:>8.1e}  {t:>6.1} s{}",
            src.guess.to_string(),
            r.iter,
            r.objective,
            r.inf_pr,
            r.inf_du,
            time_left(mu_start, r.mu, self.mu_end, t)
        )
    }
}

/// The estimate of the time left in a solve after `elapsed` seconds, from how far the
/// barrier parameter went from `mu_start` to `mu` on the way to `mu_end` (log scale):
/// `, ~N s left on this mesh`, or a word when no estimate can be made.
fn time_left(mu_start: f64, mu: f64, mu_end: f64, elapsed: f64) -> String {
    let span = (mu_start / mu_end).ln();
    let done = (mu_start / mu).ln() / span;
    if !(span > 0.0 && done.is_finite()) || done < 0.05 {
        return String::new();
    }
    if done >= 1.0 {
        return ", converging".into();
    }
    let left = elapsed * (1.0 - done) / done;
    format!(", ~{left:.0} s left on this mesh")
}

#[cfg(test)]
mod tests {
    use super::time_left;

    #[test]
    fn the_time_left_follows_the_barrier_parameter_in_log_scale() {
        // μ from 0.1 to 1e-9: at 1e-5, half way (in log scale): as much time again
        assert_eq!(
            time_left(0.1, 1e-5, 1e-9, 20.0),
            ", ~20 s left on this mesh"
        );
        assert_eq!(time_left(0.1, 1e-9, 1e-9, 20.0), ", converging");
        assert_eq!(time_left(0.1, 0.1, 1e-9, 1.0), "");
    }
}
