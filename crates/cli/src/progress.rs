//! Live progress of `stride predict`: one line per initial guess with the mesh being
//! solved, its iteration, objective and infeasibilities, the time spent on that mesh and an
//! estimate of the time left there ([`time_left`]).

mod time_left;

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use stride_ocp::guess::GuessKind;
use stride_predict::predict::{MeshStage, ProgressSource};
use stride_solve::solver::IterationRecord;
use time_left::{seconds_left, MeshProgress, SolvedMesh};

/// Least time between two redraws on a terminal.
const REDRAW: Duration = Duration::from_millis(500);
/// Least time between two plain lines of one guess when stderr is not a terminal.
const PLAIN_EVERY: Duration = Duration::from_secs(10);

/// The progress lines of the guesses of one prediction, written to stderr: redrawn in place
/// on a terminal, else a plain line per guess at each new mesh and every 10 s.
pub struct ProgressBoard {
    guesses: Vec<GuessKind>,
    /// Barrier parameter μ where a solve ends (the solver's floor): without a coarse mesh
    /// solved before, the time estimate measures progress as the fraction of the way from
    /// the first μ to it, in log scale.
    mu_end: f64,
    tty: bool,
    state: Mutex<BoardState>,
}

struct BoardState {
    lines: Vec<String>,
    stage: Vec<Option<MeshStage>>,
    /// Per guess: its current mesh's first record (μ, elapsed [s]) and last record.
    first: Vec<(f64, f64)>,
    last: Vec<Option<(usize, f64)>>,
    /// Per guess: the coarse mesh it solved before the current one.
    solved: Vec<Option<SolvedMesh>>,
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
                first: vec![(f64::NAN, 0.0); n],
                last: vec![None; n],
                solved: vec![None; n],
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
        let t = r.elapsed.as_secs_f64();
        let new_stage = st.stage[i] != Some(src.stage);
        if new_stage {
            if let (Some(MeshStage::Coarse(n)), Some((iterations, end))) = (st.stage[i], st.last[i])
            {
                st.solved[i] = Some(SolvedMesh {
                    intervals: n,
                    iterations,
                    seconds: end - st.first[i].1,
                });
            }
            st.stage[i] = Some(src.stage);
            st.first[i] = (r.mu, t);
        }
        st.last[i] = Some((r.iter, t));
        let (intervals, before) = match src.stage {
            MeshStage::Coarse(n) => (n, None),
            MeshStage::Final(n) => (n, st.solved[i].as_ref()),
        };
        let now = MeshProgress {
            intervals,
            iterations: r.iter,
            seconds: t - st.first[i].1,
            mu_start: st.first[i].0,
            mu: r.mu,
            mu_end: self.mu_end,
        };
        st.lines[i] = self.line(src, r, seconds_left(&now, before));
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

    fn line(&self, src: ProgressSource, r: &IterationRecord, left: Option<f64>) -> String {
        let stage = match src.stage {
            MeshStage::Coarse(n) => format!("coarse mesh ({n} intervals)"),
            MeshStage::Final(n) => format!("final mesh ({n} intervals)"),
        };
        let t = r.elapsed.as_secs_f64();
        let left = left.map_or(String::new(), |s| format!(", ~{s:.0} s left on this mesh"));
        format!(
            "{:<22} {stage:<28} iteration {:>4}  objective {:>11.4e}  constraint violation {:>8.1e}  optimality {:>8.1e}  {t:>6.1} s{left}",
            src.guess.to_string(),
            r.iter,
            r.objective,
            r.inf_pr,
            r.inf_du,
        )
    }
}
